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
from fkcheck.engine.verdict import KINDS, evidence_sentences
from fkcheck.engine.verdict import headline as verdict_headline
from fkcheck.io.format import (
    format_deg,
    format_m,
    format_mm,
    format_rad,
    format_seconds,
)
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

__all__ = ["build_report_page", "verdict_line"]


def verdict_line(check: CheckResult) -> str:
    """The verdict as one sentence."""
    ran = check.ran
    failing = [r.name for r in check.backends if r.status == "fail"]
    errored = [r.name for r in check.backends if r.status == "error"]
    skipped = [r.name for r in check.backends if r.status == "skipped"]
    expected = [r.name for r in check.backends if r.status == "xfail"]
    stale = [r.name for r in check.backends if r.status == "xpass"]
    parts = []
    if not ran:
        parts.append("No reference backend ran: nothing was cross-checked")
    elif failing:
        parts.append(
            f"{len(failing)} of {len(ran)} backends that ran disagree with the in-house core: "
            + ", ".join(failing)
        )
    else:
        agreed = sum(r.status == "pass" for r in ran)
        parts.append(f"{agreed} of {len(ran)} backends that ran agree with the in-house core")
    if errored:
        parts.append(f"{len(errored)} errored: " + ", ".join(errored))
    if skipped:
        parts.append(f"{len(skipped)} skipped: " + ", ".join(skipped))
    if expected:
        parts.append(
            f"{len(expected)} disagree as the model records (expected failure, known "
            "difference): " + ", ".join(expected)
        )
    if stale:
        parts.append(
            f"{len(stale)} agree though the model records a difference (known difference no "
            "longer seen): " + ", ".join(stale)
        )
    jac_bad = [r.name for r in check.backends if r.jacobian and r.jacobian.status == "fail"]
    jac_error = [r.name for r in check.backends if r.jacobian and r.jacobian.status == "error"]
    if jac_bad:
        parts.append(f"the Jacobian of {len(jac_bad)} disagrees: " + ", ".join(jac_bad))
    if jac_error:
        parts.append(f"the Jacobian of {len(jac_error)} errored: " + ", ".join(jac_error))
    return "; ".join(parts) + "."


def _headline(check: CheckResult) -> tuple[str, ...]:
    out = []
    for r in check.backends:
        if r.status != "fail":
            continue
        assert r.position_error_m is not None
        assert r.rotation_error_rad is not None
        n_bad = int(
            (
                (r.position_error_m > check.tol_pos_m) | (r.rotation_error_rad > check.tol_rot_rad)
            ).sum()
        )
        out.append(
            f"{r.name}: max position error {format_mm(r.max_position_error_m)} "
            f"({format_m(r.max_position_error_m)}), max rotation error "
            f"{format_rad(r.max_rotation_error_rad)} ({format_deg(r.max_rotation_error_rad)}); "
            f"{n_bad} of {r.position_error_m.size} configurations beyond tolerance"
        )
    return tuple(out)


def _with_also(d: DiagnosisView) -> str:
    """``pinocchio-urdf`` or ``pinocchio-urdf (and yourdfpy-urdf, rtb-urdf)``."""
    return d.backend + (f" (and {', '.join(d.also)})" if d.also else "")


def _configurations(check: CheckResult) -> str:
    counts = Counter(o.split(":")[0] for o in check.origin)
    names = {
        "pose": "named poses",
        "zero": "zero",
        "mid": "mid-range",
        "corner": "limit corners",
        "edge": "limit edges",
        "random": f"{check.sampler} samples",
    }
    parts = [f"{counts[key]} {label}" for key, label in names.items() if counts.get(key)]
    return f"{check.q.shape[0]} ({', '.join(parts)}); seed {check.seed}"


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

    failing = [r for r in check.backends if r.status == "fail"]
    details = tuple(backend_detail(check, r, plots) for r in failing)
    diagnosis_views = tuple(diagnosis_view(d) for d in diagnoses)
    rows = tuple(backend_row(check, r, r.status == "fail") for r in check.backends)
    images: list[Image] = []
    if plots:
        images = [
            im for im in (error_distribution(check), error_against_joints(check)) if im is not None
        ]
    versions = library_versions() if versions is None else versions
    tol = (
        f"{check.tol_pos_m:g} m ({format_mm(check.tol_pos_m)}) position, "
        f"{check.tol_rot_rad:g} rad ({format_deg(check.tol_rot_rad)}) rotation"
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
        Fact("reference", f"{REFERENCE_NAME}: the in-house DH core ({model.convention} DH)"),
        Fact(
            "model file",
            str(model.path) if model.path is not None else "(built in memory)",
            volatile="path",
        ),
        Fact(
            "configuration",
            f"[tool.fkcheck] of {check.config}" if check.config is not None else "none",
            volatile="path" if check.config is not None else "",
        ),
        Fact("checked at", check.created or "–", volatile="date"),
        Fact("took", format_seconds(check.duration_s), volatile="duration"),
        Fact("versions", " · ".join(f"{k} {v}" for k, v in versions.items()), volatile="version"),
        Fact("reproduce", check.command or "(run from Python: no command line)", code=True),
    )
    parting_views = partings(check)
    headline = (
        _headline(check)
        + tuple(f"Diagnosis against {_with_also(d)}: {d.short}" for d in diagnosis_views)
        + tuple(f"Where the chains part: {p.short}." for p in parting_views if p.short)
    )
    evidence = check.evidence
    return ReportPage(
        title=f"fkcheck {model.name}: {check.verdict.upper()}",
        model=model.name,
        verdict=check.verdict,
        verdict_line=verdict_line(check),
        verdict_headline=verdict_headline(check.verdict, evidence, len(check.ran)),
        evidence=tuple(
            EvidenceLine(kind, evidence.of(kind).status, text)
            for kind, text in zip(KINDS, evidence_sentences(evidence), strict=True)
        ),
        badge_note=(
            "expected failure: known difference"
            if check.verdict == "pass" and evidence.table.status == "expected-failure"
            else "table partly verified"
            if check.verdict == "pass" and evidence.table.status == "partly-verified"
            else "implementation only"
            if check.verdict == "pass" and evidence.table.status != "verified"
            else ""
        ),
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
        jacobian=jacobian_section(check),
        numbers=numbers_view(check),
    )
