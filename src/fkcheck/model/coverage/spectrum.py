"""The linear algebra: sensitivities, spans, weak directions and trades.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.model.coverage.clock import _NO_LIMIT, _Clock
from fkcheck.model.coverage.sensitivity import _Number, _Pose, _twists
from fkcheck.model.coverage.tuning import (
    BLAME_MARGIN,
    MOVING_EPS,
    RESOLUTION_LIMIT,
    SPAN_RTOL,
    TRADE_SHARE,
)
from fkcheck.model.types import FrameSpec, Model

__all__: list[str] = []


def _sensitivities(
    model: Model,
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    q: Float,
    tol: tuple[float, float],
    clock: _Clock = _NO_LIMIT,
) -> tuple[Float, Float, tuple[int, ...]]:
    """Columns in tolerances per unit ``(N·6, P)``, which numbers move the pose, joints spanned."""
    pose = _Pose(model, q, specs["from"], specs["to"])
    F_inv = invert(pose.pose())
    twists = np.stack([_twists(pose, F_inv, n, clock) for n in numbers], axis=2)  # (N, 6, P)
    moving = np.abs(twists).max(axis=(0, 1)) > MOVING_EPS
    joints = [_Number("", "", "rad", "joint", i) for i in range(model.dof)]
    spanned = tuple(
        i + 1
        for i, j in enumerate(joints)
        if np.abs(_twists(pose, F_inv, j, clock)).max() > MOVING_EPS
    )
    scale = np.array([1.0 / tol[0]] * 3 + [1.0 / tol[1]] * 3)
    J: Float = (twists * scale[None, :, None]).reshape(-1, len(numbers))
    return J, moving, spanned


def _worst(residual: Float, configurations: int) -> Float:
    """Per column, the worst configuration's ``max(|Δp| / tol_pos, angle / tol_rot)`` per unit."""
    per = residual.reshape(configurations, 6, -1)
    worst: Float = np.maximum(
        np.linalg.norm(per[:, :3], axis=1), np.linalg.norm(per[:, 3:], axis=1)
    ).max(axis=0)
    return worst


def _without(J: Float, directions: Sequence[Float]) -> Float:
    """``J`` with the span of ``directions`` projected out."""
    if not directions:
        return J
    basis, sv, _ = np.linalg.svd(np.stack(directions, axis=1), full_matrices=False)
    basis = basis[:, sv > SPAN_RTOL * sv.max()]
    out: Float = J - basis @ (basis.T @ J)
    return out


def _needs_full(J: Float) -> bool:
    """Whether ``svd(J)`` needs ``full_matrices`` for all of ``Vᵀ`` (fewer rows than columns).

    With at least as many rows, the reduced SVD has the whole ``Vᵀ`` already;
    the full one would also build ``U`` of rows × rows (6N × 6N: 3.6·10⁹ numbers
    at the 10⁴ configurations of a check), which nothing reads.
    """
    return bool(J.shape[0] < J.shape[1])


def _spectrum(J: Float) -> tuple[Float, Float]:
    """``J``'s singular values, one per column (zeros past its row count), and all of ``Vᵀ``.

    One SVD that :func:`_trades` and :func:`_unseen` both read (the same generic
    ``J``, each against its own threshold).
    """
    _, sv, vt = np.linalg.svd(J, full_matrices=_needs_full(J))
    sv = np.concatenate([sv, np.zeros(J.shape[1] - len(sv))]) if len(sv) < J.shape[1] else sv
    return sv, vt


def _weak(spectrum: tuple[Float, Float], configurations: int, limit: float) -> Float:
    """Orthonormal rows spanning the combinations a ``J`` shows under ``1/limit`` of (RMS).

    ``spectrum`` is that ``J``'s :func:`_spectrum`.
    """
    sv, vt = spectrum
    weak: Float = vt[sv < math.sqrt(configurations) / limit]
    return weak


def _unseen(
    generic: Float,
    checked: Float,
    candidates: Sequence[bool],
    generic_configurations: int,
    checked_configurations: int,
    clock: _Clock = _NO_LIMIT,
    generic_spectrum: tuple[Float, Float] | None = None,
) -> dict[int, tuple[int, ...]]:
    """Numbers in combinations the check's configurations hide but generic ones show.

    Both ``J`` in tolerances per tolerance of each number. A combination the
    check's configurations show less than a tenth of (:data:`RESOLUTION_LIMIT`,
    root mean square, and at the worst configuration) and that lies well outside
    what generic configurations show less than :data:`BLAME_MARGIN` tenths of
    (a margin, so a borderline near-trade is no fault of the check) is theirs:
    its numbers are ``{i: (the others in it, …)}``. ``generic_spectrum``: the
    :func:`_spectrum` of ``generic``'s candidate columns, when already computed.
    """
    idx = [i for i, c in enumerate(candidates) if c]
    if not idx:
        return {}
    spectrum = generic_spectrum if generic_spectrum is not None else _spectrum(generic[:, idx])
    loose = _weak(spectrum, generic_configurations, RESOLUTION_LIMIT / BLAME_MARGIN)
    clock.check()
    strict = _weak(_spectrum(checked[:, idx]), checked_configurations, RESOLUTION_LIMIT)
    clock.check()
    if not len(strict):
        return {}
    extra = strict - (strict @ loose.T) @ loose if len(loose) else strict
    _, sv, vt = np.linalg.svd(extra, full_matrices=False)
    clock.check()
    per = checked[:, idx].reshape(-1, 6, len(idx))
    supports = _supports(per, vt[sv > 0.5])  # at least half outside what generic ones blur
    # Each number with the others of every combination it is in: one product of
    # the supports, not a set per pair (a whole table is ~10⁶ pairs per combination).
    together = (supports.T.astype(np.int64) @ supports.astype(np.int64)) > 0
    return {
        idx[k]: tuple(idx[j] for j in np.flatnonzero(together[k]) if j != k)
        for k in np.flatnonzero(supports.any(axis=0))
    }


def _supports(per: Float, vecs: Float, limit: float = RESOLUTION_LIMIT) -> NDArray[np.bool_]:
    """Per combination the check cannot see, the numbers taking part in it, ``(V, K)``.

    ``per`` is ``J`` as ``(N, 6, K)``, ``vecs`` the combinations ``(V, K)``. A
    combination is kept when its worst configuration shows it under ``1/limit``
    of its length; its numbers are those with a share above :data:`TRADE_SHARE`
    of its largest. Rows of combinations not kept are empty.
    """
    if not len(vecs):
        return np.zeros((0, per.shape[2]), dtype=np.bool_)
    effect = np.einsum("nrk,vk->vnr", per, vecs)
    shows = np.maximum(
        np.linalg.norm(effect[:, :, :3], axis=2), np.linalg.norm(effect[:, :, 3:], axis=2)
    ).max(axis=1)
    kept = shows * limit < np.linalg.norm(vecs, axis=1)
    share = np.abs(vecs)
    out: NDArray[np.bool_] = (share > TRADE_SHARE * share.max(axis=1, keepdims=True)) & kept[
        :, None
    ]
    return out


def _trades(
    J: Float,
    candidates: Sequence[bool],
    configurations: int,
    limit: float = RESOLUTION_LIMIT,
    clock: _Clock = _NO_LIMIT,
    spectrum: tuple[Float, Float] | None = None,
) -> dict[int, tuple[int, ...]]:
    """Numbers whose columns depend on each other only: ``{i: (j, …)}``.

    ``J`` is in tolerances of the pose per tolerance of each number. A set of
    numbers trades when some combination of them, :data:`RESOLUTION_LIMIT`
    tolerances large, moves the pose by less than one tolerance over the
    configurations: found among the singular directions below ``√N /
    RESOLUTION_LIMIT`` (the columns' length is at most ``√N`` times the worst
    configuration's), kept when the worst configuration shows under a tenth.
    Exact dependencies (UR's parallel d2, d3, d4) and near ones (a calibrated
    arm's almost parallel axes) alike. The reduced row echelon basis of those
    combinations has the smallest supports, so independent groups stay apart.
    ``spectrum``: the :func:`_spectrum` of ``J``'s candidate columns, when already computed.
    """
    idx = [i for i, c in enumerate(candidates) if c]
    if len(idx) < 2:
        return {}
    weak = _weak(spectrum if spectrum is not None else _spectrum(J[:, idx]), configurations, limit)
    clock.check()
    parent = list(range(len(idx)))

    def root(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]  # path halving: the trees stay shallow
            k = parent[k]
        return k

    per = J[:, idx].reshape(-1, 6, len(idx))
    # The singular value bounds the columns' length; the check sees the worst
    # configuration: a combination counts only if that stays under a tenth.
    for support in _supports(per, _rref(weak, clock), limit):
        members = np.flatnonzero(support)
        for k in members[1:]:
            parent[root(int(k))] = root(int(members[0]))
    groups: dict[int, list[int]] = {}
    for k, i in enumerate(idx):
        groups.setdefault(root(k), []).append(i)
    return {
        m: tuple(x for x in members if x != m)
        for members in groups.values()
        if len(members) > 1
        for m in members
    }


def _rref(rows: Float, clock: _Clock = _NO_LIMIT) -> Float:
    """Reduced row echelon form of a few orthonormal rows (partial pivoting)."""
    M = np.array(rows, dtype=np.float64)
    r = 0
    for c in range(M.shape[1]):
        clock.check()
        if r == M.shape[0]:
            break
        p = r + int(np.argmax(np.abs(M[r:, c])))
        if abs(M[p, c]) < TRADE_SHARE:
            continue
        M[[r, p]] = M[[p, r]]
        M[r] /= M[r, c]
        factors = M[:, c].copy()
        factors[r] = 0.0
        M -= np.outer(factors, M[r])  # every other row at once: the same arithmetic
        r += 1
    return M[:r]
