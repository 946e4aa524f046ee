"""Which URDF joints and links a DH model's joints and frames are, found by behaviour.

``fkcheck map`` proposes a model's ``[urdf]`` and ``[frames.*]`` block; ``fkcheck
check --to urdf:LINK`` places a link the model does not declare. Both compare the
in-house DH frames (:meth:`fkcheck.model.Model.fk`) with fkcheck's own URDF
chain geometry (:mod:`fkcheck.urdf.chain`) over seeded configurations: this is
a *mapping* tool, not a check (``fkcheck check`` on the result compares the
model against the independent URDF parsers).

Joints are matched by what they do, never by name. For each window of ``n``
consecutive movable URDF joints on a path from the root (every arm of a tree is
tried), and each axis direction, the relative motions of the last DH frame in
DH frame 0 are fitted to those of the window's last link in its first link's
parent (hand–eye calibration, ``M(q) = X·U(q)·Y``: rotation axes aligned with
:meth:`scipy.spatial.transform.Rotation.align_vectors`, then the translation by
least squares). A joint whose URDF axis turns the other way from the DH joint
(the URDF receives ``q`` unchanged) needs ``flip`` toggled in the table: the
directions are found by a beam search over the chain's prefixes, preferring no
flip where both fit (a planar chain is ambiguous).

Links: a link sits at a *constant* offset from a DH frame when that offset
varies over the samples by at most the model's check tolerances. Joints the
model does not map (fingers) take seeded random values then, so links below
them never count as rigid. Offsets are written with numbers within 1e-9 of a
round one (0, a multiple of 90°, a whole micrometre) snapped to it
(:func:`fkcheck.urdf.to_dh.clean_number`).
"""

from __future__ import annotations

import fnmatch
import math
import re
import tomllib
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from fkcheck.core.geometry import invert
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.errors import FkcheckError, FrameError, UrdfError
from fkcheck.io.files import MAX_MODEL_FILE_BYTES, InputFileError, read_text
from fkcheck.io.format import format_deg, format_mm
from fkcheck.model.coverage import Competitor, Coverage, coverage
from fkcheck.model.edits import TableEdits, half_turns_as_signs
from fkcheck.model.names import PARAMS, Param
from fkcheck.model.sampling import sample_configurations, sampling_box
from fkcheck.model.types import (
    URDF_FRAME_PREFIX,
    CheckSpec,
    FrameSpec,
    Model,
    Offset,
    UrdfSpec,
)
from fkcheck.model.write import frame_toml, toml_comment, toml_string, xacro_toml
from fkcheck.urdf.chain import MOVABLE, JointGeometry, UrdfKinematics
from fkcheck.urdf.to_dh import clean_offset
from fkcheck.urdf.tree import listed

__all__ = [
    "COMMON_NAMES",
    "DEFAULT_SAMPLES",
    "JointMatch",
    "LinkFit",
    "MapResult",
    "ProposedFrame",
    "Reconciled",
    "link_frame",
    "map_model",
    "proposal_toml",
    "reconcile_table",
    "with_link_frames",
]

#: Link names by how common they are as a robot's base or tool frame (glob patterns,
#: most common first); other names follow in the URDF's order.
COMMON_NAMES = (
    "base",
    "base_link",
    "tool0",
    "flange",
    "ee_link",
    "tcp",
    "*_link0",
    "*_link8",
    "*_base",
    "*_base_link",
    "*_tool0",
    "*_flange",
    "*_ee_link",
    "*_hand",
    "*_tcp",
    "world",
)
#: Random configurations tried on top of the structured ones (poses, corners, edges).
DEFAULT_SAMPLES = 64
#: Configuration pairs the hand–eye fit uses, and the largest step between the two
#: of a pair (rad or m per joint, shrunk for long chains so the motion stays below π).
_FIT_PAIRS = 48
_FIT_STEP = 0.2
#: Sign hypotheses kept per chain prefix while the axis directions are searched.
_BEAM = 8
#: Relative turns below this (rad, root-mean-square over the fit's pairs) leave a
#: translation direction of the hand–eye fit free: a pair's turn is ~0.1 rad
#: (:data:`_FIT_STEP`), round-off ~1e-15 rad, a URDF's rounded π/2 ~4e-6 rad off.
_FREE_TURN_RAD = 1e-6
#: A turn of the split that leaves the fit this much worse (m + rad) is not free:
#: round-off of a fit is ~1e-15, a real change of the fit is of the reach's size.
_SAME_FIT = 1e-9
#: Hypotheses polished by least squares when no closed-form fit fits, and the
#: spins each starts from (:func:`_refine`).
_REFINE = 4
_SPINS = 8

#: Zero offsets tried per joint when no chain moves like the table as it is (the
#: vendor's zero and the URDF's differ by quarter turns: KUKA's A2, A3), and the
#: hypotheses kept per prefix then (offsets that undo each other through an
#: intersecting axis tie on a prefix and part only further down).
_QUARTERS = (0.0, math.pi / 2, -math.pi / 2, math.pi)
_WIDE_BEAM = 16
#: A chain still this far off (m + rad) once the flips and zeros are found is tried
#: for one number that differs; farther off, the table is another arm's.
_NUMBER_REACH = 0.1

Anchor = int | Literal["world", "tcp"]  # a DH frame 0…n, "tcp" or "world"


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
class LinkFit:
    """A URDF link seen from one DH frame over the samples.

    Attributes:
        link: The URDF link.
        anchor: The DH frame (``0…n``, ``"tcp"`` or ``"world"``).
        offset: The offset anchor → link at the first sample, round numbers snapped.
        spread_m: How far the offset's origin moves over the samples, metres.
        spread_rad: How far its orientation turns over the samples, radians.
    """

    link: str
    anchor: Anchor
    offset: Offset
    spread_m: float
    spread_rad: float

    def fits(self, tol_pos_m: float, tol_rot_rad: float) -> bool:
        """Whether the offset is constant within the tolerances."""
        return self.spread_m <= tol_pos_m and self.spread_rad <= tol_rot_rad

    def evidence(self) -> str:
        """``max deviation 2.2e-16 m, 4.4e-16 rad over the samples`` or the like."""
        return f"max deviation {self.spread_m:.2g} m, {self.spread_rad:.2g} rad"


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


# ----------------------------------------------------------------------------- geometry


def _with_thetas(model: Model, thetas: Sequence[float]) -> Model:
    """The model with ``thetas`` (radians) added to its first joints' θ (zeros moved)."""
    joints = tuple(
        replace(j, theta=j.theta + thetas[k]) if k < len(thetas) and thetas[k] else j
        for k, j in enumerate(model.joints)
    )
    return replace(model, joints=joints)


def _dh_in_frame0(model: Model, q: Float) -> Float:
    """``dh0_T_dhk`` for k = 0…n, ``(N, n+1, 4, 4)``, from the in-house core."""
    frames = np.asarray(model.fk(q, all_frames=True)).reshape(q.shape[0], model.dof + 1, 4, 4)
    return invert(frames[:, :1]) @ frames


def _anchor_poses(model: Model, dh0: Float, anchor: Anchor) -> Float:
    """The anchor frame in DH frame 0, ``(N, 4, 4)``."""
    if anchor == "world":
        return np.broadcast_to(invert(model.base.matrix), dh0[:, 0].shape)
    if anchor == "tcp":
        return dh0[:, -1] @ model.tool.matrix
    return dh0[:, int(anchor)]


def _joint_values(
    kin: UrdfKinematics,
    mapped: Sequence[str],
    signs: Sequence[float],
    q: Float,
    rng: np.random.Generator | None,
) -> dict[str, Float]:
    """Every movable URDF joint's values: the mapped ones from ``q``, the others random or 0."""
    N = q.shape[0]
    values: dict[str, Float] = {}
    for joint in kin.joints.values():
        if joint.type == "fixed":
            continue
        if rng is None:
            values[joint.name] = np.zeros(N)
            continue
        default = 0.5 if joint.type == "prismatic" else math.pi
        lo, hi = joint.limits or (-default, default)
        values[joint.name] = lo + (hi - lo) * np.asarray(rng.random(N), dtype=np.float64)
    for col, (name, sign) in enumerate(zip(mapped, signs, strict=True)):
        values[name] = sign * q[:, col]
    return values


def _root_poses(
    kin: UrdfKinematics, links: Sequence[str], values: Mapping[str, Float], N: int
) -> dict[str, Float]:
    """``root_T_link`` ``(N, 4, 4)`` of ``links`` (and of the links on their way).

    Links below a joint fkcheck cannot follow (``floating``, ``planar``) are left out.
    """
    out: dict[str, Float] = {kin.root: np.broadcast_to(np.eye(4), (N, 4, 4))}
    for link in links:
        if link in out:
            continue
        chain = kin.chain(kin.root, link)
        try:
            movable = kin.movable(chain)
        except UrdfError:
            continue
        q = np.column_stack([values[j.name] for j in movable]) if movable else np.zeros((N, 0))
        poses = kin.chain_poses(chain, q)
        for i, joint in enumerate(chain):
            out.setdefault(joint.child, poses[:, i])
    return out


def _spread(offsets: Float) -> tuple[float, float]:
    """How far the offsets ``(N, 4, 4)`` stray from the first one: ``(m, rad)``."""
    ref = np.broadcast_to(offsets[0], offsets.shape)
    return (
        float(position_error_m(ref, offsets).max()),
        float(rotation_error_rad(ref, offsets).max()),
    )


def _hand_eye(M: Float, U: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` with ``M ≈ X·U·Y``, from configuration pairs ``(M[2i], M[2i+1])``.

    Each pair's relative motions satisfy ``Y·C = D·Y`` (``C = M_a⁻¹M_b``,
    ``D = U_a⁻¹U_b``): the rotation maps ``C``'s rotation vectors onto ``D``'s
    (pure translations use their translation instead), the translation solves
    ``(I − R_D)·t = t_D − R·t_C`` by least squares in the directions the turns
    determine; the others are left to :func:`_pinned`.
    """
    C = invert(M[0::2]) @ M[1::2]
    D = invert(U[0::2]) @ U[1::2]
    c = Rotation.from_matrix(C[:, :3, :3]).as_rotvec()
    d = Rotation.from_matrix(D[:, :3, :3]).as_rotvec()
    still = np.linalg.norm(d, axis=1) < 1e-9
    c[still], d[still] = C[still, :3, 3], D[still, :3, 3]
    with warnings.catch_warnings():  # a single axis (a one-joint prefix) leaves a spin free
        warnings.simplefilter("ignore", UserWarning)
        rotation, _ = Rotation.align_vectors(d, c)
    R = rotation.as_matrix()
    lhs = (np.eye(3) - D[:, :3, :3]).reshape(-1, 3)
    rhs = (D[:, :3, 3] - C[:, :3, 3] @ R.T).reshape(-1)
    _, sv, Vt = np.linalg.svd(lhs, full_matrices=False)
    fixed = sv > _FREE_TURN_RAD * math.sqrt(D.shape[0])
    # The least-squares t with no component in the free directions (no pseudo-inverse of
    # round-off: with slides only, every direction is free and t is 0 here).
    t = Vt[fixed].T @ ((Vt[fixed] @ (lhs.T @ rhs)) / sv[fixed] ** 2)
    Y = np.eye(4)
    Y[:3, :3], Y[:3, 3] = R, t
    return _pinned(M, U, M[0] @ invert(Y) @ invert(U[0]), Y)


def _free_directions(U: Float) -> Float:
    """Directions (rows, in the tip's frame) along which ``Y``'s translation is free.

    ``X·U·Y = X·T(s)·U·T(−Rᵀs)·Y`` whenever every turn of ``U`` keeps ``s``: a
    slide's offset can sit on either side of it. With slides only that is every
    direction; with turns about one axis (parallel axes, one revolute joint among
    slides), that axis. The rows are orthonormal (none: ``Y`` is determined).
    """
    D = invert(U[0::2]) @ U[1::2]
    lhs = (np.eye(3) - D[:, :3, :3]).reshape(-1, 3)
    _, sv, Vt = np.linalg.svd(lhs, full_matrices=False)
    free: Float = Vt[sv <= _FREE_TURN_RAD * math.sqrt(D.shape[0])]
    return free


def _pinned(M: Float, U: Float, X: Float, Y: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` with the free part of the split chosen: the least turn, then the nearest.

    The motion cannot tell where along a free direction (:func:`_free_directions`)
    the URDF chain's base link sits from DH frame 0 (it moves the tip link the
    other way), nor, when every joint turns about one line and slides along it, how
    far the base link is turned about that line (:func:`_spin`). The base link is
    turned as little from DH frame 0 and put as close to its origin as the motion
    leaves free — where a URDF that starts its chain at DH frame 0 has it, and
    never 10²⁰ m away.
    """
    X, Y = _spin(M, U, X, Y)
    N = _free_directions(U).T  # (3, k), orthonormal columns, in the tip's frame
    if N.shape[1] == 0:
        return X, Y
    # Y → T(N·c)·Y moves X to A·T(−N·c)·U₀⁻¹ (A = M₀·Y⁻¹): its translation by −R_A·N·c.
    A = M[0] @ invert(Y)
    c = (A[:3, :3] @ N).T @ X[:3, 3]
    Y = Y.copy()
    Y[:3, 3] += N @ c
    return M[0] @ invert(Y) @ invert(U[0]), Y


def _deviation(M: Float, U: Float, X: Float, Y: Float) -> float:
    """How far ``X·U·Y`` strays from ``M``: metres plus radians, at worst."""
    E = invert(M) @ X @ U @ Y
    eye = np.broadcast_to(np.eye(4), E.shape)
    return float(position_error_m(eye, E).max() + rotation_error_rad(eye, E).max())


def _spin(M: Float, U: Float, X: Float, Y: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` turned about the chain's one turning line, if that is free, by the least turn.

    When every joint turns about one line and slides along it (a lift under a
    turntable, a single slide), turning the base link about that line and the tip
    link back is the same motion: the turn that leaves ``X`` closest to no turn is
    kept, if the fit stays as good (it does not when the turns have several lines).
    """
    B = U[1::2] @ invert(U[0::2])  # relative motions in the base link's frame
    r = Rotation.from_matrix(B[:, :3, :3]).as_rotvec()
    turning = np.linalg.norm(r, axis=1) > 1e-9
    directions = r[turning] if turning.any() else B[:, :3, 3]
    if len(directions) == 0:
        return X, Y
    _, sv, Vt = np.linalg.svd(directions, full_matrices=False)
    if sv[0] == 0.0 or (len(sv) > 1 and sv[1] > _FREE_TURN_RAD * sv[0]):
        return X, Y  # turns (or slides) in more than one direction: the spin is set
    n = Vt[0]
    point: Float = np.zeros(3)
    if turning.any():  # the line's point: (I − R)·p = t across the axis, for every turn
        lhs = (np.eye(3) - B[turning, :3, :3]).reshape(-1, 3)
        t = B[turning, :3, 3]
        rhs = (t - np.outer(t @ n, n)).reshape(-1)
        point = np.asarray(np.linalg.lstsq(lhs, rhs, rcond=None)[0], dtype=np.float64)
    # The turn φ about n that leaves X least turned: max of trace(R_X·Rot(n, φ)).
    R = X[:3, :3]
    K = np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])
    phi = math.atan2(float(np.trace(R @ K)), float(np.trace(R) - n @ R @ n))
    about = np.eye(4)
    about[:3, :3] = Rotation.from_rotvec(phi * n).as_matrix()
    about[:3, 3] = point - about[:3, :3] @ point
    X2 = X @ about
    Y2 = invert(U[0]) @ invert(X2) @ M[0]
    if _deviation(M, U, X2, Y2) > _deviation(M, U, X, Y) + _SAME_FIT:
        return X, Y
    return X2, Y2


def _refine(M: Float, U: Float, X: Float, Y: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` with ``M ≈ X·U·Y`` by least squares on every configuration.

    When every relative turn of ``U`` is about one direction (parallel axes, a
    single revolute joint among slides) the rotation fit leaves ``Y``'s spin about
    it free, and the closed form picks one at random: the translations decide it.
    Starts from :data:`_SPINS` spins of ``Y`` about that direction and keeps the best.
    """
    D = invert(U[0::2]) @ U[1::2]
    d = Rotation.from_matrix(D[:, :3, :3]).as_rotvec()
    d = d[np.linalg.norm(d, axis=1) > 1e-9]
    axis = np.linalg.svd(d)[2][0] if len(d) else np.array([0.0, 0.0, 1.0])
    M_inv = invert(M)

    def pose(p: Float) -> Float:
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = Rotation.from_rotvec(p[:3]).as_matrix(), p[3:]
        return T

    def residual(p: Float, X0: Float, Y0: Float) -> Float:
        E = M_inv @ (X0 @ pose(p[:6])) @ U @ (pose(p[6:]) @ Y0)
        rot = Rotation.from_matrix(E[:, :3, :3]).as_rotvec()
        return np.concatenate([rot.reshape(-1), E[:, :3, 3].reshape(-1)])

    best = (np.inf, X, Y)
    for spin in np.linspace(0.0, 2.0 * math.pi, _SPINS, endpoint=False):
        Y0 = pose(np.concatenate([spin * axis, np.zeros(3)])) @ Y
        X0 = M[0] @ invert(Y0) @ invert(U[0])
        sol = least_squares(residual, np.zeros(12), args=(X0, Y0), method="lm", xtol=1e-15)
        if sol.cost < best[0]:
            best = (float(sol.cost), X0 @ pose(sol.x[:6]), pose(sol.x[6:]) @ Y0)
    return best[1], best[2]


@dataclass(frozen=True, eq=False)
class _Fit:
    """A joint window with axis directions, fitted: ``dh0_T_dhn = X · base_T_tip · Y``.

    ``thetas``: radians added to the table's θ of each joint of the prefix (empty:
    none), the zero offsets :meth:`_Problem.reconcile` tries.
    """

    joints: tuple[str, ...]
    signs: tuple[float, ...]
    base: str
    X: Float
    Y: Float
    dev_m: float
    dev_rad: float
    thetas: tuple[float, ...] = ()

    @property
    def changes(self) -> int:
        """How many edits of the table it asks for: flips toggled, zeros moved.

        Two neighbouring zeros half a turn away count once: they are one sign typed
        the other way (:func:`fkcheck.model.edits.half_turns_as_signs`).
        """
        pairs, k = 0, 0
        while k + 1 < len(self.thetas):
            if (
                abs(abs(self.thetas[k]) - math.pi) < 1e-12
                and abs(abs(self.thetas[k + 1]) - math.pi) < 1e-12
            ):
                pairs, k = pairs + 1, k + 2
            else:
                k += 1
        return sum(s < 0 for s in self.signs) + sum(t != 0.0 for t in self.thetas) - pairs

    def score(self, tol: tuple[float, float]) -> tuple[int, int, int, float, float]:
        """Sort key: fitting first, then fewer edits (flips), then the smaller deviation.

        Between fits with as many flips (slides at right angles: flipping the x or
        the y slide is the same motion seen from a base turned 180°), the one whose
        URDF base link is turned least from DH frame 0 comes first.
        """
        fits = self.dev_m <= tol[0] and self.dev_rad <= tol[1]
        turn = math.acos(min(1.0, max(-1.0, (np.trace(self.X[:3, :3]) - 1.0) / 2.0)))
        return (
            0 if fits else 1,
            self.changes,
            sum(t != 0.0 for t in self.thetas),
            round(turn, 6) if fits else 0.0,
            self.dev_m + self.dev_rad,
        )

    def near(self, tol: tuple[float, float]) -> tuple[int, int, int, int, float]:
        """Sort key of :meth:`_Problem.reconcile`: fitting, then as near within a factor of ten.

        A wrong flip or zero leaves the chain off by a link's length; a table number
        off by a millimetre leaves a millimetre whatever else is tried: among
        hypotheses that leave the same order of magnitude, fewer edits come first.
        """
        fits = self.dev_m <= tol[0] and self.dev_rad <= tol[1]
        dev = self.dev_m + self.dev_rad
        magnitude = 0 if fits else math.floor(math.log10(max(dev, 1e-15)))
        # Among as many edits, a reversed joint before a zero moved: a half turn of the
        # zero before an intersecting axis reverses that axis as a flip does.
        turns = sum(t != 0.0 for t in self.thetas)
        return (0 if fits else 1, magnitude, self.changes, turns, dev)


class _Problem:
    """A model, a URDF and the configurations both are evaluated at."""

    def __init__(self, model: Model, kin: UrdfKinematics, samples: int, seed: int) -> None:
        self.model, self.kin = model, kin
        self.tol = (model.check.tol_pos_m, model.check.tol_rot_rad)
        self.q = sample_configurations(model, samples, seed).q
        rng = np.random.default_rng(seed)
        n = model.dof
        step = min(_FIT_STEP, 2.0 / max(n, 1))
        lo, hi = sampling_box(model)
        first = lo + (hi - lo) * rng.random((_FIT_PAIRS, n))
        pairs = np.empty((2 * _FIT_PAIRS, n))
        pairs[0::2], pairs[1::2] = first, first + rng.uniform(-step, step, first.shape)
        self.fit_q = pairs
        self.dh_fit = _dh_in_frame0(model, pairs)
        self.dh = _dh_in_frame0(model, self.q)
        self.seed = seed
        self.samples = samples
        self._turned: dict[tuple[float, ...], Float] = {}

    def turned(self, thetas: Sequence[float]) -> Float:
        """:attr:`dh_fit` of the table with ``thetas`` added to its first joints' θ."""
        if not any(thetas):
            return self.dh_fit
        key = tuple(thetas)
        if key not in self._turned:
            model = _with_thetas(self.model, key)
            self._turned[key] = _dh_in_frame0(model, self.fit_q)
        return self._turned[key]

    def relative(
        self,
        q: Float,
        joints: Sequence[str],
        signs: Sequence[float],
        base: str,
        links: Sequence[str],
        rng: np.random.Generator | None,
    ) -> dict[str, Float]:
        """``base_T_link`` for ``links`` at ``q`` (unmapped joints random with ``rng``, else 0)."""
        values = _joint_values(self.kin, joints, signs, q, rng)
        poses = _root_poses(self.kin, [base, *links], values, q.shape[0])
        base_inv = invert(poses[base])
        return {link: base_inv @ poses[link] for link in links if link in poses}

    def fit(
        self,
        joints: Sequence[str],
        signs: Sequence[float],
        refine: bool = False,
        thetas: Sequence[float] = (),
    ) -> _Fit:
        """Fit the first ``len(signs)`` joints of ``joints``: DH frame k vs their last child.

        With ``refine``, the closed-form fit is polished by least squares on every
        pair (:func:`_refine`): needed when the joints' turns leave a spin free.
        ``thetas`` are added to the table's θ first (:meth:`reconcile`).
        """
        k = len(signs)
        used = tuple(joints[:k])
        base = self.kin.joints[used[0]].parent
        tip = self.kin.joints[used[-1]].child
        U = self.relative(self.fit_q[:, :k], used, signs, base, [tip], None)[tip]
        M = self.turned(thetas)[:, k]
        X, Y = _hand_eye(M, U)
        if refine:
            X, Y = _pinned(M, U, *_refine(M, U, X, Y))
        E = invert(M) @ X @ U @ Y
        eye = np.broadcast_to(np.eye(4), E.shape)
        return _Fit(
            used, tuple(signs), base, X, Y,
            float(position_error_m(eye, E).max()), float(rotation_error_rad(eye, E).max()),
            tuple(thetas),
        )  # fmt: skip

    def search(self, joints: Sequence[str], polish: bool = True) -> _Fit:
        """The axis directions of a window of joints, by a beam search over its prefixes.

        When no directions fit, zeros too (:meth:`reconcile`); then, with
        ``polish``, the likeliest directions polished by least squares.
        """
        beam: list[tuple[float, ...]] = [()]
        best: list[_Fit] = []
        for _ in joints:
            fits = [self.fit(joints, (*signs, s)) for signs in beam for s in (1.0, -1.0)]
            best = sorted(fits, key=lambda f: f.score(self.tol))[:_BEAM]
            beam = [f.signs for f in best]
        if best[0].score(self.tol)[0] == 0:
            return best[0]
        # Zeros that differ (a vendor's convention), then parallel turns and slides
        # (the closed form leaves a spin free): polish the likeliest.
        reconciled = self.reconcile(joints)
        if reconciled.score(self.tol)[0] == 0 or not polish:
            return min(best[0], reconciled, key=lambda f: f.near(self.tol))
        polished = [self.fit(joints, f.signs, refine=True) for f in best[:_REFINE]]
        best = sorted([*polished, *best], key=lambda f: f.score(self.tol))
        return min(best[0], reconciled, key=lambda f: f.near(self.tol))

    def reconcile(self, joints: Sequence[str]) -> _Fit:
        """Flips and quarter-turn zero offsets together: the fewest that make the chain fit.

        A beam search over the chain's prefixes, as :meth:`search`, where each step
        also tries the previous revolute joint's θ turned by each of
        :data:`_QUARTERS` (its zero shows only once the next joint moves; the last
        joint's is the tip frame's business). Kept: :data:`_WIDE_BEAM` per prefix,
        by :meth:`_Fit.near`.
        """
        n = len(joints)
        if not any(j.type == "revolute" for j in self.model.joints[: n - 1]):
            return self.fit(joints, (1.0,) * n)  # no zero to move
        beam = [self.fit(joints, (s,), thetas=(0.0,) * n) for s in (1.0, -1.0)]
        for k in range(1, n):
            turns = _QUARTERS if self.model.joints[k - 1].type == "revolute" else (0.0,)
            fits = []
            for prev in beam:
                for turn in turns:
                    thetas = list(prev.thetas)
                    thetas[k - 1] = turn
                    for s in (1.0, -1.0):
                        fits.append(self.fit(joints, (*prev.signs, s), thetas=thetas))
            beam = sorted(fits, key=lambda f: f.near(self.tol))[:_WIDE_BEAM]
        return beam[0]

    def evaluate(self, fit: _Fit, links: Sequence[str], anchor: Anchor) -> list[LinkFit]:
        """Each link's offset from ``anchor`` over the evaluation samples.

        DH frame 0 and ``world`` hold the tip to the URDF (``dh0_T_link = M·Y⁻¹·U⁻¹·…``),
        every other DH frame holds the base (``X·…``): either way the offset stays
        constant only when the whole chain moves as the URDF does.
        """
        q = self.q
        n = len(fit.joints)
        rng = np.random.default_rng(self.seed + 1)
        tip = self.kin.joints[fit.joints[-1]].child
        rel = self.relative(q[:, :n], fit.joints, fit.signs, fit.base, [tip, *links], rng)
        if anchor in (0, "world"):
            W = self.dh[:, -1] @ invert(fit.Y) @ invert(rel[tip])
        else:
            W = np.broadcast_to(fit.X, (q.shape[0], 4, 4))
        P_inv = invert(_anchor_poses(self.model, self.dh, anchor))
        out = []
        for link in links:
            if link not in rel:
                continue
            offsets = P_inv @ W @ rel[link]
            spread_m, spread_rad = _spread(offsets)
            out.append(LinkFit(link, anchor, clean_offset(offsets[0]), spread_m, spread_rad))
        return out

    def one_number(self, fit: _Fit) -> tuple[int, Param, float, _Fit] | None:
        """The one table number that, set to another value, makes the whole chain fit.

        Each ``a``, ``α``, ``d``, ``θ`` in turn is fitted alone (least squares from
        the table's value) to the chain's motion, the end offsets fitted anew at
        each step: as a diagnosis's single-parameter fits, but on the URDF's chain,
        so the end frames need not be known. Numbers an end offset carries (d1, θ1,
        the last row's) do not change the motion and are never the answer.

        Returns:
            ``(joint index, parameter, value, fit)`` of the number that makes the
            chain fit (the smallest change, if several do), or ``None``.
        """
        n = len(fit.joints)
        tip = self.kin.joints[fit.joints[-1]].child
        U = self.relative(self.fit_q[:, :n], fit.joints, fit.signs, fit.base, [tip], None)[tip]

        def evaluate(model: Model) -> tuple[Float, _Fit]:
            M = _dh_in_frame0(model, self.fit_q)[:, n]
            X, Y = _hand_eye(M, U)
            E = invert(M) @ X @ U @ Y
            eye = np.broadcast_to(np.eye(4), E.shape)
            vector = np.concatenate(
                [
                    Rotation.from_matrix(E[:, :3, :3]).as_rotvec().reshape(-1),
                    E[:, :3, 3].reshape(-1),
                ]
            )
            dev = (float(position_error_m(eye, E).max()), float(rotation_error_rad(eye, E).max()))
            return vector, replace(fit, X=X, Y=Y, dev_m=dev[0], dev_rad=dev[1])

        found: list[tuple[float, int, Param, float, _Fit]] = []
        for k, joint in enumerate(self.model.joints[:n]):
            for param in PARAMS:
                old = float(getattr(joint, param))

                def residual(x: Float, k: int = k, param: Param = param) -> Float:
                    return evaluate(_with_value(self.model, k, param, float(x[0])))[0]

                sol = least_squares(
                    residual, [old], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=60
                )
                new = float(sol.x[0])
                if abs(new - old) <= 1e-9:
                    continue
                _, trial = evaluate(_with_value(self.model, k, param, new))
                if trial.score(self.tol)[0] == 0:
                    found.append((abs(new - old), k, param, new, trial))
        if not found:
            return None
        _, k, param, new, trial = min(found, key=lambda f: f[0])
        return k, param, new, trial


def _with_value(model: Model, k: int, param: str, value: float) -> Model:
    joints = list(model.joints)
    joints[k] = replace(joints[k], **{param: value})  # type: ignore[arg-type]
    return replace(model, joints=tuple(joints))


def _windows(kin: UrdfKinematics, model: Model) -> list[tuple[str, ...]]:
    """Every run of ``n`` consecutive movable joints down from the root whose types fit."""
    n = model.dof
    want = [("prismatic",) if j.type == "prismatic" else ("revolute", "continuous")
            for j in model.joints]  # fmt: skip
    out: dict[tuple[str, ...], None] = {}
    for joint in kin.joints.values():
        if joint.type == "fixed":
            continue
        try:
            movable = kin.movable(kin.chain(kin.root, joint.child))
        except UrdfError:
            continue
        window = tuple(j.name for j in movable[-n:])
        if len(window) == n and all(
            kin.joints[name].type in types for name, types in zip(window, want, strict=True)
        ):
            out.setdefault(window)
    return list(out)


def _rank(link: str, order: Mapping[str, int]) -> tuple[int, int]:
    """Sort key of a link: how common its name is, then its place in the URDF."""
    common = next(
        (i for i, pattern in enumerate(COMMON_NAMES) if fnmatch.fnmatchcase(link, pattern)),
        len(COMMON_NAMES),
    )
    return common, order.get(link, 0)


def _complexity(offset: Offset) -> int:
    return sum(1 for v in (*offset.xyz, *offset.rpy) if v != 0.0)


_NAME = re.compile(r"^[A-Za-z0-9_-]+$")


def _frame_name(link: str, taken: set[str]) -> str:
    """A frame name for an undeclared link: the link's own, unless taken or reserved."""
    base = (
        link
        if _NAME.match(link) and link not in ("world", "tcp")
        else "urdf_" + re.sub(r"[^A-Za-z0-9_-]", "_", link)
    )
    name, k = base, 2
    while name in taken:
        name, k = f"{base}_{k}", k + 1
    return name


# ----------------------------------------------------------------------------- the map


def map_model(
    model: Model,
    kin: UrdfKinematics,
    urdf_path: str,
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, str] | None = None,
) -> MapResult:
    """Find the model's joints and frames in a URDF.

    Args:
        model: The DH model (its ``[urdf]`` and ``[frames]`` are only used for names).
        kin: The URDF's geometry (:func:`fkcheck.urdf.chain.urdf_kinematics`).
        urdf_path: What ``[urdf] path`` should say.
        samples: Random configurations on top of the structured ones.
        seed: Seed of the samples.
        xacro_args: The URDF is xacro, expanded with these arguments: the block
            opts in (``xacro = true``) with them. ``None``: a plain URDF.
        packages: With ``xacro_args``: the ``packages`` line, as written.

    Returns:
        The proposal; :attr:`MapResult.complete` says whether it can pass as pasted.

    Raises:
        UrdfError: The URDF has no run of ``n`` movable joints of the table's types.
    """
    windows = _windows(kin, model)
    if not windows:
        movable = [j.name for j in kin.joints.values() if j.type != "fixed"]
        raise UrdfError(
            kin.path,
            f"has no chain of {model.dof} consecutive movable joints of the types of model "
            f"{model.name}'s table; movable joints are: {listed(movable)}",
        )
    problem = _Problem(model, kin, samples, seed)
    fits = sorted((problem.search(w) for w in windows), key=lambda f: f.score(problem.tol))
    best = fits[0]
    fitting = [f for f in fits if f.score(problem.tol)[0] == 0]
    joints = tuple(
        JointMatch(dh.name, urdf, sign < 0)
        for dh, urdf, sign in zip(model.joints, best.joints, best.signs, strict=True)
    )
    edits, problem, best = _reconciled(problem, best)
    edited = problem.model
    frames, nearest = _frames(problem, best)
    pair, numbers, absorbs = _check_pair(edited, frames, best.score(problem.tol)[0] == 0)
    declared = _declares_check(model)
    return MapResult(
        model=model,
        urdf_path=urdf_path,
        joints=joints,
        fit_m=best.dev_m,
        fit_rad=best.dev_rad,
        also_fit=tuple(f.joints for f in fitting[1:]),
        frames=tuple(frames),
        nearest=tuple(nearest),
        configurations=problem.q.shape[0],
        seed=seed,
        xacro_args=None if xacro_args is None else dict(xacro_args),
        packages=dict(packages or {}) if xacro_args is not None else {},
        pair=pair,
        numbers=numbers,
        absorbs=absorbs,
        check_declared=declared,
        twins=_default_twins(model, frames) if declared and pair is not None else (),
        edits=edits,
    )


def _reconciled(problem: _Problem, fit: _Fit) -> tuple[TableEdits, _Problem, _Fit]:
    """The fit's edits of the table, the problem of the table so edited, and its fit there.

    Zeros moved and signs changed are made in the table (flips stay in the fit's
    signs); when the chain still does not fit, the one number that makes it fit
    (:meth:`_Problem.one_number`), if any, is set too.
    """
    model = problem.model
    edits = _edits(model, fit)
    if edits.thetas or edits.negated:
        problem = _Problem(replace(edits, flips=()).apply(model), problem.kin,
                           problem.samples, problem.seed)  # fmt: skip
        fit = problem.fit(fit.joints, fit.signs)
    if fit.score(problem.tol)[0] != 0 and fit.dev_m + fit.dev_rad < _NUMBER_REACH:
        number = problem.one_number(fit)
        if number is not None:
            k, param, value, fit = number
            edits = replace(edits, values=((model.joints[k].name, param, value),))
            problem = _Problem(replace(edits, flips=()).apply(model), problem.kin,
                               problem.samples, problem.seed)  # fmt: skip
            fit = problem.fit(fit.joints, fit.signs)
    return edits, problem, fit


def _edits(model: Model, fit: _Fit) -> TableEdits:
    """The fit's flips and zeros as edits of the table; half-turn pairs said as signs."""
    thetas = list(fit.thetas or (0.0,) * model.dof)
    negated = half_turns_as_signs(model.joints, model.convention, thetas)
    names = [j.name for j in model.joints]
    return TableEdits(
        flips=tuple(n for n, s in zip(names, fit.signs, strict=True) if s < 0),
        thetas=tuple((n, t) for n, t in zip(names, thetas, strict=True) if t),
        negated=tuple((names[k], p) for k, p in negated),
    )


@dataclass(frozen=True)
class Reconciled:
    """How a table's rows must change to move like its URDF chain.

    Attributes:
        edits: The fewest flips, quarter-turn zeros and signs found (empty: none needed).
        fit_m: How far the last DH frame of the edited table then strays from the
            chain's last link (over the samples, a constant offset fitted), metres.
        fit_rad: The same for orientation, radians.
    """

    edits: TableEdits
    fit_m: float
    fit_rad: float


def reconcile_table(
    model: Model,
    kin: UrdfKinematics,
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    joints: Sequence[str] | None = None,
) -> Reconciled:
    """The table's edits that make it move like the description's joints it maps.

    ``joints``: the description's joint of each DH joint (an MJCF's ``[mjcf].joints``);
    default ``[urdf].joints``.

    As ``fkcheck map`` finds them, on the model's own mapping: each joint's
    direction, then (when no directions fit) quarter-turn zero offsets too, by a
    beam search over the chain's prefixes with a constant offset fitted at each
    end. The frames at the ends are not judged (a diagnosis fits them).

    Raises:
        FkcheckError: The model has no ``[urdf]``, or maps joints the URDF lacks.
    """
    if joints is None:
        if model.urdf is None:
            raise FkcheckError(f"model {model.name} has no [urdf]")
        joints = model.urdf.joints
    missing = [name for name in joints if name not in kin.joints]
    if missing:
        raise FkcheckError(
            f"model {model.name}'s joints name {listed(missing)}, which "
            f"{kin.path.name} does not have"
        )
    problem = _Problem(model, kin, samples, seed)
    edits, _, fit = _reconciled(problem, problem.search(tuple(joints), polish=False))
    return Reconciled(edits, fit.dev_m, fit.dev_rad)


def _default_twins(model: Model, frames: Sequence[ProposedFrame]) -> tuple[FrameSpec, ...]:
    """``world`` / ``tcp`` of the model's own check, each given the link sitting exactly on it.

    A link on DH frame 0 is on the world when the model has no ``[base]`` (and on
    the last DH frame, the TCP, without a ``[tool]``). Ends that already have a
    twin, and ends no link sits exactly on, get none.
    """
    n = model.dof
    on: dict[Literal["world", "tcp"], tuple[Anchor, ...]] = {
        "world": ("world", 0) if model.base.is_identity else ("world",),
        "tcp": ("tcp", n) if model.tool.is_identity else ("tcp",),
    }
    twins: list[FrameSpec] = []
    for end in on:
        spec = model.frames.get(end)
        if end not in (model.check.frame_from, model.check.frame_to) or spec is None:
            continue
        if not _builtin(spec):
            continue
        exact = [
            p.spec.urdf
            for p in frames
            if p.fit is not None and p.spec.dh in on[end] and p.spec.offset.is_identity
        ]
        if exact and exact[0] is not None:
            twins.append(FrameSpec(end, end, Offset(), exact[0]))
    return tuple(twins)


def _check_pair(
    model: Model, frames: Sequence[ProposedFrame], chain_ok: bool
) -> tuple[tuple[str, str] | None, Coverage | None, dict[str, tuple[str, ...]]]:
    """The ``[check]`` pair to propose, what it verifies, and what each frame could hide.

    Each end is judged alone against the other end of the chain (the TCP, the
    world): a frame whose offset carries what a table number produces could be
    hiding an error in that number. The pair takes, at each end, the linked frame
    hiding the fewest table numbers, then the outermost (``world`` over DH frame
    0, the TCP over the last DH frame: they cover ``[base]`` and ``[tool]``).
    """
    n = model.dof
    linked = [p.spec for p in frames if p.fit is not None]
    specs = {s.name: s for s in model.frames.values() if s.name in ("world", "tcp")}
    specs.update({s.name: s for s in linked})
    mapped = replace(model, frames=specs)
    tol = (model.check.tol_pos_m, model.check.tol_rot_rad)
    absorbs: dict[str, tuple[str, ...]] = {}
    score: dict[str, tuple[int, int, int]] = {}
    rivals = _rivals(model, linked)
    for spec in linked:
        judged = _hidden_at_end(mapped, spec, tol, rivals)
        if judged is None:
            continue
        hidden, outer = judged
        if hidden:
            absorbs[spec.name] = hidden
        score[spec.name] = (len(hidden), outer, _complexity(spec.offset))
    base = sorted((s for s in linked if s.dh in (0, "world") and s.name in score),
                  key=lambda s: score[s.name])  # fmt: skip
    tip = sorted((s for s in linked if s.dh in (n, "tcp") and s.name in score),
                 key=lambda s: score[s.name])  # fmt: skip
    if not (chain_ok and base and tip):
        return None, None, absorbs
    pair = (base[0].name, tip[0].name)
    return pair, coverage(mapped, pair[0], pair[1], *tol, competitors=rivals), absorbs


def _rivals(model: Model, linked: Sequence[FrameSpec]) -> dict[str, list[Competitor]]:
    """For each linked frame, the other linked frames at its end: which is the DH frame is a choice.

    Frames at DH frame 0 and at the world are at one place when the model has no
    ``[base]``; at the last DH frame and the TCP when it has no ``[tool]``.
    """
    n = model.dof
    same: dict[Anchor, Anchor] = {}
    if model.base.is_identity:
        same["world"] = 0
    if model.tool.is_identity:
        same["tcp"] = n

    def place(spec: FrameSpec) -> Anchor:
        return same.get(spec.dh, spec.dh)

    return {
        spec.name: [
            Competitor(str(other.urdf), other.offset.matrix)
            for other in linked
            if other is not spec and place(other) == place(spec)
        ]
        for spec in linked
    }


def _hidden_at_end(
    mapped: Model,
    spec: FrameSpec,
    tol: tuple[float, float],
    rivals: Mapping[str, Sequence[Competitor]],
) -> tuple[tuple[str, ...], int] | None:
    """What a frame at one end of the chain hides, judged against the other end.

    Returns:
        The table numbers its offset carries, or that another link at its end
        could take (``"d1: translation along z of …"``), and ``0`` for the
        outermost end (``world``, ``tcp``), ``1`` for a DH frame; ``None`` for a
        frame at neither end.
    """
    n = mapped.dof
    if spec.dh in (0, "world"):
        c = coverage(mapped, spec.name, "tcp", *tol, competitors=rivals)
        outer = 0 if spec.dh == "world" else 1
    elif spec.dh in (n, "tcp"):
        c = coverage(mapped, "world", spec.name, *tol, competitors=rivals)
        outer = 0 if spec.dh == "tcp" else 1
    else:
        return None
    mine = f"[frames.{spec.name}]"
    hidden = tuple(
        f"{e.name}: {e.absorbed_by.removeprefix(mine + ': ')}"
        for e in c.table_numbers
        if e.status == "not-identifiable" and e.reason in ("offset", "link") and mine in e.by
    )
    return hidden, outer


def _frames(problem: _Problem, fit: _Fit) -> tuple[list[ProposedFrame], list[LinkFit]]:
    """The frames at DH frame 0 and at the tip, then the model's other declared frames."""
    model, kin, tol = problem.model, problem.kin, problem.tol
    n = model.dof
    links = list(kin.links)
    order = {link: i for i, link in enumerate(links)}
    anchors: list[Anchor] = [0, "world", n, "tcp"]
    declared = {s.name: s for s in model.frames.values() if not _builtin(s)}
    for spec in declared.values():
        if spec.dh not in anchors:
            anchors.append(spec.dh)
    table = {
        anchor: {f.link: f for f in problem.evaluate(fit, links, anchor)} for anchor in anchors
    }
    chain_ok = fit.score(tol)[0] == 0

    def fits(f: LinkFit | None) -> bool:
        return f is not None and chain_ok and f.fits(*tol)

    proposals: list[ProposedFrame] = []
    used: set[str] = set()
    for spec in declared.values():
        proposals.append(_declared(spec, table, fits, kin))
        if proposals[-1].fit is not None:
            used.add(proposals[-1].fit.link)
    taken = set(model.frames)
    nearest: list[LinkFit] = []
    # On a tie the outer anchor wins where the model has a base or a tool: a frame
    # there covers [base] / [tool], one on the DH frame leaves it out of the check.
    base_side: tuple[Anchor, ...] = (0, "world") if model.base.is_identity else ("world", 0)
    tip_side: tuple[Anchor, ...] = (n, "tcp") if model.tool.is_identity else ("tcp", n)
    for group in (base_side, tip_side):
        found = False
        for link in sorted(links, key=lambda name: _rank(name, order)):
            candidates = [table[a][link] for a in group if fits(table[a].get(link))]
            if not candidates:
                continue
            found = True
            if link in used:
                continue
            pick = min(candidates, key=lambda f: (_complexity(f.offset), group.index(f.anchor)))
            name = _frame_name(link, taken)
            taken.add(name)
            proposals.append(
                ProposedFrame(FrameSpec(name, pick.anchor, pick.offset, link), pick, False)
            )
        if not found:
            nearest.append(
                min(
                    (f for a in group for f in table[a].values()),
                    key=lambda f: f.spread_m + f.spread_rad,
                )
            )
    proposals.sort(
        key=lambda p: (
            0 if p.spec.dh in (0, "world") else 2 if p.spec.dh in (n, "tcp") else 1,
            _rank(p.spec.urdf or p.spec.name, order),
        )
    )
    return proposals, nearest


def _builtin(spec: FrameSpec) -> bool:
    return spec.name in ("world", "tcp") and spec.dh == spec.name and spec.urdf is None


def _declared(
    spec: FrameSpec,
    table: Mapping[Anchor, Mapping[str, LinkFit]],
    fits: Callable[[LinkFit | None], bool],
    kin: UrdfKinematics,
) -> ProposedFrame:
    """A declared frame, checked: its link at its DH frame, or why not."""
    if spec.urdf is None:
        return ProposedFrame(spec, None, True, "declared without a URDF link: kept as it is")
    if spec.urdf not in kin.links:
        return ProposedFrame(
            replace(spec, urdf=None),
            None,
            True,
            f"its URDF link {spec.urdf!r} is not a link of {kin.path.name}: kept without one",
        )
    here = table[spec.dh].get(spec.urdf)
    if fits(here):
        assert here is not None
        if _same(here.offset, spec.offset):  # the declared numbers, as written
            return ProposedFrame(spec, replace(here, offset=spec.offset), True)
        note = (
            f"the model had xyz {list(spec.offset.xyz)}, rpy {list(spec.offset.rpy)} (rad): "
            "the URDF says otherwise"
        )
        return ProposedFrame(replace(spec, offset=here.offset), here, True, note)
    elsewhere = [row[spec.urdf] for row in table.values() if fits(row.get(spec.urdf))]
    if elsewhere:
        moved = elsewhere[0]
        return ProposedFrame(
            replace(spec, dh=moved.anchor, offset=moved.offset),
            moved,
            True,
            f"declared at DH frame {spec.dh}, but {spec.urdf!r} is rigid to DH frame "
            f"{moved.anchor}",
        )
    shown = (
        f"{format_mm(here.spread_m)} / {format_deg(here.spread_rad)}" if here is not None else "?"
    )
    return ProposedFrame(
        replace(spec, urdf=None),
        None,
        True,
        f"{spec.urdf!r} is at no constant offset from DH frame {spec.dh} (it moves by "
        f"{shown} over the samples): kept without a URDF link",
    )


def _same(a: Offset, b: Offset) -> bool:
    return bool(np.allclose(a.matrix, b.matrix, atol=1e-9, rtol=0.0))


# ----------------------------------------------------------------------------- the text


def proposal_toml(
    result: MapResult,
    section: str = "urdf",
    twin: Callable[[FrameSpec], FrameSpec] | None = None,
) -> str:
    """The ``[urdf]`` (or ``section``) and ``[frames.*]`` block, with the evidence in comments.

    ``twin`` maps a proposed frame (whose ``urdf`` names its link) onto the
    description's format (:meth:`fkcheck.description.types.DescriptionFormat.with_frame`);
    default: as it is, ``urdf = "LINK"``.

    Every comment goes through :func:`~fkcheck.model.write.toml_comment`: names
    from the URDF or the model (which may hold newlines) can never start a line
    of TOML of their own.
    """
    model = result.model
    unit = model.angle_unit
    tol_m, tol_rad = result.tolerances
    out = toml_comment(
        [
            f"fkcheck map: model {model.name} onto {result.urdf_path}",
            f"{result.configurations} configurations (seed {result.seed}); a link is at a "
            "constant offset when it stays within",
            f"the model's check tolerances ({tol_m:g} m, {tol_rad:g} rad); numbers within 1e-9 "
            "of 0, a multiple of 90° or a whole µm are snapped to it.",
        ]
    )
    out += ["", f"[{section}]", f"path = {toml_string(result.urdf_path)}"]
    notes: list[str] = []
    if result.joints_fit:
        notes.append(
            f"The joints, found by how they move (last DH frame vs URDF link: "
            f"{result.fit_m:.2g} m, {result.fit_rad:.2g} rad):"
        )
    else:
        notes.append(
            f"NO chain of the URDF moves like this table: the nearest leaves the last DH frame "
            f"{format_mm(result.fit_m)} / {format_deg(result.fit_rad)} off its link:"
        )
    for j in result.joints:
        if j.flipped:
            notes.append(
                f"  {j.dh} = {j.urdf}: turns the OTHER way; the URDF gets q unchanged, so set "
                f"flip = {'false' if _flip_of(model, j.dh) else 'true'} on [[joint]] {j.dh}"
            )
        else:
            notes.append(f"  {j.dh} = {j.urdf}: same direction")
    moved = [line for line in result.edits.lines(model) if not line.endswith(("= true", "= false"))]
    if moved:
        notes.append(
            "The chain moves like the table only with these rows changed (a vendor's zeros "
            "a quarter turn apart, or a number typed otherwise: one of the two is wrong):"
        )
        notes += [f"  {line}" for line in moved]
        notes.append("The frames below are those of the table so changed: change it, then paste.")
    notes += [f"Another chain moves the same way: {', '.join(other)}" for other in result.also_fit]
    out += toml_comment(notes)
    out.append(f"joints = [{', '.join(toml_string(j.urdf) for j in result.joints)}]")
    if result.xacro_args is not None:
        out += toml_comment(
            "A xacro file: fkcheck expands it only with this opt-in (it runs the file's Python)."
        )
        urdf = UrdfSpec(result.urdf_path, (), True, dict(result.xacro_args), dict(result.packages))
        out += xacro_toml(urdf)
    n = model.dof
    ends: tuple[Anchor, ...] = (0, "world", n, "tcp")
    groups: tuple[tuple[str, tuple[Anchor, ...] | None], ...] = (
        ("DH frame 0", (0, "world")),
        ("the middle DH frames", None),
        (f"the last DH frame ({n}) and the TCP", (n, "tcp")),
    )
    for title, members in groups:
        chosen = [
            p
            for p in result.frames
            if (p.spec.dh in members if members is not None else p.spec.dh not in ends)
        ]
        if not chosen:
            continue
        out += [
            "",
            *toml_comment(
                f"--- Links at a constant offset from {title}, most common name first ---"
            ),
        ]
        for p in chosen:
            comment = []
            if p.fit is not None:
                new = "" if p.declared else " (not declared in the model)"
                comment.append(f"{p.fit.link}: {p.fit.evidence()}{new}")
            if p.note:
                comment.append(p.note)
            comment += _absorb_warning(p, result.absorbs.get(p.spec.name, ()))
            spec = p.spec if twin is None else twin(p.spec)
            out.append(frame_toml(spec, unit, comment).rstrip("\n"))
    for near in result.nearest:
        where = "DH frame 0" if near.anchor == 0 else f"DH frame {near.anchor}"
        out += [
            "",
            *toml_comment(
                f"NO URDF link sits at a constant offset from {where}: the nearest, "
                f"{near.link}, moves by {format_mm(near.spread_m)} / {format_deg(near.spread_rad)} "
                "over the samples."
            ),
        ]
    out += _check_block(result)
    return "\n".join(out) + "\n"


def _absorb_warning(p: ProposedFrame, hidden: Sequence[str]) -> list[str]:
    """The comment over a frame whose offset could be hiding table numbers."""
    if not hidden or p.spec.source:
        return []
    anchor = (
        "the world"
        if p.spec.dh == "world"
        else "the TCP"
        if p.spec.dh == "tcp"
        else (f"DH frame {p.spec.dh}")
    )
    chosen = [h for h in hidden if _CHOSEN in h]
    carried = [h for h in hidden if _CHOSEN not in h]
    out = []
    if carried:
        names = ", ".join(h.split(":", 1)[0] for h in carried)
        out += [
            f"NOT IDENTIFIABLE: this offset from {anchor} carries what {names} of the table "
            f"{'produces' if len(carried) == 1 else 'produce'}:",
            *(f"  {h}" for h in carried),
        ]
    if chosen:
        names = ", ".join(h.split(":", 1)[0] for h in chosen)
        out += [
            f"NOT IDENTIFIABLE: another link fixed beside this one could be {anchor} instead, "
            f"with {names} of the table changed:",
            *(f"  {h}" for h in chosen),
        ]
    return [
        *out,
        "either the URDF defines the link so, or the table is off by it: fkcheck cannot tell "
        "(a check through this frame does not verify those numbers). If the vendor defines "
        'the link so, vouch for it: source = "<where the vendor says so>".',
    ]


#: What a number a choice among links could hide says (:func:`fkcheck.model.coverage`).
_CHOSEN = "of the description would be"


def _check_block(result: MapResult) -> list[str]:
    """The proposed ``[check]`` pair, live when the model declares no check of its own."""
    if result.pair is None or result.numbers is None:
        return []
    frm, to = result.pair
    lines = [
        "",
        *toml_comment(
            [
                "--- The check: at each end the outermost link whose offset hides the fewest "
                "table numbers ---",
                f"It can verify {result.numbers.scope()}.",
            ]
        ),
    ]
    body = ["[check]", f"from = {toml_string(frm)}", f"to = {toml_string(to)}"]
    if not result.check_declared:
        return lines + body
    own = result.model.check
    for twin in result.twins:  # the model's own check then compares these links
        lines.append(
            frame_toml(
                twin,
                result.model.angle_unit,
                f"The model's own [check] compares {own.frame_from} → {own.frame_to}: "
                f"{twin.urdf} sits exactly on {twin.name}.",
            ).rstrip("\n")
        )
    # a second [check] would not parse
    lines += toml_comment(["The model declares its own [check]: to check this pair, set there:"])
    lines += toml_comment(body)
    return lines


def _declares_check(model: Model) -> bool:
    """Whether the model's file has a ``[check]`` table (a model built in memory: not default)."""
    if model.path is None or model.path.suffix.lower() != ".toml":
        return model.check != CheckSpec()
    try:
        return "check" in tomllib.loads(read_text(model.path, MAX_MODEL_FILE_BYTES))
    except (InputFileError, FkcheckError, ValueError, RecursionError):  # it was read before
        return True


def _flip_of(model: Model, joint: str) -> bool:
    return next(j.flip for j in model.joints if j.name == joint)


# ----------------------------------------------------------------------------- urdf:LINK


def link_frame(model: Model, kin: UrdfKinematics, link: str, *, seed: int = 0) -> LinkFit:
    """Where an undeclared URDF link sits on the model's DH chain, by its ``[urdf]`` joints.

    The URDF receives each DH joint's value unchanged (as every URDF backend
    does). The link must stay at a constant offset from one DH frame ``0…n``
    over the samples, which the placement can only show when the whole chain
    moves as the table does: the placement is fitted from it.

    Raises:
        FrameError: ``link`` is not a link of the URDF (listing them).
        FkcheckError: The model has no ``[urdf]``, or the link cannot be placed,
            saying why: the table and the URDF disagree over the chain (no
            placement can be trusted; where the link hangs is named), or the link
            moves with a URDF joint the model does not map, or hangs below a
            joint fkcheck cannot follow.
    """
    where = f"{URDF_FRAME_PREFIX}{link}"
    if model.urdf is None:
        raise FkcheckError(f"{where}: model {model.name} has no [urdf]")
    if link not in kin.links:
        raise FrameError(link, f"URDF {kin.path.name}", kin.links)
    missing = [name for name in model.urdf.joints if name not in kin.joints]
    if missing:
        raise FkcheckError(
            f"{where}: model {model.name}'s [urdf] joints name {listed(missing)}, which "
            f"{kin.path.name} does not have"
        )
    hang = _hanging(kin, link, model.urdf.joints)
    if hang.unfollowed is not None:
        raise FkcheckError(
            f"{where}: URDF link {link!r} hangs below the {hang.unfollowed.type} joint "
            f"{hang.unfollowed.name!r}, which fkcheck cannot follow: it has no place on model "
            f"{model.name}'s DH chain"
        )
    problem = _Problem(model, kin, DEFAULT_SAMPLES, seed)
    signs = [1.0] * model.dof
    fit = problem.fit(model.urdf.joints, signs)
    if fit.score(problem.tol)[0] != 0:  # parallel turns, slides: polish it
        fit = min(fit, problem.fit(model.urdf.joints, signs, refine=True),
                  key=lambda f: f.score(problem.tol))  # fmt: skip
    rows = [problem.evaluate(fit, [link], k)[0] for k in range(model.dof + 1)]
    if fit.score(problem.tol)[0] != 0:
        raise FkcheckError(_untrusted(model, kin, link, fit, hang))
    for row in rows:
        if row.fits(*problem.tol):
            return row
    near = min(rows, key=lambda f: f.spread_m + f.spread_rad)
    moves = (
        f"moves with URDF joint {hang.unmapped!r}, which model {model.name}'s [urdf] joints do "
        "not map (its value is not the table's)"
        if hang.unmapped is not None
        else "does not move with any one DH frame"
    )
    raise FkcheckError(
        f"{where}: URDF link {link!r} {moves}: it is at no constant offset from any DH frame of "
        f"model {model.name} (nearest: DH frame {near.anchor}, moving by "
        f"{format_mm(near.spread_m)} / {format_deg(near.spread_rad)} over the samples), though "
        "the table and the URDF agree over the chain"
    )


@dataclass(frozen=True)
class _Hanging:
    """Where a URDF link hangs, by the URDF's tree alone.

    Attributes:
        anchor: The DH frame it moves with if the table agrees with the URDF: the
            DH joint of the last mapped joint above it (``0``: none, it is fixed
            to the chain's root side), or ``None`` when an unmapped joint moves it.
        joint: The last movable URDF joint above it, if any.
        unmapped: The first movable joint above it that ``[urdf] joints`` do not map.
        unfollowed: A joint above it that fkcheck cannot follow (floating, planar).
    """

    anchor: int | None
    joint: str | None = None
    unmapped: str | None = None
    unfollowed: JointGeometry | None = None


def _hanging(kin: UrdfKinematics, link: str, mapped: Sequence[str]) -> _Hanging:
    """Which joints move ``link``, read off the URDF's tree."""
    path = [] if link == kin.root else kin.chain(kin.root, link)
    for joint in path:
        if joint.type != "fixed" and joint.type not in MOVABLE:
            return _Hanging(None, unfollowed=joint)
    movable = [j.name for j in path if j.type != "fixed"]
    unmapped = next((name for name in movable if name not in mapped), None)
    if not movable:
        return _Hanging(0)
    if unmapped is not None:
        return _Hanging(None, movable[-1], unmapped)
    return _Hanging(list(mapped).index(movable[-1]) + 1, movable[-1])


def _untrusted(model: Model, kin: UrdfKinematics, link: str, fit: _Fit, hang: _Hanging) -> str:
    """The refusal when the chain itself does not move as the table does."""
    tip = kin.joints[fit.joints[-1]].child
    if hang.anchor == 0:
        place = f"URDF link {link!r} is fixed to the chain's root side (DH frame 0's side)"
    elif hang.anchor is not None:
        place = (
            f"URDF link {link!r} moves with URDF joint {hang.joint!r} (DH joint {hang.anchor}: "
            f"it belongs on DH frame {hang.anchor})"
        )
    else:
        place = (
            f"URDF link {link!r} moves with URDF joint {hang.unmapped!r}, which the model's "
            "[urdf] joints do not map"
        )
    known = [
        k
        for k in model.known_differences
        if k.reads == "urdf" or any(b.endswith("-urdf") for b in k.backends)
    ]
    recorded = (
        f" (the model file records a difference with its URDF: {known[0].finding})" if known else ""
    )
    return (
        f"{URDF_FRAME_PREFIX}{link}: {place}, but no placement of it on model {model.name}'s DH "
        f"frames can be trusted: the table and the URDF disagree over the chain — its last DH "
        f"frame strays up to {format_mm(fit.dev_m)} / {format_deg(fit.dev_rad)} from URDF link "
        f"{tip!r} over the samples{recorded}, and the placement is fitted from that chain. "
        f"Find the disagreement first (fkcheck check / fkcheck diagnose on the model's own "
        f'frames), or declare [frames.NAME] with dh, its offset and urdf = "{link}" to compare '
        "it anyway"
    )


def with_link_frames(
    model: Model, kin: UrdfKinematics, names: Sequence[str]
) -> tuple[Model, dict[str, LinkFit]]:
    """The model with a frame ``urdf:LINK`` added for each undeclared link ``names`` ask for.

    A name that is not ``urdf:LINK``, or whose link a declared frame already
    maps, is left to :func:`fkcheck.model.resolve_frame`.

    Returns:
        ``(model, placed)``: the model (the same object when nothing was added)
        and each added frame's placement, by frame name.
    """
    placed: dict[str, LinkFit] = {}
    for name in names:
        if not name.startswith(URDF_FRAME_PREFIX) or name in placed:
            continue
        link = name[len(URDF_FRAME_PREFIX) :]
        if any(spec.urdf == link for spec in model.frames.values()):
            continue
        placed[name] = link_frame(model, kin, link)
    if not placed:
        return model, placed
    frames = dict(model.frames)
    for name, fit in placed.items():
        frames[name] = FrameSpec(name, fit.anchor, fit.offset, fit.link)
    return replace(model, frames=frames), placed
