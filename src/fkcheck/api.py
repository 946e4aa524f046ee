"""The Python façade: check a model and write its reports in two calls.

Example:
    >>> import fkcheck
    >>> outcome = fkcheck.check("ur5", against=["rtb-dh", "pinocchio-urdf"], samples=200)
    >>> outcome.verdict
    'pass'
    >>> fkcheck.write_report(outcome, html="reports/ur5.html", json="reports/ur5.json")

:func:`check` builds one request (:class:`~fkcheck.engine.request.CheckRequest`),
runs it through the engine (:func:`fkcheck.engine.runner.run_request`) and, when
it fails, the diagnosis of each distinct disagreement
(:func:`fkcheck.diagnose.failures.diagnose_failures`); :func:`write_report`
formats that outcome — it runs no backend, no forward kinematics and no
parser. ``fkcheck check`` is these two calls plus the terminal.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Unpack

from fkcheck.backends.base import Backend
from fkcheck.backends.registry import BackendOptions, default_backends, make_backend
from fkcheck.diagnose.failures import BackendDiagnosis, diagnose_failures
from fkcheck.diagnose.jacobian import explain_sample
from fkcheck.engine.plan import Plan
from fkcheck.engine.prepare import PreparedCheck
from fkcheck.engine.request import CheckRequest
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.engine.runner import Progress, run_request
from fkcheck.engine.verdict import Verdict, headline
from fkcheck.model.options import CheckOptions, OptionArgs, resolve_options
from fkcheck.model.read import load_model
from fkcheck.model.types import Model

__all__ = ["Outcome", "check", "check_request", "write_report"]


@dataclass(frozen=True, eq=False, repr=False)
class Outcome:
    """A finished check and the diagnoses of its disagreements: all a report shows.

    In a notebook it shows as a short HTML summary (``_repr_html_``: verdict,
    headline, each backend's status and largest errors), elsewhere as one line
    (``repr``); both are laid out from the check's record
    (:func:`fkcheck.report.record.check_record`), as every report is.

    Attributes:
        check: The check result (backends, errors, verdict, evidence).
        diagnoses: One per distinct disagreement, when the check failed and was
            diagnosed; empty otherwise.
    """

    check: CheckResult
    diagnoses: tuple[BackendDiagnosis, ...] = ()

    @property
    def verdict(self) -> Verdict:
        """``pass``, ``fail``, ``error`` or ``unverified``."""
        return self.check.verdict

    @property
    def headline(self) -> str:
        """The verdict with what it proved, e.g. ``pass — implementation only; …``."""
        return headline(self.check.verdict, self.check.evidence, len(self.check.ran))

    @property
    def backends(self) -> tuple[BackendResult, ...]:
        """One result per backend, in the order asked."""
        return self.check.backends

    def __repr__(self) -> str:
        """One line: the model, its headline and how many backends answered."""
        answered = len(self.check.ran)
        return (
            f"<fkcheck.Outcome {self.check.model.name!r}: {self.headline} "
            f"({answered} of {len(self.check.backends)} backends ran)>"
        )

    def _repr_html_(self) -> str:
        """The check's summary as an HTML fragment (Jupyter's rich display), escaped."""
        from fkcheck.report.html import render_summary
        from fkcheck.report.record import check_record

        return render_summary(check_record(self.check, self.diagnoses))


def check(
    model: Model | str | Path,
    against: Sequence[Backend | str] | None = None,
    *,
    options: CheckOptions | None = None,
    diagnose: bool = True,
    explain_jacobians: bool = True,
    on_progress: Progress | None = None,
    on_done: Callable[[BackendResult], None] | None = None,
    on_plan: Callable[[Plan], None] | None = None,
    lint_ignore: Sequence[str] = (),
    **given: Unpack[OptionArgs],
) -> Outcome:
    """Cross-check a model's forward kinematics, and diagnose a failure.

    The options are :class:`~fkcheck.model.options.CheckOptions`'s, given by
    name (``samples=200``, ``seed=3``, ``timeout_s=30``, ``require=["table"]``,
    ``jacobian=True``…) and checked by its one rule; each one given wins over
    ``options``, which wins over the defaults
    (:data:`~fkcheck.model.options.DEFAULT_SAMPLES` samples, seed 0, Sobol,
    :data:`~fkcheck.model.options.DEFAULT_TIMEOUT_S` s) and the model's ``[check]``
    (frames, tolerances, Jacobian).

    Args:
        model: A loaded model, a bundled model's name (``"ur5"``) or a model file.
        against: Backends, as objects or names (``"rtb-dh"``, ``"pinocchio-urdf"``,
            ``"poses:measured.csv"``, ``"cmd:./fk"``, ``"module:function"``…);
            default: the standard set (see :mod:`fkcheck.backends.registry`).
            Backends named here get ``timeout_s`` as their own limit too (a
            ``cmd:`` program's, a plugin's); objects keep the one they were built with.
        options: Options resolved already (``fkcheck check``'s flags over
            ``[tool.fkcheck]``, the pytest plugin's), with where each came from.
        diagnose: When the check fails, run ``fkcheck diagnose`` against each
            distinct disagreeing backend (about a second each).
        explain_jacobians: Name the convention behind each Jacobian that
            disagrees (:func:`fkcheck.diagnose.jacobian.explain_sample`, on the
            kept configurations: milliseconds).
        on_progress: Called as ``(backend, configurations done, total)``.
        on_done: Called with each backend's result as it finishes.
        on_plan: Called with the check's plan before any backend starts.
        lint_ignore: Lint rules the check's ``lint`` leaves out (as ``fkcheck lint
            --ignore``), on top of the model's own ``[lint] ignore``.
        **given: The options by name (:class:`~fkcheck.model.options.OptionArgs`):
            ``samples``, ``seed``, ``sampler``, ``frame_from``, ``frame_to``,
            ``tol_pos_m``, ``tol_rot_rad``, ``timeout_s``, ``require``,
            ``jacobian``, ``jacobian_reference``, ``tol_jacobian``, ``full``…

    Returns:
        The outcome: ``outcome.verdict``, ``outcome.check``, ``outcome.diagnoses``.

    Raises:
        FkcheckError: Bad input (unknown model, backend or frame, bad file…); an
            option out of its range is an ``OptionError`` naming it (also a
            ``ValueError``; a ``ToleranceError`` for a tolerance).
    """
    opts = resolve_options(given, base=options)  # refuses a bad value before any work
    loaded = model if isinstance(model, Model) else load_model(model)
    limit = BackendOptions(  # the frames too: a ROS 2 bag composes its transform for them
        timeout_s=opts.timeout_s, frame_from=opts.frame_from, frame_to=opts.frame_to
    )
    if against is None:
        backends = default_backends(limit, loaded)
    else:
        backends = [b if not isinstance(b, str) else make_backend(b, limit) for b in against]
    explain = explain_sample if explain_jacobians else None
    request = CheckRequest(loaded, tuple(backends), opts, tuple(lint_ignore), explain)
    return check_request(
        request, diagnose=diagnose, on_progress=on_progress, on_done=on_done, on_plan=on_plan
    )


def check_request(
    request: CheckRequest | PreparedCheck,
    *,
    diagnose: bool = True,
    on_progress: Progress | None = None,
    on_done: Callable[[BackendResult], None] | None = None,
    on_plan: Callable[[Plan], None] | None = None,
) -> Outcome:
    """One request's check (:func:`~fkcheck.engine.runner.run_request`), and its diagnoses.

    :func:`check`, ``fkcheck check`` and the pytest plugin each build one
    :class:`~fkcheck.engine.request.CheckRequest`; the command line passes it
    prepared (its inputs read before the header is printed).

    Args:
        request: The request, or the request prepared.
        diagnose: When the check fails, diagnose each distinct disagreeing backend.
        on_progress: Called as ``(backend, configurations done, total)``.
        on_done: Called with each backend's result as it finishes.
        on_plan: Called with the check's plan before any backend starts.

    Returns:
        The outcome.

    Raises:
        FkcheckError: Bad input.
    """
    result = run_request(request, on_done=on_done, on_progress=on_progress, on_plan=on_plan)
    backends = (request.request if isinstance(request, PreparedCheck) else request).backends
    diagnoses = diagnose_failures(result, backends) if diagnose else ()
    return Outcome(result, diagnoses)


def write_report(
    outcome: Outcome,
    *,
    html: Path | str | None = None,
    json: Path | str | None = None,
    junit: Path | str | None = None,
    summary: Path | str | None = None,
    plots: bool = True,
) -> tuple[Path, ...]:
    """Write an outcome's reports, each atomically; only formats, never recomputes.

    ``fkcheck check`` writes its reports through the same function
    (:func:`fkcheck.report.write.write_reports`).

    Args:
        outcome: What :func:`check` returned.
        html: The self-contained HTML report.
        json: The JSON result (the contract other tools read).
        junit: JUnit XML, one test case per backend and per kind of evidence.
        summary: The Markdown summary (as for ``$GITHUB_STEP_SUMMARY``).
        plots: Draw the HTML report's pictures.

    Returns:
        The paths written, in the order html, json, junit, summary.
    """
    from fkcheck.report.write import write_reports

    return write_reports(
        outcome.check,
        outcome.diagnoses,
        html=html,
        json=json,
        junit=junit,
        summary=summary,
        plots=plots,
    )
