"""Joint axes against the URDF over several configurations: which joint's axis differs first.

The line geometry is :mod:`fkcheck.engine.axes` (the engine uses it at one
configuration for the report); here it runs over up to
:data:`AXIS_CONFIGURATIONS` of a diagnosis's configurations
(:func:`compare_axes`) and is put in one line (:func:`axes_note`).
"""

from __future__ import annotations

from fkcheck.description.registry import model_format
from fkcheck.diagnose.problem import Problem
from fkcheck.engine.axes import (
    AxisRow,
    axis_lines,
    axis_rows,
    first_difference,
    read_urdf_kinematics,
)
from fkcheck.model.types import Model

__all__ = ["AXIS_CONFIGURATIONS", "axes_note", "compare_axes"]


#: Configurations used (axes depend on the joints before them).
AXIS_CONFIGURATIONS = 6


def compare_axes(problem: Problem) -> tuple[AxisRow, ...]:
    """Each joint's axis from the table and from the model's URDF, compared.

    Over up to :data:`AXIS_CONFIGURATIONS` of the problem's configurations, evenly
    spaced. Returns an empty tuple when the model has no URDF or the ``from``
    frame has no URDF twin (the axes then cannot be put in a common frame).
    """
    model = problem.model
    fmt = model_format(model)
    if fmt is None or fmt.frame(model.frames[problem.frame_from]) is None:
        return ()
    kin = read_urdf_kinematics(model)
    step = max(1, problem.q.shape[0] // AXIS_CONFIGURATIONS)
    lines = []
    for q in problem.q[::step][:AXIS_CONFIGURATIONS]:
        at = axis_lines(model, q, problem.frame_from, kin)
        assert at is not None  # the URDF and the twin were checked above
        lines.append(at)
    return axis_rows(model, lines, problem.tol_pos_m, problem.tol_rot_rad)


def axes_note(model: Model, rows: tuple[AxisRow, ...]) -> str:
    """What the axis comparison points at, in one line."""
    if not rows:
        return ""
    first = first_difference(rows)
    if first is None:
        return (
            "every joint axis agrees with the URDF: the tables differ only in the frames "
            "at the ends (base, tool, the frame mapping) or along the last axis"
        )
    k = first.joint + 1
    if first.reversed and all(r.agrees for r in rows if r.joint != first.joint):
        return f"joint {k} ({first.name}) is the only axis that differs, and it is reversed: flip?"
    if k == 1:
        return (
            "joint 1's axis already differs: the base ([base], or the mapping of the "
            "from-frame) is where the tables part"
        )
    if model.convention == "standard":
        return (
            f"first axis that differs: joint {k} ({first.name}); in standard DH it is "
            f"z{k - 1}, placed by row {k - 1} (a{k - 1}, α{k - 1}, and d{k - 1}, θ{k - 1}) "
            f"on top of the rows before: look at row {k - 1}"
        )
    return (
        f"first axis that differs: joint {k} ({first.name}); in modified DH it is z{k}, "
        f"placed by row {k} (a{k - 1}, α{k - 1}) on top of the rows before: look at row {k}"
    )
