"""Plugins that fail in every way PluginBackend must report (test fixtures)."""

from __future__ import annotations

import numpy as np

NOT_CALLABLE = 42


def raises(q: np.ndarray) -> np.ndarray:
    raise ZeroDivisionError("the plugin divided by zero")


def wrong_shape(q: np.ndarray) -> np.ndarray:
    return np.tile(np.eye(4), (q.shape[0], 1, 1))[:, :3, :]


def single_pose(q: np.ndarray) -> np.ndarray:
    return np.eye(4)


def nan_output(q: np.ndarray) -> np.ndarray:
    T = np.tile(np.eye(4), (q.shape[0], 1, 1))
    T[2, 0, 3] = np.nan
    return T


def float32_output(q: np.ndarray) -> np.ndarray:
    return np.tile(np.eye(4, dtype=np.float32), (q.shape[0], 1, 1))


def complex_output(q: np.ndarray) -> np.ndarray:
    return np.tile(np.eye(4, dtype=complex), (q.shape[0], 1, 1))


def ragged_output(q: np.ndarray) -> list[list[float]]:
    return [[1.0, 2.0], [3.0]]


def mutates_input(q: np.ndarray) -> np.ndarray:
    q[:] = np.nan
    return np.tile(np.eye(4), (q.shape[0], 1, 1))


def identity_int(q: np.ndarray) -> np.ndarray:
    return np.tile(np.eye(4, dtype=int), (q.shape[0], 1, 1))
