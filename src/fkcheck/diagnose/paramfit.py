"""The general form: a least-squares fit of every DH parameter, the base and the tool.

All ``4n`` table parameters plus the base and tool transforms (each as a small
SE(3) increment on the table's, 6 numbers) are fitted to the reference poses
with :func:`scipy.optimize.least_squares`. Several of them are redundant (a base
shift along z is a change of d1; the tool absorbs the last row's a and α), so
the fit is tied to the table by a tiny penalty — weaker for DH parameters than
for base and tool — which picks, among equally good fits, the one that moves the
table's own numbers least, and keeps untouched parameters exactly where they
were. Parameters that moved are reported next to the table's values.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.diagnose.findings import Change, Explanation
from fkcheck.diagnose.problem import Problem, pose_residuals, se3_from_rotvec_translation
from fkcheck.model.names import PARAMS, param_symbol
from fkcheck.model.offsets import offset_from_matrix
from fkcheck.model.types import Model, Offset

__all__ = ["MOVED", "explain_parameter_fit", "fit_all_parameters"]


#: Configurations the fit uses (36 unknowns for 6 joints; 6 residuals per configuration).
#: The fitted table is then checked on all of the problem's configurations.
FIT_CONFIGURATIONS = 64
#: A parameter that moved by more than this (m or rad) is reported as moved.
MOVED = 1e-9
#: Penalty weights tying the fit to the table (per metre / radian of change). Far
#: below the pose residuals of any real error, so they only break ties.
_TIE_DH = 1e-6
_TIE_OFFSET = 1e-4


def _model_from(model: Model, x: Float) -> Model:
    n = model.dof
    table = x[: 4 * n].reshape(n, 4)
    joints = tuple(
        replace(j, a=float(r[0]), alpha=float(r[1]), d=float(r[2]), theta=float(r[3]))
        for j, r in zip(model.joints, table, strict=True)
    )
    base = Offset(*_parts(model.base.matrix @ se3_from_rotvec_translation(x[4 * n : 4 * n + 6])))
    tool = Offset(*_parts(model.tool.matrix @ se3_from_rotvec_translation(x[4 * n + 6 :])))
    return replace(model, joints=joints, base=base, tool=tool)


def _parts(T: Float) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    off = offset_from_matrix(T)
    return off.xyz, off.rpy


def fit_all_parameters(problem: Problem) -> tuple[Model, Float]:
    """Fit every DH parameter, the base and the tool.

    Returns:
        ``(fitted model, x)`` where ``x`` holds the 4n table values then the base
        and tool increments (rotation vector, translation).
    """
    from scipy.optimize import least_squares

    model = problem.model
    problem = problem.subset(FIT_CONFIGURATIONS)
    n = model.dof
    x0 = np.concatenate(
        [
            np.array([[getattr(j, p) for p in PARAMS] for j in model.joints]).reshape(-1),
            np.zeros(12),
        ]
    )
    weights = np.concatenate([np.full(4 * n, _TIE_DH), np.full(12, _TIE_OFFSET)])

    def residuals(x: Float) -> Float:
        poses = problem.poses(_model_from(model, x))
        return np.concatenate([pose_residuals(poses, problem.reference), weights * (x - x0)])

    # At most 40 evaluations of the residuals (each iteration adds a finite-difference
    # Jacobian, len(x0) more): about a second for a 6-joint arm. A fit that has not
    # converged by then cannot reach the reference, and the residual it leaves says so.
    sol = least_squares(residuals, x0, method="lm", xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=40)
    return _model_from(model, sol.x), sol.x


def explain_parameter_fit(problem: Problem) -> list[Explanation]:
    """The full fit as an explanation: every parameter that moved, with its table value."""
    model = problem.model
    fitted, x = fit_all_parameters(problem)
    residual = problem.residual(fitted)
    n = model.dof
    changes: list[Change] = []
    for i, (old, new) in enumerate(zip(model.joints, fitted.joints, strict=True)):
        for param in PARAMS:
            a, b = float(getattr(old, param)), float(getattr(new, param))
            if abs(b - a) > MOVED:
                symbol = f"{param_symbol(model, i, param)} ({old.name})"
                changes.append(
                    Change(f"joint[{i}].{param}", symbol, a, b, param in ("alpha", "theta"))
                )
    details = []
    moved_offsets = 0  # [base]/[tool] numbers that moved, at least one per moved side
    sides = (("base", 4 * n, model.base, fitted.base), ("tool", 4 * n + 6, model.tool, fitted.tool))
    for label, start, before, after in sides:
        if np.abs(x[start : start + 6]).max() > MOVED:
            pairs = zip((*before.xyz, *before.rpy), (*after.xyz, *after.rpy), strict=True)
            moved_offsets += max(sum(abs(a - b) > MOVED for a, b in pairs), 1)
            details.append(
                f"[{label}] moved: xyz {before.xyz} → "
                f"{tuple(round(v, 9) for v in after.xyz)}, rpy {before.rpy} → "
                f"{tuple(round(v, 9) for v in after.rpy)}"
            )
    if not changes and not details:
        return []
    details += _redundancy_notes(fitted, changes)
    explains = problem.explained(residual)
    numbers = len(changes) + moved_offsets
    title = (
        f"a fit of all {4 * n} DH parameters, base and tool "
        f"{'matches' if explains else 'comes closest'}: {numbers} "
        f"number{'s' if numbers != 1 else ''} moved"
    )
    return [
        Explanation(
            "fit",
            title,
            residual,
            explains,
            tuple(details),
            tuple(changes),
            model=fitted,
            numbers=numbers,
        )
    ]


def _parallel_groups(model: Model) -> list[list[int]]:
    """Runs of consecutive joints (0-based) whose axes are parallel in the table."""
    groups: list[list[int]] = [[0]]
    for i in range(1, model.dof):
        # Standard row i-1 (α_{i-1}) or modified row i (α_{i-1}) turns axis i-1 into axis i.
        alpha = model.joints[i - 1 if model.convention == "standard" else i].alpha
        if abs(np.sin(alpha)) < 1e-9:
            groups[-1].append(i)
        else:
            groups.append([i])
    return [g for g in groups if len(g) > 1]


def _redundancy_notes(model: Model, changes: list[Change]) -> list[str]:
    """Say where a fit cannot tell parameters apart (d along parallel axes)."""
    notes = []
    moved_d = {int(c.field[6:].split("]")[0]): c for c in changes if c.field.endswith("].d")}
    for group in _parallel_groups(model):
        involved = [moved_d[i] for i in group if i in moved_d]
        if len(involved) < 2:
            continue
        total = sum(c.delta for c in involved) * 1e3
        names = " + ".join(c.symbol.split(" ")[0] for c in involved)
        notes.append(
            f"joints {group[0] + 1}–{group[-1] + 1} have parallel axes: only {names} is "
            f"determined, and it moved by {total:+.3f} mm in total (the split between them is "
            "the fit's smallest change, not a measurement)"
        )
    return notes
