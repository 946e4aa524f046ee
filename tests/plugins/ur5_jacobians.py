"""UR5 poses and Jacobians of a plugin's own (shares no code with fkcheck), right and wrong.

``correct`` / ``correct_jacobian``: the TCP pose and its world-aligned geometric
Jacobian (linear rows first, world axes). ``end_effector`` /
``end_effector_jacobian``: the same poses, but the Jacobian expressed in the
end-effector frame — the classic mistake when the world one is expected.
``angular_first`` / ``angular_first_jacobian``: rows in textbook order.
"""

from __future__ import annotations

import numpy as np

A = (0.0, -0.425, -0.39225, 0.0, 0.0, 0.0)
D = (0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823)
ALPHA = (np.pi / 2, 0.0, 0.0, np.pi / 2, -np.pi / 2, 0.0)


def _frames(q: np.ndarray) -> np.ndarray:
    """Frames 0..6 of the standard-DH chain, (N, 7, 4, 4)."""
    q = np.asarray(q, dtype=float)
    n_configs = q.shape[0]
    out = np.zeros((n_configs, 7, 4, 4))
    out[:, 0] = np.eye(4)
    for i in range(6):
        ct, st = np.cos(q[:, i]), np.sin(q[:, i])
        ca, sa = np.cos(ALPHA[i]), np.sin(ALPHA[i])
        link = np.zeros((n_configs, 4, 4))
        link[:, 0] = np.stack([ct, -st * ca, st * sa, A[i] * ct], axis=1)
        link[:, 1] = np.stack([st, ct * ca, -ct * sa, A[i] * st], axis=1)
        link[:, 2] = np.array([0.0, sa, ca, D[i]])
        link[:, 3] = np.array([0.0, 0.0, 0.0, 1.0])
        out[:, i + 1] = out[:, i] @ link
    return out


def _world_aligned(q: np.ndarray) -> np.ndarray:
    frames = _frames(q)
    tip = frames[:, 6, :3, 3]
    jac = np.zeros((q.shape[0], 6, 6))
    for i in range(6):
        z = frames[:, i, :3, 2]
        jac[:, :3, i] = np.cross(z, tip - frames[:, i, :3, 3])
        jac[:, 3:, i] = z
    return jac


def correct(q: np.ndarray) -> np.ndarray:
    return _frames(q)[:, 6]


def correct_jacobian(q: np.ndarray) -> np.ndarray:
    return _world_aligned(q)


end_effector = correct
angular_first = correct


def end_effector_jacobian(q: np.ndarray) -> np.ndarray:
    R_t = np.swapaxes(_frames(q)[:, 6, :3, :3], 1, 2)
    jac = _world_aligned(q)
    return np.concatenate([R_t @ jac[:, :3], R_t @ jac[:, 3:]], axis=1)


def angular_first_jacobian(q: np.ndarray) -> np.ndarray:
    jac = _world_aligned(q)
    return np.concatenate([jac[:, 3:], jac[:, :3]], axis=1)


# Jacobians a plugin must not get away with (poses right, Jacobian unusable).
wrong_shape = float32 = complex_out = strings = raises = not_callable = correct


def wrong_shape_jacobian(q: np.ndarray) -> np.ndarray:
    return _world_aligned(q)[:, :, :5]


def float32_jacobian(q: np.ndarray) -> np.ndarray:
    return _world_aligned(q).astype(np.float32)


def complex_out_jacobian(q: np.ndarray) -> np.ndarray:
    return _world_aligned(q) + 1j


def strings_jacobian(q: np.ndarray) -> np.ndarray:
    return _world_aligned(q).astype(str)


def raises_jacobian(q: np.ndarray) -> np.ndarray:
    raise ValueError("no Jacobian here")


not_callable_jacobian = 3
