"""A check → its report page's view model: verdict, facts, headline, sections.

Every number goes through :mod:`fkcheck.io.format`; text from a model
file or URDF passes through unchanged and is escaped by the templates.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import TYPE_CHECKING

from fkcheck._version import __version__
from fkcheck.engine.results import REFERENCE_NAME, CheckResult
from fkcheck.io.format import format_deg, format_mm, format_pair, format_seconds
from fkcheck.report.views import (
    DiagnosisView,
    EvidenceLine,
    Fact,
    Image,
    ReportPage,
)

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis

from fkcheck.report.backend_view import backend_detail, backend_row
from fkcheck.report.model_view import frame_sides, model_view
from fkcheck.report.numbers_view import numbers_view
from fkcheck.report.partings import partings
from fkcheck.report.record import CheckRecord, check_record, verdict_line
from fkcheck.urdf.locate import display_path

__all__ = ["build_report_page", "verdict_line"]  # verdict_line: see fkcheck.report.record


def _headline(record: CheckRecord) -> tuple[str, ...]:
    """One line per failing backend's summary; backends with the same summary share one."""
    names: dict[str, list[str]] = {}
    for r in record.backends:
        if r.status == "fail":
            names.setdefault(r.summary, []).append(r.name)
    return tuple(f"{', '.join(who)}: {summary}" for summary, who in names.items())


def _diagnosis_bullets(views: Sequence[DiagnosisView]) -> tuple[str, ...]:
    """One line per diagnosis; diagnoses that say the same thing share one.

    ``Diagnosis against pinocchio-urdf (and yourdfpy-urdf, rtb-urdf): …``.
    """
    names: dict[str, list[str]] = {}
    for d in views:
        names.setdefault(d.short, []).extend([d.backend, *d.also])
    out = []
    for short, who in names.items():
        first, *also = dict.fromkeys(who)
        others = f" (and {', '.join(also)})" if also else ""
        out.append(f"Diagnosis against {first}{others}: {short}")
    return tuple(out)


def _configurations(check: CheckResult) -> str:
    counts = Counter(o.split(":")[0] for o in check.origin)
    names = {
        "pose": "named poses",
        "zero": "zero",
        "mid": "mid-range",
        "corner": "limit corners",
        "edge": "limit edges",
        "random": f"{check.options.sampler} samples",
    }
    parts = [f"{counts[key]} {label}" for key, label in names.items() if counts.get(key)]
    return f"{check.q.shape[0]} ({', '.join(parts)}); seed {check.options.seed}"


def build_report_page(
    check: CheckResult,
    *,
    diagnoses: Sequence[BackendDiagnosis] = (),
    versions: dict[str, str] | None = None,
    plots: bool = True,
) -> ReportPage:
    """The report page of one check, from what the check and the diagnosis gathered.

    Runs no backend, no forward kinematics and no parser: the worst
    configurations' poses, the chains and the axes come from each failing
    backend's :attr:`~fkcheck.engine.results.BackendResult.detail`.

    Args:
        check: The check result.
        diagnoses: The diagnoses of its disagreements (see
            :func:`fkcheck.diagnose.failures.diagnose_failures`), for the
            Diagnosis section; each also gets a line on the first screen.
        versions: Library versions to show (default: the installed ones).
        plots: Draw the pictures (Matplotlib); off, the page has none.

    Returns:
        The page's view model.
    """
    from fkcheck.report.diagnosis import diagnosis_view
    from fkcheck.report.jacobian_view import jacobian_section
    from fkcheck.report.plots import error_against_joints, error_distribution
    from fkcheck.report.versions import library_versions

    record = check_record(check, diagnoses)
    failing = [r for r in check.backends if r.status == "fail"]
    details = tuple(backend_detail(check, r, plots) for r in failing)
    diagnosis_views = tuple(diagnosis_view(d) for d in diagnoses)
    rows = tuple(backend_row(r, r.status == "fail") for r in record.backends)
    images: list[Image] = []
    if plots:
        images = [
            im for im in (error_distribution(check), error_against_joints(check)) if im is not None
        ]
    versions = library_versions() if versions is None else versions
    tol = (
        f"{format_pair(format_mm(check.tol_pos_m), f'{check.tol_pos_m:g} m')} position, "
        f"{format_pair(format_deg(check.tol_rot_rad), f'{check.tol_rot_rad:g} rad')} rotation"
    )
    model = check.model
    facts = (
        Fact("model", model.name),
        Fact(
            "compared",
            f"{check.frame_from}_T_{check.frame_to}: the pose of "
            f"{check.frame_to} in {check.frame_from}",
        ),
        Fact("tolerance", tol),
        Fact("configurations", _configurations(check)),
        Fact("time limit", f"{check.options.timeout_s:g} s per backend"),
        Fact("reference", f"{REFERENCE_NAME}: the in-house DH core ({model.convention} DH)"),
        Fact(
            "model file",
            display_path(model.path) if model.path is not None else "(built in memory)",
            volatile="path",
        ),
        Fact(
            "configuration",
            "none" if check.config is None else f"[tool.fkcheck] of {display_path(check.config)}",
            volatile="path" if check.config is not None else "",
        ),
        Fact("checked at", check.created or "–", volatile="date"),
        Fact("took", format_seconds(check.duration_s), volatile="duration"),
        Fact("versions", " · ".join(f"{k} {v}" for k, v in versions.items()), volatile="version"),
        Fact("reproduce", check.command or "(run from Python: no command line)", code=True),
    )
    parting_views = partings(check)
    headline = (
        _headline(record)
        + _diagnosis_bullets(diagnosis_views)
        + tuple(f"Where the chains part: {p.short}." for p in parting_views if p.short)
    )
    return ReportPage(
        title=f"fkcheck {model.name}: {check.verdict.upper()}",
        model=model.name,
        verdict=check.verdict,
        verdict_line=record.verdict_line,
        verdict_headline=record.headline,
        evidence=tuple(EvidenceLine(e.kind, e.status, e.sentence) for e in record.evidence),
        badge_note=record.partial,
        disagreeing=tuple(r.name for r in failing),
        headline=headline,
        facts=facts,
        sides=frame_sides(check),
        backends=rows,
        plots=tuple(images),
        partings=parting_views,
        details=details,
        model_view=model_view(check),
        generator=f"fkcheck {__version__}",
        diagnoses=diagnosis_views,
        jacobian=jacobian_section(check, record),
        numbers=numbers_view(check, record),
        calibration=record.calibration_line,
    )
