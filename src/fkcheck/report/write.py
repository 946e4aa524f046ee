"""A check's reports written: the one function ``fkcheck check`` and ``fkcheck.write_report`` call.

Each file is written atomically (no half-written report); which paths are safe
to write (never an input of the run) is the caller's decision, made before the
check runs (:mod:`fkcheck.cli._outputs` plans the CLI's).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis
    from fkcheck.engine.results import CheckResult

__all__ = ["write_reports"]


def write_reports(
    check: CheckResult,
    diagnoses: Sequence[BackendDiagnosis] = (),
    *,
    html: Path | str | None = None,
    json: Path | str | None = None,
    junit: Path | str | None = None,
    summary: Path | str | None = None,
    plots: bool = True,
) -> tuple[Path, ...]:
    """Write a check's reports, each atomically; only formats, never recomputes.

    Args:
        check: The finished check.
        diagnoses: Its diagnoses (:func:`fkcheck.diagnose.failures.diagnose_failures`),
            for the causes the HTML, JUnit and Markdown show.
        html: The self-contained HTML report.
        json: The JSON result (the contract other tools read).
        junit: JUnit XML, one test case per backend and per kind of evidence.
        summary: The Markdown summary (as for ``$GITHUB_STEP_SUMMARY``).
        plots: Draw the HTML report's pictures.

    Returns:
        The paths written, in the order html, json, junit, summary (they are
        written JSON, JUnit, HTML, summary: the files machines read first).
    """
    from fkcheck.report.html import write_html
    from fkcheck.report.json_report import write_json
    from fkcheck.report.junit import write_junit
    from fkcheck.report.markdown import markdown_summary, write_summary

    written: dict[str, Path] = {}
    # Machine-read files first, the HTML (plots: the slowest) after them.
    if json is not None:
        written["json"] = write_json(check, json)
    if junit is not None:
        written["junit"] = write_junit(check, junit, diagnoses=diagnoses)
    if html is not None:
        written["html"] = write_html(check, html, diagnoses=diagnoses, plots=plots)
    if summary is not None:
        text = markdown_summary([check], diagnoses={check.model.name: diagnoses})
        written["summary"] = write_summary(summary, text)
    return tuple(written[k] for k in ("html", "json", "junit", "summary") if k in written)
