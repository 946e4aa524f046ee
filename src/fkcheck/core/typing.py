"""Type aliases shared across fkcheck (typing only; imports nothing but NumPy).

``Float`` is the one name for a float64 array — a batch of joint values, a stack
of 4×4 poses — so every module spells it the same way. ``JacobianReference``
names the reference frames a Jacobian is expressed in (defined in
:mod:`fkcheck.core.jacobian`), for the core and the backends alike.
"""

from __future__ import annotations

from typing import Literal, get_args

import numpy as np
from numpy.typing import NDArray

__all__ = ["JACOBIAN_REFERENCES", "Float", "JacobianReference"]

#: A NumPy array of float64 (shape given in each function's docstring).
Float = NDArray[np.float64]

#: A Jacobian's reference frame: Pinocchio's ``WORLD``, ``LOCAL``, ``LOCAL_WORLD_ALIGNED``.
JacobianReference = Literal["world", "local", "world-aligned"]
#: The reference frames, in the order they are listed.
JACOBIAN_REFERENCES: tuple[JacobianReference, ...] = get_args(JacobianReference)
