"""Small SE(3) helpers on plain 4×4 NumPy arrays (NumPy only, batched).

Names say the direction: ``a_T_b`` is the pose of frame *b* in frame *a*, so
``a_T_c = a_T_b @ b_T_c`` checks itself. Angles are radians.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "invert",
    "matrix_from_rpy",
    "matrix_from_xyz_rpy",
    "rot_x",
    "rot_z",
    "translation",
]

Float = NDArray[np.float64]


def matrix_from_rpy(rpy: Sequence[float] | ArrayLike) -> Float:
    """Rotation matrix from URDF-style fixed-axis roll, pitch, yaw.

    ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)``, the convention of URDF ``<origin rpy>``.

    Args:
        rpy: Roll, pitch, yaw in radians.

    Returns:
        A 3×3 rotation matrix.
    """
    roll, pitch, yaw = (float(v) for v in np.asarray(rpy, dtype=np.float64).reshape(3))
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(yaw), np.sin(yaw)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_from_xyz_rpy(
    xyz: Sequence[float] | ArrayLike, rpy: Sequence[float] | ArrayLike
) -> Float:
    """Homogeneous 4×4 transform from a translation (m) and URDF-style rpy (rad)."""
    T = np.eye(4)
    T[:3, :3] = matrix_from_rpy(rpy)
    T[:3, 3] = np.asarray(xyz, dtype=np.float64).reshape(3)
    return T


def translation(x: float, y: float, z: float) -> Float:
    """Pure translation as a 4×4 transform (metres)."""
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def rot_x(angle: float) -> Float:
    """Rotation about x as a 4×4 transform (radians)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def rot_z(angle: float) -> Float:
    """Rotation about z as a 4×4 transform (radians)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]])


def invert(a_T_b: Float) -> Float:
    """Inverse of rigid transforms, ``b_T_a``, for shape ``(..., 4, 4)``.

    Uses ``Rᵀ`` and ``-Rᵀ p`` rather than a general matrix inverse, so the
    result is exactly rigid when the input is.
    """
    R = a_T_b[..., :3, :3]
    p = a_T_b[..., :3, 3]
    out = np.zeros_like(a_T_b)
    Rt = np.swapaxes(R, -1, -2)
    out[..., :3, :3] = Rt
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", Rt, p)
    out[..., 3, 3] = 1.0
    return out
