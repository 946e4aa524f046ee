"""A check's last stage: from the backends' results to the verdict.

:func:`judge` takes a :class:`~fkcheck.engine.prepare.PreparedCheck` and the
run's results (:mod:`fkcheck.engine.runner`): it applies the model's known
differences (:mod:`fkcheck.engine.expected`), provenance (a URDF exported
from this very table proves nothing about it, :mod:`fkcheck.engine.provenance`)
and reader findings (one reader of a file disagrees where another agrees with
the table, :mod:`fkcheck.engine.readers`), judges the numbers on what the
table's evidence answered, lints the model, and returns the
:class:`~fkcheck.engine.results.CheckResult` with its verdict and the request's
options.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import replace

from fkcheck.calibration.lint import lint_calibrated
from fkcheck.engine.expected import (
    apply_known_differences,
    known_difference_findings,
    library_of,
)
from fkcheck.engine.prepare import PreparedCheck, numbers_of
from fkcheck.engine.provenance import apply_provenance
from fkcheck.engine.readers import apply_reader_findings
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.engine.verdict import summarize, verdict_of
from fkcheck.model.lint import lint_lines
from fkcheck.model.types import Model

__all__ = ["judge"]


def judge(prepared: PreparedCheck, results: Sequence[BackendResult]) -> CheckResult:
    """The check's result: ``results`` (one per backend, in order) judged, with the verdict."""
    request, model, pair, tol = prepared.request, prepared.model, prepared.pair, prepared.tol
    backends, q = request.backends, prepared.samples
    readers = {b.name: b.reads for b in backends if getattr(b, "formats", ())}
    libraries = {b.name: library_of(b) for b in backends if b.name in readers or _versioned(model)}
    ordered = apply_known_differences(
        model, pair, tol, list(results), {b.name: b.reads for b in backends}, libraries
    )
    ordered = apply_provenance(model, backends, tol, ordered)  # a URDF from this very table
    ordered = apply_reader_findings(ordered, readers, libraries)  # one reader of a file wrong
    numbers = prepared.numbers
    answered = _table_answered(ordered, len(q.q))
    if 0 < answered < len(q.q):  # the numbers are judged on what the table's evidence compared
        numbers = numbers_of(
            model, pair, tol, q.q[:answered], prepared.competitors, request.options.timeout_s
        )
    # A Jacobian that disagrees fails the check, one that could not be computed is
    # its error; the evidence (what the poses proved) is the poses' alone.
    jacobians = [replace(r, status=r.jacobian.status) for r in ordered if r.jacobian and r.ran]
    return CheckResult(
        model=model,
        options=request.options,
        frame_from=pair[0],
        frame_to=pair[1],
        tol_pos_m=tol[0],
        tol_rot_rad=tol[1],
        q=q.q,
        origin=q.origin,
        backends=ordered,
        verdict=verdict_of((*ordered, *jacobians), summarize(ordered, prepared.required, numbers)),
        required=prepared.required,
        created=prepared.created,
        duration_s=time.perf_counter() - prepared.started_s,
        jacobian=prepared.jacobian,
        numbers=numbers,
        calibration=prepared.calibration,
        lint=_lint(model, request.lint_ignore),
    )


def _lint(model: Model, ignore: tuple[str, ...]) -> tuple[str, ...]:
    """What lint finds in the model; nothing for a table fkcheck derived (no one wrote it)."""
    if model.derived is not None:
        return ()
    return lint_lines(
        model,
        [*lint_calibrated(model, ignore)[0], *known_difference_findings(model, ignore)],
    )


def _table_answered(results: Sequence[BackendResult], total: int) -> int:
    """How many configurations the agreeing table evidence compared: the most any one did.

    A backend on a subset compares a prefix of the check's configurations
    (:mod:`fkcheck.engine.plan`), so the prefixes nest: the longest one is their
    union, and it is one backend's own. Each number is then verified only when
    configurations that one agreeing backend answered tell it apart. ``0`` when
    no table evidence agreed (no number is verified then anyway).
    """
    return max(
        (
            r.subset[0] if r.subset is not None else total
            for r in results
            if r.evidence == "table" and r.status == "pass"
        ),
        default=0,
    )


def _versioned(model: Model) -> bool:
    """Whether a known difference of the model is tied to a library's versions."""
    return any(e.versions for e in model.known_differences)
