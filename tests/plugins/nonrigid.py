"""A closed form with a printing error: the UR5 closed form with one entry wrong (test fixture).

Published closed forms often carry a typo that makes the "rotation" not a
rotation (the ARma6 paper's eq. (19) as printed is one). Here r11 gets an extra
factor 2: the position column is right, the matrix is not a rigid transform.
"""

from __future__ import annotations

import numpy as np
from ur5_closed_form import forward as ur5_forward


def forward(q: np.ndarray) -> np.ndarray:
    """UR5 world_T_tool0 with r11 doubled."""
    T = ur5_forward(q)
    T[:, 0, 0] *= 2.0
    return T
