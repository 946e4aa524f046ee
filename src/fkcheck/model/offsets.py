"""Rigid transforms ⇄ the numbers model files hold (xyz + URDF rpy), NumPy only.

:mod:`fkcheck.core.geometry` builds matrices from numbers; this module goes back:
a 4×4 transform to an :class:`~fkcheck.model.Offset` (rpy by
:func:`fkcheck.core.geometry.rpy_from_matrix`), with round-off cleaned
so that generated model files read ``rpy = [0.0, 0.0, 3.141592653589793]``
rather than ``[1.2e-16, -3.1e-17, 3.1415926535897927]``.
"""

from __future__ import annotations

import math

import numpy as np

from fkcheck.core.geometry import rpy_from_matrix
from fkcheck.core.typing import Float
from fkcheck.model.types import Offset

__all__ = ["ANGLE_SNAP_RAD", "LENGTH_SNAP_M", "offset_from_matrix", "snap"]


#: Angles this close to a multiple of π/2 are written as that multiple: round-off
#: of a few products of exact rotations is ~1e-16; no real design angle is 1e-14 off.
ANGLE_SNAP_RAD = 1e-14
#: Lengths this close to zero are written as zero (round-off of metre-scale sums).
LENGTH_SNAP_M = 1e-15


def snap(value: float, *, angle: bool) -> float:
    """``value`` with round-off removed: near-zero lengths, near-multiple-of-π/2 angles."""
    if angle:
        quarter = round(value / (math.pi / 2))
        exact = quarter * (math.pi / 2)
        if quarter != 0 and abs(value - exact) <= ANGLE_SNAP_RAD:
            # Use the float nearest to k·π/2 (π itself for 2, -π/2 for -1 …).
            return {1: math.pi / 2, -1: -math.pi / 2, 2: math.pi, -2: -math.pi}.get(quarter, exact)
        return 0.0 if abs(value) <= ANGLE_SNAP_RAD else value
    return 0.0 if abs(value) <= LENGTH_SNAP_M else value


def offset_from_matrix(T: Float) -> Offset:
    """The :class:`~fkcheck.model.Offset` (xyz in m, rpy in rad) of a rigid 4×4 transform."""
    T = np.asarray(T, dtype=np.float64)
    roll, pitch, yaw = (snap(float(v), angle=True) for v in rpy_from_matrix(T))
    x, y, z = (snap(float(v), angle=False) for v in T[:3, 3])
    return Offset(xyz=(x, y, z), rpy=(roll, pitch, yaw))
