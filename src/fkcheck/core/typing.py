"""Type aliases shared across fkcheck (typing only; imports nothing but NumPy).

``Float`` is the one name for a float64 array — a batch of joint values, a stack
of 4×4 poses — so every module spells it the same way.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["Float"]

#: A NumPy array of float64 (shape given in each function's docstring).
Float = NDArray[np.float64]
