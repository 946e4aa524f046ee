"""UR5 forward kinematics written out in closed form: a plugin fixture for the tests.

Shares no code with fkcheck. The nominal UR table (standard DH, θ offsets 0,
α = π/2, 0, 0, π/2, −π/2, 0) is multiplied out by hand. With c1 = cos q1,
c234 = cos(q2+q3+q4) etc., the link products collapse to:

* A2·A3 is a planar motion: Rz(q2+q3), origin (a2 c2 + a3 c23, a2 s2 + a3 s23, 0).
* A2·A3·A4 rotates by [[c234, 0, s234], [s234, 0, −c234], [0, 1, 0]], origin z = d4.
* A5·A6 rotates by [[c5 c6, −c5 s6, −s5], [s5 c6, −s5 s6, c5], [−s6, −c6, 0]],
  origin (−d6 s5, d6 c5, d5).
* A1 maps frame 1's rows (r1, r2, r3) to world rows (c1 r1 + s1 r3, s1 r1 − c1 r3, r2),
  and adds d1 to z.
"""

from __future__ import annotations

import numpy as np

D1, A2, A3, D4, D5, D6 = 0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823


def forward(q: np.ndarray) -> np.ndarray:
    """world_T_tool0 for q of shape (N, 6), radians; returns (N, 4, 4)."""
    q = np.asarray(q, dtype=float)
    q1, q2, q3, q4, q5, q6 = q.T
    c1, s1 = np.cos(q1), np.sin(q1)
    c2, s2 = np.cos(q2), np.sin(q2)
    c23, s23 = np.cos(q2 + q3), np.sin(q2 + q3)
    c234, s234 = np.cos(q2 + q3 + q4), np.sin(q2 + q3 + q4)
    c5, s5 = np.cos(q5), np.sin(q5)
    c6, s6 = np.cos(q6), np.sin(q6)

    # Rotation and origin of the TCP in frame 1 (after A1).
    r1 = (c234 * c5 * c6 - s234 * s6, -c234 * c5 * s6 - s234 * c6, -c234 * s5)
    r2 = (s234 * c5 * c6 + c234 * s6, -s234 * c5 * s6 + c234 * c6, -s234 * s5)
    r3 = (s5 * c6, -s5 * s6, c5)
    x1 = -D6 * c234 * s5 + D5 * s234 + A2 * c2 + A3 * c23
    y1 = -D6 * s234 * s5 - D5 * c234 + A2 * s2 + A3 * s23
    z1 = D6 * c5 + D4

    T = np.zeros((q.shape[0], 4, 4))
    for col in range(3):
        T[:, 0, col] = c1 * r1[col] + s1 * r3[col]
        T[:, 1, col] = s1 * r1[col] - c1 * r3[col]
        T[:, 2, col] = r2[col]
    T[:, 0, 3] = c1 * x1 + s1 * z1
    T[:, 1, 3] = s1 * x1 - c1 * z1
    T[:, 2, 3] = y1 + D1
    T[:, 3, 3] = 1.0
    return T
