"""Joint values as an array: shape and finiteness checked, nothing computed.

Used by the in-house core and by the reference backends alike, which may not
import the core: this module holds no kinematics, only the input check.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.core.typing import Float
from fkcheck.errors import JointInputError

__all__ = ["joint_array", "require_finite"]


def joint_array(q: ArrayLike, n: int) -> Float:
    """``q`` as a C-contiguous float64 ``(N, n)`` array (a ``(n,)`` vector becomes ``(1, n)``).

    Raises:
        JointInputError: Not numbers, or not ``n`` values per configuration.
    """
    try:
        q_arr = np.asarray(q, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise JointInputError(f"joint values are not numbers: {exc}") from None
    if q_arr.ndim == 1:
        q_arr = q_arr.reshape(1, -1)
    if q_arr.ndim != 2 or q_arr.shape[1] != n:
        raise JointInputError(
            f"expected {n} joint values per configuration (shape ({n},) or (N, {n})), "
            f"got shape {np.shape(q)}"
        )
    return np.ascontiguousarray(q_arr)


def require_finite(q: Float) -> None:
    """Raise :class:`JointInputError` naming the first non-finite value of ``(N, n)`` ``q``."""
    if not np.isfinite(q).all():
        bad = np.argwhere(~np.isfinite(q))[0]
        raise JointInputError(
            f"joint values must be finite; configuration {bad[0]} joint {bad[1] + 1} "
            f"is {q[bad[0], bad[1]]}"
        )
