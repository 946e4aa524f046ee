r"""HTML pages from view models: Jinja2 templates shipped in the package, autoescaped.

The pages are static and self-contained: CSS inline, pictures as PNG data URIs,
no scripts, no fonts or anything else fetched from the network, so a report
opens from disk or from a CI artifact store. Every value is escaped on output
(``autoescape=True`` for every template), so a model whose name holds
``<script>`` shows it as text, and every string goes through
:func:`fkcheck.io.text.document_text` first (the environment's
``finalize``), so a control character from input shows as a visible escape
(``\x1b``) instead of reaching the page.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fkcheck.io.atomic import write_text_atomic
from fkcheck.io.text import document_text
from fkcheck.report.views import IndexPage, ReportPage

if TYPE_CHECKING:
    import jinja2

    from fkcheck.diagnose.failures import BackendDiagnosis
    from fkcheck.engine.results import CheckResult
    from fkcheck.report.record import CheckRecord

__all__ = ["render_index", "render_report", "render_summary", "write_html", "write_index"]


def _finalize(value: Any) -> Any:
    """Every ``{{ … }}`` value: strings without control characters (markup kept as markup)."""
    from markupsafe import Markup

    if isinstance(value, Markup):
        return Markup(document_text(value))
    if isinstance(value, str):
        return document_text(value)
    return value


@lru_cache(maxsize=1)
def _environment() -> jinja2.Environment:
    import jinja2

    return jinja2.Environment(
        finalize=_finalize,
        loader=jinja2.PackageLoader("fkcheck.report", "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )


def render_report(page: ReportPage) -> str:
    """One model's report page as HTML text."""
    return _environment().get_template("report.html.j2").render(page=page)


def render_index(page: IndexPage) -> str:
    """The index page as HTML text."""
    return _environment().get_template("index.html.j2").render(page=page)


def render_summary(record: CheckRecord) -> str:
    """A check's short summary as an HTML fragment, for a notebook cell.

    Verdict, headline and each backend's status and largest errors, laid out
    from the record alone: no page, no pictures, a diagnosis by its headline only.
    """
    return _environment().get_template("summary.html.j2").render(record=record)


def write_html(
    check: CheckResult,
    path: Path | str,
    *,
    diagnoses: Sequence[BackendDiagnosis] = (),
    plots: bool = True,
) -> Path:
    """Build, render and write a check's report, atomically.

    Formats what the check gathered (and the diagnoses, when given); runs no
    backend, no forward kinematics and no parser.

    Args:
        check: The check result.
        path: Where to write the page.
        diagnoses: The diagnoses of the check's disagreements (see
            :func:`fkcheck.diagnose.failures.diagnose_failures`), for the page's
            Diagnosis section.
        plots: Draw the pictures.

    Returns:
        The path written.
    """
    from fkcheck.report.page import build_report_page

    page = build_report_page(check, diagnoses=diagnoses, plots=plots)
    return write_text_atomic(path, render_report(page))


def write_index(page: IndexPage, path: Path | str) -> Path:
    """Render and write the index page, atomically."""
    return write_text_atomic(path, render_index(page))
