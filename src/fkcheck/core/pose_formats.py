"""Poses the way people read them off a controller: quaternion, rpy, rotation vector, Z-Y'-X''.

Inside fkcheck a pose is a 4×4 homogeneous transform, metres and radians. At the
boundary it is often six or seven numbers instead:

* ``quat``: position + unit quaternion ``(qx, qy, qz, qw)`` (the ROS order), with
  ``qw ≥ 0`` (``q`` and ``-q`` are the same rotation; the one with ``qw ≥ 0`` is printed);
* ``rpy``: position + URDF-style fixed-axis roll, pitch, yaw, ``R = Rz(yaw)·Ry(pitch)·Rx(roll)``;
* ``rotvec``: position + rotation vector ``(rx, ry, rz)`` = unit axis × angle (radians,
  angle in ``[0, π]``), as a Universal Robots teach pendant shows a pose;
* ``zyx``: position + Z-Y'-X'' Euler angles ``(A, B, C)``,
  ``R = Rot(z, A)·Rot(y', B)·Rot(x'', C)`` (KUKA-style A, B, C; the ARma6 paper's
  eqs. 20–22). It is the same matrix as ``rpy`` with the angles in the other order:
  ``(A, B, C) = (yaw, pitch, roll)``.

Roll-pitch-yaw (and so Z-Y'-X'') comes from :func:`fkcheck.core.geometry.rpy_from_matrix`,
fkcheck's one matrix → rpy function; the other conversions go through
:class:`scipy.spatial.transform.Rotation`, imported when first used. Every function
takes one pose ``(4, 4)`` or a batch ``(N, 4, 4)``.
"""

from __future__ import annotations

from typing import Any, Literal, get_args

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.core.geometry import rpy_from_matrix
from fkcheck.core.typing import Float
from fkcheck.io.format import format_fixed

__all__ = [
    "POSE_FORMATS",
    "PoseFormat",
    "format_pose",
    "matrix_from_pose",
    "pose_from_matrix",
    "pose_record",
]

PoseFormat = Literal["quat", "rpy", "rotvec", "zyx"]

#: The formats, in the order ``--help`` lists them.
POSE_FORMATS: tuple[str, ...] = get_args(PoseFormat)

_ROTATION_LABELS: dict[str, tuple[str, ...]] = {
    "quat": ("qx", "qy", "qz", "qw"),
    "rpy": ("roll", "pitch", "yaw"),
    "rotvec": ("rx", "ry", "rz"),
    "zyx": ("A", "B", "C"),
}
#: Formats whose rotation numbers are angles (printed in degrees on request).
_ANGLE_FORMATS = ("rpy", "zyx")


def _rotation_class() -> Any:
    from scipy.spatial.transform import Rotation

    return Rotation


def _check_format(fmt: str) -> None:
    if fmt not in POSE_FORMATS:
        raise ValueError(f"unknown pose format {fmt!r}; formats are: {', '.join(POSE_FORMATS)}")


def pose_from_matrix(T: ArrayLike, fmt: PoseFormat) -> Float:
    """Position (m) and rotation numbers of pose(s) ``T`` in format ``fmt``.

    Args:
        T: Shape ``(4, 4)`` or ``(N, 4, 4)``.
        fmt: ``quat``, ``rpy``, ``rotvec`` or ``zyx``.

    Returns:
        Shape ``(7,)``/``(N, 7)`` for ``quat``, else ``(6,)``/``(N, 6)``; angles in radians.
        ``rpy`` and ``zyx`` come from :func:`fkcheck.core.geometry.rpy_from_matrix`
        and share its gimbal-lock rule: at pitch / B = ±90° yaw / A is 0 and
        roll / C carries the rotation; the matrix they describe is exact.

    Raises:
        ValueError: An unknown format or a matrix that is not ``(…, 4, 4)``.
    """
    _check_format(fmt)
    arr = np.asarray(T, dtype=np.float64)
    if arr.shape[-2:] != (4, 4) or arr.ndim not in (2, 3):
        raise ValueError(f"expected a pose (4, 4) or a batch (N, 4, 4), got shape {arr.shape}")
    single = arr.ndim == 2
    batch = arr.reshape(-1, 4, 4)
    if fmt == "quat":
        numbers = _rotation_class().from_matrix(batch[:, :3, :3]).as_quat(canonical=True)
    elif fmt == "rotvec":
        numbers = _rotation_class().from_matrix(batch[:, :3, :3]).as_rotvec()
    else:
        rpy = rpy_from_matrix(batch)
        numbers = rpy[:, ::-1] if fmt == "zyx" else rpy  # Z-Y'-X'' (A, B, C) = (yaw, pitch, roll)
    out = np.concatenate([batch[:, :3, 3], numbers], axis=1)
    return out[0] if single else out


def matrix_from_pose(values: ArrayLike, fmt: PoseFormat) -> Float:
    """The 4×4 pose(s) from position (m) and rotation numbers in format ``fmt`` (radians).

    The inverse of :func:`pose_from_matrix`. A quaternion is normalised first
    (values read off a display are rounded); a zero quaternion is an error.

    Args:
        values: Shape ``(k,)`` or ``(N, k)``, ``k`` = 7 for ``quat``, else 6.
        fmt: ``quat``, ``rpy``, ``rotvec`` or ``zyx``.

    Returns:
        Shape ``(4, 4)`` or ``(N, 4, 4)``.

    Raises:
        ValueError: Unknown format, wrong number of values, non-finite values or a
            zero quaternion.
    """
    _check_format(fmt)
    arr = np.asarray(values, dtype=np.float64)
    width = 7 if fmt == "quat" else 6
    if arr.ndim not in (1, 2) or arr.shape[-1] != width:
        raise ValueError(f"format {fmt!r} needs {width} numbers per pose, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError("pose values must be finite")
    single = arr.ndim == 1
    batch = arr.reshape(-1, width)
    Rotation = _rotation_class()
    rest = batch[:, 3:]
    if fmt == "quat":
        norms = np.linalg.norm(rest, axis=1)
        if (norms < 1e-9).any():
            raise ValueError("a quaternion of (near) zero length is not a rotation")
        rot = Rotation.from_quat(rest / norms[:, None])
    elif fmt == "rotvec":
        rot = Rotation.from_rotvec(rest)
    elif fmt == "zyx":
        rot = Rotation.from_euler("ZYX", rest)
    else:
        rot = Rotation.from_euler("ZYX", rest[:, ::-1])
    out = np.zeros((batch.shape[0], 4, 4))
    out[:, :3, :3] = rot.as_matrix()
    out[:, :3, 3] = batch[:, :3]
    out[:, 3, 3] = 1.0
    return out[0] if single else out


def pose_record(T: ArrayLike, fmt: PoseFormat) -> dict[str, list[float]]:
    """One pose as JSON-ready fields: ``position_m`` and the rotation in ``fmt``.

    Field names carry the unit and order: ``quaternion_xyzw``, ``rpy_rad``,
    ``rotvec_rad``, ``zyx_abc_rad``.
    """
    numbers = pose_from_matrix(T, fmt)
    if numbers.ndim != 1:
        raise ValueError("pose_record takes one pose (4, 4)")
    key = {
        "quat": "quaternion_xyzw",
        "rpy": "rpy_rad",
        "rotvec": "rotvec_rad",
        "zyx": "zyx_abc_rad",
    }[fmt]
    return {"position_m": numbers[:3].tolist(), key: numbers[3:].tolist()}


def format_pose(T: ArrayLike, fmt: PoseFormat, *, degrees: bool = False, mm: bool = False) -> str:
    """One pose as a line a person compares with a controller display.

    Args:
        T: One pose ``(4, 4)``.
        fmt: ``quat``, ``rpy``, ``rotvec`` or ``zyx``.
        degrees: Print ``rpy``/``zyx`` angles in degrees (a rotation vector stays in
            radians, as on a UR pendant; a quaternion has no unit).
        mm: Print the position in millimetres (a UR pendant's unit).

    Returns:
        E.g. ``x=0.817250 y=0.191450 z=-0.005491 m  rx=0.000000 ry=2.221441 rz=-2.221441 rad``.
    """
    numbers = pose_from_matrix(T, fmt)
    if numbers.ndim != 1:
        raise ValueError("format_pose takes one pose (4, 4)")
    scale, unit = (1000.0, "mm") if mm else (1.0, "m")
    position = " ".join(
        f"{label}={format_fixed(value * scale, 3 if mm else 6)}"
        for label, value in zip("xyz", numbers[:3], strict=True)
    )
    labels = _ROTATION_LABELS[fmt]
    rotation = numbers[3:]
    if fmt in _ANGLE_FORMATS and degrees:
        rotation = np.degrees(rotation)
        rot_unit = "deg"
    else:
        rot_unit = "" if fmt == "quat" else "rad"
    text = " ".join(
        f"{label}={format_fixed(value, 6)}" for label, value in zip(labels, rotation, strict=True)
    )
    return f"{position} {unit}  {text}" + (f" {rot_unit}" if rot_unit else "")
