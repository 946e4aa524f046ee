"""A short Markdown summary for CI pages (GitHub's job summary and the like).

The verdict, one table and the cause of each failure, so a CI page shows which
backend disagrees, by how much and why without opening an artifact. One model:
a row per backend with its numbers. Several models: a row per model and a
column per backend (:data:`MARK` — ✔ pass, ✘ fail, – skipped or not run,
! error — with the legend under the table), compact for twenty models and
more. Under either table, one line per failure: the numbers and the headline
of its diagnosis (the diagnoses are passed in, already run; nothing here runs
one). Text from input is escaped
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
from typing import TYPE_CHECKING

from fkcheck._version import __version__
from fkcheck.engine.results import CheckResult
from fkcheck.io.format import format_angle_summary, format_length_summary, format_scientific
from fkcheck.io.text import markdown_text as escape_markdown
from fkcheck.report.record import CheckRecord, check_record

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis

__all__ = ["LEGEND", "MARK", "escape_markdown", "markdown_summary", "write_summary"]

#: A backend's status in the several-models table, one character wide.
MARK = {"pass": "✔", "fail": "✘", "skipped": "–", "error": "!", "xfail": "x", "xpass": "✘"}

#: The legend printed under that table.
LEGEND = (
    "✔ pass · ✘ fail (or a recorded difference no longer seen) · x expected failure "
    "(a recorded known difference) · – skipped or not run · ! error"
)

_ICON = {
    "pass": "✅",
    "fail": "❌",
    "error": "⚠️",
    "skipped": "⏭️",
    "xfail": "🔶",
    "xpass": "❌",
    "expected-failure": "🔶",
    "unverified": "❔",
    "verified": "✅",
    "failed": "❌",
    "not-checked": "❔",
    "partly-verified": "🟡",
}


def markdown_summary(
    checks: Sequence[CheckResult],
    links: Mapping[str, str] | None = None,
    *,
    diagnoses: Mapping[str, Sequence[BackendDiagnosis]] | None = None,
) -> str:
    """The summary of one check or of a run over several models.

    Args:
        checks: One result per model.
        links: Model name → link to its HTML report (relative or absolute), optional.
        diagnoses: Model name → the diagnoses of its check (as
            :func:`fkcheck.diagnose.failures.diagnose_failures` returned them),
            optional; each failure's line then ends with its diagnosis headline.

    Returns:
        Markdown text ending in a newline.
    """
    from fkcheck.report.index import overall_verdict

    links = links or {}
    diagnoses = diagnoses or {}
    records = [check_record(c, diagnoses.get(c.model.name, ())) for c in checks]
    lines: list[str] = []
    overall = overall_verdict([c.verdict for c in checks])
    if len(checks) == 1:
        (check,), (record,) = checks, records
        name = escape_markdown(check.model.name)
        icon = {"expected failure: known difference": "expected-failure",
                "table partly verified": "partly-verified",
                "implementation only": "not-checked"}  # fmt: skip
        heading = (
            f"{_ICON[icon[record.partial]]} PASS ({record.partial})"
            if overall == "pass" and record.partial
            else f"{_ICON[overall]} {overall.upper()}"
        )
        lines.append(f"## fkcheck {name}: {heading}")
        lines.append("")
        lines.append(escape_markdown(record.headline))
        lines.append("")
        lines.append(escape_markdown(record.verdict_line))
        lines.append("")
        for evidence in record.evidence:
            lines.append(f"- {_ICON[evidence.status]} {escape_markdown(evidence.sentence)}")
        lines.append("")
        lines.append(
            f"{escape_markdown(check.frame_from)} → {escape_markdown(check.frame_to)}, "
            f"{record.configurations} configurations (seed {check.options.seed}), tolerance "
            f"{check.tol_pos_m:g} m / {check.tol_rot_rad:g} rad; time limit "
            f"{check.options.timeout_s:g} s per backend."
        )
        for line in (record.numbers_line, record.calibration_line):
            if line:
                lines.append("")
                lines.append(escape_markdown(line))
        lines.append("")
        lines.append("| backend | status | max position error | max rotation error | message |")
        lines.append("|---" * 5 + "|")
        if not record.backends:
            lines.append(f"| – | {_ICON['error']} error | – | – | no backends |")
        for r in record.backends:
            lines.append(
                f"| {escape_markdown(r.name)} | {_ICON[r.status]} {r.label} | "
                f"{format_length_summary(r.max_position_m)} | "
                f"{format_angle_summary(r.max_rotation_rad)} | "
                f"{escape_markdown(r.message)} |"
            )
        lines.extend(_jacobian_table(check, record))
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
        lines.extend(_matrix(records, links))
    causes = _causes(records, many=len(checks) > 1)
    if causes:
        lines.append("")
        lines.extend(causes)
    lines.append("")
    lines.append(f"<sub>fkcheck {__version__}</sub>")
    return "\n".join(lines) + "\n"


def _matrix(records: Sequence[CheckRecord], links: Mapping[str, str]) -> list[str]:
    """A row per model, a column per backend (in the order first met), then the legend."""
    names: list[str] = []
    for record in records:
        names += [r.name for r in record.backends if r.name not in names]
    table_mark = {"verified": "✔", "failed": "✘", "not-checked": "–", "expected-failure": "x",
                  "partly-verified": "½"}  # fmt: skip
    head = ["model", "verdict", "table verified", *map(escape_markdown, names)]
    lines = ["| " + " | ".join(head) + " |", "|---|---|" + ":-:|" * (len(head) - 2)]
    for record in records:
        name = escape_markdown(record.model)
        link = links.get(record.model)
        status = {r.name: r.status for r in record.backends}
        cells = [
            f"[{name}]({link})" if link else name,
            f"{_ICON[record.verdict]} {record.verdict}",
            table_mark[record.of("table").status],
            *(MARK[status[n]] if n in status else MARK["skipped"] for n in names),
        ]
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")
    lines.append(f"{LEGEND}; table verified: ✔ by something independent of the table, "
                 "✘ it disagrees, x it differs as recorded (known difference, "
                 "not verified), – not checked.")  # fmt: skip
    return lines


def _causes(records: Sequence[CheckRecord], *, many: bool) -> list[str]:
    """One line per failing or erroring backend: its message and its diagnosis headline.

    Backends that one diagnosis stands for (the same disagreement) share a line.
    With one model the numbers are in its table already: only the diagnosed
    failures get a line, with the headline.
    """
    lines: list[str] = []
    for record in records:
        prefix = f"{escape_markdown(record.model)} · " if many else ""
        done: set[str] = set()
        for r in record.backends:
            if r.status not in ("fail", "error", "xfail", "xpass") or r.name in done:
                continue
            diagnosed = r.status == "fail" and bool(r.diagnosis)
            done.update(r.diagnosed_with)
            if not many and not diagnosed and r.status in ("fail", "error"):
                continue  # one model: its table already holds the message
            who = ", ".join(escape_markdown(n) for n in r.diagnosed_with)
            text = f"- {MARK[r.status]} **{prefix}{who}**"
            if many:
                text += f": {escape_markdown(r.message)}"
            if diagnosed:
                text += f" — diagnosis: {escape_markdown(r.diagnosis)}"
            lines.append(text)
        for r in record.backends:
            j = r.jacobian
            if many and j is not None and j.status in ("fail", "error"):
                lines.append(
                    f"- {MARK[j.status]} **{prefix}{escape_markdown(r.name)} (Jacobian)**: "
                    f"{escape_markdown(j.message)}"
                    + (f" — diagnosis: {escape_markdown(j.diagnosis)}" if j.diagnosis else "")
                )
    return lines


def _jacobian_table(check: CheckResult, record: CheckRecord) -> list[str]:
    """The Jacobian comparison of one check, one row per backend (``check --jacobian``)."""
    if check.jacobian is None:
        return []
    lines = [
        "",
        f"Jacobian of {escape_markdown(check.frame_to)} ({check.jacobian.reference}), "
        f"tolerance {check.jacobian.tol:g} m/rad and rad/rad:",
        "",
        "| backend | status | max linear difference | max angular difference | how |",
        "|---" * 5 + "|",
    ]
    for r in record.backends:
        j = r.jacobian
        if j is None:
            continue
        numbers = ["–", "–"]
        if j.ran:
            numbers = [
                format_scientific(j.max_linear, "m/rad"),
                format_scientific(j.max_angular, "rad/rad"),
            ]
        how = j.method if j.ran else j.message
        if j.diagnosis:
            how = f"{how} — diagnosis: {j.diagnosis}"
        lines.append(
            f"| {escape_markdown(r.name)} | {_ICON[j.status]} {j.status} | "
            f"{numbers[0]} | {numbers[1]} | {escape_markdown(how)} |"
        )
    return lines


def write_summary(path: Path | str, text: str) -> Path:
    """Write the summary, atomically (replacing the file)."""
    from fkcheck.io.atomic import write_text_atomic

    return write_text_atomic(path, text)
