"""A vendor's conventions against a URDF: several joints reversed and zeros apart, together.

A published table and a ROS-Industrial URDF of the same arm commonly differ in
several rows at once — a FANUC's joints 3–6 all turn the other way, a KUKA's A1,
A4 and A6 do while A2's and A3's zeros are a quarter turn apart — and one
hypothesis at a time (:mod:`.hypotheses`) explains none of it. Here the
directions and zeros are found together, as ``fkcheck map`` finds them
(:func:`fkcheck.urdf.mapping.reconcile_table`: the URDF's chain followed prefix
by prefix, each joint's direction and the zero before it tried), then the
frames at the ends are fitted on the table so edited (:mod:`.offsets`), and
what is still left is fitted one number at a time. The explanation lists the
model-file edits that reconcile the two, and what they leave unexplained.
"""

from __future__ import annotations

from dataclasses import replace

from fkcheck.backends.base import reads_model_description
from fkcheck.description.registry import model_format
from fkcheck.diagnose.findings import Change, Explanation
from fkcheck.diagnose.hypotheses import fit_single_parameters
from fkcheck.diagnose.offsets import explain_offsets
from fkcheck.diagnose.problem import Problem, Residual
from fkcheck.engine.axes import read_urdf_kinematics
from fkcheck.model.edits import TableEdits, format_turn
from fkcheck.model.names import param_symbol
from fkcheck.model.types import Model

__all__ = ["explain_conventions"]


def _changes(model: Model, edits: TableEdits) -> tuple[Change, ...]:
    """The numbers the edits change (a flip is a setting, not a number: it has none)."""
    index = {j.name: k for k, j in enumerate(model.joints)}
    out = []
    for name, turn in edits.thetas:
        k = index[name]
        old = model.joints[k].theta
        out.append(
            Change(
                f"joint[{k}].theta",
                f"{param_symbol(model, k, 'theta')} ({name})",
                old,
                old + turn,
                True,
                f"the zero {format_turn(turn)} away",
            )
        )
    negated = [(name, param, -float(getattr(model.joints[index[name]], param)))
               for name, param in edits.negated]  # fmt: skip
    for name, param, value in [*negated, *edits.values]:
        k = index[name]
        out.append(
            Change(
                f"joint[{k}].{param}",
                f"{param_symbol(model, k, param)} ({name})",
                float(getattr(model.joints[k], param)),
                value,
                param in ("alpha", "theta"),
            )
        )
    return tuple(out)


def _leftover(residual: Residual, before: Residual) -> float:
    """What is left of the disagreement, the worse of position and rotation (as :func:`.rank`)."""
    pos = residual.position_m / before.position_m if before.position_m > 0 else 0.0
    rot = residual.rotation_rad / before.rotation_rad if before.rotation_rad > 0 else 0.0
    return max(pos, rot)


def _title(model: Model, edits: TableEdits, frames: bool) -> str:
    parts = []
    if edits.flips:
        one = len(edits.flips) == 1
        parts.append(f"{', '.join(edits.flips)} {'turns' if one else 'turn'} the other way")
    if edits.thetas:
        parts.append(
            "the zeros differ: "
            + ", ".join(f"{name}'s by {format_turn(t)}" for name, t in edits.thetas)
        )
    index = {j.name: k for k, j in enumerate(model.joints)}
    if edits.negated:
        signs = [f"{param_symbol(model, index[n], p)} ({n})" for n, p in edits.negated]
        parts.append(f"{', '.join(signs)} with the other sign")
    if frames:
        parts.append("the frames at the ends differ")
    text = f"the table and the URDF differ by conventions: {'; '.join(parts)}"
    if edits.values:
        numbers = [f"{param_symbol(model, index[n], p)} ({n})" for n, p, _ in edits.values]
        one = len(numbers) == 1
        text += f"; and {'one number differs' if one else 'numbers differ'}: {', '.join(numbers)}"
    return text


def _one_number(problem: Problem, edited: Model) -> Explanation | None:
    """The first single-number fit that explains what the edited table leaves, if any."""
    singles = [e for e in fit_single_parameters(replace(problem, model=edited)) if e.explains]
    return singles[0] if singles else None


def _more_than_half_left(problem: Problem, residual: Residual, before: Residual) -> bool:
    """The edits leave more than half the disagreement (rotation: or more than the tolerance)."""
    return residual.position_m > before.position_m / 2 or residual.rotation_rad > max(
        before.rotation_rad / 2, problem.tol_rot_rad
    )


def explain_conventions(problem: Problem) -> list[Explanation]:
    """Reversed joints, quarter-turn zeros and the frames at the ends, together.

    Only against a reference that reads the model's URDF (the edits are found on
    its chain), and only when it takes more than one hypothesis alone: two or more
    edits of the table, or one together with a frame offset.

    Returns:
        One explanation (or none): the edits, with the frames' fix and, when a
        number is still off, that number; explaining, or leaving at most half of
        the disagreement.
    """
    model = problem.model
    source = problem.source
    if source is None or not reads_model_description(source, model):
        return []
    from fkcheck.urdf.mapping import reconcile_table  # SciPy: the reference extra's

    fmt = model_format(model)
    joints = fmt.mapped_joints(model) if fmt is not None else None
    found = reconcile_table(model, read_urdf_kinematics(model), seed=0, joints=joints)
    edits = found.edits
    if not edits:
        return []
    edited = edits.apply(model)
    before = problem.residual(model)
    residual = problem.residual(edited)
    changes = _changes(model, edits)
    details = [
        "found as fkcheck map finds a mapping: the URDF's chain followed joint by joint, each "
        "joint's direction tried together with the zero of the joint before it",
    ]
    fix_toml, numbers, frames = "", edits.count, False
    if not problem.explained(residual):
        offsets = explain_offsets(replace(problem, model=edited))
        if offsets and _leftover(offsets[0].residual, before) < _leftover(residual, before):
            off = offsets[0]
            assert off.model is not None
            edited, residual, fix_toml, frames = off.model, off.residual, off.fix_toml, True
            numbers += off.changed
            details += [d for d in off.details if not d.startswith("with the fix applied")]
    if not problem.explained(residual):
        single = _one_number(problem, edited)
        if single is not None:
            assert single.model is not None
            assert len(single.changes) == 1
            change = single.changes[0]
            edited, residual = single.model, single.residual
            changes += single.changes
            name = model.joints[int(change.field.split("]")[0].removeprefix("joint["))].name
            param = change.field.rsplit(".", 1)[1]
            edits = replace(edits, values=(*edits.values, (name, param, change.new)))
            numbers += 1
        else:
            details.append(
                f"these edits leave {residual.text()} unexplained: something else differs too"
            )
    if edits.count == 1 and not frames:
        return []  # one flip, one zero or one sign: a hypothesis of its own
    explains = problem.explained(residual)
    if not explains and _more_than_half_left(problem, residual, before):
        return []
    return [
        Explanation(
            "conventions",
            _title(model, edits, frames),
            residual,
            explains,
            tuple(details),
            changes,
            fix_toml=fix_toml,
            model=edited,
            numbers=numbers,
            edits=tuple(edits.lines(model)),
        )
    ]
