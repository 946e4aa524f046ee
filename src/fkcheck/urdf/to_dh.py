"""An exact DH table from a serial chain of a URDF, built from its joint axes.

Every revolute or prismatic joint has an axis: a line in space. A DH table is a
choice of frames along those lines; this module makes that choice
geometrically, at q = 0, from the axes expressed in the chain's base link:

* **standard DH** (frame *i* on axis *i+1*): ``x_i`` along the common normal of
  axes *i* and *i+1*, origin where it meets axis *i+1*;
* **modified DH** (Craig; frame *i* on axis *i*): ``x_i`` along the common normal
  of axes *i* and *i+1*, origin where it leaves axis *i*.

The usual conventions settle the cases a common normal does not:

* **intersecting axes**: ``x = ±(z_i × z_{i+1})``, origin at the intersection, ``a = 0``;
* **parallel axes**: the common normal is only defined up to a slide along the
  axes; it is taken through the previous frame's origin so that ``d = 0``;
* **coincident axes**: ``x`` is kept from the previous frame (``θ = 0``, ``a = 0``);
* the sign of each ``x`` is chosen so that the θ offset lies within ±90° (``a`` may
  then be negative, as in UR's published table);
* **frame 0** has z along axis 1, its origin where the base link's origin projects
  onto axis 1, x from the base link's x; **the last frame** has z along the last
  axis, its origin where the tip link's origin projects onto it and x from the
  tip's x, so that ``[base]`` and ``[tool]`` hold what is left and stay simple.

θ and d at q = 0 become the table's offsets; each DH z follows the URDF axis
direction, so no joint needs ``flip``. Every number of the table and of its
offsets within :data:`CLEAN_TOL` (1e-9) of a round number is written as that
number (:func:`clean_number`): an angle near 0 or a multiple of 90° becomes it
exactly (``-1.5707963267948966``, not ``-1.5707963267899``), a length near a whole
micrometre (so any round millimetre) becomes it (``0.0823``, not
``0.08230000000000001``; ``0.0``, not ``1.07e-10``). Such noise is the
URDF's rounding of π or float round-off, not geometry; the self-check runs on
the cleaned table. Joint limits are cleaned only where that narrows them
(the URDF's ``6.28318530718`` becomes 2π, written ``360.0`` with ``--deg``). A
difference larger than that (an ``rpy`` of ``1.5708``, 3.7e-6
rad from 90°) is kept: it is what the URDF says. The result maps back onto the URDF: the
base link is the model's ``world``, the tip link its ``tcp``, every link of the
chain a named frame on the DH frame of the body it belongs to, and
``[check]`` compares base → tip. :func:`dh_from_urdf` verifies the table
against this module's own URDF FK before returning it; the proof that matters
is ``fkcheck check`` against the independent URDF backends.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from fkcheck.core.dh import Convention, dh_matrix
from fkcheck.core.geometry import invert, rpy_from_matrix
from fkcheck.core.typing import Float
from fkcheck.errors import UrdfError
from fkcheck.model.offsets import snap
from fkcheck.model.types import (
    CheckSpec,
    FrameSpec,
    Joint,
    Model,
    Offset,
    UrdfSpec,
    default_frames,
)
from fkcheck.urdf.chain import JointGeometry, UrdfKinematics

__all__ = [
    "CLEAN_TOL",
    "INTERSECT_TOL_M",
    "PARALLEL_TOL_RAD",
    "AxisRelation",
    "DhExtraction",
    "clean_number",
    "clean_offset",
    "dh_from_urdf",
]

AxisRelation = Literal["intersecting", "parallel", "coincident", "skew"]

#: Axes closer than this to parallel (sine of the angle between them) are treated
#: as parallel. URDFs that round π to 11 digits leave ~1e-11 between axes meant to
#: be parallel; treating that as a real skew would put the common normal kilometres
#: away. The approximation costs at most this angle times the arm's reach.
PARALLEL_TOL_RAD = 1e-9
#: Axes closer than this are treated as intersecting (metres).
INTERSECT_TOL_M = 1e-9
#: The table must reproduce the URDF's frames to this accuracy at q = 0 and at
#: random configurations (own URDF FK), or extraction fails loudly.
SELF_CHECK_TOL = 1e-8
#: Numbers this close to a round one (rad, m) are written as the round one.
CLEAN_TOL = 1e-9
#: The grid lengths are cleaned to: whole micrometres (round millimetres included).
_LENGTH_GRID_M = 1e-6


def clean_number(value: float, *, angle: bool) -> float:
    """``value``, or the round number within :data:`CLEAN_TOL` of it (0, k·90°, whole µm)."""
    return snap(value, angle=angle, tol=CLEAN_TOL, grid_m=_LENGTH_GRID_M)


def _clean_limits(limits: tuple[float, float] | None, *, angle: bool) -> tuple[float, float] | None:
    """The URDF's limits, cleaned only where that narrows them (6.28318530718 → 2π).

    A limit is never widened, so no configuration the table samples lies beyond
    the URDF's own limits.
    """
    if limits is None:
        return None
    lo, hi = (clean_number(v, angle=angle) for v in limits)
    return (max(lo, limits[0]), min(hi, limits[1]))


def clean_offset(T: Float) -> Offset:
    """A fixed transform's xyz and rpy, numbers within :data:`CLEAN_TOL` of a round one snapped.

    The rotation's entries within :data:`CLEAN_TOL` of 0 or ±1 are snapped first,
    so that a pitch of ±90° reads as the gimbal lock it is (yaw 0, roll the whole
    turn) rather than as two large angles that cancel.
    """
    x, y, z = (clean_number(float(v), angle=False) for v in T[:3, 3])
    R = np.array(T[:3, :3], dtype=np.float64)
    for value in (0.0, 1.0, -1.0):
        R[np.abs(R - value) <= CLEAN_TOL] = value
    roll, pitch, yaw = (clean_number(float(v), angle=True) for v in rpy_from_matrix(R))
    return Offset(xyz=(x, y, z), rpy=(roll, pitch, yaw))


@dataclass(frozen=True, eq=False)
class DhExtraction:
    """A DH model extracted from a URDF, with how each frame was chosen.

    Attributes:
        model: The model (``[urdf]``, ``[frames]`` and ``[check]`` included).
        relations: For each pair of consecutive axes (``i``, ``i+1``), how they relate.
        notes: One comment per joint row explaining its numbers.
        self_check_error: Largest pose difference (m or rad) between the table and
            this module's own URDF FK, over all chain links and sampled configurations.
    """

    model: Model
    relations: tuple[AxisRelation, ...]
    notes: tuple[str, ...]
    self_check_error: float


def _unit(v: Float) -> Float:
    return v / np.linalg.norm(v)


def _perp(v: Float, axis: Float) -> Float:
    """``v`` without its component along unit ``axis``."""
    return v - (v @ axis) * axis


def _project_on_line(point: Float, line_point: Float, line_dir: Float) -> Float:
    return line_point + ((point - line_point) @ line_dir) * line_dir


def _x_from(reference: Float, z: Float, fallback: Float) -> Float:
    """A unit x ⊥ z as close as possible to ``reference`` (``fallback`` if parallel to z)."""
    v = _perp(reference, z)
    if np.linalg.norm(v) < 1e-9:
        v = _perp(fallback, z)
    return _unit(v)


def _frame(origin: Float, x: Float, z: Float) -> Float:
    z = _unit(z)
    x = _unit(_perp(x, z))
    T = np.eye(4)
    T[:3, 0] = x
    T[:3, 1] = np.cross(z, x)
    T[:3, 2] = z
    T[:3, 3] = origin
    return T


def _closest_points(p1: Float, u1: Float, p2: Float, u2: Float) -> tuple[Float, Float]:
    """Closest points of two non-parallel lines ``p + t·u`` (on line 1, on line 2)."""
    w0 = p1 - p2
    b = u1 @ u2
    d, e = u1 @ w0, u2 @ w0
    denom = 1.0 - b * b
    s = (b * e - d) / denom
    t = (e - b * d) / denom
    return p1 + s * u1, p2 + t * u2


def _relate(p1: Float, u1: Float, p2: Float, u2: Float) -> AxisRelation:
    if np.linalg.norm(np.cross(u1, u2)) < PARALLEL_TOL_RAD:
        off = _perp(p2 - p1, u1)
        return "coincident" if np.linalg.norm(off) < INTERSECT_TOL_M else "parallel"
    c1, c2 = _closest_points(p1, u1, p2, u2)
    return "intersecting" if np.linalg.norm(c2 - c1) < INTERSECT_TOL_M else "skew"


def _signed(x: Float, previous_x: Float) -> Float:
    """``x`` or ``-x``, whichever keeps the θ offset within ±90°."""
    return -x if x @ previous_x < 0 else x


def _common_normal(
    p1: Float, u1: Float, p2: Float, u2: Float, rel: AxisRelation, previous_x: Float
) -> tuple[Float, Float, Float]:
    """Where the common normal of two non-parallel axes leaves axis 1 and meets axis 2, and x.

    Intersecting axes (``rel``, from :func:`_relate`) have no normal: both points are
    the intersection and x is along ``u1 × u2``. x is signed by :func:`_signed`.
    """
    c1, c2 = _closest_points(p1, u1, p2, u2)
    if rel == "intersecting":
        mid = (c1 + c2) / 2.0
        return mid, mid, _signed(_unit(np.cross(u1, u2)), previous_x)
    return c1, c2, _signed(_unit(c2 - c1), previous_x)


def _standard_frames(
    points: Float, dirs: Float, tip: Float
) -> tuple[list[Float], list[AxisRelation]]:
    n = len(points)
    base_x = np.array([1.0, 0.0, 0.0])
    o = _project_on_line(np.zeros(3), points[0], dirs[0])
    x = _x_from(base_x, dirs[0], np.array([0.0, 1.0, 0.0]))
    frames = [_frame(o, x, dirs[0])]
    relations: list[AxisRelation] = []
    for i in range(n - 1):  # frame i+1 (0-based: on axis i+1), from axes i and i+1
        p1, u1, p2, u2 = points[i], dirs[i], points[i + 1], dirs[i + 1]
        prev_o, prev_x = frames[-1][:3, 3], frames[-1][:3, 0]
        rel = _relate(p1, u1, p2, u2)
        relations.append(rel)
        if rel == "coincident":
            o, x = prev_o, prev_x
        elif rel == "parallel":
            offset = _perp(p2 - prev_o, u1)  # the normal through the previous origin: d = 0
            o, x = prev_o + offset, _signed(_unit(offset), prev_x)
        else:
            _, o, x = _common_normal(p1, u1, p2, u2, rel, prev_x)
        frames.append(_frame(o, x, u2))
    # Last frame: z along the last axis, origin = the tip origin projected onto it.
    o = _project_on_line(tip[:3, 3], points[-1], dirs[-1])
    x = _x_from(tip[:3, 0], dirs[-1], tip[:3, 1])
    frames.append(_frame(o, x, dirs[-1]))
    return frames, relations


def _modified_frames(
    points: Float, dirs: Float, tip: Float
) -> tuple[list[Float], list[AxisRelation]]:
    n = len(points)
    o = _project_on_line(np.zeros(3), points[0], dirs[0])
    x = _x_from(np.array([1.0, 0.0, 0.0]), dirs[0], np.array([0.0, 1.0, 0.0]))
    frames = [_frame(o, x, dirs[0])]
    relations: list[AxisRelation] = []
    for i in range(n):  # frame i+1 (0-based: on axis i), from axes i and i+1
        p1, u1 = points[i], dirs[i]
        prev_o, prev_x = frames[-1][:3, 3], frames[-1][:3, 0]
        foot = _project_on_line(prev_o, p1, u1)  # where the previous x meets this axis
        if i == n - 1:  # last frame: origin = the tip origin projected onto the axis
            o = _project_on_line(tip[:3, 3], p1, u1)
            x = _x_from(tip[:3, 0], u1, tip[:3, 1])
            frames.append(_frame(o, x, u1))
            break
        p2, u2 = points[i + 1], dirs[i + 1]
        rel = _relate(p1, u1, p2, u2)
        relations.append(rel)
        if rel == "coincident":
            o, x = foot, _x_from(prev_x, u1, prev_x)
        elif rel == "parallel":
            offset = _perp(p2 - foot, u1)  # the normal through the foot: d = 0
            o, x = foot, _signed(_unit(offset), prev_x)
        else:
            o, _, x = _common_normal(p1, u1, p2, u2, rel, prev_x)
        frames.append(_frame(o, x, u1))
    return frames, relations


def _standard_row(A: Float) -> tuple[float, float, float, float]:
    """``(a, α, d, θ)`` of ``A = Rz(θ)·Tz(d)·Tx(a)·Rx(α)``."""
    theta = math.atan2(A[1, 0], A[0, 0])
    alpha = math.atan2(A[2, 1], A[2, 2])
    a = A[0, 3] * math.cos(theta) + A[1, 3] * math.sin(theta)
    return a, alpha, float(A[2, 3]), theta


def _modified_row(A: Float) -> tuple[float, float, float, float]:
    """``(a, α, d, θ)`` of ``A = Rx(α)·Tx(a)·Rz(θ)·Tz(d)``."""
    theta = math.atan2(-A[0, 1], A[0, 0])
    alpha = math.atan2(-A[1, 2], A[2, 2])
    d = -A[1, 3] * math.sin(alpha) + A[2, 3] * math.cos(alpha)
    return float(A[0, 3]), alpha, d, theta


_RELATION_NOTE = {
    "intersecting": "axes {i} and {j} intersect: a = 0, x along z{i} × z{j}",
    "parallel": "axes {i} and {j} are parallel: common normal taken through the previous "
    "origin, so d = 0",
    "coincident": "axes {i} and {j} coincide: x kept from the previous frame, a = 0",
    "skew": "axes {i} and {j} are skew: x along their common normal",
}


def dh_from_urdf(
    kin: UrdfKinematics,
    base: str,
    tip: str,
    convention: Convention = "standard",
    *,
    name: str | None = None,
    urdf_spec: str | None = None,
) -> DhExtraction:
    """Extract an exact DH model for the chain ``base`` → ``tip`` of a URDF.

    Args:
        kin: The URDF's geometry (:func:`fkcheck.urdf.chain.urdf_kinematics`).
        base: The chain's base link (becomes the model's world).
        tip: The chain's tip link (becomes the TCP).
        convention: ``"standard"`` or ``"modified"``.
        name: Model name (default: the URDF's robot name).
        urdf_spec: ``[urdf].path`` to write (default: the URDF's absolute path).

    Returns:
        The model, how consecutive axes relate, per-row notes and the self-check error.

    Raises:
        FrameError: ``base`` or ``tip`` is not a link.
        UrdfError: No chain from base to tip, no movable joint on it, a joint type
            other than fixed/revolute/continuous/prismatic, or a mimic joint.
        UrdfError: The extracted table does not reproduce the URDF's frames to
            :data:`SELF_CHECK_TOL` (nothing is written).
    """
    chain = kin.chain(base, tip)
    movable = kin.movable(chain)
    for j in movable:
        if j.mimic is not None:
            raise UrdfError(
                kin.path,
                f"joint {j.name!r} mimics {j.mimic!r}: a DH table has "
                "one independent variable per joint",
            )
    if not movable:
        raise UrdfError(kin.path, f"no movable joint between {base!r} and {tip!r}")
    n = len(movable)
    points, dirs = kin.axes_at(chain, np.zeros(n))
    zero_poses = kin.chain_poses(chain, np.zeros((1, n)))[0]  # every link of the chain at q = 0
    tip_T = zero_poses[-1]
    if convention == "standard":
        frames, relations = _standard_frames(points, dirs, tip_T)
    else:
        frames, relations = _modified_frames(points, dirs, tip_T)

    row_of = _standard_row if convention == "standard" else _modified_row
    joints: list[Joint] = []
    notes: list[str] = []
    for i, joint in enumerate(movable):
        A = invert(frames[i]) @ frames[i + 1]
        is_angle = (False, True, False, True)
        a, alpha, d, theta = (
            clean_number(v, angle=ang) for v, ang in zip(row_of(A), is_angle, strict=True)
        )
        structure = float(np.abs(dh_matrix(convention, a, alpha, d, theta) - A).max())
        if structure > SELF_CHECK_TOL:
            raise RuntimeError(f"frame {i}→{i + 1} is not a DH step (defect {structure:.3g})")
        jtype: Literal["revolute", "prismatic"] = (
            "prismatic" if joint.type == "prismatic" else "revolute"
        )
        joints.append(
            Joint(
                name=joint.name,
                a=a,
                alpha=alpha,
                d=d,
                theta=theta,
                type=jtype,
                limits=_clean_limits(joint.limits, angle=jtype == "revolute"),
            )
        )
        notes.append(_row_note(i, joint, relations, convention, n))

    base_offset = clean_offset(frames[0])
    tool_offset = clean_offset(invert(frames[-1]) @ tip_T)
    named = _named_frames(chain, zero_poses, frames, base, tip)
    robot = name or kin.name
    model = Model(
        name=robot,
        convention=convention,
        joints=tuple(joints),
        description=f"{robot}: {base} → {tip}, {convention} DH extracted from the URDF's joint "
        "axes by fkcheck table-from",
        source=f"URDF {kin.path.name}",
        base=base_offset,
        tool=tool_offset,
        poses={"zero": tuple(0.0 for _ in joints)},
        urdf=UrdfSpec(path=urdf_spec or str(kin.path), joints=tuple(j.name for j in movable)),
        frames=named,
        check=CheckSpec(base, tip),
        angle_unit="rad",
    )
    error = _self_check(kin, chain, model)
    if error > SELF_CHECK_TOL:
        # Seen with URDFs whose right angles are rounded (Baxter's 1.5708, 0.7854): the
        # DH rows reproduce the tip, a named link's rpy offset does not. No table is
        # better than one that silently misses its own URDF.
        raise UrdfError(
            kin.path,
            f"the DH table extracted from it misses the URDF's own link frames by "
            f"{error:.3g} (more than {SELF_CHECK_TOL:g}); no table written",
        )
    return DhExtraction(model, tuple(relations), tuple(notes), error)


def _row_note(
    i: int, joint: JointGeometry, relations: list[AxisRelation], convention: Convention, n: int
) -> str:
    kind = "prismatic" if joint.type == "prismatic" else "revolute"
    text = f"joint {i + 1}: URDF {joint.type} joint {joint.name!r} ({kind})"
    # Which axis pair fixed this row's a and α: standard row i+1 ends on the normal of
    # axes i+1, i+2; modified row i+1 starts on the normal of axes i, i+1.
    k = i if convention == "standard" else i - 1
    if 0 <= k < len(relations):
        text += "; " + _RELATION_NOTE[relations[k]].format(i=k + 1, j=k + 2)
    elif convention == "standard" and i == n - 1:
        text += "; last frame: z along this axis, origin and x from the tip link (a = α = 0)"
    elif convention == "modified" and i == 0:
        text += "; frame 0 lies on axis 1 (a = α = 0), origin and x from the base link"
    return text


def _named_frames(
    chain: list[JointGeometry], poses: Float, frames: list[Float], base: str, tip: str
) -> dict[str, FrameSpec]:
    """Every link of the chain as a named frame on the DH frame of its body.

    Args:
        chain: The URDF chain, base to tip.
        poses: ``(len(chain), 4, 4)`` each joint's child link in the base link at q = 0.
        frames: The DH frames at q = 0, in the base link.
        base: The base link (the model's world).
        tip: The tip link (the model's TCP).
    """
    out = default_frames()
    out[base] = FrameSpec(base, "world", Offset(), base)
    body = 0  # DH frame index of the body a link belongs to
    for joint, pose in zip(chain, poses, strict=True):
        if joint.type != "fixed":
            body += 1
        link = joint.child
        if link == tip:
            continue
        if link in ("world", "tcp"):
            continue  # would redefine a built-in frame name
        offset = clean_offset(invert(frames[body]) @ pose)
        out[link] = FrameSpec(link, body, offset, link)
    out[tip] = FrameSpec(tip, "tcp", Offset(), tip)
    return out


def _self_check(kin: UrdfKinematics, chain: list[JointGeometry], model: Model) -> float:
    """Largest difference between the table's named frames and own URDF FK."""
    from fkcheck.core.metrics import position_error_m, rotation_error_rad
    from fkcheck.model.frames import reference_poses
    from fkcheck.model.sampling import sample_configurations

    q = sample_configurations(model, 64, seed=0).q[:200]
    links = [j.child for j in chain]
    urdf_T = kin.chain_poses(chain, q)  # (N, len(chain), 4, 4) in the base link
    names = [name for name in links if name in model.frames]
    ours = reference_poses(model, q, names)  # world = base link
    theirs = np.stack([urdf_T[:, links.index(name)] for name in names])
    return float(max(position_error_m(ours, theirs).max(), rotation_error_rad(ours, theirs).max()))
