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

    from fkcheck.backends.base import Backend
    from fkcheck.engine.results import CheckResult

__all__ = ["render_index", "render_report", "write_html", "write_index"]


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


def write_html(
    check: CheckResult,
    path: Path | str,
    backends: Sequence[Backend] | None = None,
    *,
    plots: bool = True,
    diagnose: bool = True,
) -> Path:
    """Build, render and write a check's report, atomically.

    Args:
        check: The check result.
        path: Where to write the page.
        backends: The backend objects the check ran, in order; when given, each
            failing backend is run again on its few worst configurations so the
            page can show both matrices side by side.
        plots: Draw the pictures.
        diagnose: When the check failed and ``backends`` are given, run
            ``fkcheck diagnose`` against the disagreeing backends for the page's
            Diagnosis section (see :mod:`fkcheck.report.diagnosis`); a diagnosis
            that raises is shown as its error, the page is written anyway.

    Returns:
        The path written.
    """
    from fkcheck.engine.evidence import collect_worst_poses
    from fkcheck.report.build import build_report_page
    from fkcheck.report.diagnosis import diagnosis_section

    worst = collect_worst_poses(check, backends) if backends is not None else None
    diagnoses = diagnosis_section(check, backends) if diagnose and backends is not None else ()
    page = build_report_page(check, worst, plots=plots, diagnoses=diagnoses)
    return write_text_atomic(path, render_report(page))


def write_index(page: IndexPage, path: Path | str) -> Path:
    """Render and write the index page, atomically."""
    return write_text_atomic(path, render_index(page))
