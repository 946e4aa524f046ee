"""A short Markdown summary for CI pages (GitHub's job summary and the like).

The verdict and one table, so a CI page shows which backend disagrees and by
how much without opening an artifact. Text from input is escaped
(:func:`escape_markdown`, which is :func:`fkcheck.io.text.markdown_text`):
control characters become visible escapes, HTML special characters become
entities and Markdown's own (``|``, backticks, brackets, emphasis marks) are
backslash-escaped, so a model name cannot break the table or inject markup.
``$GITHUB_STEP_SUMMARY`` is appended to by
:func:`fkcheck.io.output_paths.append_step_summary`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from fkcheck.engine.results import CheckResult
from fkcheck.engine.verdict import KINDS, evidence_sentences, headline
from fkcheck.io.format import format_angle_summary, format_length_summary
from fkcheck.io.text import markdown_text as escape_markdown

__all__ = ["escape_markdown", "markdown_summary", "write_summary"]

_ICON = {
    "pass": "✅",
    "fail": "❌",
    "error": "⚠️",
    "skipped": "⏭️",
    "unverified": "❔",
    "verified": "✅",
    "failed": "❌",
    "not-checked": "❔",
}


def markdown_summary(checks: Sequence[CheckResult], links: Mapping[str, str] | None = None) -> str:
    """The summary of one check or of a run over several models.

    Args:
        checks: One result per model.
        links: Model name → link to its HTML report (relative or absolute), optional.

    Returns:
        Markdown text ending in a newline.
    """
    from fkcheck.report.index import overall_verdict
    from fkcheck.report.page import verdict_line

    links = links or {}
    lines: list[str] = []
    overall = overall_verdict([c.verdict for c in checks])
    if len(checks) == 1:
        (check,) = checks
        name = escape_markdown(check.model.name)
        partial = overall == "pass" and check.evidence.table.status != "verified"
        heading = (
            f"{_ICON['not-checked']} PASS (implementation only)"
            if partial
            else (f"{_ICON[overall]} {overall.upper()}")
        )
        lines.append(f"## fkcheck {name}: {heading}")
        lines.append("")
        lines.append(escape_markdown(headline(check.verdict, check.evidence, len(check.ran))))
        lines.append("")
        lines.append(escape_markdown(verdict_line(check)))
        lines.append("")
        evidence = check.evidence
        for kind, text in zip(KINDS, evidence_sentences(evidence), strict=True):
            lines.append(f"- {_ICON[evidence.of(kind).status]} {escape_markdown(text)}")
        lines.append("")
        lines.append(
            f"{escape_markdown(check.frame_from)} → {escape_markdown(check.frame_to)}, "
            f"{check.q.shape[0]} configurations (seed {check.seed}), tolerance "
            f"{check.tol_pos_m:g} m / {check.tol_rot_rad:g} rad."
        )
    else:
        n_fail = sum(c.verdict != "pass" for c in checks)
        verified = sum(c.evidence.table.status == "verified" for c in checks)
        lines.append(f"## fkcheck: {len(checks)} models, {_ICON[overall]} {overall.upper()}")
        lines.append("")
        lines.append(
            f"{len(checks) - n_fail} of {len(checks)} models pass; the table is verified "
            f"independently for {verified} of {len(checks)} (the others: implementation only)."
        )
        lines.append("")
        for check in checks:
            status = check.evidence.table.status
            text = evidence_sentences(check.evidence)[1]
            lines.append(
                f"- {escape_markdown(check.model.name)}: {_ICON[status]} {escape_markdown(text)}"
            )
    lines.append("")
    many = len(checks) > 1
    head = "| backend | status | max position error | max rotation error | message |"
    lines.append(("| model " if many else "") + head)
    lines.append("|---" * (6 if many else 5) + "|")
    for check in checks:
        name = escape_markdown(check.model.name)
        link = links.get(check.model.name)
        model_cell = (f"| [{name}]({link}) " if link else f"| {name} ") if many else ""
        if not check.backends:
            lines.append(f"{model_cell}| – | {_ICON['error']} error | – | – | no backends |")
        for r in check.backends:
            lines.append(
                f"{model_cell}| {escape_markdown(r.name)} | {_ICON[r.status]} {r.status} | "
                f"{format_length_summary(r.max_position_error_m)} | "
                f"{format_angle_summary(r.max_rotation_error_rad)} | "
                f"{escape_markdown(r.message)} |"
            )
    return "\n".join(lines) + "\n"


def write_summary(path: Path | str, text: str) -> Path:
    """Write the summary, atomically (replacing the file)."""
    from fkcheck.io.atomic import write_text_atomic

    return write_text_atomic(path, text)
