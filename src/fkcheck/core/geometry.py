"""Small SE(3) helpers on plain 4×4 NumPy arrays (NumPy only, batched).

Names say the direction: ``a_T_b`` is the pose of frame *b* in frame *a*, so
``a_T_c = a_T_b @ b_T_c`` checks itself. Angles are radians.

This module is fkcheck's one rotation ⇄ roll-pitch-yaw vocabulary:
:func:`matrix_from_rpy` and its inverse :func:`rpy_from_matrix`, with one
gimbal-lock rule (see :data:`GIMBAL_LOCK_COS`). Every place that prints or
writes rpy (model files, ``fkcheck fk --format rpy|zyx``, the HTML report) goes
through them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.core.typing import Float

__all__ = [
    "GIMBAL_LOCK_COS",
    "invert",
    "matrix_from_rpy",
    "matrix_from_xyz_rpy",
    "rot_x",
    "rot_z",
    "rpy_from_matrix",
    "translation",
]


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


#: Below this value of ``cos(pitch)`` a rotation counts as gimbal-locked (pitch = ±π/2):
#: roll and yaw then turn about the same axis and only their sum (pitch = +π/2) or
#: difference (pitch = -π/2) is defined. Round-off of a matrix built at exactly ±π/2
#: leaves ``cos(pitch)`` near 1e-16; 1e-12 keeps every designed pitch out.
GIMBAL_LOCK_COS = 1e-12


def rpy_from_matrix(R: ArrayLike) -> Float:
    """URDF-style fixed-axis roll, pitch, yaw of rotation(s); inverts :func:`matrix_from_rpy`.

    ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)`` with roll, yaw in ``(-π, π]`` and pitch in
    ``[-π/2, π/2]``. The Z-Y'-X'' Euler angles ``(A, B, C)`` of the same matrix are
    ``(yaw, pitch, roll)``.

    Gimbal lock: where ``cos(pitch) ≤`` :data:`GIMBAL_LOCK_COS` (pitch = ±π/2), yaw is
    0 and roll carries the whole rotation about the locked axis. The angles
    reproduce the matrix to round-off at every pitch, near the lock too.

    Args:
        R: Shape ``(..., 3, 3)`` rotation(s) or ``(..., 4, 4)`` transform(s); only
            the upper-left 3×3 block is read.

    Returns:
        Shape ``(..., 3)``: roll, pitch, yaw in radians.
    """
    M = np.asarray(R, dtype=np.float64)[..., :3, :3]
    cos_pitch = np.hypot(M[..., 0, 0], M[..., 1, 0])
    pitch = np.arctan2(-M[..., 2, 0], cos_pitch)
    locked = cos_pitch <= GIMBAL_LOCK_COS
    # Yaw from the first column (0 when locked). Roll from the second row of
    # Rz(yaw)ᵀ·R = Ry(pitch)·Rx(roll), whose second row is (0, cos roll, −sin roll)
    # at any pitch: the last row of R (cos pitch · …) would lose roll's digits near
    # pitch = ±π/2 (a pitch 5e-12 from 90° read roll 1e-5 rad off).
    yaw = np.where(locked, 0.0, np.arctan2(M[..., 1, 0], M[..., 0, 0]))
    cy, sy = np.cos(yaw), np.sin(yaw)
    row1 = -sy[..., None] * M[..., 0, :] + cy[..., None] * M[..., 1, :]
    roll = np.arctan2(-row1[..., 2], row1[..., 1])
    roll = np.where(roll == -np.pi, np.pi, roll)  # (-π, π]: −0.0 rounding gives −π for π
    return np.stack([roll, pitch, yaw], axis=-1) + 0.0  # + 0.0: no -0.0 from arctan2


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
