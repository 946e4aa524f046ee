"""Where a DH table parts from its URDF: every joint axis compared, as a line in space.

DH frames and URDF link frames are different frames, so they cannot be compared
one by one — but both descriptions put every joint on the same physical *axis*:
a line with a direction (the way the joint turns or slides). DH joint *i* turns
about ``z`` of DH frame ``i−1`` (standard) or of DH frame ``i`` (modified),
times −1 for a flipped joint; URDF joint *i* turns about its ``<axis>`` in its
joint frame. Expressed in the compared ``from`` frame (whose URDF twin the model
names), the two lines must coincide. The first joint whose axis does not sits on
the first DH frame that is wrong, which names the row of the table to look at.

The URDF side comes from :mod:`fkcheck.urdf_kinematics` (the screened URDF text,
NumPy only); this is evidence for a report, not a backend, and the check's
verdict never depends on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from fkcheck.check import CheckResult, reference_poses
from fkcheck.model import Model
from fkcheck.transforms import invert

__all__ = ["AxisParting", "compare_joint_axes", "urdf_axis_parting"]

Float = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class AxisParting:
    """Each joint's axis from the DH table and from the URDF, at one configuration.

    Attributes:
        index: Configuration index in ``CheckResult.q`` (−1 outside a check).
        urdf_joints: URDF joint names, DH order.
        angle_rad: Angle between the two axis directions, per joint (π: opposite).
        offset_m: Distance of the URDF joint's origin from the DH axis line, per joint.
        first: Index (0-based) of the first joint whose axis differs, or ``None``.
        urdf_lines: The URDF's axes in the ``from`` frame, shape ``(n, 2, 3)``: a point
            (the joint frame's origin) and the unit direction, per joint.
    """

    index: int
    urdf_joints: tuple[str, ...]
    angle_rad: Float
    offset_m: Float
    first: int | None
    urdf_lines: Float


def _angle(u: Float, v: Float) -> float:
    return math.atan2(float(np.linalg.norm(np.cross(u, v))), float(np.dot(u, v)))


def urdf_axis_parting(check: CheckResult, index: int) -> AxisParting | None:
    """Compare every joint axis of the DH table with the URDF's at one configuration of a check.

    Args:
        check: The check (its model must have a ``[urdf]`` table and its ``from``
            frame a URDF twin).
        index: Which configuration of ``check.q``.

    Returns:
        The comparison, or ``None`` when the model has no URDF, the ``from``
        frame has no URDF twin, or the URDF cannot be read here.
    """
    return compare_joint_axes(
        check.model, check.q[index], check.frame_from, check.tol_pos_m, check.tol_rot_rad, index
    )


def _urdf_axes(model: Model, q: Float, from_link: str) -> tuple[Float, Float] | None:
    """The URDF's axes of the mapped joints, DH order, in ``from_link``: points, directions."""
    from fkcheck.errors import FkcheckError
    from fkcheck.urdf_kinematics import urdf_kinematics
    from fkcheck.urdf_source import load_urdf

    assert model.urdf is not None
    try:
        info = load_urdf(model)
        kin = urdf_kinematics(info.path, info.text)
        chain = kin.chain(from_link, kin.joints[model.urdf.joints[-1]].child)
        movable = [j.name for j in chain if j.type != "fixed"]
        values = dict(zip(model.urdf.joints, (float(v) for v in q), strict=True))
        points, directions = kin.axes_at(chain, np.array([values.get(n, 0.0) for n in movable]))
    except (FkcheckError, KeyError, ValueError):
        return None
    if not set(model.urdf.joints) <= set(movable):
        return None
    order = [movable.index(name) for name in model.urdf.joints]
    return points[order], directions[order]


def compare_joint_axes(
    model: Model,
    q: Float,
    frame_from: str,
    tol_pos_m: float,
    tol_rot_rad: float,
    index: int = -1,
) -> AxisParting | None:
    """Compare every joint axis of the DH table with the URDF's at one configuration.

    Args:
        model: The model (with a ``[urdf]`` table).
        q: One configuration, shape ``(n,)``, radians / metres.
        frame_from: The named frame both sets of axes are expressed in; it must
            have a URDF twin.
        tol_pos_m: Distance beyond which an axis differs, metres.
        tol_rot_rad: Angle beyond which an axis differs, radians.
        index: The configuration's index in a check, for display.

    Returns:
        The comparison, or ``None`` when the model has no URDF, ``frame_from``
        has no URDF twin, or the URDF cannot be read here (or its mapped joints
        do not hang below that frame's link).
    """
    from_spec = model.frames[frame_from]
    if model.urdf is None or from_spec.urdf is None:
        return None
    urdf = _urdf_axes(model, q, from_spec.urdf)
    if urdf is None:
        return None
    urdf_points, urdf_dirs = urdf
    from_T_world = invert(reference_poses(model, q[None], (frame_from,))[0, 0])
    dh_frames = np.asarray(model.fk(q, all_frames=True))
    n = model.dof
    angle = np.empty(n)
    offset = np.empty(n)
    for i, joint in enumerate(model.joints):
        on = from_T_world @ (dh_frames[i] if model.convention == "standard" else dh_frames[i + 1])
        dh_point = on[:3, 3]
        dh_dir = on[:3, 2] * (-1.0 if joint.flip else 1.0)
        angle[i] = _angle(dh_dir, urdf_dirs[i])
        offset[i] = float(np.linalg.norm(np.cross(urdf_points[i] - dh_point, dh_dir)))
    beyond = np.flatnonzero((offset > tol_pos_m) | (angle > tol_rot_rad))
    first = int(beyond[0]) if beyond.size else None
    lines = np.stack([urdf_points, urdf_dirs], axis=1)
    return AxisParting(index, tuple(model.urdf.joints), angle, offset, first, lines)
