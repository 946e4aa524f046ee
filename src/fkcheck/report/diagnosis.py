"""The Diagnosis section of a failed check's report: views of the diagnoses already run.

The diagnoses come from :func:`fkcheck.diagnose.failures.diagnose_failures`,
run after the check; :func:`diagnosis_view` turns one outcome into the view
model the template lays out. Nothing here runs a diagnosis.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from fkcheck.description.registry import model_format
from fkcheck.io.format import format_seconds
from fkcheck.report.measures import measure_m, measure_rad
from fkcheck.report.views import AxisView, DiagnosisView, ExplanationView

if TYPE_CHECKING:
    from fkcheck.diagnose import Diagnosis, Explanation
    from fkcheck.diagnose.failures import BackendDiagnosis

__all__ = ["diagnosis_for", "diagnosis_headline", "diagnosis_view"]


def _explanation_view(rank: int, e: Explanation) -> ExplanationView:
    return ExplanationView(
        rank=rank,
        kind=e.kind,
        title=e.title,
        explains=e.explains,
        verdict="explains it" if e.explains else "explains part of it",
        position_after=measure_m(e.residual.position_m),
        rotation_after=measure_rad(e.residual.rotation_rad),
        changes=tuple(c.text() + (f" ({c.note})" if c.note else "") for c in e.changes),
        details=e.details,
        fix_toml=e.fix_toml,
        edits=e.edits,
    )


def _axes(d: Diagnosis) -> tuple[AxisView, ...]:
    fmt = model_format(d.model)
    urdf = fmt.mapped_joints(d.model) if fmt is not None else ()
    first = next((a.joint for a in d.axes if not a.agrees), None)
    return tuple(
        AxisView(
            joint=f"{a.joint + 1} · {a.name}",
            urdf_joint=urdf[a.joint] if a.joint < len(urdf) else "",
            angle=measure_rad(a.angle_rad),
            distance=measure_m(a.distance_m),
            status="agrees" if a.agrees else ("reversed" if a.reversed else "differs"),
            first=a.joint == first,
        )
        for a in d.axes
    )


def _sentence(text: str) -> str:
    """``first axis that differs: …`` as a sentence: capital first letter, full stop."""
    if not text:
        return ""
    text = text[0].upper() + text[1:]
    return text if text.endswith((".", "?", "!")) else text + "."


def _verdict(d: Diagnosis) -> tuple[str, str]:
    """The sentence for the section and the few words for the first screen."""
    best = d.best
    if best is not None:
        changes = "; ".join(c.text() for c in best.changes[:3])
        more = f" (and {len(best.changes) - 3} more)" if len(best.changes) > 3 else ""
        short = best.title + (f" — {changes}{more}" if changes else "")
        return f"Most likely: {best.title}.", short
    if d.agrees:
        text = (
            f"On its {d.configurations} configurations the diagnosis finds the table within "
            f"tolerance of {d.backend}: the check's disagreement lies at configurations it does "
            "not sample (limit corners and edges)."
        )
        return text, "no disagreement on the diagnosis's own configurations"
    if d.explanations:
        text = (
            "Not explained: no single change makes the disagreement vanish; the changes "
            "below remove at least half of it."
        )
        return text, "not explained by any one change (partial explanations below)"
    text = "Not explained: no hypothesis explains the disagreement, or even half of it."
    return text, "not explained by any hypothesis tried"


def diagnosis_view(outcome: BackendDiagnosis) -> DiagnosisView:
    """The view model of one outcome of :func:`~fkcheck.diagnose.failures.diagnose_failures`."""
    d = outcome.diagnosis
    if d is None:
        first_line = outcome.error.splitlines()[0] if outcome.error else "failed"
        return DiagnosisView(
            backend=outcome.backend,
            also=outcome.also,
            error=outcome.error or "the diagnosis failed",
            explained=False,
            verdict=f"The diagnosis against {outcome.backend} could not run.",
            short=f"could not run: {first_line}",
            configurations=0,
            position_before=measure_m(None),
            rotation_before=measure_rad(None),
            explanations=(),
            axes=(),
            axes_note="",
            tried=(),
            command=outcome.command,
            duration="",
        )
    verdict, short = _verdict(d)
    return DiagnosisView(
        backend=outcome.backend,
        also=outcome.also,
        error="",
        explained=d.explained,
        verdict=verdict,
        short=short,
        configurations=d.configurations,
        position_before=measure_m(d.before.position_m),
        rotation_before=measure_rad(d.before.rotation_rad),
        explanations=tuple(_explanation_view(k, e) for k, e in enumerate(d.explanations, start=1)),
        axes=_axes(d),
        axes_note=_sentence(d.axes_note),
        tried=d.tried,
        command=outcome.command,
        duration=format_seconds(d.duration_s),
    )


def diagnosis_for(diagnoses: Sequence[BackendDiagnosis], backend: str) -> BackendDiagnosis | None:
    """The diagnosis that stands for ``backend`` (its own, or a twin's via ``also``), if any."""
    return next((d for d in diagnoses if backend == d.backend or backend in d.also), None)


def diagnosis_headline(outcome: BackendDiagnosis) -> str:
    """The cause in one line, for a CI artefact: the best explanation's title, else why not.

    ``α5 (wrist_2) has the wrong sign: 90° here, the opposite matches``; without
    an explanation, the few words of :func:`diagnosis_view` (``not explained by
    any hypothesis tried``, ``could not run: …``).
    """
    d = outcome.diagnosis
    best = d.best if d is not None else None
    return best.title if best is not None else diagnosis_view(outcome).short
