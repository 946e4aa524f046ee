"""The configurations an IK check starts from: the check's samples plus the singular ones.

The check's own set (:func:`fkcheck.model.sampling.sample_configurations`:
named poses, zero, mid-range, limit corners and edges, seeded samples), and for
a 6R arm (:func:`fkcheck.ik.branches.classifiable`), from :data:`SEEDS_PER_KIND`
seeded configurations each:

* ``wrist-singular``: joint 5's DH angle ``θ5 = 0``; ``near-wrist`` at
  ``θ5 = ±1e-3`` and ``±1e-6`` rad (:data:`NEAR`);
* ``elbow-singular``: θ3 where the elbow is straight (the elbow quantity of
  :mod:`fkcheck.ik.branches` is zero); ``near-elbow`` beside it;
* ``shoulder-singular``: θ2 where the wrist point is in the plane of the base
  axis and joint 2's axis (on the base axis for an arm without a shoulder
  offset), when the arm reaches it; ``near-shoulder`` beside it.

Each is found from the branch quantities themselves (they are sinusoids of the
joint they depend on), so no arm's formula is assumed. A configuration outside
the limits is moved by whole turns into them, or left out.
"""

from __future__ import annotations

import math

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.ik.branches import branch_values, classifiable
from fkcheck.model.sampling import Samples, sample_configurations, sampling_box
from fkcheck.model.types import Model

__all__ = ["NEAR", "SEEDS_PER_KIND", "ik_configurations"]

#: Seeded configurations each singular kind is built from.
SEEDS_PER_KIND = 8
#: Distances from a singularity tried, radians: near enough to trip a solver's
#: threshold, far enough (σ_min ≥ about 1e-8) to be a regular pose with all its solutions.
NEAR = (1e-3, 1e-6)


def ik_configurations(model: Model, samples: int, seed: int) -> Samples:
    """The check's configurations, then the singular and near-singular ones.

    Args:
        model: The model.
        samples: Random samples (besides the structured ones).
        seed: Their seed; the singular ones are built from configurations of
            the same seed.
    """
    base = sample_configurations(model, samples, seed=seed)
    if not classifiable(model):
        return base
    lo, hi = sampling_box(model)
    rng = np.random.default_rng(seed)
    starts = lo + rng.random((SEEDS_PER_KIND, model.dof)) * (hi - lo)
    rows: list[Float] = []
    origin: list[str] = []
    sign = np.array([-1.0 if j.flip else 1.0 for j in model.joints])
    offset = np.array([j.theta for j in model.joints])

    def add(q: Float, kind: str) -> None:
        fitted = _into_limits(q, lo, hi)
        if fitted is not None:
            rows.append(fitted)
            origin.append(kind)

    for start in starts:
        for theta5, kind in _around(0.0, "wrist"):
            q = start.copy()
            q[4] = sign[4] * (theta5 - offset[4])
            add(q, kind)
        zero3 = _sinusoid_zero(model, start, joint=2, quantity=1)
        for theta3, kind in _around(zero3, "elbow"):
            q = start.copy()
            q[2] = theta3
            add(q, kind)
        zero2 = _sinusoid_zero(model, start, joint=1, quantity=0)
        for theta2, kind in _around(zero2, "shoulder"):
            q = start.copy()
            q[1] = theta2
            add(q, kind)
    if not rows:
        return base
    return Samples(q=np.concatenate([base.q, np.array(rows)]), origin=(*base.origin, *origin))


def _around(at: float | None, what: str) -> list[tuple[float, str]]:
    """``at`` (singular) and ``at ± NEAR`` (near-singular), labelled."""
    if at is None:
        return []
    out = [(at, f"{what}-singular")]
    out += [(at + s * d, f"near-{what}") for d in NEAR for s in (1.0, -1.0)]
    return out


def _sinusoid_zero(model: Model, q: Float, joint: int, quantity: int) -> float | None:
    """A value of joint ``joint`` (joint value) where branch quantity ``quantity`` is zero.

    The quantity is ``A cos x + B sin x + C`` in the joint's value ``x``: three
    evaluations give ``A, B, C``; ``None`` when ``|C| > hypot(A, B)`` (never zero).
    """
    trials = np.repeat(q[None, :], 3, axis=0)
    trials[:, joint] = (0.0, math.pi / 2, math.pi)
    f0, f1, f2 = branch_values(model, trials, raw=True)[:, quantity]
    c = (f0 + f2) / 2.0
    a = (f0 - f2) / 2.0
    b = f1 - c
    r = math.hypot(a, b)
    if r == 0.0 or abs(c) > r:
        return None
    return math.atan2(b, a) + math.acos(max(-1.0, min(1.0, -c / r)))


def _into_limits(q: Float, lo: Float, hi: Float) -> Float | None:
    """``q`` moved by whole turns into ``[lo, hi]`` where a joint needs it, or ``None``."""
    out = q.copy()
    for i in range(len(q)):
        if lo[i] <= out[i] <= hi[i]:
            continue
        moved = out[i] - 2.0 * math.pi * math.floor((out[i] - lo[i]) / (2.0 * math.pi))
        if not lo[i] <= moved <= hi[i]:
            return None
        out[i] = moved
    return out
