"""The index page of a run over several models: one row per model, one overall verdict.

Every number goes through :mod:`fkcheck.io.format`; text from a model
file or URDF passes through unchanged and is escaped by the templates.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from fkcheck._version import __version__
from fkcheck.engine.results import CheckResult
from fkcheck.report.views import (
    Fact,
    IndexModel,
    IndexPage,
    IndexRow,
)

if TYPE_CHECKING:
    pass

from fkcheck.report.measures import measure_m, measure_rad
from fkcheck.report.record import CheckRecord, check_record
from fkcheck.urdf.locate import display_path

__all__ = ["IndexEntry", "build_index_page", "overall_verdict"]


@dataclass(frozen=True, eq=False)
class IndexEntry:
    """One model on the index: its result and where its files are (relative links).

    Attributes:
        check: The model's check result.
        report: Relative path of its HTML report.
        json: Relative path of its JSON result.
        junit: Relative path of its JUnit XML.
    """

    check: CheckResult
    report: str
    json: str
    junit: str


def overall_verdict(verdicts: Sequence[str]) -> str:
    """The verdict of a run over several models.

    ``fail`` when any model fails; else ``error`` when any errors or there are
    none; else ``unverified`` when any lacks required evidence; else ``pass``.
    """
    if any(v == "fail" for v in verdicts):
        return "fail"
    if any(v == "error" for v in verdicts) or not verdicts:
        return "error"
    if any(v == "unverified" for v in verdicts):
        return "unverified"
    return "pass"


def _model(e: IndexEntry, record: CheckRecord) -> IndexModel:
    """One model's row of the index, from its check's record."""
    return IndexModel(
        name=record.model,
        verdict=record.verdict,
        report=e.report,
        json=e.json,
        junit=e.junit,
        pair=f"{record.frame_from} → {record.frame_to}",
        configurations=record.configurations,
        table_evidence=record.of("table").status,
        evidence_text=record.of("table").sentence,
        numbers_text=record.numbers_line,
        rows=tuple(
            IndexRow(
                backend=r.name,
                status=r.status,
                label=r.label,
                pos_max=measure_m(r.max_position_m),
                rot_max=measure_rad(r.max_rotation_rad),
                message=r.message,
            )
            for r in record.backends
        ),
    )


def build_index_page(
    entries: Sequence[IndexEntry],
    *,
    command: str = "",
    created: str = "",
    versions: dict[str, str] | None = None,
) -> IndexPage:
    """The dashboard of a run over several models.

    Args:
        entries: One per model, in the order to list them.
        command: The command line that reproduces the run.
        created: When the run started (ISO 8601).
        versions: Library versions to show (default: the installed ones).
    """
    from fkcheck.report.versions import library_versions

    models = tuple(_model(e, check_record(e.check)) for e in entries)
    verdicts = [m.verdict for m in models]
    overall = overall_verdict(verdicts)
    counts = Counter(verdicts)
    verdict_words = ("pass", "fail", "error", "unverified")
    line = ", ".join(f"{counts[v]} {v}" for v in verdict_words if counts.get(v))
    verified = sum(m.table_evidence == "verified" for m in models)
    line += f"; table verified independently for {verified} of {len(models)}"
    versions = library_versions() if versions is None else versions
    facts = [Fact("checked at", created or "–", volatile="date")]
    facts += [Fact(k, v, volatile="version") for k, v in versions.items()]
    if command:
        facts.append(Fact("command", command, code=True))
    configs = sorted({e.check.config for e in entries if e.check.config is not None})
    facts.append(
        Fact(
            "configuration",
            ", ".join(f"[tool.fkcheck] of {display_path(c)}" for c in configs) or "none",
            volatile="path" if configs else "",
        )
    )
    return IndexPage(
        title=f"fkcheck: {len(models)} models, {overall.upper()}",
        verdict=overall,
        verdict_line=f"{len(models)} models checked: {line or 'none'}.",
        badge_note=f"table verified for {verified} of {len(models)}"
        if overall == "pass" and verified < len(models)
        else "",
        facts=tuple(facts),
        models=models,
        generator=f"fkcheck {__version__}",
    )
