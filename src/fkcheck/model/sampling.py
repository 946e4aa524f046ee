"""Which configurations a check tries.

Named poses, zero, the mid-range configuration, the joint-limit corners and
edges, and seeded random samples within limits.

A model has ``2^n`` limit corners: all of them are tried up to ``n = 8``
(:data:`MAX_CORNERS` = 256), beyond that a seeded subset of 256 distinct ones,
for any ``n`` up to :data:`fkcheck.model.MAX_JOINTS` (256 joints). Up to
``n = 62`` the subset is drawn as corner numbers ``0 … 2^n − 1``; from 63 joints
on, where ``2^n`` no longer fits NumPy's 64-bit integers, as random rows of bits.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.model.options import Sampler
from fkcheck.model.types import Model

__all__ = [
    "MAX_CORNERS",
    "Sampler",
    "Samples",
    "sample_configurations",
    "sampling_box",
]

#: At most this many of the 2^n limit corners are used (all of them up to n = 8).
MAX_CORNERS = 256
#: Corners are numbered 0 … 2^n − 1 up to this n (numbers within NumPy's int64).
_MAX_NUMBERED_CORNER_BITS = 62
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


def _fill_random(out: Float, lo: Float, hi: Float, seed: int, sampler: Sampler) -> None:
    """Fill ``out`` (``(N, n)``) with seeded samples in the box, in bounded chunks.

    Writes in place, a chunk at a time: peak memory is ``out`` plus one chunk.
    """
    n_samples, dof = out.shape
    if n_samples == 0:
        return
    span = hi - lo
    draw: Callable[[int], Float]
    if sampler == "uniform":
        rng = np.random.default_rng(seed)

        def draw(count: int) -> Float:
            return rng.random((count, dof))
    else:
        from scipy.stats import qmc

        engine = qmc.Sobol(d=dof, scramble=True, seed=seed)
        if n_samples <= _CHUNK:
            # One power-of-two draw keeps the sequence's balance properties.
            m = max(0, math.ceil(math.log2(n_samples)))
            out[:] = lo + engine.random_base2(m)[:n_samples] * span
            return

        def draw(count: int) -> Float:
            # Always a power-of-two draw (_CHUNK), for the sequence's balance.
            return engine.random(_CHUNK)[:count]  # type: ignore[no-any-return]

    for start in range(0, n_samples, _CHUNK):
        stop = min(start + _CHUNK, n_samples)
        block = out[start:stop]
        block[:] = draw(stop - start)
        block *= span
        block += lo


def _corners(n: int, seed: int) -> list[tuple[int, ...]]:
    """The limit corners tried, as bits (1: upper limit): all, or a seeded subset."""
    if 2**n <= MAX_CORNERS:
        return list(itertools.product((0, 1), repeat=n))
    rng = np.random.default_rng(seed)
    if n <= _MAX_NUMBERED_CORNER_BITS:
        pick = rng.choice(2**n, MAX_CORNERS, replace=False)
        return [tuple(int(b) for b in np.binary_repr(int(k), n)) for k in pick]
    corners: dict[tuple[int, ...], None] = {}  # distinct, in the order drawn
    while len(corners) < MAX_CORNERS:  # one round, unless two of 2^n rows collide
        for row in rng.integers(0, 2, size=(MAX_CORNERS, n)):
            corners.setdefault(tuple(int(b) for b in row))
    return list(corners)[:MAX_CORNERS]


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
    for bits in _corners(n, seed):
        rows.append(np.where(np.array(bits, dtype=bool), hi, lo))
        origin.append("corner")
    for j in range(n):  # each joint at its limits with the others mid-range
        for bound in (lo[j], hi[j]):
            edge = mid.copy()
            edge[j] = bound
            rows.append(edge)
            origin.append("edge")
    count = max(n_samples, 0)
    q = np.empty((len(rows) + count, n))
    q[: len(rows)] = np.array(rows).reshape(-1, n)
    _fill_random(q[len(rows) :], lo, hi, seed, sampler)
    origin.extend(["random"] * count)
    return Samples(q=q, origin=tuple(origin))
