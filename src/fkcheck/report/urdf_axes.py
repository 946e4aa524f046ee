"""Where a DH table parts from its URDF: every joint axis compared, as a line in space.

DH frames and URDF link frames are different frames, so they cannot be compared
one by one — but both descriptions put every joint on the same physical *axis*:
a line with a direction (the way the joint turns or slides). DH joint *i* turns
about ``z`` of DH frame ``i−1`` (standard) or of DH frame ``i`` (modified),
times −1 for a flipped joint; URDF joint *i* turns about its ``<axis>`` in its
joint frame. Expressed in the compared ``from`` frame (whose URDF twin the model
names), the two lines must coincide. The first joint whose axis does not sits on
the first DH frame that is wrong, which names the row of the table to look at.

This module reads the screened URDF text (:func:`fkcheck.urdf_source.load_urdf`)
with the standard library and walks the tree with NumPy; it is evidence for a
report, not a backend, and the check's verdict never depends on it.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from fkcheck.check import CheckResult, reference_poses
from fkcheck.model import Model
from fkcheck.transforms import invert, matrix_from_xyz_rpy

__all__ = [
    "AxisParting",
    "UrdfJointGeometry",
    "compare_joint_axes",
    "parse_joint_geometry",
    "urdf_axis_parting",
]

Float = NDArray[np.float64]


@dataclass(frozen=True)
class UrdfJointGeometry:
    """A URDF joint's fixed geometry.

    Attributes:
        name: Joint name.
        type: ``revolute``, ``continuous``, ``prismatic``, ``fixed`` …
        parent: Parent link.
        child: Child link.
        origin: ``parent_T_joint`` (4×4) from ``<origin xyz rpy>``.
        axis: Unit axis in the joint frame (``<axis xyz>``, default ``1 0 0``).
    """

    name: str
    type: str
    parent: str
    child: str
    origin: tuple[tuple[float, ...], ...]
    axis: tuple[float, float, float]


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


def _floats(text: str | None, default: tuple[float, float, float]) -> tuple[float, float, float]:
    if text is None:
        return default
    parts = [float(v) for v in text.split()]
    if len(parts) != 3 or not all(math.isfinite(v) for v in parts):
        raise ValueError(f"expected three finite numbers, got {text!r}")
    return (parts[0], parts[1], parts[2])


def parse_joint_geometry(text: str) -> dict[str, UrdfJointGeometry]:
    """Every ``<joint>`` of a URDF with its origin and axis.

    Args:
        text: The URDF, already screened (no DTD) by :func:`fkcheck.urdf_source.load_urdf`.

    Raises:
        ValueError: An origin or axis that is not three finite numbers, or a zero axis.
    """
    root = ET.fromstring(text)
    out: dict[str, UrdfJointGeometry] = {}
    for el in root.iter("joint"):
        parent, child, name = el.find("parent"), el.find("child"), el.get("name")
        if name is None or parent is None or child is None:
            continue  # a <joint> inside <transmission>
        origin = el.find("origin")
        xyz = _floats(origin.get("xyz") if origin is not None else None, (0.0, 0.0, 0.0))
        rpy = _floats(origin.get("rpy") if origin is not None else None, (0.0, 0.0, 0.0))
        axis_el = el.find("axis")
        axis = np.array(
            _floats(axis_el.get("xyz") if axis_el is not None else None, (1.0, 0.0, 0.0))
        )
        norm = float(np.linalg.norm(axis))
        if norm == 0.0:
            raise ValueError(f"joint {name!r} has a zero axis")
        unit = axis / norm
        out[name] = UrdfJointGeometry(
            name=name,
            type=el.get("type", ""),
            parent=str(parent.get("link")),
            child=str(child.get("link")),
            origin=tuple(tuple(float(v) for v in row) for row in matrix_from_xyz_rpy(xyz, rpy)),
            axis=(float(unit[0]), float(unit[1]), float(unit[2])),
        )
    return out


def _motion(joint: UrdfJointGeometry, value: float) -> Float:
    """The joint's own motion for a joint value (rotation about / slide along its axis)."""
    T = np.eye(4)
    u = np.array(joint.axis)
    if joint.type in ("revolute", "continuous"):
        K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
        T[:3, :3] = np.eye(3) + math.sin(value) * K + (1.0 - math.cos(value)) * (K @ K)
    elif joint.type == "prismatic":
        T[:3, 3] = value * u
    return T


class _Tree:
    """Link and joint-frame poses of a URDF for one configuration."""

    def __init__(self, joints: dict[str, UrdfJointGeometry], values: dict[str, float]) -> None:
        self.by_child = {j.child: j for j in joints.values()}
        self.values = values
        self.cache: dict[str, Float] = {}

    def link(self, name: str) -> Float:
        """``root_T_link``."""
        if name not in self.cache:
            joint = self.by_child.get(name)
            if joint is None:  # the root
                self.cache[name] = np.eye(4)
            else:
                value = self.values.get(joint.name, 0.0)
                self.cache[name] = self.joint_frame(joint) @ _motion(joint, value)
        return self.cache[name]

    def joint_frame(self, joint: UrdfJointGeometry) -> Float:
        """``root_T_joint`` before the joint's own motion (its axis does not depend on it)."""
        frame: Float = self.link(joint.parent) @ np.array(joint.origin)
        return frame


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
        has no URDF twin, or the URDF cannot be read here.
    """
    from fkcheck.errors import FkcheckError
    from fkcheck.urdf_source import load_urdf

    from_spec = model.frames[frame_from]
    if model.urdf is None or from_spec.urdf is None:
        return None
    try:
        info = load_urdf(model)
        joints = parse_joint_geometry(info.text)
    except (FkcheckError, ValueError, ET.ParseError):
        return None
    tree = _Tree(joints, dict(zip(model.urdf.joints, (float(v) for v in q), strict=True)))
    urdf_from_T_root = invert(tree.link(from_spec.urdf))

    world_T_from = reference_poses(model, q[None], (frame_from,))[0, 0]
    from_T_world = invert(world_T_from)
    dh_frames = np.asarray(model.fk(q, all_frames=True))
    n = model.dof
    angle = np.empty(n)
    offset = np.empty(n)
    lines = np.empty((n, 2, 3))
    for i, (joint, urdf_name) in enumerate(zip(model.joints, model.urdf.joints, strict=True)):
        on = dh_frames[i] if model.convention == "standard" else dh_frames[i + 1]
        sign = -1.0 if joint.flip else 1.0
        dh_point = (from_T_world @ on)[:3, 3]
        dh_dir = (from_T_world @ on)[:3, 2] * sign
        J = urdf_from_T_root @ tree.joint_frame(joints[urdf_name])
        urdf_point = J[:3, 3]
        urdf_dir = J[:3, :3] @ np.array(joints[urdf_name].axis)
        angle[i] = _angle(dh_dir, urdf_dir)
        offset[i] = float(np.linalg.norm(np.cross(urdf_point - dh_point, dh_dir)))
        lines[i] = (urdf_point, urdf_dir)
    beyond = np.flatnonzero((offset > tol_pos_m) | (angle > tol_rot_rad))
    first = int(beyond[0]) if beyond.size else None
    return AxisParting(index, tuple(model.urdf.joints), angle, offset, first, lines)
