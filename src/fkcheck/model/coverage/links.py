"""Numbers a choice among the description's links could hide (:class:`Competitor`).

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.model.coverage.carrying import _carries_matrix
from fkcheck.model.coverage.clock import _NO_LIMIT, _Clock
from fkcheck.model.coverage.results import Competitor, Unit
from fkcheck.model.coverage.sensitivity import _Number, _Pose, _twists, _unit
from fkcheck.model.coverage.tuning import SPAN_RTOL, STEP
from fkcheck.model.types import FrameSpec, Model

__all__ = [
    "FEWEST",
    "MAX_COMPETITORS",
    "PRODUCE_ITERATIONS",
    "TURNS_RAD",
]


@dataclass
class _LinkChoice:
    """Numbers a choice among the description's links could hide (see :class:`Competitor`).

    Attributes:
        absorbed: Number → the compared frame (``[frames.NAME]``) and how.
        competing: Number → the competing links.
        on_word: Number → the vouched frames that settle the choice.
        sources: Vouched frame → its ``source``.
    """

    absorbed: dict[int, tuple[str, str]] = field(default_factory=dict)
    competing: dict[int, list[str]] = field(default_factory=dict)
    on_word: dict[int, list[str]] = field(default_factory=dict)
    sources: dict[str, str] = field(default_factory=dict)


#: At most this many places of competing links are solved for at one end (nearest
#: first); a description with more links fixed there has the end's numbers reported
#: not identifiable, unanalysed, rather than costing time out of proportion.
MAX_COMPETITORS = 128
#: Gauss–Newton iterations of the search for the numbers that put the DH frame on a
#: competing link; a turn about an axis the numbers produce converges in one or two.
PRODUCE_ITERATIONS = 12


def _link_choice(
    model: Model,
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    analysed: tuple[Float, Float, Float],
    tols: tuple[float, float],
    competitors: Mapping[str, Sequence[Competitor]],
    carried: set[int],
    clock: _Clock = _NO_LIMIT,
) -> _LinkChoice:
    """Which table numbers could put a competing link exactly on the compared frame's DH frame.

    At each end of the pair, the table numbers acting there (those whose effect a
    change of that frame's offset reproduces at every configuration: d1 and θ1 at
    DH frame 0, the last row's and ``[tool]``'s at the TCP) are solved for, so that
    a competing link would be the DH frame exactly. If they can (within the check's
    tolerances, at two configurations), the numbers that change are not
    identifiable — or, when a frame of the group is vouched for with an offset the
    description bears out, verified on its word.

    ``analysed`` is the generic configurations, the numbers' columns over them and
    which numbers move the pose; ``carried`` the numbers the compared frames'
    offsets already make not identifiable.
    """
    generic, J, moving = analysed
    found = _LinkChoice()
    if specs["from"].name == specs["to"].name:
        return found
    unit_tol = np.array([tols[0] if n.unit == "m" else tols[1] for n in numbers])
    pose = _Pose(model, generic, specs["from"], specs["to"])
    F_inv = invert(pose.pose())
    scale = np.array([1.0 / tols[0]] * 3 + [1.0 / tols[1]] * 3)
    for side in ("from", "to"):
        spec = specs[side]
        comps = competitors.get(spec.name, ())
        if not comps:
            continue
        end = _end_numbers(pose, F_inv, numbers, J, moving, side, scale)
        if not end:
            continue
        solved: dict[bytes, list[tuple[dict[int, float], bool]]] = {}  # each place once
        anchor = {"world": "the world", "tcp": "the TCP"}.get(str(spec.dh), f"DH frame {spec.dh}")
        places = {np.round(c.anchor_T_link, 9).tobytes() for c in comps}
        if len(places) > MAX_COMPETITORS:
            _too_many(found, spec, comps, end, len(places))
            continue
        for comp in comps:
            clock.check()
            key = np.round(comp.anchor_T_link, 9).tobytes()
            if key not in solved:
                exact = _fewest(pose, side, numbers, end, comp.anchor_T_link, tols, unit_tol)
                tidy = _turned(pose, side, numbers, end, comp.anchor_T_link, tols, carried)
                solved[key] = [(c, True) for c in exact] + [(c, False) for c in tidy]
            for changes, exactly in solved[key]:
                how = _how(numbers, changes, exactly, anchor)
                unsettled = set(changes) - carried  # what the choice alone could hide
                pins = _pins(model, spec, comps, tols, (pose, side, numbers, end), unsettled)
                _record(found, changes, pins, spec, comp, how)
    return found


def _too_many(
    found: _LinkChoice,
    spec: FrameSpec,
    comps: Sequence[Competitor],
    end: Iterable[int],
    places: int,
) -> None:
    """Record the end's numbers as hidden by a choice too wide to analyse (or vouched)."""
    group = f"[frames.{spec.name}]"
    why = (
        f"{places} places of links fixed beside {spec.urdf or spec.name} in the "
        f"description, more than the {MAX_COMPETITORS} fkcheck analyses: any of them "
        "could be the DH frame"
    )
    for i in end:
        if spec.source:  # the compared frame is vouched for: its word settles it
            found.on_word.setdefault(i, []).append(group)
            found.sources[group] = spec.source
        else:
            found.absorbed.setdefault(i, (group, why))
            found.competing.setdefault(i, [c.link for c in comps[:3]] + ["…"])


def _how(
    numbers: Sequence[_Number], changes: Mapping[int, float], exactly: bool, anchor: str
) -> str:
    """Where a competing link would be with the table's numbers so changed."""
    change = ", ".join(
        f"{numbers[i].name} changed by {_amount(d, numbers[i].unit)}" for i, d in changes.items()
    )
    if exactly:
        return f"would be {anchor} exactly with {change}"
    return f"would sit, with {change}, at an offset from {anchor} that carries none of it"


def _record(
    found: _LinkChoice,
    changes: Iterable[int],
    pins: Sequence[tuple[str, str]],
    spec: FrameSpec,
    comp: Competitor,
    how: str,
) -> None:
    """Record the changed numbers as settled by the vouched ``pins``, or as hidden by the choice."""
    group = f"[frames.{spec.name}]"
    for i in changes:
        if pins:
            for frame, source in pins:
                if frame not in found.on_word.setdefault(i, []):
                    found.on_word[i].append(frame)
                found.sources[frame] = source
            continue
        found.absorbed.setdefault(
            i,
            (
                group,
                f"link {comp.link} of the description {how}: choosing "
                f"{spec.urdf or spec.name} over it is a fit",
            ),
        )
        if comp.link not in found.competing.setdefault(i, []):
            found.competing[i].append(comp.link)


#: The turns of one angle of the table tried for a competing link that a turned table
#: would make as tidy as the compared one (a θn off by 180° moves a flange 0.2 m across
#: z to −0.2 m, and an offset across z carries nothing).
TURNS_RAD = (math.pi / 2, math.pi, -math.pi / 2)


def _turned(
    pose: _Pose,
    side: str,
    numbers: Sequence[_Number],
    end: Sequence[int],
    target: Float,
    tols: tuple[float, float],
    carried: set[int],
) -> list[dict[int, float]]:
    """Angles of the end whose turn leaves a competing link at an offset that carries none of it.

    The compared link's offset carries none of the angle (else it is not identifiable
    already); a competing link whose offset carries it now, but would carry none of it
    were the angle a quarter or half turn different, is as tidy a choice under that
    other table: poses through either cannot tell the two tables apart.
    """
    from scipy.spatial.transform import Rotation

    two = _first(pose, 1)
    P0 = two.changed(())
    length_m = tols[0] / tols[1]

    def placed(number: _Number, delta: float) -> Float:
        E = _anchor_change(two, side, P0, two.changed([(number, delta)]))[0]
        out: Float = invert(E) @ target
        return out

    def log(X: Float) -> Float:
        out: Float = np.concatenate([X[:3, 3], Rotation.from_matrix(X[:3, :3]).as_rotvec()])
        return out

    def carries(number: _Number, delta: float) -> bool:
        # The number's motion of the link, in the link's own axes at ``delta``: central
        # differences (a one-sided one leaves ~h·|ξ| across the shift, above CARRY_EPS).
        here = placed(number, delta)
        back = invert(here)
        ahead, behind = back @ placed(number, delta + STEP), back @ placed(number, delta - STEP)
        xi = (log(ahead) - log(behind)) / (2.0 * STEP)
        return _carries_matrix(here, xi, length_m)

    out = []
    for i in end:
        n = numbers[i]
        if i in carried or n.kind != "row" or n.unit != "rad" or not carries(n, 0.0):
            continue
        for delta in TURNS_RAD:
            if not carries(n, delta):
                out.append({i: delta})
                break
    return out


#: At most this many of an end's numbers (a ``[base]`` or ``[tool]`` counts as one) are
#: tried together for the fewest that put the DH frame on a competing link; beyond,
#: all of them at once (a least-norm change).
FEWEST = 3


def _fewest(
    pose: _Pose,
    side: str,
    numbers: Sequence[_Number],
    end: Sequence[int],
    target: Float,
    tols: tuple[float, float],
    unit_tol: Float,
) -> list[dict[int, float]]:
    """The smallest sets of ``end`` numbers whose change puts the DH frame on ``target``.

    Each solution maps a number to its change (only those beyond one tolerance).
    With several numbers able to do it, a least-norm change would spread over all
    of them; the fewest that do it alone are what could hide behind the choice.
    Empty when not even all of them together reach ``target``.
    """
    every = _produce(pose, side, [numbers[i] for i in end], target, tols)
    if every is None:
        return []
    groups: dict[str, list[int]] = {}
    for i in end:
        key = numbers[i].group if numbers[i].kind in ("base", "tool") else numbers[i].name
        groups.setdefault(key, []).append(i)
    units = list(groups.values())
    for size in range(1, min(FEWEST, len(units)) + 1):
        found = []
        for combo in itertools.combinations(units, size):
            chosen = [i for unit in combo for i in unit]
            delta = _produce(pose, side, [numbers[i] for i in chosen], target, tols)
            if delta is None:
                continue
            changes = {i: float(d) for i, d in zip(chosen, delta, strict=True)
                       if abs(d) > unit_tol[i]}  # fmt: skip
            if changes:
                found.append(changes)
        if found:
            return found
    changes = {i: float(d) for i, d in zip(end, every, strict=True) if abs(d) > unit_tol[i]}
    return [changes] if changes else []


def _end_numbers(
    pose: _Pose,
    F_inv: Float,
    numbers: Sequence[_Number],
    J: Float,
    moving: Float,
    side: str,
    scale: Float,
) -> list[int]:
    """Table numbers whose effect a change of ``side``'s offset reproduces at every configuration.

    ``J`` holds the numbers' columns over ``pose``'s configurations (in tolerances).
    """
    comps = [_Number("", "", _unit(c), side, c) for c in range(6)]  # type: ignore[arg-type]
    A = np.stack([_twists(pose, F_inv, c) for c in comps], axis=2)
    A = (A * scale[None, :, None]).reshape(-1, 6)
    idx = [i for i, n in enumerate(numbers) if n.table and n.kind != "flip" and moving[i]]
    if not idx:
        return []
    cols = J[:, idx]
    left = cols - A @ np.linalg.lstsq(A, cols, rcond=None)[0]
    inside = np.linalg.norm(left, axis=0) <= SPAN_RTOL * np.linalg.norm(cols, axis=0)
    return [i for i, ok in zip(idx, inside, strict=True) if ok]


def _first(pose: _Pose, k: int) -> _Pose:
    """``pose`` on its first ``k`` configurations, for :meth:`_Pose.changed` alone.

    The search for a competing link's change evaluates finite changes of several
    numbers at a time, the whole chain each time: a few configurations, not all of
    them, and none of :class:`_Pose`'s incremental state.
    """
    few = _Pose.__new__(_Pose)
    few.chain, few.q, few.spec = pose.chain, pose.q[:k], pose.spec
    return few


def _anchor_change(pose: _Pose, side: str, P0: Float, P: Float) -> Float:
    """How a change of the table moves ``side``'s DH frame (right-multiplied), ``(N, 4, 4)``."""
    M = pose.spec[side].offset.matrix
    if side == "from":  # P = M⁻¹·E⁻¹·M·P0
        return invert(M @ P @ invert(P0) @ invert(M))
    return M @ invert(P0) @ P @ invert(M)  # P = P0·M⁻¹·E·M


def _produce(
    pose: _Pose,
    side: str,
    end: Sequence[_Number],
    target: Float,
    tols: tuple[float, float],
) -> Float | None:
    """The change of the ``end`` numbers that moves ``side``'s DH frame onto ``target``.

    Gauss–Newton on the group over two configurations: each step linearises the
    frame's motion about where it is (smooth even half a turn away, where the
    rotation vector of the rest flips sign). ``None`` when no change reaches
    ``target`` within the check's tolerances.
    """
    from scipy.spatial.transform import Rotation

    two = _first(pose, 2)
    P0 = two.changed(())
    scale = np.array([1.0 / tols[0]] * 3 + [1.0 / tols[1]] * 3)

    def frame(delta: Float) -> Float:
        P = two.changed(list(zip(end, (float(d) for d in delta), strict=True)))
        return _anchor_change(two, side, P0, P)

    def log(X: Float) -> Float:
        rot = Rotation.from_matrix(X[:, :3, :3]).as_rotvec()
        out: Float = (np.concatenate([X[:, :3, 3], rot], axis=1) * scale).reshape(-1)
        return out

    delta = np.zeros(len(end))
    here = frame(delta)
    rest = log(invert(here) @ target)
    for _ in range(PRODUCE_ITERATIONS):
        if np.abs(rest).max() <= 1e-3:
            break
        inv_here = invert(here)
        Jl = np.stack([log(inv_here @ frame(delta + STEP * e)) / STEP for e in np.eye(len(end))], 1)
        step = delta + np.linalg.lstsq(Jl, rest, rcond=None)[0]
        there = frame(step)
        rest_there = log(invert(there) @ target)
        if not np.linalg.norm(rest_there) < 0.5 * np.linalg.norm(rest):  # no way there: stop
            break
        delta, here, rest = step, there, rest_there
    if not np.all(np.isfinite(rest)) or np.abs(rest).max() > 1.0:
        return None
    return delta


def _pins(
    model: Model,
    spec: FrameSpec,
    comps: Sequence[Competitor],
    tols: tuple[float, float],
    where: tuple[_Pose, str, Sequence[_Number], Sequence[int]],
    hidden: set[int],
) -> list[tuple[str, str]]:
    """The vouched frames that settle which link is the DH frame: ``[(group, source)]``.

    The compared frame itself when vouched for; else any frame of the model at the
    same DH frame, on a competing link, vouched for with an offset the description
    bears out — where the compared frame's offset and the description put it, up to
    what numbers other than the ``hidden`` ones produce (a d1 fitted into the
    compared frame's offset, already not identifiable through it, leaves a vouch
    for a half turn standing; a vouch off by the half turn itself settles nothing).
    """
    if spec.source:
        return [(f"[frames.{spec.name}]", spec.source)]
    pose, side, numbers, end = where
    placed = {c.link: c.anchor_T_link for c in comps}
    others = [numbers[i] for i in end if i not in hidden]
    out = []
    for other in model.frames.values():
        if not other.source or other.dh != spec.dh or other.urdf not in placed:
            continue
        declared, described = other.offset.matrix, placed[other.urdf]
        agrees = (
            float(position_error_m(declared, described)) <= tols[0]
            and float(rotation_error_rad(declared, described)) <= tols[1]
        )
        if not agrees and others:  # off only by what other numbers produce?
            agrees = _produce(pose, side, others, described @ invert(declared), tols) is not None
        if agrees:
            out.append((f"[frames.{other.name}]", other.source))
    return out


def _amount(value: float, unit: Unit) -> str:
    """``-180°`` or ``+10 mm``: a change as a person reads it."""
    if unit == "rad":
        return f"{math.degrees(value):+.6g}°"
    return f"{value * 1000.0:+.6g} mm"
