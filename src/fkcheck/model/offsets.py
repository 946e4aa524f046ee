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


#: The float nearest k·π/2 for the quarter turns a table holds.
_QUARTERS = {0: 0.0, 1: math.pi / 2, -1: -math.pi / 2, 2: math.pi, -2: -math.pi}


def snap(value: float, *, angle: bool, tol: float | None = None, grid_m: float = 0.0) -> float:
    """``value``, or the round number within ``tol`` of it; anything further is kept.

    Angles (radians) go to 0 or a multiple of π/2 (the float nearest it); lengths
    (metres) to a multiple of ``grid_m`` (``1e-6``: whole micrometres), or to 0
    when ``grid_m`` is 0. The default ``tol`` removes round-off only
    (:data:`ANGLE_SNAP_RAD`, :data:`LENGTH_SNAP_M`); ``table-from`` cleans
    with a looser one (:data:`fkcheck.urdf.to_dh.CLEAN_TOL`).
    """
    if tol is None:
        tol = ANGLE_SNAP_RAD if angle else LENGTH_SNAP_M
    if angle:
        quarter = round(value / (math.pi / 2))
        exact = _QUARTERS.get(quarter, quarter * (math.pi / 2))
    elif grid_m:
        exact = round(value / grid_m) / round(1 / grid_m)
    else:
        exact = 0.0
    return exact + 0.0 if abs(value - exact) <= tol else value


def offset_from_matrix(T: Float) -> Offset:
    """The :class:`~fkcheck.model.Offset` (xyz in m, rpy in rad) of a rigid 4×4 transform."""
    T = np.asarray(T, dtype=np.float64)
    roll, pitch, yaw = (snap(float(v), angle=True) for v in rpy_from_matrix(T))
    x, y, z = (snap(float(v), angle=False) for v in T[:3, 3])
    return Offset(xyz=(x, y, z), rpy=(roll, pitch, yaw))
