"""An analytic UR IK written for the tests (Hawkins' closed form), and seeded wrong versions.

Independent of fkcheck: plain NumPy, its own DH matrices and numbers (the UR5e's
published table), so the check's verdict on it is not fkcheck agreeing with itself.
Its module-level :func:`solve` and :func:`fk` are a ``module:function`` solver.
"""

from __future__ import annotations

import math

import numpy as np

#: The UR5e's nominal DH numbers (UR's support article), standard DH.
UR5E = {"d1": 0.1625, "a2": -0.425, "a3": -0.3922, "d4": 0.1333, "d5": 0.0997, "d6": 0.0996}
ALPHA = (math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0)
#: |sin θ5| below which the wrist is singular: θ6 is chosen 0.
_WRIST_EPS = 1e-10


def _dh(theta: float, d: float, a: float, alpha: float) -> np.ndarray:
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array(
        [
            [ct, -st * ca, st * sa, a * ct],
            [st, ct * ca, -ct * sa, a * st],
            [0, sa, ca, d],
            [0, 0, 0, 1],
        ]
    )


def _rows(p: dict[str, float]) -> list[tuple[float, float]]:
    """(d, a) per joint."""
    return [
        (p["d1"], 0.0),
        (0.0, p["a2"]),
        (0.0, p["a3"]),
        (p["d4"], 0.0),
        (p["d5"], 0.0),
        (p["d6"], 0.0),
    ]


def fk_with(p: dict[str, float], q: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    for (d, a), alpha, theta in zip(_rows(p), ALPHA, q, strict=True):
        T = T @ _dh(float(theta), d, a, alpha)
    return T


def solve_with(
    p: dict[str, float],
    T: np.ndarray,
    *,
    flip_wrist_theta6: bool = False,
    drop_elbow_down: bool = False,
    none_near_wrist: float = 0.0,
) -> np.ndarray:
    """Every solution of base_T_tool0 ``T`` (k, 6); the seeded mistakes on request."""
    d1, a2, a3, d4, d5, d6 = (p[k] for k in ("d1", "a2", "a3", "d4", "d5", "d6"))
    T = np.asarray(T, dtype=float)
    p05 = T @ np.array([0.0, 0.0, -d6, 1.0])
    r = math.hypot(p05[0], p05[1])
    if r < abs(d4):
        return np.zeros((0, 6))
    psi = math.atan2(p05[1], p05[0])
    phi = math.acos(d4 / r)
    out = []
    for theta1 in (psi + phi + math.pi / 2, psi - phi + math.pi / 2):
        T1_6 = np.linalg.inv(_dh(theta1, d1, 0.0, ALPHA[0])) @ T
        R = T1_6[:3, :3]
        # atan2, not acos(R[2, 2]): acos loses half the digits next to θ5 = 0.
        abs5 = math.atan2(math.hypot(R[2, 0], R[2, 1]), R[2, 2])
        for s in (1.0, -1.0):
            theta5 = s * abs5
            s5 = math.sin(theta5)
            if none_near_wrist and abs(s5) < none_near_wrist:
                continue
            if abs(s5) < _WRIST_EPS:
                theta6 = 0.0
                theta234 = math.atan2(R[1, 0], R[0, 0]) - theta6
            else:
                theta6 = math.atan2(-R[2, 1] / s5, R[2, 0] / s5)
                theta234 = math.atan2(-R[1, 2] / s5, -R[0, 2] / s5)
            R14 = _dh(theta234, 0.0, 0.0, ALPHA[3])[:3, :3]
            p46 = (_dh(theta5, d5, 0.0, ALPHA[4]) @ _dh(theta6, d6, 0.0, ALPHA[5]))[:3, 3]
            p14 = T1_6[:3, 3] - R14 @ p46
            x, y = p14[0], p14[1]
            c3 = (x * x + y * y - a2 * a2 - a3 * a3) / (2 * a2 * a3)
            if abs(c3) > 1.0 + 1e-12:
                continue
            c3 = max(-1.0, min(1.0, c3))
            for e in (1.0, -1.0):
                theta3 = e * math.acos(c3)
                theta2 = math.atan2(y, x) - math.atan2(
                    a3 * math.sin(theta3), a2 + a3 * math.cos(theta3)
                )
                theta4 = theta234 - theta2 - theta3
                if drop_elbow_down and elbow_down(p, theta2, theta3):
                    continue
                t6 = -theta6 if flip_wrist_theta6 and s < 0 else theta6
                out.append([theta1, theta2, theta3, theta4, theta5, t6])
    sols = np.array(out).reshape(-1, 6)
    return np.angle(np.exp(1j * sols))  # into (-π, π]


def elbow_down(p: dict[str, float], theta2: float, theta3: float) -> bool:
    """Below the shoulder–wrist line in frame 1's plane (y1 is z0, up): the solver's own maths."""
    a2, a3 = p["a2"], p["a3"]
    elbow = np.array([a2 * math.cos(theta2), a2 * math.sin(theta2)])
    wrist = elbow + a3 * np.array([math.cos(theta2 + theta3), math.sin(theta2 + theta3)])
    normal = np.array([-wrist[1], wrist[0]])
    if normal[1] < 0:
        normal = -normal
    return float(normal @ elbow) < 0.0


def solve(T: np.ndarray) -> np.ndarray:
    """The honest solver, for ``--solver tests.ik.ur_ik:solve``."""
    return solve_with(UR5E, T)


def fk(q: np.ndarray) -> np.ndarray:
    """Its own FK."""
    return fk_with(UR5E, q)
