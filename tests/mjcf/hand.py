"""Hand-written rigid-body maths for the MJCF tests: independent of fkcheck and of MuJoCo.

Written from MuJoCo's documented MJCF semantics (XML reference, "body"/"frame"
orientation attributes and ``<compiler>``), never from fkcheck's code.
"""

from __future__ import annotations

import numpy as np

__all__ = ["T", "deg", "quat", "rot", "rx", "ry", "rz", "tr"]


def deg(angle: float) -> float:
    return float(np.radians(angle))


def rot(axis, angle: float) -> np.ndarray:
    """4×4 rotation by ``angle`` (rad) about ``axis`` (normalised here), Rodrigues."""
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    out = np.eye(4)
    out[:3, :3] = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    return out


def rx(angle: float) -> np.ndarray:
    return rot((1, 0, 0), angle)


def ry(angle: float) -> np.ndarray:
    return rot((0, 1, 0), angle)


def rz(angle: float) -> np.ndarray:
    return rot((0, 0, 1), angle)


def tr(x: float, y: float, z: float) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def quat(w: float, x: float, y: float, z: float) -> np.ndarray:
    """4×4 rotation of the quaternion (w, x, y, z), normalised: as an angle about an axis."""
    q = np.array([w, x, y, z], dtype=float)
    q = q / np.linalg.norm(q)
    angle = 2 * np.arctan2(np.linalg.norm(q[1:]), q[0])
    return rot(q[1:], angle) if np.linalg.norm(q[1:]) > 0 else np.eye(4)


def T(*factors: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    for f in factors:
        out = out @ f
    return out
