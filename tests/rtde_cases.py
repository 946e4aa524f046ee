"""RTDE recordings written by the tests, as UR's recorder writes them (``record.py``).

UR's recorder (``rtde/csv_writer.py`` of UR's RTDE client library) writes a header of
output names, a vector output ``name`` as ``name_0 … name_5``, then one row per sample
through :func:`csv.writer` with ``delimiter=" "``: a float as ``str(float)``, the shortest
text that reads back as the same double. The poses here come from the in-house core
through the model (``base`` → ``tool0`` by default), the rotation vectors from SciPy.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from fkcheck.model.types import Model
from tests.calibration.ur_test_data import Table, fk

__all__ = [
    "RTDE_HEADER",
    "near_half_turn_configurations",
    "poses_of",
    "rtde_rows",
    "write_rtde_csv",
]

#: Outputs in the order written, with their sizes: the 12 columns read among others.
_OUTPUTS: tuple[tuple[str, int], ...] = (
    ("timestamp", 1),
    ("target_q", 6),
    ("actual_TCP_pose", 6),
    ("actual_qd", 6),
    ("actual_q", 6),
    ("robot_mode", 1),
    ("speed_scaling", 1),
)
#: The header line's names, as UR's recorder expands them.
RTDE_HEADER: tuple[str, ...] = tuple(
    name if size == 1 else f"{name}_{i}" for name, size in _OUTPUTS for i in range(size)
)


def poses_of(model: Model, q: np.ndarray, pair: tuple[str, str] = ("base", "tool0")) -> np.ndarray:
    """``base_T_tool0`` at each configuration, ``(N, 4, 4)``, by the tests' own composition.

    Not fkcheck's core: a recording written by the core would agree with the core
    whatever its maths. For a UR table, ``base`` is DH frame 0 and ``tool0`` the
    last DH frame (no offsets), which the assertions below hold the model to.
    """
    assert pair == ("base", "tool0"), pair
    assert model.convention == "standard"
    assert model.dof == 6
    for name, dh in zip(pair, (0, model.dof), strict=True):
        frame = model.frames[name]
        assert frame.dh == dh, (name, frame)
        assert frame.offset.is_identity, (name, frame)
    assert model.base.is_identity
    assert not any(j.flip for j in model.joints)
    js = model.joints
    table = Table(
        tuple(j.theta for j in js), tuple(j.a for j in js), tuple(j.d for j in js),
        tuple(j.alpha for j in js),
    )  # fmt: skip
    return fk(table, q)


def near_half_turn_configurations(
    model: Model, rng: np.random.Generator, count: int, within: float = 1e-6
) -> np.ndarray:
    """Configurations whose ``base`` → ``tool0`` rotation turns by π − δ, 0 < δ < ``within``.

    Half of them about an axis ``u``, half about ``-u`` (the two rotation vectors of
    almost the same rotation, pointing opposite ways).
    """
    found = []
    while len(found) < count:
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        sign = 1.0 if len(found) % 2 == 0 else -1.0
        delta = rng.uniform(0.05, 0.5) * within
        target = Rotation.from_rotvec(sign * (np.pi - delta) * u)

        def residual(q: np.ndarray, target: Rotation = target) -> np.ndarray:
            R = poses_of(model, q[None])[0, :3, :3]
            rotvec: np.ndarray = (target.inv() * Rotation.from_matrix(R)).as_rotvec()
            return rotvec

        fit = least_squares(residual, rng.uniform(-2.5, 2.5, size=6), xtol=1e-15, ftol=1e-15)
        angle = Rotation.from_matrix(poses_of(model, fit.x[None])[0, :3, :3]).magnitude()
        if 0.0 < np.pi - angle < within:
            found.append(fit.x)
    return np.array(found)


def rtde_rows(model: Model, q: np.ndarray, flip: Sequence[bool] | None = None) -> list[list[float]]:
    """One recorder row per configuration, every output filled (others with plausible values).

    Args:
        model: The model whose table gives the poses.
        q: ``(N, 6)`` joint values, radians.
        flip: Per row, write the rotation vector ``r`` as ``r − 2π r/|r|``: the same
            rotation, pointing the other way (what a controller may write near π).
    """
    T = poses_of(model, q)
    rotvec = Rotation.from_matrix(T[:, :3, :3]).as_rotvec()
    if flip is not None:
        angle = np.linalg.norm(rotvec, axis=1, keepdims=True)
        flipped = rotvec - 2.0 * np.pi * rotvec / np.where(angle > 0, angle, 1.0)
        rotvec = np.where(np.asarray(flip)[:, None], flipped, rotvec)
    pose = np.hstack([T[:, :3, 3], rotvec])
    rows = []
    for k in range(q.shape[0]):
        values = {
            "timestamp": [0.008 * k],
            "target_q": list(q[k] + 1e-4),
            "actual_TCP_pose": list(pose[k]),
            "actual_qd": [0.0] * 6,
            "actual_q": list(q[k]),
            "robot_mode": [7.0],
            "speed_scaling": [1.0],
        }
        rows.append([float(v) for name, _ in _OUTPUTS for v in values[name]])
    return rows


def write_rtde_csv(
    path: Path,
    model: Model,
    q: np.ndarray,
    *,
    flip: Sequence[bool] | None = None,
    delimiter: str = " ",
) -> Path:
    """Write ``q`` and the model's poses there as UR's recorder writes a recording."""
    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f, delimiter=delimiter)
        writer.writerow(RTDE_HEADER)
        writer.writerows(rtde_rows(model, q, flip))
    return path
