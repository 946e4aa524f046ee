"""Joints the check holds still or its limits confine, and what that hides.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.model.coverage.sensitivity import _configurations, _Number, _Pose, _twists
from fkcheck.model.coverage.spectrum import _rref, _sensitivities, _spectrum, _weak, _without
from fkcheck.model.coverage.tuning import BLAME_MARGIN, RESOLUTION_LIMIT, TRADE_SHARE
from fkcheck.model.sampling import sampling_box
from fkcheck.model.types import FrameSpec, Model

__all__: list[str] = []


def _held_still(
    model: Model,
    specs: dict[str, FrameSpec],
    q: Float,
    spanned: Sequence[int],
    tols: tuple[float, float],
) -> list[int]:
    """Joints (0-based) whose whole range moves the pose by at most ``RESOLUTION_LIMIT`` tolerances.

    Over configurations ``q`` within limits: the joint's twist per unit, at its
    worst, times its range (``[0, 0]``, ``[v, v]``, ±1e-7°: held still).
    """
    lo, hi = sampling_box(model)
    pose = _Pose(model, q, specs["from"], specs["to"])
    F_inv = invert(pose.pose())
    out = []
    for j in range(model.dof):
        if j + 1 not in spanned:
            continue
        twist = _twists(pose, F_inv, _Number("", "", "rad", "joint", j))
        per_unit = max(
            float(np.linalg.norm(twist[:, :3], axis=1).max()) / tols[0],
            float(np.linalg.norm(twist[:, 3:], axis=1).max()) / tols[1],
        )
        if per_unit * float(hi[j] - lo[j]) <= RESOLUTION_LIMIT:
            out.append(j)
    return out


def _limited(
    model: Model,
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    removed: Sequence[tuple[list[int], Float]],
    within: Float,
    candidates: Sequence[bool],
    frozen: Sequence[int],
    samples: int,
    seed: int,
    tols: tuple[float, float],
) -> dict[int, tuple[tuple[int, ...], tuple[int, ...]]]:
    """Numbers the joint limits tie: ``{i: (the numbers, the joints whose limits do)}``.

    ``within`` is the residual over configurations within limits, in tolerances
    per tolerance of each number; ``frozen`` the joints whose whole range moves
    the pose by at most :data:`RESOLUTION_LIMIT` tolerances (``[0, 0]``,
    ±1e-7°). The same numbers with those joints free (a whole turn each, a slide
    :data:`~fkcheck.model.coverage.tuning.FREED_PRISMATIC_M` either side, or its
    held displacement when farther out) show
    what the kinematics could tell: a combination only their limits hide is the
    limits'. A joint is named when freeing it alone shows that number's combination.
    """
    if not frozen:  # every joint moves the pose within its limits: they hide nothing
        return {}
    unit_tol = np.array([tols[0] if n.unit == "m" else tols[1] for n in numbers])

    def residual(free: Sequence[int] | None) -> Float:
        J = _sensitivities(
            model, specs, numbers, _configurations(model, samples, seed, free), tols
        )[0]
        out: Float = _without(J, [J[:, c] @ k for c, k in removed]) * unit_tol
        return out

    ties = _hidden(residual(frozen), within, candidates, samples)
    if not ties:
        return {}
    held: dict[int, list[int]] = {}
    for j in frozen:
        shown = _hidden(residual([j]), within, candidates, samples)
        for i in ties:
            if i in shown:  # freeing this joint alone tells the number apart
                held.setdefault(i, []).append(j)
    return {i: (others, tuple(held.get(i, ()))) for i, others in ties.items()}


def _hidden(
    free: Float, within: Float, candidates: Sequence[bool], configurations: int
) -> dict[int, tuple[int, ...]]:
    """Numbers in combinations ``within`` hides and ``free`` shows: ``{i: (the others, …)}``.

    Among the combinations ``within`` shows under a tenth of (root mean square),
    those free joints do not leave a trade: ``free`` shows them at least a tenth
    (:data:`RESOLUTION_LIMIT`) root mean square, or at the worst configuration —
    the complement of :func:`_trades`' test, with no margin: a combination an
    error of :data:`RESOLUTION_LIMIT` tolerances of would show with the joints
    free describes other kinematics, which only the limits keep from failing the
    check. They are read in sparsest (reduced row echelon) bases: of those shown
    at :data:`BLAME_MARGIN` tenths and of those at one tenth (root mean square),
    and of the rest, those shown at a tenth at the worst configuration — each
    basis on its own, since the sparsest basis of a larger set can mix every
    combination the limits hide with one they do not. Each combination is kept
    when the worst configuration within limits shows it under a tenth too.
    """
    idx = [i for i, c in enumerate(candidates) if c]
    if len(idx) < 2:
        return {}
    strict = _weak(_spectrum(within[:, idx]), configurations, RESOLUTION_LIMIT)
    if not len(strict):
        return {}
    _, sv, vt = np.linalg.svd(free[:, idx] @ strict.T, full_matrices=False)
    bar = math.sqrt(configurations) / RESOLUTION_LIMIT  # a tenth, root mean square
    bases = [_rref(vt[sv >= level * bar] @ strict) for level in (BLAME_MARGIN, 1.0)]
    rest = _rref(vt[sv < bar] @ strict)
    if len(rest):  # shown at the worst configuration with the joints free
        effect = np.einsum("nrk,vk->vnr", free[:, idx].reshape(-1, 6, len(idx)), rest)
        worst = np.maximum(
            np.linalg.norm(effect[:, :, :3], axis=2), np.linalg.norm(effect[:, :, 3:], axis=2)
        ).max(axis=1)
        bases.append(rest[worst * RESOLUTION_LIMIT >= np.linalg.norm(rest, axis=1)])
    shown = np.vstack(bases)
    per = within[:, idx].reshape(-1, 6, len(idx))
    out: dict[int, set[int]] = {}
    for vec in shown:
        size = float(np.linalg.norm(vec))
        effect = np.einsum("nrk,k->nr", per, vec)
        shows = np.maximum(
            np.linalg.norm(effect[:, :3], axis=1), np.linalg.norm(effect[:, 3:], axis=1)
        )
        if float(shows.max()) * RESOLUTION_LIMIT >= size:
            continue
        support = [idx[k] for k in np.flatnonzero(np.abs(vec) > TRADE_SHARE * np.abs(vec).max())]
        for m in support:
            out.setdefault(m, set()).update(x for x in support if x != m)
    return {m: tuple(sorted(others)) for m, others in out.items()}
