"""What a diagnosis found, as frozen dataclasses, and how it is printed and serialised.

The steps (:mod:`.offsets`, :mod:`.axes`, :mod:`.hypotheses`, :mod:`.paramfit`)
each produce :class:`Explanation` rows; :func:`rank` orders them (explanations
that make the disagreement vanish first, the fewest changed numbers first, then
the simplest kind of mistake); :func:`format_text` and :func:`to_dict` render a
:class:`Diagnosis`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal, get_args

from fkcheck.diagnose.identify import Unsettled
from fkcheck.diagnose.problem import Residual
from fkcheck.engine.axes import AxisRow
from fkcheck.io.format import format_delta, format_distinct, format_pair, format_seconds
from fkcheck.io.text import terminal_text
from fkcheck.model.types import Model

__all__ = [
    "KIND_ORDER",
    "AxisRow",
    "Change",
    "Diagnosis",
    "Explanation",
    "Kind",
    "format_text",
    "rank",
    "to_dict",
]

#: What kind of mistake an explanation names, most plausible first among
#: explanations that make the disagreement vanish and change as many numbers: the
#: difference the model file already records (``[[known_difference]]``), a
#: frame-naming difference (base_link vs base, flange vs tool0) or two URDF joints
#: swapped in the mapping before a whole-table mistake (units, convention, a vendor's
#: conventions against a URDF: joints reversed, zeros apart), before a
#: one-character typo (a sign, a flip, a missing θ offset), before a different number
#: (one parameter), before unexplained constant offsets, before a fit of everything.
Kind = Literal[
    "known",
    "frames",
    "mapping",
    "degrees",
    "convention",
    "conventions",
    "sign",
    "flip",
    "theta-offset",
    "parameter",
    "offset",
    "fit",
]

#: The kinds in :data:`Kind`'s order, the order :func:`rank` sorts them in.
KIND_ORDER: tuple[Kind, ...] = get_args(Kind)


@dataclass(frozen=True)
class Change:
    """One parameter of the table, as it is and as it would match.

    Attributes:
        field: The model-file field, ``joint[0].d`` or ``base.xyz[2]``.
        symbol: Its textbook name with the joint, ``d1 (shoulder_pan)``.
        old: The table's value (m or rad).
        new: The value that matches the reference (m or rad).
        angle: Whether it is an angle.
        note: Where the new (or old) value is known from, if anywhere.
    """

    field: str
    symbol: str
    old: float
    new: float
    angle: bool
    note: str = ""

    @property
    def delta(self) -> float:
        """``new - old``."""
        return self.new - self.old

    @property
    def sign_flip(self) -> bool:
        """Whether the value that matches is this one with the other sign (``α4 = -90°`` → 90°)."""
        return self.old != 0 and math.isclose(self.new, -self.old, rel_tol=1e-9, abs_tol=0.0)

    def text(self) -> str:
        """``d1 = 0.089459 here, 0.089159 would match, Δ = -0.300 mm``.

        An angle reads in degrees, then radians in parentheses (as every two-unit
        reading, :func:`~fkcheck.io.format.format_pair`). The two values get as
        many digits as tell them apart (:func:`~fkcheck.io.format.format_distinct`:
        ``-90.0002° (-1.5708 rad) here, -90° (-1.570796 rad) would match``), and
        a difference too small for its decimals reads in scientific notation. A sign flip says so,
        ``…, 90° (1.5708 rad) would match: the sign flipped``,
        not ``Δ = +180°``: a difference of 180° reads as a turn, which it is not.
        """
        if self.angle:
            old_deg, new_deg = format_distinct(math.degrees(self.old), math.degrees(self.new), 4)
            old_rad, new_rad = format_distinct(self.old, self.new, 6)
            old = format_pair(f"{old_deg}°", f"{old_rad} rad")
            new = format_pair(f"{new_deg}°", f"{new_rad} rad")
            head = f"{self.symbol} = {old} here, {new} would match"
            delta = f"Δ = {format_delta(math.degrees(self.delta), 4)}°"
        else:
            old, new = format_distinct(self.old, self.new, 6)
            head = f"{self.symbol} = {old} here, {new} would match"
            delta = f"Δ = {format_delta(self.delta * 1e3, 3)} mm"
        return f"{head}: the sign flipped" if self.sign_flip else f"{head}, {delta}"


@dataclass(frozen=True, eq=False)
class Explanation:
    """One candidate explanation and its evidence.

    Attributes:
        kind: What kind of mistake (see :data:`KIND_ORDER`).
        title: One line that says it.
        residual: The disagreement left once the table is changed this way.
        explains: Whether that is within tolerance.
        details: More lines of evidence or caveats.
        changes: The parameters it changes.
        fix_toml: Model-file text that applies it (``[frames…]`` tables), if any.
        edits: Edits of the ``[[joint]]`` tables that apply it, one line each
            (``[[joint]] J3: flip = true``), if any.
        model: The changed model (not serialised).
        numbers: How many numbers (or settings) of the model file it changes, when
            that is not one per change: ``angle_unit`` is one setting however many
            angles it rescales, a frame offset counts its changed components.
            ``None``: one per change, and at least one.
    """

    kind: Kind
    title: str
    residual: Residual
    explains: bool
    details: tuple[str, ...] = ()
    changes: tuple[Change, ...] = ()
    fix_toml: str = ""
    model: Model | None = field(default=None, repr=False)
    numbers: int | None = None
    edits: tuple[str, ...] = ()

    @property
    def changed(self) -> int:
        """How many numbers of the model file it changes (see ``numbers``)."""
        return self.numbers if self.numbers is not None else max(len(self.changes), 1)


@dataclass(frozen=True, eq=False)
class Diagnosis:
    """Everything a diagnosis found.

    Attributes:
        model: The model diagnosed.
        backend: The reference backend's name.
        frame_from: Frame the pose is expressed in.
        frame_to: Frame whose pose is compared.
        configurations: How many configurations were compared.
        before: The disagreement as given.
        tol_pos_m: Position tolerance (m).
        tol_rot_rad: Rotation tolerance (rad).
        explanations: Ranked, most likely first.
        axes: Joint axes compared (empty when the reference has no URDF).
        axes_note: What the axes say, in one line.
        tried: The hypotheses tried, one line each.
        duration_s: Wall time, seconds.
        unsettled: When the table agrees with a reference independent of it: the
            numbers the agreement says nothing about, each with what would settle
            it (:mod:`.identify`).
    """

    model: Model
    backend: str
    frame_from: str
    frame_to: str
    configurations: int
    before: Residual
    tol_pos_m: float
    tol_rot_rad: float
    explanations: tuple[Explanation, ...]
    axes: tuple[AxisRow, ...] = ()
    axes_note: str = ""
    tried: tuple[str, ...] = ()
    duration_s: float = 0.0
    unsettled: tuple[Unsettled, ...] = ()

    @property
    def agrees(self) -> bool:
        """The table already agrees with the reference: nothing to explain."""
        return self.before.within(self.tol_pos_m, self.tol_rot_rad)

    @property
    def explained(self) -> bool:
        """Some explanation makes the disagreement vanish."""
        return any(e.explains for e in self.explanations)

    @property
    def best(self) -> Explanation | None:
        """The most likely explanation, if one explains the disagreement."""
        first = self.explanations[0] if self.explanations else None
        return first if first is not None and first.explains else None


def rank(
    explanations: list[Explanation], before: Residual, same: tuple[float, float] = (0.0, 0.0)
) -> tuple[Explanation, ...]:
    """Explaining ones first, fewest changed numbers first; then partial ones by what is left.

    Every explanation that explains leaves, by definition, the same residual (within
    tolerance, or within the model's recorded known difference): among them the one
    that changes the fewest numbers comes first (one wrong number before a fit that
    moves 29), then the kind (:data:`KIND_ORDER`), then what is left. Partial ones
    are ordered by what they leave, relative to the disagreement; those whose
    residuals are equal within ``same`` (metres, radians: the diagnosis's
    tolerances, below which the check cannot tell two poses apart) by the fewest
    changed numbers too. A partial explanation is kept only if it removes at least
    half of the disagreement (position or rotation), so the list stays short.
    """

    def leftover(e: Explanation) -> float:
        pos = e.residual.position_m / before.position_m if before.position_m > 0 else 0.0
        rot = e.residual.rotation_rad / before.rotation_rad if before.rotation_rad > 0 else 0.0
        return max(pos, rot)

    full = [e for e in explanations if e.explains]
    full.sort(key=lambda e: (e.changed, KIND_ORDER.index(e.kind), e.residual.position_m))
    partial = [e for e in explanations if not e.explains and leftover(e) <= 0.5]
    partial.sort(key=leftover)
    ordered: list[Explanation] = []
    while partial:  # runs of residuals equal within `same`, each by the fewest numbers
        head = partial[0]
        run = [
            e
            for e in partial
            if abs(e.residual.position_m - head.residual.position_m) <= same[0]
            and abs(e.residual.rotation_rad - head.residual.rotation_rad) <= same[1]
        ]
        run.sort(key=lambda e: (e.changed, leftover(e)))
        ordered += run
        partial = [e for e in partial if all(e is not r for r in run)]
    return (*full, *ordered)


def _residual_dict(r: Residual) -> dict[str, float]:
    return {"position_m": r.position_m, "rotation_rad": r.rotation_rad}


def to_dict(d: Diagnosis) -> dict[str, Any]:
    """The diagnosis as JSON-ready data (a contract: keys are only ever added)."""
    return {
        "model": d.model.name,
        "reference": d.backend,
        "from": d.frame_from,
        "to": d.frame_to,
        "configurations": d.configurations,
        "tolerance": {"position_m": d.tol_pos_m, "rotation_rad": d.tol_rot_rad},
        "before": _residual_dict(d.before),
        "agrees": d.agrees,
        "explained": d.explained,
        "explanations": [
            {
                "kind": e.kind,
                "title": e.title,
                "explains": e.explains,
                "after": _residual_dict(e.residual),
                "details": list(e.details),
                "changes": [
                    {
                        "field": c.field,
                        "symbol": c.symbol,
                        "table": c.old,
                        "matches": c.new,
                        "delta": c.delta,
                        "unit": "rad" if c.angle else "m",
                        "note": c.note,
                    }
                    for c in e.changes
                ],
                "fix_toml": e.fix_toml,
                "edits": list(e.edits),
                "numbers_changed": e.changed,
            }
            for e in d.explanations
        ],
        "axes": [
            {
                "joint": a.joint + 1,
                "name": a.name,
                "angle_rad": a.angle_rad,
                "distance_m": a.distance_m,
                "agrees": a.agrees,
            }
            for a in d.axes
        ],
        "axes_note": d.axes_note,
        "tried": list(d.tried),
        "duration_s": d.duration_s,
        "not_identifiable": [
            {"name": u.name, "group": u.group, "why": u.why, "settle": u.settle}
            for u in d.unsettled
        ],
    }


def format_text(d: Diagnosis) -> str:
    """The terminal summary: the disagreement, explanations ranked, axes, what was tried.

    Names from input are shown on one line each (:func:`fkcheck.io.text.terminal_text`).
    """
    name, frame_from, frame_to = map(terminal_text, (d.model.name, d.frame_from, d.frame_to))
    lines = [
        f"fkcheck diagnose {name}: {frame_from} → {frame_to} against {terminal_text(d.backend)}, "
        f"{d.configurations} configurations",
        f"disagreement as given: {d.before.text()} (tolerance {d.tol_pos_m:g} m, "
        f"{d.tol_rot_rad:g} rad)",
    ]
    lines.extend(_verdict_lines(d))
    for k, e in enumerate(d.explanations, start=1):
        lines.extend(_explanation_lines(k, e, d.before))
    lines.extend(_axes_lines(d))
    if d.tried:
        lines.append("")
        lines.append("tried: " + "; ".join(d.tried))
    lines.append(f"took {format_seconds(d.duration_s)}")
    return "\n".join(lines) + "\n"


def _verdict_lines(d: Diagnosis) -> list[str]:
    """Whether the table agrees, and what an agreement leaves unidentified."""
    if d.agrees and d.unsettled:
        one = len(d.unsettled) == 1
        lines = [
            f"the table agrees with the reference, but {len(d.unsettled)} "
            f"{'number is' if one else 'numbers are'} not identifiable in this comparison: "
            f"the agreement says nothing about {'it' if one else 'them'}"
        ]
        settles: list[str] = []
        for u in d.unsettled:
            lines.append(
                f"   {terminal_text(u.name)} ({terminal_text(u.group)}): {terminal_text(u.why)}"
            )
            if u.settle not in settles:
                settles.append(u.settle)
        lines.extend(f"   to settle {'it' if one else 'them'}: {s}" for s in settles)
        return lines
    if d.agrees:
        return ["the table agrees with the reference: nothing to explain"]
    if not d.explanations:
        return ["no hypothesis explains the disagreement, or even half of it"]
    return []


def _explanation_lines(k: int, e: Explanation, before: Residual) -> list[str]:
    """The ``k``-th explanation: what it leaves, its changes, details and fix."""
    verdict = "explains it" if e.explains else "explains part of it"
    lines = [
        "",
        f"{k}. [{e.kind}] {e.title}",
        f"   {verdict}: {before.text()} → {e.residual.text()}",
    ]
    lines.extend(f"   {c.text()}" + (f" ({c.note})" if c.note else "") for c in e.changes)
    lines.extend(f"   {line}" for line in e.details)
    if e.edits:
        lines.append("   edit, in the model file:")
        lines.extend(f"     {line}" for line in e.edits)
    if e.fix_toml:
        lines.append("   and set these tables:" if e.edits else "   fix, in the model file:")
        lines.extend(f"     {line}" for line in e.fix_toml.rstrip("\n").splitlines())
    return lines


def _axes_lines(d: Diagnosis) -> list[str]:
    """The joint axes compared as lines in the base frame, and the note on them."""
    lines: list[str] = []
    if d.axes:
        lines.append("")
        lines.append("joint axes as lines in the base frame (convention-free):")
        for a in d.axes:
            dist = "-" if a.distance_m is None else f"{a.distance_m * 1e3:.3f} mm"
            mark = "ok" if a.agrees else ("REVERSED" if a.reversed else "DIFFERS")
            lines.append(
                f"   joint {a.joint + 1} ({terminal_text(a.name)}): "
                f"{math.degrees(a.angle_rad):.3f}°, {dist}  {mark}"
            )
    if d.axes_note:
        lines.append(f"   {d.axes_note}")
    return lines
