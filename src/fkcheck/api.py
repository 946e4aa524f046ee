"""The Python façade: check a model and write its reports in two calls.

Example:
    >>> import fkcheck
    >>> outcome = fkcheck.check("ur5", against=["rtb-dh", "pinocchio-urdf"], samples=200)
    >>> outcome.verdict
    'pass'
    >>> fkcheck.write_report(outcome, html="reports/ur5.html", json="reports/ur5.json")

:func:`check` runs the engine (:func:`fkcheck.engine.runner.run_check`) and, when
it fails, the diagnosis of each distinct disagreement
(:func:`fkcheck.diagnose.failures.diagnose_failures`); :func:`write_report`
formats that outcome — it runs no backend, no forward kinematics and no
parser. ``fkcheck check`` is these two calls plus the terminal.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from fkcheck.backends.base import Backend
from fkcheck.backends.registry import BackendOptions, default_backends, make_backend
from fkcheck.core.typing import JacobianReference
from fkcheck.diagnose.failures import BackendDiagnosis, diagnose_failures
from fkcheck.diagnose.jacobian import explain_sample
from fkcheck.engine.jacobian import JacobianSpec
from fkcheck.engine.plan import Plan
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.engine.runner import Progress, run_check
from fkcheck.engine.verdict import Verdict, headline
from fkcheck.model.options import CheckOptions, Sampler, jacobian_for, resolve_options
from fkcheck.model.read import load_model
from fkcheck.model.require import Kind
from fkcheck.model.types import Model

__all__ = ["Outcome", "check", "write_report"]


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
    samples: int | None = None,
    seed: int | None = None,
    sampler: Sampler | None = None,
    frame_from: str | None = None,
    frame_to: str | None = None,
    tol_pos_m: float | None = None,
    tol_rot_rad: float | None = None,
    timeout_s: float | None = None,
    require: Sequence[Kind] = (),
    jacobian: bool | None = None,
    jacobian_reference: JacobianReference | None = None,
    tol_jacobian: float | None = None,
    options: CheckOptions | None = None,
    diagnose: bool = True,
    explain_jacobians: bool = True,
    on_progress: Progress | None = None,
    on_done: Callable[[BackendResult], None] | None = None,
    full: bool | None = None,
    on_plan: Callable[[Plan], None] | None = None,
    lint_ignore: Sequence[str] = (),
) -> Outcome:
    """Cross-check a model's forward kinematics, and diagnose a failure.

    The options (``samples`` … ``tol_jacobian``) are those of
    :class:`~fkcheck.model.options.CheckOptions`, checked by its one rule; each
    one given wins over ``options``, which wins over the defaults
    (:data:`~fkcheck.model.options.DEFAULT_SAMPLES` samples, seed 0, Sobol,
    :data:`~fkcheck.model.options.DEFAULT_TIMEOUT_S` s) and the model's ``[check]``.

    Args:
        model: A loaded model, a bundled model's name (``"ur5"``) or a model file.
        against: Backends, as objects or names (``"rtb-dh"``, ``"pinocchio-urdf"``,
            ``"poses:measured.csv"``, ``"cmd:./fk"``, ``"module:function"``…);
            default: the standard set (see :mod:`fkcheck.backends.registry`).
            Backends named here get ``timeout_s`` as their own limit too (a
            ``cmd:`` program's, a plugin's); objects keep the one they were built with.
        samples: Random samples, on top of named poses, zero, mid-range and limit corners.
        seed: Seed of the random samples (0 … 2**64 - 1).
        sampler: ``"sobol"`` or ``"uniform"``.
        frame_from: Frame the compared pose is expressed in (default: the model's ``[check]``).
        frame_to: Frame whose pose is compared (default: the model's ``[check]``).
        tol_pos_m: Position tolerance, metres (default: the model's ``[check]``).
        tol_rot_rad: Rotation tolerance, radians (default: the model's ``[check]``).
        timeout_s: Time limit per backend, seconds.
        require: Kinds of evidence that must be verified (``"table"``,
            ``"implementation"``); else the verdict is ``unverified``.
        jacobian: Also compare each backend's Jacobian of ``frame_to`` (default:
            the model's ``[check] jacobian``); see :mod:`fkcheck.engine.jacobian`.
        jacobian_reference: ``"world-aligned"``, ``"local"`` or ``"world"``
            (default: the model's ``[check]``, else ``"world-aligned"``).
        tol_jacobian: Jacobian tolerance, m/rad and rad/rad (default: the model's ``[check]``).
        options: Options resolved already (``fkcheck check``'s flags over
            ``[tool.fkcheck]``, the pytest plugin's), with where each came from.
        diagnose: When the check fails, run ``fkcheck diagnose`` against each
            distinct disagreeing backend (about a second each).
        explain_jacobians: Name the convention behind each Jacobian that
            disagrees (:func:`fkcheck.diagnose.jacobian.explain_sample`, on the
            kept configurations: milliseconds).
        on_progress: Called as ``(backend, configurations done, total)``.
        on_done: Called with each backend's result as it finishes.
        full: Every backend compares every configuration (default: ``options``'s,
            else no: a backend whose declared cost does not fit its time limit
            compares a stated subset, :mod:`fkcheck.engine.plan`).
        on_plan: Called with the check's plan before any backend starts.
        lint_ignore: Lint rules the check's ``lint`` leaves out (as ``fkcheck lint
            --ignore``), on top of the model's own ``[lint] ignore``.

    Returns:
        The outcome: ``outcome.verdict``, ``outcome.check``, ``outcome.diagnoses``.

    Raises:
        FkcheckError: Bad input (unknown model, backend or frame, bad file…); an
            option out of its range is an ``OptionError`` naming it (also a
            ``ValueError``; a ``ToleranceError`` for a tolerance).
    """
    given = {
        "samples": samples, "seed": seed, "sampler": sampler, "timeout_s": timeout_s,
        "frame_from": frame_from, "frame_to": frame_to, "tol_pos_m": tol_pos_m,
        "tol_rot_rad": tol_rot_rad, "require": tuple(require), "jacobian": jacobian,
        "jacobian_reference": jacobian_reference, "tol_jacobian": tol_jacobian, "full": full,
    }  # fmt: skip
    opts = resolve_options(given, base=options)  # refuses a bad value before any work
    loaded = model if isinstance(model, Model) else load_model(model)
    limit = BackendOptions(  # the frames too: a ROS 2 bag composes its transform for them
        timeout_s=opts.timeout_s, frame_from=opts.frame_from, frame_to=opts.frame_to
    )
    if against is None:
        backends = default_backends(limit)
    else:
        backends = [b if not isinstance(b, str) else make_backend(b, limit) for b in against]
    jacobian_asked = jacobian_for(opts, loaded)
    spec = JacobianSpec(*jacobian_asked) if jacobian_asked is not None else None
    result = run_check(
        loaded,
        backends,
        samples=opts.samples,
        seed=opts.seed,
        sampler=opts.sampler,
        frame_from=opts.frame_from,
        frame_to=opts.frame_to,
        tol_pos_m=opts.tol_pos_m,
        tol_rot_rad=opts.tol_rot_rad,
        timeout_s=opts.timeout_s,
        require=opts.require,
        jacobian=spec,
        explain_jacobian=explain_sample if explain_jacobians else None,
        on_done=on_done,
        on_progress=on_progress,
        tolerance_source=opts.tolerance_source,
        full=opts.full,
        on_plan=on_plan,
        lint_ignore=lint_ignore,
    )
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
