"""The report's table of the model's numbers: what the check verified of each, as views."""

from __future__ import annotations

from fkcheck.engine.results import CheckResult
from fkcheck.engine.verdict import number_status
from fkcheck.io.format import format_deg, format_mm
from fkcheck.model.coverage import NumberEvidence
from fkcheck.model.types import Model
from fkcheck.report.record import CheckRecord
from fkcheck.report.views import NumberRow, NumbersView

__all__ = ["numbers_view"]


def _value(model: Model, n: NumberEvidence) -> str:
    """A table number's value in the model (mm or degrees); ``""`` for an offset component."""
    if not n.group.startswith("joint "):
        return ""
    row = int(n.group.split()[1]) - 1
    joint = model.joints[row]
    if n.name.startswith("flip"):
        return "flipped" if joint.flip else "as is"
    field = {"a": "a", "α": "alpha", "d": "d", "θ": "theta"}[n.name[0]]
    value = float(getattr(joint, field))
    return format_mm(value) if n.unit == "m" else format_deg(value)


def _note(n: NumberEvidence, status: str) -> str:
    parts = []
    if n.resolution is not None:
        shown = format_mm(n.resolution) if n.unit == "m" else format_deg(n.resolution)
        verb = "failed" if status == "verified" else "failed, had the table been compared"
        parts.append(f"an error above {shown} alone would have {verb}")
    if n.absorbed_by:
        parts.append(n.absorbed_by)
    if n.trades_with:
        parts.append("only its combination with " + ", ".join(n.trades_with) + " is checked")
    if n.source:
        parts.append(f"source: {n.source}")
    if n.on_word_of and status == "verified":
        parts.append("verified on the word of " + ", ".join(n.on_word_of))
    if n.status == "not-covered":
        parts.append("the compared pose does not depend on it")
    return "; ".join(parts)


def numbers_view(check: CheckResult, record: CheckRecord) -> NumbersView | None:
    """The section, or ``None`` when the check did not analyse its numbers."""
    numbers = check.numbers
    if numbers is None:
        return None
    table = check.evidence.table.status
    rows = []
    for n in numbers.numbers:
        status = number_status(n.status, table)
        rows.append(NumberRow(n.name, n.group, _value(check.model, n), status, _note(n, status)))
    return NumbersView(record.numbers_line, tuple(rows))
