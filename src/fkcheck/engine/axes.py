"""Joint axes, convention-free: the table's and the URDF's, compared as lines in space.

DH frames and URDF link frames are different frames, but both descriptions put
each joint on the same physical axis. Expressed in the compared ``from`` frame,
joint *i*'s axis from the table (``z`` of DH frame ``i−1`` in standard DH, of
frame ``i`` in modified DH, reversed for a flipped joint) and from the URDF
(``<axis>`` in the joint frame) must be the same line at every configuration:
the same direction (angle 0 between them) and no distance between the lines
(:func:`line_distance`). :func:`axis_lines` puts both at one configuration,
:func:`axis_rows` compares them per joint. The engine uses them at a failing
backend's worst configuration (the report's "where the chains part");
:mod:`fkcheck.diagnose.axes` over several configurations.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.description.registry import load_description, model_format
from fkcheck.model.frames import reference_poses
from fkcheck.model.types import Model
from fkcheck.urdf.chain import KinematicTree

__all__ = [
    "AxisLines",
    "AxisRow",
    "axis_lines",
    "axis_rows",
    "first_difference",
    "line_distance",
    "read_urdf_kinematics",
]


@dataclass(frozen=True)
class AxisRow:
    """One joint's axis from the table and from the URDF, compared as lines.

    Attributes:
        joint: 0-based joint index.
        name: Joint name.
        angle_rad: Largest angle between the two directions over the configurations.
        distance_m: Largest distance between the two lines (``None`` for a prismatic
            joint, whose line has no position).
        agrees: Both within tolerance.
    """

    joint: int
    name: str
    angle_rad: float
    distance_m: float | None
    agrees: bool

    @property
    def reversed(self) -> bool:
        """The axes are anti-parallel: the joint turns the other way."""
        return self.angle_rad > math.pi - 1e-6


def line_distance(p1: Float, d1: Float, p2: Float, d2: Float) -> float:
    """Distance between two lines (unit directions), parallel lines included."""
    cross = np.cross(d1, d2)
    norm = float(np.linalg.norm(cross))
    diff = p2 - p1
    if norm < 1e-9:
        return float(np.linalg.norm(np.cross(diff, d1)))
    return abs(float(diff @ cross)) / norm


def _dh_axes(model: Model, q: Float, frame_from: str) -> tuple[Float, Float]:
    """Table axes in ``frame_from``: ``(points, directions)``, each ``(n, 3)``."""
    frames = model.fk(q, all_frames=True)  # (n+1, 4, 4) world_T_i
    from_T_world = invert(reference_poses(model, q[None], [frame_from])[0, 0])
    k0 = 0 if model.convention == "standard" else 1
    points, dirs = [], []
    for i, joint in enumerate(model.joints):
        T = from_T_world @ frames[i + k0]
        points.append(T[:3, 3])
        dirs.append(T[:3, 2] * (-1.0 if joint.flip else 1.0))
    return np.array(points), np.array(dirs)


def _urdf_axes(model: Model, kin: KinematicTree, q: Float, from_link: str) -> tuple[Float, Float]:
    """The description's axes of the mapped joints in link ``from_link`` at ``q`` (DH order)."""
    fmt = model_format(model)
    assert fmt is not None
    mapped = fmt.mapped_joints(model)
    value = dict(zip(mapped, q, strict=True))
    root = kin.root

    def pose(link: str) -> Float:
        if link == root:
            return np.eye(4)
        chain = kin.chain(root, link)
        qs = np.array([[value.get(j.name, 0.0) for j in chain if j.type != "fixed"]])
        link_T: Float = kin.chain_poses(chain, qs)[0, -1]
        return link_T

    from_T_root = invert(pose(from_link))
    points, dirs = [], []
    for name in mapped:
        joint = kin.joints[name]
        chain = kin.chain(root, joint.child)
        qs = np.array([value.get(j.name, 0.0) for j in chain if j.type != "fixed"])
        p, d = kin.axes_at(chain, qs)
        points.append(from_T_root[:3, :3] @ p[-1] + from_T_root[:3, 3])
        dirs.append(from_T_root[:3, :3] @ d[-1])
    return np.array(points), np.array(dirs)


@dataclass(frozen=True, eq=False)
class AxisLines:
    """Every joint's axis at one configuration, from the table and from the URDF.

    All in the compared ``from`` frame, DH joint order; a line is a point on it
    and its unit direction (each array ``(n, 3)``).

    Attributes:
        dh_points: The DH frame's origin the joint turns about.
        dh_directions: Its ``z`` axis, reversed for a flipped joint.
        urdf_points: The URDF joint frame's origin.
        urdf_directions: The URDF joint's ``<axis>``.
    """

    dh_points: Float
    dh_directions: Float
    urdf_points: Float
    urdf_directions: Float


def read_urdf_kinematics(model: Model) -> KinematicTree:
    """The model's description, read and screened, as a kinematic tree (whatever its format)."""
    return load_description(model).tree


def axis_lines(
    model: Model, q: Float, frame_from: str, kin: KinematicTree | None = None
) -> AxisLines | None:
    """Each joint's axis from the table and from the model's URDF at one configuration.

    Args:
        model: The model.
        q: One configuration, ``(n,)``, radians / metres.
        frame_from: The named frame both are expressed in; its URDF twin anchors
            the URDF side.
        kin: The model's URDF, already read (default: read it now).

    Returns:
        The lines, or ``None`` when the model has no URDF or ``frame_from`` has no
        URDF twin (the axes then cannot be put in a common frame).

    Raises:
        UrdfError, FrameError: The URDF cannot be read or does not fit the mapping.
    """
    spec = model.frames[frame_from]
    fmt = model_format(model)
    twin = None if fmt is None else fmt.frame(spec)
    if twin is None:
        return None
    kin = kin if kin is not None else read_urdf_kinematics(model)
    p_dh, d_dh = _dh_axes(model, q, frame_from)
    p_u, d_u = _urdf_axes(model, kin, q, twin)
    return AxisLines(p_dh, d_dh, p_u, d_u)


def axis_rows(
    model: Model, lines: Sequence[AxisLines], tol_pos_m: float, tol_rot_rad: float
) -> tuple[AxisRow, ...]:
    """Per joint, the largest angle and line distance over configurations, and whether it agrees.

    A prismatic joint's line has no position (only its direction matters), so
    its distance is ``None`` and only the angle decides.
    """
    n = model.dof
    angles = np.zeros(n)
    distances = np.zeros(n)
    for at in lines:
        for i in range(n):
            u, v = at.dh_directions[i], at.urdf_directions[i]
            cos = float(np.clip(u @ v, -1.0, 1.0))
            sin = float(np.linalg.norm(np.cross(u, v)))
            angles[i] = max(angles[i], math.atan2(sin, cos))
            gap = line_distance(at.dh_points[i], u, at.urdf_points[i], v)
            distances[i] = max(distances[i], gap)
    rows = []
    for i, joint in enumerate(model.joints):
        prismatic = joint.type == "prismatic"
        distance = None if prismatic else float(distances[i])
        agrees = angles[i] <= tol_rot_rad and (prismatic or distances[i] <= tol_pos_m)
        rows.append(AxisRow(i, joint.name, float(angles[i]), distance, bool(agrees)))
    return tuple(rows)


def first_difference(rows: Sequence[AxisRow]) -> AxisRow | None:
    """The first joint whose axis differs, or ``None`` when every axis agrees."""
    return next((r for r in rows if not r.agrees), None)
