"""Each number's status and evidence from what the analysis found.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

from fkcheck.core.typing import Float
from fkcheck.model.coverage.carrying import _Absorption
from fkcheck.model.coverage.links import _LinkChoice
from fkcheck.model.coverage.results import NumberEvidence, Reason, Status
from fkcheck.model.coverage.sensitivity import _Number
from fkcheck.model.coverage.tuning import RESOLUTION_LIMIT
from fkcheck.model.types import FrameSpec

__all__: list[str] = []


@dataclass(frozen=True)
class _Findings:
    """What the analysis of one frame pair found, for deciding each number's status.

    Attributes:
        specs: The compared frames, ``"from"`` and ``"to"``.
        numbers: The model's numbers, in column order.
        moving: Per number, whether the compared pose depends on it.
        spanned: The joints (1-based) that move the compared pose.
        offsets: What the compared frames' offsets absorb.
        links: What a choice among the description's links could hide.
        tied: Number → the numbers the check's configurations cannot tell it from.
        limited: Number → the numbers the joint limits keep it from being told
            from, and the joints whose limits do (free joints would tell them apart).
        takers: Number → the offsets that could take it over the check's configurations.
        alone: Per number, its worst effect with the carried directions only removed.
        worst: Per number, its worst effect once every offset took what it can.
        flips: Per joint, the worst error of the joint turned the other way, in tolerances.
        flips_within: The same over generic configurations within limits.
        unit_tol: Per number, the tolerance of its unit.
        configurations: How many of the check's configurations were analysed.
        box: The joints' sampling box (lower, upper), radians / metres.
        revolute: Per joint, whether it is revolute.
    """

    specs: dict[str, FrameSpec]
    numbers: Sequence[_Number]
    moving: Float
    spanned: tuple[int, ...]
    offsets: _Absorption
    links: _LinkChoice
    tied: dict[int, tuple[int, ...]]
    limited: dict[int, tuple[tuple[int, ...], tuple[int, ...]]]
    takers: dict[int, list[str]]
    alone: Float
    worst: Float
    flips: Float
    flips_within: Float
    unit_tol: Float
    configurations: int
    box: tuple[Float, Float]
    revolute: tuple[bool, ...]


def _number_evidence(i: int, n: _Number, f: _Findings) -> NumberEvidence:
    """Number ``i``'s status, and why (its ``trades_with`` left empty)."""
    absorbed, carrying = f.offsets.absorbed, f.offsets.carrying
    if n.kind in ("from", "to") and f.specs[n.kind].source:
        return _evidence(n, "vouched", source=f.specs[n.kind].source)
    if n.kind == "flip":
        return _flip_evidence(n, f)
    if not f.moving[i]:
        return _evidence(n, "not-covered")
    if i in absorbed:
        return _evidence(
            n,
            "not-identifiable",
            why=f"{absorbed[i][0]}: {absorbed[i][1]}",
            reason="offset",
            by=(absorbed[i][0],),
        )
    if i in f.links.absorbed:
        frame, why = f.links.absorbed[i]
        return replace(
            _evidence(n, "not-identifiable", why=f"{frame}: {why}", reason="link", by=(frame,)),
            competing=tuple(f.links.competing.get(i, ())),
        )
    if i in carrying:
        return _evidence(
            n,
            "not-identifiable",
            why=f"{n.group}: carries what {', '.join(carrying[i])} produce",
            reason="offset",
            by=(n.group,),
        )
    if i in f.limited:
        return _limited_evidence(i, n, f)
    if i in f.tied:
        others = ", ".join(f.numbers[j].name for j in f.tied[i]) or "the others"
        return _evidence(
            n,
            "not-identifiable",
            why=(
                f"the check's {f.configurations} configurations cannot tell it from {others} "
                "(more configurations would)"
            ),
            reason="configurations",
        )
    return _resolved_evidence(i, n, f)


def _limited_evidence(i: int, n: _Number, f: _Findings) -> NumberEvidence:
    """A number the joint limits keep from others (a joint frozen at ``[0, 0]``)."""
    tied, joints = f.limited[i]
    others = ", ".join(f.numbers[j].name for j in tied) or "the others"
    lo, hi = f.box
    held = ", ".join(
        f"joint {j + 1} ([{math.degrees(lo[j]):.3g}°, {math.degrees(hi[j]):.3g}°])"
        if f.revolute[j]
        else f"joint {j + 1} ([{lo[j]:.3g}, {hi[j]:.3g}] m)"
        for j in joints
    )
    whose = f"the limits of {held}" if held else "the joint limits"
    return _evidence(
        n,
        "not-identifiable",
        why=(
            f"{whose} keep any configuration from telling it from {others} "
            "(free joints would: are the limits right?)"
        ),
        reason="limits",
    )


def _flip_evidence(n: _Number, f: _Findings) -> NumberEvidence:
    """A joint's direction: not covered, told apart by the check's configurations or not."""
    if n.index + 1 not in f.spanned:
        return _evidence(n, "not-covered")
    if f.flips_within[n.index] <= 1.0:  # no configuration within limits tells it
        lo, hi = f.box
        span = (
            f"[{math.degrees(lo[n.index]):.3g}°, {math.degrees(hi[n.index]):.3g}°]"
            if f.revolute[n.index]
            else f"[{lo[n.index]:.3g}, {hi[n.index]:.3g}] m"
        )
        return _evidence(
            n,
            "not-identifiable",
            why=(
                f"joint {n.index + 1} turned the other way would pass: its limits {span} keep "
                "any configuration from telling its direction (are the limits right?)"
            ),
            reason="limits",
        )
    if f.flips[n.index] <= 1.0:
        return _evidence(
            n,
            "not-identifiable",
            why=(
                f"joint {n.index + 1} turned the other way would pass: the check's "
                f"{f.configurations} configurations cannot tell its direction"
            ),
            reason="direction",
        )
    return _evidence(n, "verified")


def _resolved_evidence(i: int, n: _Number, f: _Findings) -> NumberEvidence:
    """A number the check sees: verified to its resolution, or too faint (or taken) if beyond."""
    unit_tol, worst = f.unit_tol, f.worst
    resolution = 1.0 / float(worst[i]) if worst[i] > 0 else None
    if resolution is not None and resolution <= RESOLUTION_LIMIT * unit_tol[i]:
        return _evidence(n, "verified", resolution=resolution)
    why = (
        f"an error up to {resolution:.3g} {n.unit} would stay within tolerance"
        if resolution is not None
        else "no error of it would show"
    )
    if i in f.takers and f.alone[i] * RESOLUTION_LIMIT * unit_tol[i] > 1.0:
        why = (  # it shows alone: an offset fitted over these configurations takes it
            f"over the check's {f.configurations} configurations the offset of "
            f"{', '.join(f.takers[i])} could take it ({why})"
        )
        return _evidence(n, "not-identifiable", why=why, reason="taken", by=tuple(f.takers[i]))
    return _evidence(n, "not-identifiable", why=why, reason="faint")


def _evidence(
    n: _Number,
    status: Status,
    *,
    resolution: float | None = None,
    why: str = "",
    source: str = "",
    reason: Reason = "",
    by: tuple[str, ...] = (),
) -> NumberEvidence:
    """Number ``n``'s evidence (its ``trades_with`` left empty)."""
    return NumberEvidence(
        n.name, n.group, n.unit, status, n.table, resolution, why, (), source, reason, by
    )
