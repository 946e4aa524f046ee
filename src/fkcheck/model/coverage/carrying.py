"""Which directions a compared frame's offset carries, and what it absorbs or takes of the table.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.model.coverage.sensitivity import _Number
from fkcheck.model.coverage.spectrum import _without
from fkcheck.model.coverage.tuning import _AXES, CARRY_EPS, FLAT, SPAN_RTOL
from fkcheck.model.types import FrameSpec, Offset

__all__: list[str] = []


def _carries(offset: Offset, xi: Float, length_m: float) -> bool:
    """:func:`_carries_matrix` of an offset."""
    return _carries_matrix(offset.matrix, xi, length_m)


def _carries_matrix(M: Float, xi: Float, length_m: float) -> bool:
    """Whether ``offset`` may hold a component along the twist ``xi`` (its own axes, m and rad).

    Moved back along ``xi`` by ``s``, the offset's turn is ``R·exp(−s·ω)`` and its
    shift ``t − s·R·v`` (first order). It carries none of ``xi`` only when ``s = 0``
    is where both are strictly nearest the identity: the slope of ``angle²``
    (``−2 φ·ω``, ``φ`` its rotation vector) and of ``|t − s·R·v|²`` (``−2 (R·v)·t``)
    are both zero — each on its own, so a turn and a shift cannot cancel — and the
    angle is not flat there (a half turn about an axis across ``ω`` stays a half
    turn whatever ``s``: a wrong θ1 hides in it). Anything else may be an error
    fitted into the offset, and counts as carried.
    """
    from scipy.spatial.transform import Rotation

    R, t = M[:3, :3], M[:3, 3]
    v, w = xi[:3], xi[3:]
    w_norm, v_norm = float(np.linalg.norm(w)), float(np.linalg.norm(v)) / length_m
    size = max(w_norm, v_norm)
    if size == 0.0:
        return False
    # A part below the differences' noise is no part: d1's shift has no turn.
    w_norm = w_norm if w_norm > SPAN_RTOL * size else 0.0
    v_norm = v_norm if v_norm > SPAN_RTOL * size else 0.0
    phi = Rotation.from_matrix(R).as_rotvec()
    if w_norm > 0.0 and abs(float(phi @ w)) / w_norm > CARRY_EPS:
        return True
    if v_norm > 0.0 and abs(float((R @ v) @ t)) / (v_norm * length_m**2) > CARRY_EPS:
        return True
    if w_norm == 0.0:
        return False
    h = 1e-3  # rad along ω: the angle's second difference, against the identity's 2h²
    unit = w / w_norm

    def angle(s: float) -> float:
        turned = R @ Rotation.from_rotvec(-s * unit).as_matrix()
        return float(np.linalg.norm(Rotation.from_matrix(turned).as_rotvec()))

    curvature = angle(h) ** 2 + angle(-h) ** 2 - 2.0 * angle(0.0) ** 2
    return curvature < FLAT * 2.0 * h * h


def _describe(xi: Float, spec: FrameSpec) -> str:
    """``translation along z of DH frame 0`` for a twist ``xi`` in the frame's own axes."""
    M = spec.offset.matrix
    R, t = M[:3, :3], M[:3, 3]
    w = R @ xi[3:]  # in the anchor's axes
    v = R @ xi[:3] + np.cross(t, w)  # the same twist seen from the anchor's origin
    anchor = {"world": "the world", "tcp": "the TCP"}.get(str(spec.dh), f"DH frame {spec.dh}")

    def axis(u: Float) -> str:
        size = float(np.linalg.norm(u))
        if size == 0.0:
            return "(no direction)"
        u = u / size
        k = int(np.argmax(np.abs(u)))
        if abs(abs(u[k]) - 1.0) < 1e-6:
            return _AXES[k]
        return "(" + ", ".join(f"{x:.3g}" for x in u) + ")"

    wn, vn = float(np.linalg.norm(w)), float(np.linalg.norm(v))
    if wn <= 1e-9 * vn:
        return f"translation along {axis(v)} of {anchor}"
    through = np.cross(w, v) / (wn * wn)  # the axis' point nearest the anchor's origin
    where = "" if np.linalg.norm(through) < 1e-9 else " (an axis off its origin)"
    kind = "screw" if abs(v @ w) > 1e-9 * wn * max(vn, 1.0) else "rotation"
    return f"{kind} about {axis(w)} of {anchor}{where}"


@dataclass
class _Absorption:
    """What the compared frames' offsets can absorb of the table, over generic configurations.

    Attributes:
        absorbed: Table number → the offset carrying it (``[frames.NAME]``) and how.
        carrying: Offset component → the table numbers it trades with.
        absorbing: Offset columns and their combination, one per absorbed number.
        exempt: Number → the sides that could absorb it but carry none of it.
        carriers: Side → its offset's columns (a side whose offset is vouched has none).
    """

    absorbed: dict[int, tuple[str, str]] = field(default_factory=dict)
    carrying: dict[int, list[str]] = field(default_factory=dict)
    absorbing: list[tuple[list[int], Float]] = field(default_factory=list)
    exempt: dict[int, set[str]] = field(default_factory=dict)
    carriers: dict[str, list[int]] = field(default_factory=dict)


def _absorption(
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    J: Float,
    moving: Float,
    norms: Float,
    tols: tuple[float, float],
    *,
    sides: tuple[str, ...] = ("from", "to"),
    vouches: bool = True,
) -> _Absorption:
    """Which table numbers each compared frame's offset absorbs (see :class:`_Absorption`).

    A vouched offset absorbs nothing, unless ``vouches`` is false (what it would
    absorb is what the check takes on its word).
    """
    tol_pos_m, tol_rot_rad = tols
    to_si = np.array([tol_pos_m] * 3 + [tol_rot_rad] * 3)
    found = _Absorption()
    for side in sides:
        spec = specs[side]
        cols = [i for i, n in enumerate(numbers) if n.kind == side]
        if not cols or (spec.source and vouches):
            continue
        found.carriers[side] = cols
        A = J[:, cols]
        for i, n in enumerate(numbers):
            if not n.table or not moving[i] or n.kind == "flip":
                continue
            coef = np.asarray(np.linalg.lstsq(A, J[:, i], rcond=None)[0], dtype=np.float64)
            if np.linalg.norm(J[:, i] - A @ coef) > SPAN_RTOL * norms[i]:
                continue
            if not _carries(spec.offset, coef * to_si, tol_pos_m / tol_rot_rad):
                found.exempt.setdefault(i, set()).add(side)
                continue
            found.absorbed.setdefault(i, (f"[frames.{spec.name}]", _describe(coef * to_si, spec)))
            found.absorbing.append((cols, coef))
            weight = np.abs(coef) * norms[cols]
            for k, c in enumerate(cols):
                if weight[k] > SPAN_RTOL * weight.max():
                    found.carrying.setdefault(c, []).append(n.name)
    return found


@dataclass
class _Word:
    """Table numbers verified only on the word of a vouched frame.

    Attributes:
        on_word: Number → the vouched frames (``[frames.NAME]``) it rests on.
        sources: Vouched frame → its ``source``.
    """

    on_word: dict[int, list[str]] = field(default_factory=dict)
    sources: dict[str, str] = field(default_factory=dict)


def _vouched_absorption(
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    J: Float,
    moving: Float,
    norms: Float,
    tols: tuple[float, float],
    honoured: _Absorption,
) -> _Word:
    """What a vouched compared frame's offset would absorb were it not vouched for."""
    word = _Word()
    for side in ("from", "to"):
        spec = specs[side]
        if not spec.source or (side == "to" and specs["from"].name == spec.name):
            continue
        group = f"[frames.{spec.name}]"
        would = _absorption(specs, numbers, J, moving, norms, tols, sides=(side,), vouches=False)
        for i in would.absorbed:  # (the numbers it would carry are among these)
            if i not in honoured.absorbed:
                word.on_word.setdefault(i, []).append(group)
                word.sources[group] = spec.source
    return word


def _take(
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    offsets: _Absorption,
    J_check: Float,
    carried: Sequence[Float],
    residual: Float,
) -> dict[int, list[str]]:
    """Table number → the offsets that could take it; ``residual`` loses what they take.

    Any offset the map could have fitted takes what it can of a table number over
    the check's configurations, unless the number is one it structurally takes
    whole but carries none of (d1 against a shift across the first axis).
    """
    takers: dict[int, list[str]] = {}
    for i, n in enumerate(numbers):
        if not n.table or n.kind == "flip":
            continue
        sides = [side for side in offsets.carriers if side not in offsets.exempt.get(i, set())]
        full = [J_check[:, c] for side in sides for c in offsets.carriers[side]]
        if full:
            residual[:, i] = _without(J_check[:, i : i + 1], [*carried, *full])[:, 0]
            takers[i] = [f"[frames.{specs[side].name}]" for side in sides]
    return takers
