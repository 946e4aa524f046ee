"""The analysis of one frame pair: :func:`coverage`.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.model.coverage.carrying import _absorption, _take, _vouched_absorption, _Word
from fkcheck.model.coverage.clock import _Clock
from fkcheck.model.coverage.evidence import _Findings, _number_evidence
from fkcheck.model.coverage.held import _held_still, _limited
from fkcheck.model.coverage.links import _link_choice, _LinkChoice
from fkcheck.model.coverage.results import Competitor, Coverage, NumberEvidence, _unique
from fkcheck.model.coverage.sensitivity import (
    _configurations,
    _flip_errors,
    _Number,
    _numbers,
    _subset,
)
from fkcheck.model.coverage.spectrum import (
    _sensitivities,
    _spectrum,
    _trades,
    _unseen,
    _without,
    _worst,
)
from fkcheck.model.coverage.tuning import CHECK_SAMPLES, SAMPLES
from fkcheck.model.sampling import sampling_box
from fkcheck.model.types import FrameSpec, Model, resolve_frame

__all__ = [
    "coverage",
]


def coverage(
    model: Model,
    frame_from: str,
    frame_to: str,
    tol_pos_m: float,
    tol_rot_rad: float,
    *,
    samples: int = SAMPLES,
    seed: int = 0,
    q: Float | None = None,
    competitors: Mapping[str, Sequence[Competitor]] | None = None,
    time_limit_s: float | None = None,
) -> Coverage:
    """Every number of ``model`` against a check of ``frame_from → frame_to``.

    A check verifies only what its own configurations exercise: pass them as
    ``q`` (a seeded subset of :data:`CHECK_SAMPLES` of them when there are more;
    a few measured poses identify less than a thousand samples, and the
    analysis then says so). Without ``q``, ``samples`` seeded configurations
    within limits.

    Args:
        model: The model (its frames include any placed ``urdf:LINK``).
        frame_from: The frame the compared pose is expressed in.
        frame_to: The frame whose pose is compared.
        tol_pos_m: The check's position tolerance, metres.
        tol_rot_rad: The check's rotation tolerance, radians.
        samples: Configurations the sensitivities are taken at (at most).
        seed: Their seed (or of the subset of ``q``).
        q: The check's configurations ``(N, n)``, radians / metres.
        competitors: By compared frame name, the other links of the description
            rigidly attached to its link (:class:`Competitor`): where one sits
            exactly where a change of the table's numbers at that end would put
            the DH frame, those numbers are not identifiable (reason ``link``),
            unless a frame of the group is vouched for (then verified on its word).
        time_limit_s: The analysis' time limit, seconds (a check's ``--timeout``);
            ``None``: none.

    Raises:
        FrameError: An unknown frame.
        TimeLimitError: The analysis did not finish within ``time_limit_s``.
    """
    specs = {"from": resolve_frame(model, frame_from), "to": resolve_frame(model, frame_to)}
    numbers = _numbers(model, (specs["from"], specs["to"]))
    tols = (tol_pos_m, tol_rot_rad)
    clock = _Clock(time_limit_s, f"{model.name} ({frame_from} → {frame_to})")
    # What the pair can tell, over generic configurations (the kinematics) …
    generic = _configurations(model, samples, seed)
    J, moving, spanned = _sensitivities(model, specs, numbers, generic, tols, clock)
    norms = np.linalg.norm(J, axis=0)
    offsets = _absorption(specs, numbers, J, moving, norms, tols)
    word = _vouched_absorption(specs, numbers, J, moving, norms, tols, offsets)
    links = _link_choice(
        model, specs, numbers, (generic, J, moving), tols, competitors or {},
        set(offsets.absorbed), clock,
    )  # fmt: skip
    _merge_word(word, links)
    # A number a choice among links could hide is a discrete ambiguity: its continuous
    # direction is still seen, and still trades (or is held by the limits) with others.
    absorbed = offsets.absorbed
    unit_tol = np.array([tol_pos_m if n.unit == "m" else tol_rot_rad for n in numbers])
    candidates = _candidates(numbers, moving, absorbed)
    rows = generic.shape[0]
    generic_residual = _without(J, [J[:, c] @ k for c, k in offsets.absorbing]) * unit_tol
    # One SVD of the candidates' generic columns: for the trades, and for what the
    # check's configurations hide that generic ones show.
    chosen = [i for i, c in enumerate(candidates) if c]
    spectrum = _spectrum(generic_residual[:, chosen]) if chosen else None
    trades = _trades(generic_residual, candidates, rows, clock=clock, spectrum=spectrum)
    # … and what the check's own configurations exercise: its resolution, its trades.
    checked, J_check = _checked(model, specs, numbers, q, seed, tols, clock, (generic, J))
    carried = [J_check[:, c] @ k for c, k in offsets.absorbing]
    residual = _without(J_check, carried)
    # Combinations the check's configurations hide that generic ones show at least
    # 1:1: its configurations, not the kinematics, leave those numbers apart.
    tied = (
        _unseen(
            generic_residual,
            residual * unit_tol,
            candidates,
            rows,
            checked.shape[0],
            clock,
            generic_spectrum=spectrum,
        )
        if q is not None
        else {}
    )
    # Combinations the joint limits hide that free joints show: the limits', not the table's.
    frozen = _held_still(model, specs, generic, spanned, tols)
    limited = _limited(
        model,
        specs,
        numbers,
        offsets.absorbing,
        generic_residual,
        candidates,
        frozen,
        rows,
        seed,
        tols,
    )
    alone = _worst(residual, checked.shape[0])  # with the carried directions only
    takers = _take(specs, numbers, offsets, J_check, carried, residual)
    findings = _Findings(
        specs=specs,
        numbers=numbers,
        moving=moving,
        spanned=spanned,
        offsets=offsets,
        links=links,
        tied=tied,
        limited=limited,
        takers=takers,
        alone=alone,
        worst=_worst(residual, checked.shape[0]),
        flips=_flip_errors(model, specs, checked, tols, clock),
        flips_within=_flip_errors(model, specs, generic, tols, clock),
        unit_tol=unit_tol,
        configurations=checked.shape[0],
        box=sampling_box(model),
        revolute=tuple(j.type != "prismatic" for j in model.joints),
    )
    out = _evidence_list(numbers, findings, trades, word)
    vouches = _vouches(out, word)
    return Coverage(
        specs["from"].name, specs["to"].name, tuple(out), spanned, tol_pos_m, tol_rot_rad,
        vouches,
    )  # fmt: skip


def _merge_word(word: _Word, links: _LinkChoice) -> None:
    """Add to ``word`` the vouched frames that settle a choice among links."""
    for i, frames in links.on_word.items():
        word.on_word.setdefault(i, []).extend(f for f in frames if f not in word.on_word[i])
    word.sources.update(links.sources)


def _candidates(
    numbers: Sequence[_Number], moving: Float, absorbed: Mapping[int, object]
) -> list[bool]:
    """Which numbers the spectrum judges: moving table numbers, no flip, no offset absorbs."""
    return [
        bool(moving[i] and n.table and n.kind != "flip" and i not in absorbed)
        for i, n in enumerate(numbers)
    ]


def _checked(
    model: Model,
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    q: Float | None,
    seed: int,
    tols: tuple[float, float],
    clock: _Clock,
    generic: tuple[Float, Float],
) -> tuple[Float, Float]:
    """The configurations the check exercises and the numbers' columns over them.

    A seeded subset of :data:`CHECK_SAMPLES` of ``q``; without ``q``, ``generic``
    (the generic configurations and their columns) as it is.
    """
    if q is None:
        return generic
    checked = _subset(q, CHECK_SAMPLES, seed)
    return checked, _sensitivities(model, specs, numbers, checked, tols, clock)[0]


def _evidence_list(
    numbers: Sequence[_Number],
    findings: _Findings,
    trades: Mapping[int, Sequence[int]],
    word: _Word,
) -> list[NumberEvidence]:
    """Each number's evidence, with what it trades with and the vouched frames it rests on."""
    out = [
        replace(
            _number_evidence(i, n, findings),
            trades_with=tuple(numbers[j].name for j in trades.get(i, ())),
        )
        for i, n in enumerate(numbers)
    ]
    return [
        replace(e, on_word_of=tuple(word.on_word[i]))
        if e.status == "verified" and word.on_word.get(i)
        else e
        for i, e in enumerate(out)
    ]


def _vouches(out: Sequence[NumberEvidence], word: _Word) -> tuple[tuple[str, str], ...]:
    """The vouched frames verified numbers rest on, each with its ``source``."""
    resting = _unique(f for e in out if e.status == "verified" for f in e.on_word_of)
    return tuple((f, word.sources[f]) for f in resting)
