"""Two readers of one MJCF compared: when they disagree, a finding about a reader, named.

:func:`compare_readers` runs every reader (:data:`fkcheck.mjcf.readers.READERS`)
on the same description, frames and joint values and says, per reader, with
its library's version, whether it failed (and why), and how far it is from a
reference when one is given (the poses a table gives, computed by the caller):
a reader that agrees with the reference while another does not is what makes
the other's disagreement a finding *about that reader*
(:attr:`ReaderComparison.disagreeing`). Without a reference, two readers that
disagree are both named: nothing here can say which is right. Nothing ends in a
library's traceback: a reader that fails is a result with its message.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.tolerances import DEFAULT_TOL_POS_M, DEFAULT_TOL_ROT_RAD
from fkcheck.core.typing import Float
from fkcheck.errors import FkcheckError, failure_text
from fkcheck.mjcf.readers import READERS, Reader, ReaderError, library_version
from fkcheck.mjcf.tree import MjcfDescription

__all__ = ["ReaderComparison", "ReaderResult", "compare_readers"]


@dataclass(frozen=True)
class ReaderResult:
    """One reader's answer.

    Attributes:
        reader: Its name (``mujoco-mjcf``).
        version: Its library and version (``"Pinocchio 4.1.0"``).
        error: Why it failed (``None``: it did not).
        position_m: Its worst position difference from the reference
            (without one: from the first reader that answered), metres; ``None``
            when it failed or is that first reader without a reference.
        rotation_rad: The same for orientation, radians.
        worst: ``"<frame>, sample <n>"`` of the worst position difference.
    """

    reader: str
    version: str
    error: str | None = None
    position_m: float | None = None
    rotation_rad: float | None = None
    worst: str = ""

    def within(self, tol_pos_m: float, tol_rot_rad: float) -> bool:
        """Whether it answered and its differences are within both tolerances."""
        if self.error is not None:
            return False
        return (self.position_m or 0.0) <= tol_pos_m and (self.rotation_rad or 0.0) <= tol_rot_rad


@dataclass(frozen=True)
class ReaderComparison:
    """Every reader's answer on one MJCF, and which of them disagrees.

    Attributes:
        path: The MJCF.
        frames: The frames compared.
        results: One per reader, in :data:`READERS` order.
        reference: What the readers were held to (``"the DH table"``), or
            ``None``: held to each other.
        tol_pos_m: Position tolerance, metres.
        tol_rot_rad: Orientation tolerance, radians.
    """

    path: Path
    frames: tuple[str, ...]
    results: tuple[ReaderResult, ...]
    reference: str | None
    tol_pos_m: float
    tol_rot_rad: float

    @property
    def disagreeing(self) -> tuple[str, ...]:
        """The readers found wrong: failed, or (with a reference) off it beyond tolerance.

        Without a reference, readers that answered but differ from each other
        beyond tolerance are all named (none can be told right).
        """
        tol = (self.tol_pos_m, self.tol_rot_rad)
        failed = [r.reader for r in self.results if r.error is not None]
        answered = [r for r in self.results if r.error is None]
        if self.reference is not None:
            return tuple(failed + [r.reader for r in answered if not r.within(*tol)])
        if all(r.within(*tol) for r in answered):
            return tuple(failed)
        return tuple(failed + [r.reader for r in answered])

    @property
    def agree(self) -> bool:
        """Whether no reader is found wrong."""
        return not self.disagreeing

    def summary(self) -> str:
        """One line per reader: its version and verdict, with the numbers."""
        against = self.reference or "each other"
        lines = [f"{self.path.name}: readers held to {against} on {', '.join(self.frames)}"]
        for r in self.results:
            if r.error is not None:
                verdict = f"failed: {r.error}"
            elif r.position_m is None:
                verdict = "the poses the others are held to"
            else:
                ok = r.within(self.tol_pos_m, self.tol_rot_rad)
                verdict = (
                    f"{'agrees' if ok else 'DISAGREES'}: {r.position_m:.3g} m, "
                    f"{r.rotation_rad:.3g} rad at most (at {r.worst})"
                )
            lines.append(f"  {r.reader} ({r.version}): {verdict}")
        return "\n".join(lines)


def _differences(frames: Sequence[str], poses: Float, held: Float) -> tuple[float, float, str]:
    pos = position_error_m(poses, held)
    rot = rotation_error_rad(poses, held)
    f, n = np.unravel_index(int(np.argmax(pos)), pos.shape)
    return float(pos.max()), float(rot.max()), f"{frames[int(f)]}, sample {int(n)}"


def compare_readers(
    desc: MjcfDescription,
    frames: Sequence[str],
    q: ArrayLike,
    *,
    joints: Sequence[str] | None = None,
    reference: tuple[str, ArrayLike] | None = None,
    readers: Mapping[str, Reader] | None = None,
    tol_pos_m: float = DEFAULT_TOL_POS_M,
    tol_rot_rad: float = DEFAULT_TOL_ROT_RAD,
) -> ReaderComparison:
    """Run every reader on one MJCF and say which disagrees.

    Args:
        desc: The description (:func:`fkcheck.mjcf.tree.read_mjcf`).
        frames: Body or site names, or ``world``.
        q: Joint values for ``joints`` (:func:`fkcheck.mjcf.readers.mujoco_poses`).
        joints: The joints ``q``'s columns are (default: ``desc.joints``).
        reference: ``(what it is, poses)``: the poses the readers are held to,
            ``(len(frames), N, 4, 4)`` in ``world``, e.g. ``("the DH table", …)``.
        readers: The readers by name (default: :data:`READERS`).
        tol_pos_m: Position tolerance, metres (default: a check's).
        tol_rot_rad: Orientation tolerance, radians (default: a check's).

    Returns:
        Each reader's result and which disagree.

    Raises:
        FkcheckError: Bad input (an unknown frame or joint, wrong ``q``): that
            is no reader's fault.
    """
    chosen = READERS if readers is None else readers
    held = None if reference is None else np.asarray(reference[1], dtype=np.float64)
    results = []
    for name, reader in chosen.items():
        version = _version(name)
        try:
            poses = reader(desc, frames, q, joints=joints)
        except FkcheckError:
            raise
        except ReaderError as exc:
            results.append(ReaderResult(name, version, error=exc.problem))
            continue
        except Exception as exc:  # a library's own failure, kept as a result with its type
            results.append(ReaderResult(name, version, error=failure_text(exc)))
            continue
        if held is None:
            held = poses
            results.append(ReaderResult(name, version))
            continue
        pos, rot, worst = _differences(frames, poses, held)
        results.append(ReaderResult(name, version, None, pos, rot, worst))
    return ReaderComparison(
        desc.path,
        tuple(frames),
        tuple(results),
        None if reference is None else reference[0],
        tol_pos_m,
        tol_rot_rad,
    )


def _version(reader: str) -> str:
    try:
        return library_version(reader)
    except (KeyError, FkcheckError):  # a caller's own reader, or a library missing
        return "version unknown"
