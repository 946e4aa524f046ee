"""The Diagnosis section of a failed check's report: ``fkcheck diagnose``, run for the page.

:func:`diagnose_failures` runs :func:`fkcheck.diagnose.diagnose` against the
check's disagreeing backends, with the check's model, frame pair, tolerances
and seed, once per distinct disagreement: a backend whose errors equal those of
one already diagnosed (within tolerance, at every configuration of the check —
the URDF backends reading one URDF, typically) shares its diagnosis. It never
raises for a diagnosis that fails: the exception is kept as text and the page
says so, so the report is always written. :func:`diagnosis_view` turns one
outcome into the view model the template lays out.
"""

from __future__ import annotations

import shlex
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from fkcheck.engine.evidence import require_aligned
from fkcheck.report.build import measure_deg, measure_m
from fkcheck.report.format import format_seconds
from fkcheck.report.views import AxisView, DiagnosisView, ExplanationView

if TYPE_CHECKING:
    from fkcheck.backends.base import Backend
    from fkcheck.diagnose import Diagnosis, Explanation
    from fkcheck.engine.results import BackendResult, CheckResult

__all__ = [
    "BackendDiagnosis",
    "diagnose_command",
    "diagnose_failures",
    "diagnosis_section",
    "diagnosis_view",
    "same_disagreement",
]


@dataclass(frozen=True, eq=False)
class BackendDiagnosis:
    """The diagnosis of one disagreeing backend, or why there is none.

    Attributes:
        backend: The backend diagnosed.
        diagnosis: What :func:`fkcheck.diagnose.diagnose` returned, or ``None`` when it raised.
        error: The exception it raised, ``"Type: message"`` in full (empty when it ran).
        also: Other disagreeing backends this diagnosis stands for (see
            :func:`same_disagreement`).
        command: The ``fkcheck diagnose`` command line that reproduces it.
    """

    backend: str
    diagnosis: Diagnosis | None
    error: str = ""
    also: tuple[str, ...] = ()
    command: str = ""


def same_disagreement(check: CheckResult, a: BackendResult, b: BackendResult) -> bool:
    """Whether two backends' errors agree within tolerance at every configuration of the check.

    Then they almost surely compute the same poses (two libraries reading the
    same URDF, say), and one diagnosis stands for both.
    """
    arrays = (a.position_error_m, b.position_error_m, a.rotation_error_rad, b.rotation_error_rad)
    if any(x is None for x in arrays):
        return False
    pa, pb, ra, rb = (np.asarray(x) for x in arrays)
    return bool(
        pa.shape == pb.shape
        and np.all(np.abs(pa - pb) <= check.tol_pos_m)
        and np.all(np.abs(ra - rb) <= check.tol_rot_rad)
    )


def diagnose_command(check: CheckResult, backend: str) -> str:
    """The ``fkcheck diagnose`` command line that reproduces a diagnosis of the report."""
    model = check.model
    argv = ["diagnose", str(model.path) if model.path is not None else model.name]
    argv += ["--against", backend, "--from", check.frame_from, "--to", check.frame_to]
    if check.seed != 0:
        argv += ["--seed", str(check.seed)]
    if check.tol_pos_m != model.check.tol_pos_m:
        argv += ["--tol-pos", repr(check.tol_pos_m)]
    if check.tol_rot_rad != model.check.tol_rot_rad:
        argv += ["--tol-rot", repr(check.tol_rot_rad)]
    return "fkcheck " + shlex.join(argv)


def _run_one(check: CheckResult, backend: Backend) -> tuple[Diagnosis | None, str]:
    """Diagnose one backend with the check's settings; an exception becomes its text."""
    from fkcheck.backends.base import FixedConfigurations
    from fkcheck.diagnose import diagnose

    try:
        # A measured-poses backend only has poses at its own configurations.
        q = (
            backend.configurations(check.model)
            if isinstance(backend, FixedConfigurations)
            else None
        )
        result = diagnose(
            check.model,
            backend,
            frame_from=check.frame_from,
            frame_to=check.frame_to,
            seed=check.seed,
            q=q,
            tol_pos_m=check.tol_pos_m,
            tol_rot_rad=check.tol_rot_rad,
        )
    except Exception as exc:  # the report must be written whatever the diagnosis does
        return None, f"{type(exc).__name__}: {exc}"
    return result, ""


def diagnose_failures(
    check: CheckResult, backends: Sequence[Backend]
) -> tuple[BackendDiagnosis, ...]:
    """Diagnose each distinct disagreement of a check, in the order of the backends.

    Args:
        check: The check result.
        backends: The backend objects the check ran, aligned with ``check.backends``.

    Returns:
        One outcome per diagnosed backend (none when no backend failed). A
        diagnosis that raises is an outcome with its error text, never an exception.

    Raises:
        ValueError: ``backends`` does not match ``check.backends``.
    """
    require_aligned(check, backends)
    diagnosed: list[tuple[BackendResult, BackendDiagnosis, list[str]]] = []
    for result, backend in zip(check.backends, backends, strict=True):
        if result.status != "fail":
            continue
        twin = next((t for t in diagnosed if same_disagreement(check, t[0], result)), None)
        if twin is not None:
            twin[2].append(result.name)
            continue
        diagnosis, error = _run_one(check, backend)
        command = diagnose_command(check, result.name)
        diagnosed.append((result, BackendDiagnosis(result.name, diagnosis, error, (), command), []))
    return tuple(
        BackendDiagnosis(d.backend, d.diagnosis, d.error, tuple(also), d.command)
        for _, d, also in diagnosed
    )


def _explanation_view(rank: int, e: Explanation) -> ExplanationView:
    return ExplanationView(
        rank=rank,
        kind=e.kind,
        title=e.title,
        explains=e.explains,
        verdict="explains it" if e.explains else "explains part of it",
        position_after=measure_m(e.residual.position_m),
        rotation_after=measure_deg(e.residual.rotation_rad),
        changes=tuple(c.text() + (f" ({c.note})" if c.note else "") for c in e.changes),
        details=e.details,
        fix_toml=e.fix_toml,
    )


def _axes(d: Diagnosis) -> tuple[AxisView, ...]:
    urdf = d.model.urdf.joints if d.model.urdf is not None else ()
    first = next((a.joint for a in d.axes if not a.agrees), None)
    return tuple(
        AxisView(
            joint=f"{a.joint + 1} · {a.name}",
            urdf_joint=urdf[a.joint] if a.joint < len(urdf) else "",
            angle=measure_deg(a.angle_rad),
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
    """The view model of one outcome of :func:`diagnose_failures`."""
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
            rotation_before=measure_deg(None),
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
        rotation_before=measure_deg(d.before.rotation_rad),
        explanations=tuple(_explanation_view(k, e) for k, e in enumerate(d.explanations, start=1)),
        axes=_axes(d),
        axes_note=_sentence(d.axes_note),
        tried=d.tried,
        command=outcome.command,
        duration=format_seconds(d.duration_s),
    )


def diagnosis_section(check: CheckResult, backends: Sequence[Backend]) -> tuple[DiagnosisView, ...]:
    """Diagnose a check's disagreements and build their views (none when nothing failed)."""
    if check.verdict != "fail":
        return ()
    return tuple(diagnosis_view(o) for o in diagnose_failures(check, backends))
