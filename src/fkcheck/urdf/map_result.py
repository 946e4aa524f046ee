"""What ``fkcheck map`` found: the joints matched, the frames proposed, the check.

Part of :mod:`fkcheck.urdf.mapping`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from fkcheck.model.coverage import Coverage
from fkcheck.model.edits import TableEdits
from fkcheck.model.types import (
    FrameSpec,
    Model,
)
from fkcheck.urdf.chain_fit import LinkFit

__all__ = [
    "JointMatch",
    "MapResult",
    "ProposedFrame",
]


@dataclass(frozen=True)
class JointMatch:
    """One DH joint and the URDF joint that moves like it.

    Attributes:
        dh: The DH joint's name.
        urdf: The URDF joint's name.
        flipped: The URDF joint turns (slides) the other way from the DH joint as
            the table has it: the table needs ``flip`` toggled on that joint.
    """

    dh: str
    urdf: str
    flipped: bool


@dataclass(frozen=True)
class ProposedFrame:
    """A ``[frames.NAME]`` table the map proposes.

    Attributes:
        spec: The frame (name, DH frame, offset, URDF link or ``None``).
        fit: The evidence for its URDF link, or ``None`` without one.
        declared: The model already declares a frame of this name.
        note: What changed from the model's declaration, or why there is no link.
    """

    spec: FrameSpec
    fit: LinkFit | None
    declared: bool
    note: str = ""


@dataclass(frozen=True)
class MapResult:
    """What ``fkcheck map`` found.

    Attributes:
        model: The model mapped.
        urdf_path: The ``[urdf] path`` to write.
        joints: The matched joints in DH order (the best window when none fits).
        fit_m: How far the last DH frame strays from its URDF link, metres, over the samples.
        fit_rad: The same for orientation, radians.
        also_fit: Other joint windows that fit as well (a two-armed robot).
        frames: The proposed frames, DH frame 0's first, each group ranked by name.
        nearest: When no link fits DH frame 0 (or the last DH frame): the nearest one.
        configurations: How many configurations were compared.
        seed: The sampling seed.
        xacro_args: The URDF is xacro, expanded with these arguments (``None``: plain).
        packages: The packages its ``$(find …)`` resolves, directories as ``[urdf]``
            writes them (relative to the model file).
        pair: The proposed ``[check]`` frame pair: the outermost frames whose offsets
            hide the fewest table numbers (``None`` when an end has no link).
        numbers: What that pair can verify of the table (:mod:`fkcheck.model.coverage`).
        absorbs: Proposed frame → the table numbers its offset could absorb
            (``d1: translation along z of DH frame 0``): a table error there and an
            offset fitted around it look the same, so fkcheck cannot tell them apart.
        check_declared: The model's file has a ``[check]`` table of its own, so the
            block's ``[check]`` is written as comments (a second one would not parse).
        twins: ``[frames.world]`` / ``[frames.tcp]`` the block declares, each the URDF
            link that sits exactly on it, so that the model's own ``[check]`` (which
            compares ``world`` → ``tcp`` unless it says otherwise) has URDF twins.
        edits: The edits of the table's rows that make it move like the chain
            (:func:`reconcile_table`): the flips of :attr:`joints`, and zeros moved
            or signs changed when no chain moves like the table as it is. The
            frames are those of the table so edited.
    """

    model: Model
    urdf_path: str
    joints: tuple[JointMatch, ...]
    fit_m: float
    fit_rad: float
    also_fit: tuple[tuple[str, ...], ...]
    frames: tuple[ProposedFrame, ...]
    nearest: tuple[LinkFit, ...]
    configurations: int
    seed: int
    xacro_args: dict[str, str] | None = None
    packages: dict[str, str] = field(default_factory=dict)
    pair: tuple[str, str] | None = None
    numbers: Coverage | None = None
    absorbs: dict[str, tuple[str, ...]] = field(default_factory=dict)
    check_declared: bool = False
    twins: tuple[FrameSpec, ...] = ()
    edits: TableEdits = field(default_factory=TableEdits)

    @property
    def tolerances(self) -> tuple[float, float]:
        """The model's check tolerances ``(m, rad)``, by which "constant" is judged."""
        return self.model.check.tol_pos_m, self.model.check.tol_rot_rad

    @property
    def joints_fit(self) -> bool:
        """Whether the table moves like the URDF chain found (directions aside)."""
        return (
            bool(self.joints)
            and self.fit_m <= self.tolerances[0]
            and (self.fit_rad <= self.tolerances[1])
        )

    @property
    def complete(self) -> bool:
        """Whether ``fkcheck check`` can pass on the block as pasted.

        The joints fit with no flip, and both ends have a link.
        """
        return (
            self.joints_fit
            and not any(j.flipped for j in self.joints)
            and not self.edits
            and not self.nearest
            and any(f.fit is not None and f.spec.dh in (0, "world") for f in self.frames)
        )

    @property
    def unmapped_ends(self) -> tuple[str, ...]:
        """Ends of the model's own ``[check]`` that have no URDF twin, the block pasted.

        Empty when the block's ``[check]`` is live (the model declares none).
        """
        if not self.check_declared:
            return ()
        mapped = {f.spec.name for f in self.frames if f.fit is not None}
        mapped |= {t.name for t in self.twins}
        mapped |= {s.name for s in self.model.frames.values() if s.urdf is not None}
        ends = dict.fromkeys((self.model.check.frame_from, self.model.check.frame_to))
        return tuple(end for end in ends if end not in mapped)

    @property
    def check_flags(self) -> tuple[str, ...]:
        """What ``fkcheck check MODEL`` needs, the block pasted, to compare mapped frames.

        ``()`` when the check the model then runs has a URDF twin at both ends (the
        block's live ``[check]``, or the model's own ``[check]`` with its frames
        mapped); else ``("--from", A, "--to", B)``, the proposed pair.
        """
        if self.pair is None or not self.unmapped_ends:
            return ()
        return ("--from", self.pair[0], "--to", self.pair[1])
