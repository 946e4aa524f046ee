"""Typical mistakes, tested as hypotheses: re-run the comparison on modified copies of the table.

Each hypothesis is one mistake people make when they type in a DH table. It
is undone on a copy of the table (a new frozen :class:`~fkcheck.model.Model`,
never a mutation), and the copy is compared with the reference poses the
:class:`~fkcheck.diagnose.problem.Problem` already holds. Tried:

* ``degrees``: the angles are degrees read as radians (or radians read as degrees);
* ``convention``: the table is the other DH convention (standard ⇄ modified);
* ``sign``: one α, a or d has the wrong sign;
* ``theta-offset``: one θ is missing a +90°, −90° or 180° offset;
* ``flip``: one joint turns the other way;
* ``mapping``: two URDF joints are swapped in ``[urdf].joints`` (only against a URDF:
  the reference itself is recomputed for each swap);
* ``parameter``: one number is off — each a, α, d, θ in turn is fitted alone to the
  reference (``d1 = 0.089459 here, 0.089159 would match, Δ = −0.300 mm``), and the
  whole table is compared with the published tables fkcheck knows.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace

import numpy as np

from fkcheck.core.dh import Convention
from fkcheck.description.registry import model_format
from fkcheck.diagnose.findings import Change, Explanation, Kind
from fkcheck.diagnose.problem import Problem, Residual, pose_residuals
from fkcheck.model.names import PARAMS, Param, param_symbol
from fkcheck.model.published import published_tables, variant_note
from fkcheck.model.types import Joint, Model, Offset

__all__ = [
    "Candidate",
    "candidates",
    "explain_hypotheses",
    "explain_swapped_mapping",
    "fit_single_parameters",
]

#: Two values closer than this are "the same number" when naming a published value.
_SAME_VALUE = 1e-9
#: A fitted angle this close to another (modulo a turn) is the same angle: the
#: one-parameter fit stops within ~1e-12 rad of the exact value; 1e-9 leaves margin.
_SAME_ANGLE_RAD = 1e-9


@dataclass(frozen=True, eq=False)
class Candidate:
    """A modified copy of the table and what was modified.

    Attributes:
        kind: The kind of mistake it undoes.
        title: What the mistake is, in one line.
        model: The modified table.
        changes: The parameters changed.
        details: Extra evidence or caveats.
    """

    kind: Kind
    title: str
    model: Model
    changes: tuple[Change, ...] = ()
    details: tuple[str, ...] = ()


def _with_joint(model: Model, index: int, **changes: object) -> Model:
    joints = list(model.joints)
    joints[index] = replace(joints[index], **changes)  # type: ignore[arg-type]
    return replace(model, joints=tuple(joints))


def _symbol(model: Model, i: int, param: str) -> str:
    return f"{param_symbol(model, i, param)} ({model.joints[i].name})"


def _change(model: Model, i: int, param: Param, new: float, note: str = "") -> Change:
    return Change(
        f"joint[{i}].{param}",
        _symbol(model, i, param),
        float(getattr(model.joints[i], param)),
        float(new),
        param in ("alpha", "theta"),
        note,
    )


#: An angle beyond this (rad) cannot have been meant in radians: a full turn, plus
#: round-off. The model reader warns at the same bound.
_FULL_TURN_RAD = 2 * math.pi + 1e-9


def _scale_angles(
    model: Model, factor: float, which: Callable[[float], bool] | None = None
) -> Model:
    """The model with the angles of the file (α, θ, rpy) scaled: all, or those ``which`` picks.

    When every angle is scaled (the file's unit, not single values), the revolute
    joints' limits and the named poses are scaled too: they are written in the
    same unit.
    """
    everything = which is None

    def angle(v: float) -> float:
        return v * factor if which is None or which(v) else v

    def offset(o: Offset) -> Offset:
        r, p, y = (angle(v) for v in o.rpy)
        return Offset(o.xyz, (r, p, y))

    def joint(j: Joint) -> Joint:
        limits = j.limits
        if everything and limits is not None and j.type == "revolute":
            limits = (limits[0] * factor, limits[1] * factor)
        return replace(j, alpha=angle(j.alpha), theta=angle(j.theta), limits=limits)

    revolute = [j.type == "revolute" for j in model.joints]
    poses = {
        name: tuple(v * factor if r else v for v, r in zip(q, revolute, strict=True))
        for name, q in model.poses.items()
    }
    frames = {
        name: replace(spec, offset=offset(spec.offset)) for name, spec in model.frames.items()
    }
    return replace(
        model,
        joints=tuple(joint(j) for j in model.joints),
        base=offset(model.base),
        tool=offset(model.tool),
        frames=frames,
        poses=poses if everything else model.poses,
    )


def _angles(model: Model) -> list[tuple[str, str, float]]:
    """Every angle the file holds in its ``angle_unit``: ``(field, symbol, value)``."""
    out = []
    for i, j in enumerate(model.joints):
        out += [(f"joint[{i}].{p}", _symbol(model, i, p), float(getattr(j, p))) for p in
                ("alpha", "theta")]  # fmt: skip
    sides = [("base", "[base]", model.base), ("tool", "[tool]", model.tool)]
    sides += [(f"frames.{n}", f"[frames.{n}]", s.offset) for n, s in model.frames.items()]
    for field_, label, o in sides:
        out += [(f"{field_}.rpy[{k}]", f"{label} rpy[{k}]", v) for k, v in enumerate(o.rpy)]
    return out


def _units(model: Model) -> Iterator[Candidate]:
    angles = _angles(model)
    if model.angle_unit == "rad":
        yield from _degrees_read_as_radians(model, angles)
    if model.angle_unit == "deg":
        yield from _radians_read_as_degrees(model, angles)


def _degrees_read_as_radians(
    model: Model, angles: list[tuple[str, str, float]]
) -> Iterator[Candidate]:
    """A radian file with an angle beyond half a turn: all, or some, angles are degrees."""
    values = [v for _, _, v in angles]
    if not any(abs(v) > math.pi + 1e-9 for v in values):
        return
    beyond = [a for a in angles if abs(a[2]) > math.pi + 1e-9]
    table = [a for a in beyond if a[0].startswith("joint[")]  # the table's own, if any
    _, symbol, biggest = max(table or beyond, key=lambda a: abs(a[2]))
    yield Candidate(
        "degrees",
        'the table\'s angles are in degrees but were read as radians: set angle_unit = "deg"',
        _scale_angles(model, math.pi / 180),
        details=(
            f'angle_unit = "rad", yet {symbol} = {biggest:g}: that is '
            f"{abs(biggest) / (2 * math.pi):.3g} turns in radians, an ordinary angle in "
            "degrees; the unit applies to every angle, limit and named pose of the file",
        ),
    )
    # Some angles typed in degrees, the others in radians: only those beyond a
    # full turn, which cannot be radians, are converted.
    typed = [a for a in angles if abs(a[2]) > _FULL_TURN_RAD]
    if typed and len(typed) < sum(1 for v in values if v != 0):
        yield _typed_in_degrees(model, typed)


def _radians_read_as_degrees(
    model: Model, angles: list[tuple[str, str, float]]
) -> Iterator[Candidate]:
    """A degree file whose every angle, as a number, is within ±2π: radians."""
    values = [v for _, _, v in angles]
    if any(v != 0 for v in values) and all(abs(math.degrees(v)) <= _FULL_TURN_RAD for v in values):
        yield Candidate(
            "degrees",
            'the table\'s angles are in radians but were read as degrees: set angle_unit = "rad"',
            _scale_angles(model, 180 / math.pi),
            details=('angle_unit = "deg", yet every angle is within ±2π (as numbers)',),
        )


def _typed_in_degrees(model: Model, typed: list[tuple[str, str, float]]) -> Candidate:
    """Only the angles beyond a full turn converted from degrees (a file of mixed units)."""
    changes = tuple(
        Change(field_, symbol, v, math.radians(v), True, f"{v:g}° read as {v:g} rad")
        for field_, symbol, v in typed
    )
    names = ", ".join(c.symbol for c in changes)
    one = len(changes) == 1
    return Candidate(
        "degrees",
        f"{names} {'is' if one else 'are'} in degrees but {'was' if one else 'were'} read as "
        f'radians (angle_unit = "rad"): write {"it" if one else "them"} in radians',
        _scale_angles(model, math.pi / 180, lambda v: abs(v) > _FULL_TURN_RAD),
        changes,
        ("the file's other angles are within a full turn: they read as radians",),
    )


def _convention(model: Model) -> Iterator[Candidate]:
    other: Convention = "modified" if model.convention == "standard" else "standard"
    names = {"standard": "standard DH", "modified": "modified (Craig) DH"}
    yield Candidate(
        "convention",
        f"the table is {names[other]}, run as {names[model.convention]}: set "
        f'convention = "{other}"',
        replace(model, convention=other),
        details=("in modified DH, row i holds a(i-1) and α(i-1), the link before the joint",),
    )


def _signs(model: Model) -> Iterator[Candidate]:
    for i, joint in enumerate(model.joints):
        params: tuple[Param, ...] = ("alpha", "a", "d")
        for param in params:
            value = getattr(joint, param)
            if value == 0:
                continue
            change = _change(model, i, param, -value)
            shown = f"{math.degrees(value):g}°" if param == "alpha" else f"{value:g} m"
            yield Candidate(
                "sign",
                f"{_symbol(model, i, param)} has the wrong sign: {shown} here, the opposite "
                "matches",
                _with_joint(model, i, **{param: -value}),
                (change,),
            )


def _theta_offsets(model: Model) -> Iterator[Candidate]:
    for i, joint in enumerate(model.joints):
        for step, label in ((math.pi / 2, "+90°"), (-math.pi / 2, "-90°"), (math.pi, "180°")):
            new = joint.theta + step
            yield Candidate(
                "theta-offset",
                f"{_symbol(model, i, 'theta')} is missing a {label} offset",
                _with_joint(model, i, theta=new),
                (_change(model, i, "theta", new),),
            )


def _flips(model: Model) -> Iterator[Candidate]:
    """One joint turned the other way: the ``flip`` to set, or what differs in a conversion.

    A table fkcheck derived (``check --source A --against-description B``) has no
    model file to set ``flip`` in: the hint says B's axis of that joint is the
    opposite of A's.
    """
    derived = model.derived
    for i, joint in enumerate(model.joints):
        if derived is not None:
            fix = f"{derived.checked}'s axis of {joint.name} is opposite to {derived.source}'s"
        else:
            fix = f"set flip = {'true' if not joint.flip else 'false'}"
        yield Candidate(
            "flip",
            f"joint {i + 1} ({joint.name}) turns the other way: {fix}",
            _with_joint(model, i, flip=not joint.flip),
        )


def _published(model: Model) -> Iterator[Candidate]:
    for table in published_tables():
        if table.dof != model.dof or table.convention != model.convention:
            continue
        changes = []
        for i, (ours, theirs) in enumerate(zip(model.joints, table.joints, strict=True)):
            for param in PARAMS:
                a, b = getattr(ours, param), getattr(theirs, param)
                if abs(a - b) > _SAME_VALUE:
                    note = f"published table {table.name}"
                    source = variant_note(table.name, i, param, a, tol=_SAME_VALUE)
                    if source:
                        note += f"; {a!r} is the value in {source}"
                    changes.append(_change(model, i, param, b, note))
        if not changes:
            continue
        joints = tuple(
            replace(ours, a=theirs.a, alpha=theirs.alpha, d=theirs.d, theta=theirs.theta)
            for ours, theirs in zip(model.joints, table.joints, strict=True)
        )
        yield Candidate(
            "parameter",
            f"the reference matches the published table {table.name} "
            f"({table.description or table.name}); this table differs in "
            + (
                f"one number, {changes[0].symbol}"
                if len(changes) == 1
                else f"{len(changes)} numbers"
            ),
            replace(model, joints=joints),
            tuple(changes),
        )


#: The generators, in the order they are listed in a diagnosis's "tried" line.
GENERATORS: tuple[tuple[str, Callable[[Model], Iterator[Candidate]]], ...] = (
    ("degrees read as radians (and the reverse)", _units),
    ("standard ⇄ modified convention", _convention),
    ("one α, a or d with the wrong sign", _signs),
    ("a missing ±90° or 180° θ offset", _theta_offsets),
    ("one joint reversed", _flips),
    ("a published table", _published),
)


def candidates(model: Model) -> list[tuple[str, Candidate]]:
    """Every modified copy of the table, with the name of the hypothesis it tests."""
    return [(label, c) for label, gen in GENERATORS for c in gen(model)]


def _known_note(model: Model, i: int, param: str, old: float, new: float) -> str:
    """Where the fitted (or the table's) value is known from."""
    notes = []
    for table in published_tables():
        if table.dof != model.dof or table.convention != model.convention:
            continue
        published = getattr(table.joints[i], param)
        if abs(published - new) <= 1e-7 and abs(published - old) > _SAME_VALUE:
            notes.append(f"{published!r} is the value in the published table {table.name}")
            source = variant_note(table.name, i, param, old, tol=_SAME_VALUE)
            if source:
                notes.append(f"{old!r} is the value in {source}")
    return "; ".join(notes)


def _degrees_note(model: Model, old: float, new: float) -> str:
    """``-90 is -90° read as radians`` when a fitted angle is the table's number in degrees."""
    if model.angle_unit != "rad" or abs(old) <= _FULL_TURN_RAD:
        return ""
    if abs(_wrap(new - math.radians(old))) > _SAME_ANGLE_RAD:
        return ""
    return f"{new:.6g} rad is {old:g}° modulo a turn: {old:g} is in degrees but was read as radians"


def _wrap(angle: float) -> float:
    """``angle`` in ``(-π, π]``."""
    return math.pi - (math.pi - angle) % (2 * math.pi)


def _halves(problem: Problem, residual: Residual, before: Residual) -> bool:
    """At most half the position error left, and half the rotation error (or within tolerance)."""
    return residual.position_m <= before.position_m / 2 and residual.rotation_rad <= max(
        before.rotation_rad / 2, problem.tol_rot_rad
    )


def fit_single_parameters(problem: Problem) -> list[Explanation]:
    """Each a, α, d, θ fitted alone to the reference; the ones that explain (or halve) it.

    A least-squares fit of one scalar (:func:`scipy.optimize.least_squares`) from the
    table's value: "d1 = 0.089459 here, 0.089159 would match, Δ = −0.300 mm". Fitted
    on up to :data:`~fkcheck.diagnose.problem.SPREAD_CONFIGURATIONS` of the problem's
    configurations, judged on all of them.
    """
    from scipy.optimize import least_squares

    model = problem.model
    fit = problem.spread()
    chain = model.chain
    before = problem.residual(model)
    out: list[Explanation] = []
    for i in range(model.dof):
        for param in PARAMS:
            old = float(getattr(model.joints[i], param))

            def residuals(x: np.ndarray, i: int = i, param: str = param) -> np.ndarray:
                # The chain of the table with this one number changed: the arrays a
                # changed Model would build, without building one per evaluation.
                values = getattr(chain, param).copy()
                values[i] = float(x[0])
                trial = replace(chain, **{param: values})
                return pose_residuals(fit.poses(model, trial), fit.reference)

            sol = least_squares(
                residuals, [old], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200
            )
            new = float(sol.x[0])
            fitted = _with_joint(model, i, **{param: new})
            residual = problem.residual(fitted)
            explains = problem.explained(residual)
            if (
                not (explains or _halves(problem, residual, before))
                or abs(new - old) <= _SAME_VALUE
            ):
                continue
            note = "; ".join(
                n
                for n in (_known_note(model, i, param, old, new), _degrees_note(model, old, new))
                if n
            )
            change = _change(model, i, param, new, note)
            title = f"one number differs: {change.symbol}"
            out.append(
                Explanation("parameter", title, residual, explains, changes=(change,), model=fitted)
            )
    return out


def explain_hypotheses(problem: Problem) -> tuple[list[Explanation], list[str]]:
    """Every hypothesis that explains (or halves) the disagreement, and what was tried.

    Returns:
        ``(explanations, tried)``: the explanations found, and one line per
        hypothesis family with how many copies of the table it compared.
    """
    before = problem.residual(problem.model)
    found: list[Explanation] = []
    counts: dict[str, int] = {}
    for label, cand in candidates(problem.model):
        counts[label] = counts.get(label, 0) + 1
        residual = problem.residual(cand.model)
        explains = problem.explained(residual)
        if label == "a published table" and not explains:
            continue  # a different robot's table that happens to be closer says little
        if explains or _halves(problem, residual, before):
            found.append(
                Explanation(
                    cand.kind,
                    cand.title,
                    residual,
                    explains,
                    cand.details,
                    cand.changes,
                    model=cand.model,
                )
            )
    singles = fit_single_parameters(problem)
    counts["one parameter fitted alone"] = 4 * problem.model.dof
    # A single-parameter fit that lands on a hypothesis already found (an angle up to
    # whole turns) says nothing new.
    seen = [c for e in found for c in e.changes if len(e.changes) == 1]
    found += [e for e in singles if not any(_same_change(e.changes[0], c) for c in seen)]
    tried = [f"{label} ({n})" for label, n in counts.items()]
    return found, tried


def _same_change(a: Change, b: Change) -> bool:
    """The same field set to the same value (an angle up to whole turns)."""
    if a.field != b.field:
        return False
    if a.angle:
        return abs(_wrap(a.new - b.new)) <= _SAME_ANGLE_RAD
    return abs(a.new - b.new) <= _SAME_VALUE


def explain_swapped_mapping(problem: Problem) -> tuple[list[Explanation], int]:
    """Two URDF joint names swapped in ``[urdf].joints``: the reference rerun per swap.

    Returns:
        ``(explanations, number of swaps tried)``.
    """
    model = problem.model
    fmt = model_format(model)
    if fmt is None or problem.source is None:
        return [], 0
    names = fmt.mapped_joints(model)
    found: list[Explanation] = []
    tried = 0
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            swapped = list(names)
            swapped[i], swapped[j] = swapped[j], swapped[i]
            cand = fmt.remapped(model, tuple(swapped))
            tried += 1
            residual = problem.verify(cand)
            if problem.explained(residual):
                listed = ", ".join(f'"{n}"' for n in swapped)
                found.append(
                    Explanation(
                        "mapping",
                        f"[urdf].joints has {names[i]!r} and {names[j]!r} swapped (DH joints "
                        f"{i + 1} and {j + 1})",
                        residual,
                        True,
                        (f"fix: joints = [{listed}]",),
                        model=cand,
                    )
                )
    return found, tried
