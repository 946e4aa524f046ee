"""Pose errors between backends, and SE(3) validity of a backend's output (NumPy only)."""

from __future__ import annotations

import numpy as np

from fkcheck.core.typing import Float

__all__ = ["jacobian_column_errors", "position_error_m", "rotation_error_rad", "se3_defect"]


def position_error_m(T_a: Float, T_b: Float) -> Float:
    """Distance between the origins of two pose batches ``(..., 4, 4)``, metres."""
    diff: Float = np.linalg.norm(T_a[..., :3, 3] - T_b[..., :3, 3], axis=-1)
    return diff


def rotation_error_rad(T_a: Float, T_b: Float) -> Float:
    """Angle of ``R_aᵀ R_b``, radians, in ``[0, π]``.

    Computed as ``atan2(‖vee(R − Rᵀ)‖/2, (tr R − 1)/2)``: ``arccos`` of the trace
    alone loses half the digits near 0 (1e-8 rad reads as 0) and ``arcsin`` of
    the skew part loses them near π; the atan2 form is accurate at both ends.
    """
    R = np.swapaxes(T_a[..., :3, :3], -1, -2) @ T_b[..., :3, :3]
    sx = R[..., 2, 1] - R[..., 1, 2]
    sy = R[..., 0, 2] - R[..., 2, 0]
    sz = R[..., 1, 0] - R[..., 0, 1]
    sin_angle = np.sqrt(sx * sx + sy * sy + sz * sz) / 2.0
    cos_angle = (R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0) / 2.0
    angle: Float = np.arctan2(sin_angle, cos_angle)
    return angle


def jacobian_column_errors(J_a: Float, J_b: Float) -> tuple[Float, Float]:
    """How far two Jacobians ``(..., 6, n)`` (linear rows first) are apart, column by column.

    The one measure every Jacobian comparison uses (the check, its diagnosis, the
    bench): the length of the difference of a column's linear 3-vector (m/rad;
    m/m for a prismatic joint) and of its angular one (rad/rad). A non-finite
    entry makes that part of its column's error ``inf``.

    Returns:
        ``(linear, angular)``, each ``(..., n)``.
    """
    diff = np.asarray(J_b, dtype=np.float64) - np.asarray(J_a, dtype=np.float64)
    linear: Float = np.linalg.norm(diff[..., :3, :], axis=-2)
    angular: Float = np.linalg.norm(diff[..., 3:, :], axis=-2)
    linear[~np.isfinite(diff[..., :3, :]).all(axis=-2)] = np.inf
    angular[~np.isfinite(diff[..., 3:, :]).all(axis=-2)] = np.inf
    return linear, angular


def se3_defect(T: Float) -> Float:
    """How far each ``(..., 4, 4)`` is from a rigid transform (0 for a perfect one).

    The largest of: entries of ``RᵀR − I``, ``|det R − 1|``, and the last row's
    distance from ``0 0 0 1``. NaN anywhere gives NaN.
    """
    R = T[..., :3, :3]
    gram = np.swapaxes(R, -1, -2) @ R - np.eye(3)
    ortho = np.abs(gram).max(axis=(-1, -2))
    det = np.abs(np.linalg.det(R) - 1.0)
    last = np.abs(T[..., 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max(axis=-1)
    defect: Float = np.maximum(np.maximum(ortho, det), last)
    bad = ~np.isfinite(T).all(axis=(-1, -2))
    defect[bad] = np.nan
    return defect
