"""A check's page: its evidence, its numbers and every section.

View models (:mod:`fkcheck.report.views`): plain text, numbers and nested views only.
"""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.report.views.backend import BackendDetail, BackendRow, FrameSide, PartingView
from fkcheck.report.views.cells import Fact, Image
from fkcheck.report.views.diagnosis import DiagnosisView
from fkcheck.report.views.jacobian import JacobianSection
from fkcheck.report.views.model import ModelView

__all__ = [
    "EvidenceLine",
    "NumberRow",
    "NumbersView",
    "ReportPage",
]


@dataclass(frozen=True)
class EvidenceLine:
    """What the check proved of one kind of evidence.

    Attributes:
        kind: ``implementation`` or ``table``.
        status: ``verified``, ``failed``, ``expected-failure`` or ``not-checked``.
        text: The sentence (see :func:`fkcheck.engine.verdict.evidence_sentences`).
    """

    kind: str
    status: str
    text: str


@dataclass(frozen=True)
class NumberRow:
    """One number of the model in the report's table of numbers.

    Attributes:
        name: ``d1``, ``[base] z``, ``[frames.base_link] rz``.
        group: ``joint 1 (shoulder_pan)``, ``[base]``, ``[frames.NAME]``.
        value: Its value in the model, formatted (mm or degrees).
        status: After the check: ``verified``, ``failed``, ``not-checked``,
            ``not-identifiable``, ``not-covered`` or ``vouched``.
        note: Its resolution, what could absorb it, what it trades with, its source.
    """

    name: str
    group: str
    value: str
    status: str
    note: str


@dataclass(frozen=True)
class NumbersView:
    """What the compared frame pair verified of the model, number by number.

    Attributes:
        line: The one-line summary every output shows.
        rows: One row per number.
    """

    line: str
    rows: tuple[NumberRow, ...]


@dataclass(frozen=True)
class ReportPage:
    """One model's report page.

    Attributes:
        title: Page title.
        model: Model name.
        verdict: ``pass``, ``fail``, ``error`` or ``unverified``.
        verdict_line: The verdict as a sentence, e.g. "3 of 5 backends disagree".
        verdict_headline: The verdict with what it proved, e.g. "pass — implementation
            only; table not checked against anything independent".
        evidence: One line per kind of evidence (implementation, table).
        badge_note: Under the verdict badge: ``"implementation only"`` for a pass
            whose table nothing independent checked (the badge is then not green).
        disagreeing: Names of the backends that fail.
        headline: The largest errors among the disagreeing backends.
        facts: What was checked and how (key/value list), library versions and
            the command line that reproduces the check.
        sides: The two compared frames and what they mean.
        backends: One row per backend.
        plots: Error distribution and error against each joint.
        partings: Where the chains part: DH frames of backends built from the
            table, and the table's joint axes against the URDF's.
        details: One section per disagreeing backend.
        model_view: The model.
        generator: ``fkcheck <version>``.
        diagnoses: What ``fkcheck diagnose`` finds, per distinct disagreement
            (empty when the check passed or the diagnosis was not asked for).
        jacobian: The Jacobian section (``check --jacobian``), or ``None``.
        numbers: The model's numbers and what the check verified of each, or ``None``.
        calibration: What a calibrated model's calibration changes, one line
            (``""`` for other models).
    """

    title: str
    model: str
    verdict: str
    verdict_line: str
    verdict_headline: str
    evidence: tuple[EvidenceLine, ...]
    badge_note: str
    disagreeing: tuple[str, ...]
    headline: tuple[str, ...]
    facts: tuple[Fact, ...]
    sides: tuple[FrameSide, ...]
    backends: tuple[BackendRow, ...]
    plots: tuple[Image, ...]
    partings: tuple[PartingView, ...]
    details: tuple[BackendDetail, ...]
    model_view: ModelView
    generator: str
    diagnoses: tuple[DiagnosisView, ...] = ()
    jacobian: JacobianSection | None = None
    numbers: NumbersView | None = None
    calibration: str = ""
