"""Numbers and poses as the report's view values: lengths, angles, matrices, pose forms.

Every string comes from :mod:`fkcheck.io.format` (the one number
formatter); this module only packs them into the view types of
:mod:`fkcheck.report.views`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.geometry import rpy_from_matrix
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.core.typing import Float
from fkcheck.io.format import (
    format_constant,
    format_deg,
    format_fixed,
    format_m,
    format_mm,
    format_rad,
    format_value,
)
from fkcheck.model.types import Model, Offset
from fkcheck.report.views import (
    JointValue,
    MatrixCell,
    MatrixView,
    Measure,
    PoseForms,
)

if TYPE_CHECKING:
    pass

__all__ = [
    "difference_entry",
    "joint_values",
    "matrix_view",
    "measure_m",
    "measure_rad",
    "pose_forms",
    "q_text",
    "xyz_rpy_text",
]


def measure_m(value: float | None) -> Measure:
    """A length: millimetres first, metres second."""
    return Measure(value, format_mm(value), format_m(value))


def measure_rad(value: float | None) -> Measure:
    """An angle given in radians: degrees first, radians second (as every output)."""
    return Measure(value, format_deg(value), format_rad(value))


def xyz_rpy_text(offset: Offset) -> str:
    """A fixed offset as ``xyz (…) m, rpy (…)°``, or ``none``."""
    if offset.is_identity:
        return "none"
    xyz = ", ".join(format_constant(v) for v in offset.xyz)
    rpy = ", ".join(format_constant(math.degrees(v)) for v in offset.rpy)
    return f"xyz ({xyz}) m, rpy ({rpy})°"


def difference_entry(value: float) -> str:
    """An entry of ``theirs − ours``; round-off (≤ SAME_CHAIN) reads as 0."""
    return "0" if abs(value) <= SAME_CHAIN else f"{value:.2e}"


def matrix_view(
    T: Float, marked: NDArray[np.bool_] | None = None, fmt: Callable[[float], str] | None = None
) -> MatrixView:
    """A 4×4 matrix as a view; ``marked`` entries highlighted, nine decimals unless ``fmt``."""
    show = fmt or (lambda v: format_fixed(v, 9))
    rows = tuple(
        tuple(
            MatrixCell(show(float(T[i, j])), bool(marked[i, j]) if marked is not None else False)
            for j in range(4)
        )
        for i in range(4)
    )
    return MatrixView(rows)


def pose_forms(T: Float, marked: NDArray[np.bool_] | None = None) -> PoseForms:
    """A pose as a matrix, xyz + quaternion (x, y, z, w) and xyz + rpy (degrees).

    The quaternion is SciPy's, scalar last, with w ≥ 0; rpy is fixed-axis
    roll-pitch-yaw as in URDF (``R = Rz(yaw) Ry(pitch) Rx(roll)``) from
    :func:`fkcheck.core.geometry.rpy_from_matrix`: at pitch ±90° yaw is 0 and roll
    carries the rotation.
    """
    from scipy.spatial.transform import Rotation

    xyz = ", ".join(format_fixed(v, 9) for v in T[:3, 3])
    if not np.isfinite(T[:3, :3]).all():  # a backend's NaN/inf answer: no rotation to convert
        quaternion = rpy_text = "(not a rotation: NaN or inf entries)"
    else:
        quat = Rotation.from_matrix(T[:3, :3]).as_quat(canonical=True)
        quaternion = "(" + ", ".join(format_fixed(v, 9) for v in quat) + ")"
        rpy = np.degrees(rpy_from_matrix(T))
        rpy_text = "(" + ", ".join(format_fixed(v, 6) for v in rpy) + ")°"
    return PoseForms(
        matrix=matrix_view(T, marked), xyz=f"({xyz}) m", quaternion=quaternion, rpy=rpy_text
    )


def q_text(model: Model, q: Float) -> str:
    """A configuration as ``[…]``, radians or metres per joint."""
    parts = (
        format_value(float(v), j.type == "prismatic") for v, j in zip(q, model.joints, strict=True)
    )
    return "[" + ", ".join(parts) + "]"


def joint_values(model: Model, q: Float) -> tuple[JointValue, ...]:
    """A configuration joint by joint: radians (and degrees) or metres."""
    out = []
    for v, joint in zip(q, model.joints, strict=True):
        if joint.type == "prismatic":
            out.append(JointValue(joint.name, f"{format_fixed(v, 9)} m", ""))
        else:
            out.append(
                JointValue(joint.name, format_fixed(v, 9), f"{format_fixed(math.degrees(v), 6)}°")
            )
    return tuple(out)
