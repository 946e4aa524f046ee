"""Joint axes, convention-free: the table's and the URDF's, compared as lines in space.

DH frames and URDF link frames are different frames, but both descriptions put
each joint on the same physical axis. Expressed in the compared ``from`` frame,
joint *i*'s axis from the table (``z`` of DH frame ``i−1`` in standard DH, of
frame ``i`` in modified DH, reversed for a flipped joint) and from the URDF
(``<axis>`` in the joint frame) must be the same line — as Plücker coordinates
``(d, p × d)`` — at every configuration. For each joint this module reports the
largest angle between the directions and the largest distance between the lines
over a few configurations, and names the first joint whose axis disagrees.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from fkcheck.check import reference_poses
from fkcheck.diagnose.problem import Problem
from fkcheck.diagnose.report import AxisRow
from fkcheck.model import Model
from fkcheck.transforms import invert
from fkcheck.urdf_kinematics import UrdfKinematics, urdf_kinematics

__all__ = ["axes_note", "compare_axes", "line_distance", "plucker"]

Float = NDArray[np.float64]

#: Configurations used (axes depend on the joints before them).
AXIS_CONFIGURATIONS = 6


def plucker(point: Float, direction: Float) -> Float:
    """Plücker coordinates ``(d, m)`` of a line, ``m = p × d`` (``d`` normalised)."""
    d = direction / np.linalg.norm(direction)
    return np.concatenate([d, np.cross(point, d)])


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


def _urdf_axes(model: Model, kin: UrdfKinematics, q: Float, from_link: str) -> tuple[Float, Float]:
    """URDF axes of the mapped joints in link ``from_link``, joints at ``q`` (DH order)."""
    assert model.urdf is not None
    value = dict(zip(model.urdf.joints, q, strict=True))
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
    for name in model.urdf.joints:
        joint = kin.joints[name]
        chain = kin.chain(root, joint.child)
        qs = np.array([value.get(j.name, 0.0) for j in chain if j.type != "fixed"])
        p, d = kin.axes_at(chain, qs)
        points.append(from_T_root[:3, :3] @ p[-1] + from_T_root[:3, 3])
        dirs.append(from_T_root[:3, :3] @ d[-1])
    return np.array(points), np.array(dirs)


def compare_axes(problem: Problem) -> tuple[AxisRow, ...]:
    """Each joint's axis from the table and from the model's URDF, compared.

    Returns an empty tuple when the model has no URDF or the ``from`` frame has no
    URDF twin (the axes then cannot be put in a common frame).
    """
    from fkcheck.urdf_source import load_urdf

    model = problem.model
    spec = model.frames[problem.frame_from]
    if model.urdf is None or spec.urdf is None:
        return ()
    info = load_urdf(model)
    kin = urdf_kinematics(info.path, info.text)
    step = max(1, problem.q.shape[0] // AXIS_CONFIGURATIONS)
    qs = problem.q[::step][:AXIS_CONFIGURATIONS]
    n = model.dof
    angles = np.zeros(n)
    distances = np.zeros(n)
    for q in qs:
        p_dh, d_dh = _dh_axes(model, q, problem.frame_from)
        p_u, d_u = _urdf_axes(model, kin, q, spec.urdf)
        for i in range(n):
            cos = float(np.clip(d_dh[i] @ d_u[i], -1.0, 1.0))
            sin = float(np.linalg.norm(np.cross(d_dh[i], d_u[i])))
            angles[i] = max(angles[i], math.atan2(sin, cos))
            distances[i] = max(distances[i], line_distance(p_dh[i], d_dh[i], p_u[i], d_u[i]))
    rows = []
    for i, joint in enumerate(model.joints):
        prismatic = joint.type == "prismatic"
        distance = None if prismatic else float(distances[i])
        agrees = angles[i] <= problem.tol_rot_rad and (
            prismatic or distances[i] <= problem.tol_pos_m
        )
        rows.append(AxisRow(i, joint.name, float(angles[i]), distance, bool(agrees)))
    return tuple(rows)


def axes_note(model: Model, rows: tuple[AxisRow, ...]) -> str:
    """What the axis comparison points at, in one line."""
    if not rows:
        return ""
    bad = [r for r in rows if not r.agrees]
    if not bad:
        return (
            "every joint axis agrees with the URDF: the tables differ only in the frames "
            "at the ends (base, tool, the frame mapping) or along the last axis"
        )
    first = bad[0]
    k = first.joint + 1
    if first.reversed and all(r.agrees for r in rows if r.joint != first.joint):
        return f"joint {k} ({first.name}) is the only axis that differs, and it is reversed: flip?"
    if k == 1:
        return (
            "joint 1's axis already differs: the base ([base], or the mapping of the "
            "from-frame) is where the tables part"
        )
    if model.convention == "standard":
        return (
            f"first axis that differs: joint {k} ({first.name}); in standard DH it is "
            f"z{k - 1}, placed by row {k - 1} (a{k - 1}, α{k - 1}, and d{k - 1}, θ{k - 1}) "
            f"on top of the rows before: look at row {k - 1}"
        )
    return (
        f"first axis that differs: joint {k} ({first.name}); in modified DH it is z{k}, "
        f"placed by row {k} (a{k - 1}, α{k - 1}) on top of the rows before: look at row {k}"
    )
