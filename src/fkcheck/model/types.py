"""Robot models: the TOML schema (and the plain DH CSV), validated into frozen dataclasses.

A model file holds a DH table and, optionally, base/tool transforms, named
poses, the reference URDF with its joint order, named frames that tie DH frames
to URDF frames, and the default check. Everything is validated on load; a bad
file raises :class:`~fkcheck.errors.ModelError` naming the file, the field and
the problem. Angles are stored in radians whatever the file's ``angle_unit``.

Files are read by :mod:`fkcheck.io.files` (a regular file of at most 1 MiB,
UTF-8, a leading byte-order mark skipped), the CSV's numbers by
:func:`fkcheck.io.numbers.parse_number` (plain ASCII decimals only). Numbers are
bounded by what an arm can be, so that the forward kinematics of a valid model
never overflows: every length (``a``, ``d``, ``xyz``, prismatic limits and pose
values) is within ±:data:`MAX_LENGTH_M` (1 km), every revolute limit and pose
value within ±:data:`MAX_JOINT_RAD` (1000 rad, 159 turns). Fixed angles
(``alpha``, ``theta``, ``rpy``) only enter sines and cosines (and ``θ + q``, with
``q`` bounded), so they need to be finite only.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.core import dh
from fkcheck.core import jacobian as core_jacobian
from fkcheck.core.geometry import invert, matrix_from_xyz_rpy
from fkcheck.core.tolerances import (
    DEFAULT_TOL_JACOBIAN,
    DEFAULT_TOL_POS_M,
    DEFAULT_TOL_ROT_RAD,
    check_limit,
)
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import FrameError, OptionError
from fkcheck.model.version_spec import parse_versions, versions_match

__all__ = [
    "MAX_JOINTS",
    "MAX_JOINT_RAD",
    "MAX_LENGTH_M",
    "PACKAGE_NAME",
    "URDF_FRAME_PREFIX",
    "CalibrationSpec",
    "CheckSpec",
    "DerivedTable",
    "FrameSpec",
    "Joint",
    "KnownDifference",
    "MjcfSpec",
    "Model",
    "Offset",
    "UrdfSpec",
    "default_frames",
    "resolve_frame",
]

JointType = Literal["revolute", "prismatic"]
DhIndex = int | Literal["world", "tcp"]

#: Larger tables are refused: no real arm has them, and a typo-generated file
#: with 10 000 rows should fail fast rather than build a huge chain.
MAX_JOINTS = 256
#: Largest length a model may hold, metres (``a``, ``d``, ``xyz``, prismatic limits
#: and pose values). No arm is a kilometre long; 256 joints this long still keep
#: every pose far from float overflow (``a = 1e308`` made the reference NaN).
MAX_LENGTH_M = 1e3
#: Largest revolute limit or pose value, radians (159 turns). Limits make the
#: sampling box, whose width must stay finite.
MAX_JOINT_RAD = 1e3
#: A package name in ``[urdf] packages`` and ``--package``: what a xacro
#: ``$(find NAME)`` can carry (letters, digits, ``_ . -``).
PACKAGE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")


@dataclass(frozen=True)
class Offset:
    """A fixed transform given as URDF-style ``xyz`` (m) and fixed-axis ``rpy`` (rad)."""

    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def matrix(self) -> Float:
        """The 4×4 homogeneous transform."""
        return matrix_from_xyz_rpy(self.xyz, self.rpy)

    @property
    def is_identity(self) -> bool:
        """Whether both translation and rotation are exactly zero."""
        return not any(self.xyz) and not any(self.rpy)


@dataclass(frozen=True)
class Joint:
    """One row of the DH table, in metres and radians.

    A model file's angles are written in its ``angle_unit``; a ``Joint`` holds them in
    radians.

    Attributes:
        name: Joint name, unique in the model.
        type: ``"revolute"`` or ``"prismatic"``.
        a: Link length (m); in a modified table, ``a_{i-1}``.
        alpha: Link twist, in the file's ``angle_unit`` (held in radians); in a
            modified table, ``α_{i-1}``.
        d: Link offset (m); for a prismatic joint, added to q.
        theta: Angle offset added to q, in the file's ``angle_unit`` (held in
            radians); for a prismatic joint, the fixed angle.
        flip: The joint moves the other way (q enters with a minus sign).
        limits: ``(lower, upper)``: for a revolute joint in the file's ``angle_unit``
            (held in radians), for a prismatic one in metres; or ``None``.
    """

    name: str
    a: float
    alpha: float
    d: float
    theta: float = 0.0
    type: JointType = "revolute"
    flip: bool = False
    limits: tuple[float, float] | None = None


@dataclass(frozen=True)
class CalibrationSpec:
    """Where a calibrated model's table came from (``[calibration]``).

    The table itself is in the model's ``[[joint]]`` rows; this is their
    provenance, and the nominal model a check compares them with to report what
    the calibration changes (:mod:`fkcheck.calibration.effect`).

    Attributes:
        nominal: The nominal model the calibration was applied to: a bundled
            model's name or a model file (relative to this file).
        file: The calibration file as it was named when the model was made.
        form: ``calibration.conf``, ``KinematicsInfo`` or ``ur_calibration YAML``.
        sha256: The SHA-256 of the calibration file's bytes (hex).
        identity: The manufacturer's name for it: the YAML's ``hash`` or the
            joints' checksums (``""`` when the file gives none).
        status: The controller's ``calibration_status`` (0 not initialised,
            1 not linearised, 2 linearised), or ``None``.
    """

    nominal: str
    file: str
    form: str
    sha256: str
    identity: str = ""
    status: int | None = None


@dataclass(frozen=True)
class UrdfSpec:
    """Where the model's reference URDF is, and which URDF joint is which DH joint.

    Attributes:
        path: As written: a path (relative to the model file) or
            ``example-robot-data:<subpath>``.
        joints: URDF joint names in DH order, one per DH joint.
        xacro: Whether the file may be xacro, expanded by fkcheck
            (:mod:`fkcheck.urdf.xacro`); without it a xacro file is refused.
        xacro_args: xacro arguments (``<xacro:arg>``) by name, as text.
        packages: The only packages ``$(find …)`` may resolve: name → directory
            as written (relative to the model file, or ``fkcheck:<subpath>``).
        xacro_files: xacro arguments that name a file (a calibration's
            ``kinematics_params``): name → file as written (relative to the model
            file). Each is passed as its absolute path and is the one file
            outside the description the expansion may read.
        expanded: A xacro file's expansion once the check has made it (the engine
            sets it, so that backends in processes of their own read it instead
            of running the file again); never read from a model file.
    """

    path: str
    joints: tuple[str, ...]
    xacro: bool = False
    xacro_args: dict[str, str] = field(default_factory=dict)
    packages: dict[str, str] = field(default_factory=dict)
    xacro_files: dict[str, str] = field(default_factory=dict)
    expanded: str | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class MjcfSpec:
    """Where the model's MJCF is, and which MJCF joint is which DH joint.

    Attributes:
        path: As written: a path relative to the model file (its ``<include>``
            files are held to the model file's folder).
        joints: MJCF hinge or slide joint names in DH order, one per DH joint.
    """

    path: str
    joints: tuple[str, ...]


@dataclass(frozen=True)
class FrameSpec:
    """A named frame: where it sits on the DH chain and its twins in the descriptions.

    Attributes:
        name: The frame's name.
        dh: DH frame index ``0…n``, ``"tcp"`` (after the tool) or ``"world"``.
        offset: Fixed transform from that DH frame to this frame.
        urdf: Name of the same frame in the URDF, or ``None``.
        source: Where the offset comes from, when the model vouches for it (e.g.
            ``"UR's ROS 2 description: flange = tool0 · rpy(−90°, −90°, 0)"``):
            the check then takes the offset as given instead of counting the
            table numbers it could absorb as unverified (:mod:`fkcheck.model.coverage`).
        mjcf: Name of the same frame in the MJCF (a body, a site or ``world``), or ``None``.
    """

    name: str
    dh: DhIndex
    offset: Offset = field(default_factory=Offset)
    urdf: str | None = None
    source: str = ""
    mjcf: str | None = None


_WORLD = FrameSpec("world", "world")
_TCP = FrameSpec("tcp", "tcp")


def default_frames() -> dict[str, FrameSpec]:
    """The frames every model has: ``world`` (before the base) and ``tcp`` (after the tool)."""
    return {"world": _WORLD, "tcp": _TCP}


@dataclass(frozen=True)
class KnownDifference:
    """A recorded disagreement between the published table and an independent reference.

    A ``[[known_difference]]`` entry says: these backends (by name, or every
    backend that reads the same input: ``reads = "urdf"``) are expected to
    disagree with the table on the model's default check (``[check] from`` →
    ``to``), for the reason in ``finding``. The engine then reports their
    failure as an expected failure (``xfail``), which never counts as the table
    being verified; a listed backend that agrees is a stale expectation and
    fails the check, as does an error beyond the recorded bounds.

    Attributes:
        backends: Names of the backends the disagreement is expected from.
        finding: What ``fkcheck diagnose`` names as the cause.
        max_position_m: Largest position error it may show, metres. Required: an
            unbounded record would turn any later failure of the backend, however
            large, into an expected one. At most
            :data:`~fkcheck.core.tolerances.MAX_KNOWN_POSITION_M` (0.1 m).
        max_angle_rad: Largest rotation error it may show, radians (required too),
            at most :data:`~fkcheck.core.tolerances.MAX_KNOWN_ANGLE_RAD` (0.1 rad)
            (with ``versions``, the reader bounds below).
        reads: ``""``, or what every backend it names reads (``"urdf"``: all URDF
            readers, whichever are installed — a difference between the table and
            the URDF is the URDF's, not one parser's).
        versions: ``""``, or the versions of the one backend's library it was
            measured on (``"<=4.1.0"``, :mod:`fkcheck.model.version_spec`): a
            reader's own difference (a bug of that library), which applies only
            while the installed version matches. Its bounds may then reach
            :data:`~fkcheck.core.tolerances.MAX_READER_POSITION_M` (10 m) and π rad.

    Raises:
        ToleranceError: A bound is not within its range.
        ValueError: ``versions`` is not a valid spec, or is given without exactly
            one backend named.
    """

    backends: tuple[str, ...]
    finding: str
    max_position_m: float
    max_angle_rad: float
    reads: str = ""
    versions: str = ""

    def applies_to(self, name: str, reads: str) -> bool:
        """Whether it records the difference of backend ``name``, which reads ``reads``."""
        return name in self.backends or (self.reads != "" and reads == self.reads)

    def applies_to_version(self, version: str | None) -> bool:
        """Whether it applies to the backend's library at ``version`` (``None``: unknown).

        A record without ``versions`` applies to every version; one with them
        only to a version they match (an unknown or unreadable one matches none).
        """
        if not self.versions:
            return True
        return version is not None and versions_match(self.versions, version)

    def __post_init__(self) -> None:
        reader = bool(self.versions)
        if reader:
            parse_versions(self.versions)
            if len(self.backends) != 1 or self.reads:
                raise ValueError("versions = … records one backend's library: name it alone")
        check_limit(
            self.max_position_m,
            "reader_position" if reader else "known_position",
            "KnownDifference.max_position_m",
        )
        check_limit(
            self.max_angle_rad,
            "reader_angle" if reader else "known_angle",
            "KnownDifference.max_angle_rad",
        )


@dataclass(frozen=True)
class CheckSpec:
    """The default check: which frame pair, and the tolerances.

    Attributes:
        frame_from: Name of the frame the pose is expressed in.
        frame_to: Name of the frame whose pose is compared.
        tol_pos_m: Position tolerance, metres.
        tol_rot_rad: Rotation tolerance, radians.
        require: Kinds of evidence a check must verify (``"table"``,
            ``"implementation"``; see :mod:`fkcheck.engine.verdict`).
        jacobian: Also compare Jacobians (``check --jacobian``).
        jacobian_reference: Their reference frame: ``"world-aligned"``,
            ``"local"`` or ``"world"`` (see :mod:`fkcheck.core.jacobian`).
        tol_jacobian: Their tolerance, m/rad (linear) and rad/rad (angular).

    Raises:
        ToleranceError: A tolerance is not within its range (at most
            :data:`~fkcheck.core.tolerances.MAX_TOL_POS_M`, ``MAX_TOL_ROT_RAD``,
            ``MAX_TOL_JACOBIAN``).
    """

    frame_from: str = "world"
    frame_to: str = "tcp"
    tol_pos_m: float = DEFAULT_TOL_POS_M
    tol_rot_rad: float = DEFAULT_TOL_ROT_RAD
    require: tuple[str, ...] = ()
    jacobian: bool = False
    jacobian_reference: JacobianReference = "world-aligned"
    tol_jacobian: float = DEFAULT_TOL_JACOBIAN

    def __post_init__(self) -> None:
        check_limit(self.tol_pos_m, "tol_pos", "CheckSpec.tol_pos_m")
        check_limit(self.tol_rot_rad, "tol_rot", "CheckSpec.tol_rot_rad")
        check_limit(self.tol_jacobian, "tol_jacobian", "CheckSpec.tol_jacobian")


@dataclass(frozen=True)
class DerivedTable:
    """A table fkcheck derived from one description to check another against it.

    ``fkcheck check --source A --against-description B``: the table comes from
    ``A`` alone and ``B`` is read by its own readers, so agreement shows that
    the two descriptions describe the same kinematics, not that either holds the
    vendor's numbers. Never read from a model file.

    Attributes:
        source: The description the table was derived from, as named.
        checked: The description checked against it, as named.
        checked_from: The link (body, site) of ``checked`` compared as the
            check's ``from`` frame: the chain's base in that file.
        checked_to: The link (body, site) of ``checked`` compared as its ``to``
            frame: the chain's tip in that file.
    """

    source: str
    checked: str
    checked_from: str
    checked_to: str

    @property
    def line(self) -> str:
        """What the check of such a table shows, one line for every output.

        The checked file's ends are named, as the check's frames (the source's
        ends) are by every output.
        """
        return (
            f"table derived by fkcheck from {self.source} (the source), {self.checked} "
            f"({self.checked_from} → {self.checked_to}) checked against it: this shows "
            "whether the two descriptions agree, not whether either holds the vendor's numbers"
        )


@dataclass(frozen=True)
class Model:
    """A validated robot model. Lengths in metres, angles in radians.

    Attributes:
        name: Model name.
        convention: ``"standard"`` or ``"modified"`` DH.
        joints: The DH table, base to tip.
        description: Free text.
        source: Where the numbers come from.
        base: Fixed transform world → DH frame 0.
        tool: Fixed transform last DH frame → TCP.
        poses: Named configurations: revolute values in the file's ``angle_unit``
            (held in radians), prismatic ones in metres.
        urdf: The reference URDF, if any.
        mjcf: The reference MJCF, if any.
        frames: Named frames (always includes ``world`` and ``tcp``; default: just
            those, :func:`default_frames`, so that a model built here checks
            ``world`` → ``tcp`` as a file's does).
        check: The default check.
        angle_unit: ``"rad"`` (the default) or ``"deg"``: the unit of every angle in
            the file — ``alpha``, ``theta``, revolute ``limits``, ``rpy`` and revolute
            pose values. The model holds them in radians; lint and export write
            them back in this unit.
        path: The file it was read from, if any.
        warnings: Things that look wrong but are not errors (e.g. degrees in a radian file).
        lint_ignore: ``fkcheck lint`` rules this model's file turns off (``[lint] ignore``).
        known_differences: Recorded disagreements with independent references
            (``[[known_difference]]``), reported as expected failures.
        calibration: Where a calibrated table came from (``[calibration]``).
        derived: The descriptions a table derived by fkcheck came from and is
            checked against (:class:`DerivedTable`), or ``None``.
    """

    name: str
    convention: dh.Convention
    joints: tuple[Joint, ...]
    description: str = ""
    source: str = ""
    base: Offset = field(default_factory=Offset)
    tool: Offset = field(default_factory=Offset)
    poses: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    urdf: UrdfSpec | None = None
    frames: Mapping[str, FrameSpec] = field(default_factory=default_frames)
    check: CheckSpec = field(default_factory=CheckSpec)
    angle_unit: Literal["rad", "deg"] = "rad"
    path: Path | None = None
    warnings: tuple[str, ...] = ()
    lint_ignore: tuple[str, ...] = ()
    known_differences: tuple[KnownDifference, ...] = ()
    calibration: CalibrationSpec | None = None
    mjcf: MjcfSpec | None = None
    derived: DerivedTable | None = None

    @property
    def dof(self) -> int:
        """Number of joints."""
        return len(self.joints)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Joint names, base to tip."""
        return tuple(j.name for j in self.joints)

    @cached_property
    def chain(self) -> dh.DHChain:
        """The table as arrays for the FK core."""
        js = self.joints
        return dh.DHChain(
            convention=self.convention,
            a=np.array([j.a for j in js], dtype=np.float64),
            alpha=np.array([j.alpha for j in js], dtype=np.float64),
            d=np.array([j.d for j in js], dtype=np.float64),
            theta=np.array([j.theta for j in js], dtype=np.float64),
            prismatic=np.array([j.type == "prismatic" for j in js], dtype=bool),
            sign=np.array([-1.0 if j.flip else 1.0 for j in js]),
            world_T_base=self.base.matrix,
            flange_T_tool=self.tool.matrix,
        )

    @cached_property
    def limits(self) -> Float:
        """Joint limits as ``(n, 2)``; ``±inf`` where a joint has none."""
        return np.array(
            [j.limits if j.limits is not None else (-math.inf, math.inf) for j in self.joints],
            dtype=np.float64,
        ).reshape(self.dof, 2)

    @cached_property
    def reach_m(self) -> float:
        """Every length of the chain added up, metres: base, ``|a| + |d|``, strokes, tool.

        An upper bound of how far any pose's origin is from the world's, sampled or
        not: the scale of the core's round-off
        (:func:`~fkcheck.core.tolerances.roundoff_floor_m`).
        """
        finite = np.where(np.isfinite(self.limits), np.abs(self.limits), 0.0)
        strokes = sum(
            float(finite[i].max()) for i, j in enumerate(self.joints) if j.type == "prismatic"
        )
        rows = sum(abs(j.a) + abs(j.d) for j in self.joints)
        ends = float(np.linalg.norm(self.base.xyz) + np.linalg.norm(self.tool.xyz))
        return float(rows + strokes + ends)

    def fk(
        self,
        q: ArrayLike,
        all_frames: bool = False,
        *,
        frame_from: str | None = None,
        frame_to: str | None = None,
    ) -> Float:
        """Forward kinematics with the in-house core.

        Joint limits are not checked: any finite value is computed (as
        ``fkcheck fk --ignore-limits``). ``fkcheck fk`` checks them by default with
        :func:`fkcheck.model.joint_input.check_limits`, which a caller can use too.

        ``frame_from`` and ``frame_to`` are the check's frame names (``[frames.NAME]``,
        ``world``, ``tcp``, ``urdf:LINK``), as Robotics Toolbox's ``fkine(q,
        start=, end=)``: ``model.fk(q, frame_from="base_link", frame_to="tool0")``
        is ``base_link_T_tool0``, ``(world_T_base_link)⁻¹ · world_T_tool0``.

        Args:
            q: Joint values, shape ``(n,)`` or ``(N, n)``, radians / metres.
            all_frames: Return DH frames ``0…n`` (base included, tool not), in
                the world; not with ``frame_from`` or ``frame_to``.
            frame_from: The frame the pose is expressed in (default: the world).
            frame_to: The frame whose pose is returned (default: the TCP, after
                the tool).

        Returns:
            ``from_T_to`` (by default ``world_T_tcp``) as ``(4, 4)`` or
            ``(N, 4, 4)``; with ``all_frames``, ``(n+1, 4, 4)`` or ``(N, n+1, 4, 4)``.

        Raises:
            JointInputError: Wrong shape or non-finite values.
            FrameError: An unknown frame; the message lists the model's frames.
            OptionError: ``all_frames`` with ``frame_from`` or ``frame_to``.
        """
        if frame_from is None and frame_to is None:
            return dh.fk(self.chain, q, all_frames=all_frames)
        specs = (
            resolve_frame(self, frame_from) if frame_from is not None else _WORLD,
            resolve_frame(self, frame_to) if frame_to is not None else _TCP,
        )
        if all_frames:
            raise OptionError(
                "all_frames",
                "gives every DH frame in the world, so it does not combine with frame_from "
                "or frame_to (ask for one frame at a time)",
            )
        world_T_dh = dh.fk(self.chain, q, all_frames=True)  # q is validated there, once
        world_T_tcp = world_T_dh[..., -1, :, :] @ self.chain.flange_T_tool
        placed: list[Float] = []
        for spec in specs:
            if spec.dh == "world":
                anchor: Float = np.broadcast_to(np.eye(4), world_T_tcp.shape)
            elif spec.dh == "tcp":
                anchor = world_T_tcp
            else:
                anchor = world_T_dh[..., spec.dh, :, :]
            placed.append(anchor @ spec.offset.matrix)
        from_T_to: Float = invert(placed[0]) @ placed[1]
        return from_T_to

    def jacobian(
        self, q: ArrayLike, frame: str = "tcp", reference: JacobianReference = "world-aligned"
    ) -> Float:
        """The geometric Jacobian of a named frame with the in-house core.

        Linear rows first, then angular; ``reference`` is ``"world-aligned"``
        (the frame origin's velocity in world axes; Pinocchio's
        ``LOCAL_WORLD_ALIGNED``, Robotics Toolbox's ``jacob0``), ``"local"``
        (the frame's own axes; ``LOCAL``, ``jacobe``) or ``"world"`` (the
        spatial twist at the world origin; ``WORLD``). See
        :mod:`fkcheck.core.jacobian`.

        Args:
            q: Joint values, ``(n,)`` or ``(N, n)``, radians / metres.
            frame: A named frame (default the TCP).
            reference: The reference frame.

        Returns:
            ``(6, n)`` or ``(N, 6, n)``.

        Raises:
            JointInputError: Wrong shape or non-finite values.
            FrameError: An unknown frame.
            ValueError: An unknown ``reference``.
        """
        spec = resolve_frame(self, frame)
        chain = self.chain
        if spec.dh == "world":
            moving, target = 0, spec.offset.matrix
        elif spec.dh == "tcp":
            moving, target = self.dof, chain.flange_T_tool @ spec.offset.matrix
        else:
            moving, target = spec.dh, spec.offset.matrix
        jac = core_jacobian.jacobian(  # q and reference are validated there, once
            chain, np.asarray(q), moving=moving, target=target, reference=reference
        )
        return jac[0] if np.ndim(q) == 1 else jac


#: Prefix that names a frame by its URDF link: ``urdf:tool0``.
URDF_FRAME_PREFIX = "urdf:"


def resolve_frame(model: Model, name: str) -> FrameSpec:
    """The named frame, or :class:`~fkcheck.errors.FrameError` listing the model's frames.

    ``urdf:LINK`` names the declared frame whose URDF twin is ``LINK``.
    """
    if name.startswith(URDF_FRAME_PREFIX):
        link = name[len(URDF_FRAME_PREFIX) :]
        twins = [spec for spec in model.frames.values() if spec.urdf == link]
        if twins:
            return twins[0]
        mapped = [f"urdf:{s.urdf} (= {s.name})" for s in model.frames.values() if s.urdf]
        raise FrameError(
            name,
            f"model {model.name}: no declared frame has URDF twin {link!r}; to compare a "
            f'link, declare [frames.NAME] with dh, its offset and urdf = "{link}"',
            mapped,
        )
    try:
        return model.frames[name]
    except KeyError:
        raise FrameError(name, f"model {model.name}", model.frames) from None
