"""The diagnosis section: the explanations found and the joint axes compared.

View models (:mod:`fkcheck.report.views`): plain text, numbers and nested views only.
"""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.report.views.cells import Measure

__all__ = [
    "AxisView",
    "DiagnosisView",
    "ExplanationView",
]


@dataclass(frozen=True)
class ExplanationView:
    """One explanation of a disagreement, with its evidence.

    Attributes:
        rank: 1 for the most likely.
        kind: What kind of mistake: ``frames``, ``mapping``, ``degrees``,
            ``convention``, ``conventions``, ``sign``, ``flip``, ``theta-offset``,
            ``parameter``, ``offset`` or ``fit``.
        title: One line that says it.
        explains: The change makes the disagreement vanish (within tolerance).
        verdict: ``"explains it"`` or ``"explains part of it"``.
        position_after: Position disagreement left once the table is changed this way.
        rotation_after: Rotation disagreement left (degrees first).
        changes: Each changed parameter: as it is, as it would match, the difference.
        details: More evidence or caveats, one line each.
        fix_toml: Model-file text that applies it, or empty.
        edits: Edits of the ``[[joint]]`` tables that apply it, one line each
            (``[[joint]] J3: flip = true``).
    """

    rank: int
    kind: str
    title: str
    explains: bool
    verdict: str
    position_after: Measure
    rotation_after: Measure
    changes: tuple[str, ...]
    details: tuple[str, ...]
    fix_toml: str
    edits: tuple[str, ...] = ()


@dataclass(frozen=True)
class AxisView:
    """One joint's axis from the table against the URDF's, as lines.

    Attributes:
        joint: ``"2 · shoulder_lift"``.
        urdf_joint: The URDF joint mapped to it.
        angle: Largest angle between the two directions (degrees first).
        distance: Largest distance between the two lines (none for a prismatic joint).
        status: ``agrees``, ``differs`` or ``reversed`` (anti-parallel: turns the other way).
        first: The first joint whose axis differs.
    """

    joint: str
    urdf_joint: str
    angle: Measure
    distance: Measure
    status: str
    first: bool


@dataclass(frozen=True)
class DiagnosisView:
    """What ``fkcheck diagnose`` finds for one disagreeing backend.

    Attributes:
        backend: The backend diagnosed.
        also: Other disagreeing backends with the same errors at every configuration
            of the check (within tolerance), which this diagnosis stands for.
        error: The diagnosis failed: the exception, in full (then nothing else is set).
        explained: Some explanation makes the disagreement vanish.
        verdict: One sentence: the most likely explanation, or that none was found.
        short: A few words for the page's first screen.
        configurations: How many configurations the diagnosis compared.
        position_before: The position disagreement as given, on those configurations.
        rotation_before: The rotation disagreement as given (degrees first).
        explanations: Most likely first.
        axes: Joint axes against the URDF (empty when the backend does not read it).
        axes_note: What the axes point at, in one line.
        tried: The hypotheses tried, one line each.
        command: The ``fkcheck diagnose`` command line that reproduces it (``""``: none,
            for a table fkcheck derived).
        duration: How long it took, formatted.
    """

    backend: str
    also: tuple[str, ...]
    error: str
    explained: bool
    verdict: str
    short: str
    configurations: int
    position_before: Measure
    rotation_before: Measure
    explanations: tuple[ExplanationView, ...]
    axes: tuple[AxisView, ...]
    axes_note: str
    tried: tuple[str, ...]
    command: str
    duration: str
