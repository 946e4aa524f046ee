"""Which configurations a check tries.

Named poses, zero, the mid-range configuration, the joint-limit corners and
edges, and seeded random samples within limits.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from fkcheck.model import Model

__all__ = ["MAX_CORNERS", "Samples", "sample_configurations", "sampling_box"]

Float = NDArray[np.float64]
Sampler = Literal["sobol", "uniform"]

#: At most this many of the 2^n limit corners are used (all of them up to n = 8).
MAX_CORNERS = 256
#: Range used for a joint that declares no limits.
UNLIMITED_REVOLUTE_RAD = math.pi
UNLIMITED_PRISMATIC_M = 1.0
#: Random samples are drawn this many at a time (a power of two, for Sobol).
_CHUNK = 1 << 16


@dataclass(frozen=True, eq=False)
class Samples:
    """Configurations to check and where each came from.

    Attributes:
        q: ``(N, n)`` joint values, radians / metres.
        origin: ``N`` labels: ``pose:<name>``, ``zero``, ``mid``, ``corner``,
            ``edge``, or ``random``.
    """

    q: Float
    origin: tuple[str, ...]


def sampling_box(model: Model) -> tuple[Float, Float]:
    """Lower and upper bounds per joint: its limits, or a default range without."""
    default = np.array(
        [
            UNLIMITED_PRISMATIC_M if j.type == "prismatic" else UNLIMITED_REVOLUTE_RAD
            for j in model.joints
        ]
    )
    lo = np.where(np.isfinite(model.limits[:, 0]), model.limits[:, 0], -default)
    hi = np.where(np.isfinite(model.limits[:, 1]), model.limits[:, 1], default)
    return lo, hi


def _random(n_samples: int, dof: int, seed: int, sampler: Sampler) -> Float:
    """``(n_samples, dof)`` points in the unit cube, generated in bounded chunks."""
    out = np.empty((max(n_samples, 0), dof))
    if n_samples <= 0:
        return out
    if sampler == "uniform":
        rng = np.random.default_rng(seed)
        for start in range(0, n_samples, _CHUNK):
            stop = min(start + _CHUNK, n_samples)
            out[start:stop] = rng.random((stop - start, dof))
        return out
    from scipy.stats import qmc

    engine = qmc.Sobol(d=dof, scramble=True, seed=seed)
    if n_samples <= _CHUNK:
        # One power-of-two draw keeps the sequence's balance properties.
        out[:] = engine.random_base2(max(0, math.ceil(math.log2(n_samples))))[:n_samples]
        return out
    for start in range(0, n_samples, _CHUNK):  # _CHUNK is a power of two
        stop = min(start + _CHUNK, n_samples)
        out[start:stop] = engine.random(_CHUNK)[: stop - start]
    return out


def sample_configurations(
    model: Model, n_samples: int, seed: int = 0, sampler: Sampler = "sobol"
) -> Samples:
    """Named poses, zero, mid-points, limit corners and edges, then seeded random samples.

    Args:
        model: The model.
        n_samples: Number of random samples (in addition to the structured ones).
        seed: Seed of the random samples: the same seed gives the same samples.
        sampler: ``"sobol"`` (scrambled Sobol sequence) or ``"uniform"``.

    Returns:
        The configurations, all within the sampling box (limits where declared).
    """
    lo, hi = sampling_box(model)
    n = model.dof
    rows: list[Float] = []
    origin: list[str] = []
    for name, pose in model.poses.items():
        rows.append(np.array(pose))
        origin.append(f"pose:{name}")
    zero = np.zeros(n)
    if ((zero >= lo) & (zero <= hi)).all():
        rows.append(zero)
        origin.append("zero")
    mid = (lo + hi) / 2.0
    rows.append(mid)
    origin.append("mid")
    corners = list(itertools.islice(itertools.product((0, 1), repeat=n), MAX_CORNERS))
    if 2**n > MAX_CORNERS:  # a seeded subset instead of the first ones only
        pick = np.random.default_rng(seed).choice(2**n, MAX_CORNERS, replace=False)
        corners = [tuple(int(b) for b in np.binary_repr(int(k), n)) for k in pick]
    for bits in corners:
        rows.append(np.where(np.array(bits, dtype=bool), hi, lo))
        origin.append("corner")
    for j in range(n):  # each joint at its limits with the others mid-range
        for bound in (lo[j], hi[j]):
            edge = mid.copy()
            edge[j] = bound
            rows.append(edge)
            origin.append("edge")
    unit = _random(n_samples, n, seed, sampler)
    structured = np.array(rows).reshape(-1, n)
    q = np.concatenate([structured, lo + unit * (hi - lo)])
    origin.extend(["random"] * unit.shape[0])
    return Samples(q=q, origin=tuple(origin))
