"""The index page: one row per model of a run of several.

View models (:mod:`fkcheck.report.views`): plain text, numbers and nested views only.
"""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.report.views.cells import Fact, Measure

__all__ = [
    "IndexModel",
    "IndexPage",
    "IndexRow",
]


@dataclass(frozen=True)
class IndexRow:
    """One model × backend line of the index.

    Attributes:
        backend: Backend name.
        status: Its status.
        label: Its status as shown (``fail (reader)`` for a reader finding,
            :func:`~fkcheck.engine.results.status_label`).
        pos_max: Largest position error.
        rot_max: Largest rotation error.
        message: Skip/error reason or failure summary.
    """

    backend: str
    status: str
    label: str
    pos_max: Measure
    rot_max: Measure
    message: str


@dataclass(frozen=True)
class IndexModel:
    """One model on the index page.

    Attributes:
        name: Model name.
        verdict: Its verdict.
        report: Relative link to its HTML report.
        json: Relative link to its JSON result.
        junit: Relative link to its JUnit XML.
        pair: The compared frame pair, e.g. ``"base → tool0"``.
        configurations: Number of configurations checked.
        rows: One row per backend.
        table_evidence: ``verified``, ``partly-verified``, ``failed``,
            ``expected-failure`` or ``not-checked``.
        evidence_text: What verified the table, or why nothing did.
        numbers_text: How many table numbers the check verified, left not
            identifiable and did not cover.
    """

    name: str
    verdict: str
    report: str
    json: str
    junit: str
    pair: str
    configurations: int
    rows: tuple[IndexRow, ...]
    table_evidence: str = "not-checked"
    evidence_text: str = ""
    numbers_text: str = ""


@dataclass(frozen=True)
class IndexPage:
    """The dashboard: every model × backend.

    Attributes:
        title: Page title.
        verdict: ``pass`` when every model passes, else ``fail``, ``error`` or ``unverified``.
        verdict_line: The verdict as a sentence.
        facts: Run facts (date, versions, command).
        models: One entry per model.
        generator: ``fkcheck <version>``.
        badge_note: Under a pass badge when some models' tables were checked for
            implementation only (the badge is then not green).
    """

    title: str
    verdict: str
    verdict_line: str
    facts: tuple[Fact, ...]
    models: tuple[IndexModel, ...]
    generator: str
    badge_note: str = ""
