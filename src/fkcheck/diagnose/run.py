"""The diagnosis, end to end: reference poses once, then every step, ranked."""

from __future__ import annotations

import time
from dataclasses import replace

from fkcheck.backends.base import Backend, FixedConfigurations, reads_model_description
from fkcheck.core.tolerances import pose_tolerances
from fkcheck.core.typing import Float
from fkcheck.diagnose.axes import axes_note, compare_axes
from fkcheck.diagnose.conventions import explain_conventions
from fkcheck.diagnose.findings import AxisRow, Diagnosis, Explanation, rank
from fkcheck.diagnose.hypotheses import explain_hypotheses, explain_swapped_mapping
from fkcheck.diagnose.identify import Unsettled, unsettled_numbers
from fkcheck.diagnose.offsets import explain_offsets
from fkcheck.diagnose.paramfit import explain_parameter_fit
from fkcheck.diagnose.problem import Problem, Residual, diagnosis_configurations
from fkcheck.engine.expected import known_difference_for, library_of
from fkcheck.model.options import DEFAULT_TIMEOUT_S
from fkcheck.model.types import KnownDifference, Model

__all__ = ["diagnose"]


def diagnose(
    model: Model,
    backend: Backend,
    *,
    frame_from: str | None = None,
    frame_to: str | None = None,
    samples: int = 200,
    seed: int = 0,
    q: Float | None = None,
    tol_pos_m: float | None = None,
    tol_rot_rad: float | None = None,
    timeout_s: float | None = DEFAULT_TIMEOUT_S,
) -> Diagnosis:
    """Explain why the table disagrees with a reference backend.

    Steps: constant frame offsets (:mod:`.offsets`), joint axes against the URDF
    (:mod:`.axes`, only when the reference reads the URDF), typical mistakes as
    hypotheses and single-parameter fits (:mod:`.hypotheses`), a vendor's
    conventions — several joints reversed, zeros a quarter turn apart, with the
    end frames — together when nothing alone explains it and the reference reads
    the URDF (:mod:`.conventions`), and a fit of every
    parameter (:mod:`.paramfit`) when nothing simpler leaves less than the tolerances.

    When the table agrees with a reference independent of it, the numbers that
    agreement does not identify are named, with what would settle each
    (:mod:`.identify`).

    A ``[[known_difference]]`` the model records for this reference applies as the
    check applies it (the model's own frame pair and tolerances): a disagreement
    within its bounds is named as that record first (the steps then say where it
    comes from); beyond them, a change that leaves no more than the record explains
    the disagreement.

    Args:
        model: The model.
        backend: The reference (e.g. ``make_backend("pinocchio-urdf")``).
        frame_from: Frame the pose is expressed in (default: the model's ``[check]``).
        frame_to: Frame whose pose is compared (default: the model's ``[check]``).
        samples: Random configurations, on top of the named poses, zero and mid-range.
        seed: Seed of the random configurations.
        q: Use these configurations instead; by default a measured-poses backend's
            own (it has poses at no others), else sampled ones.
        tol_pos_m: Position tolerance (default: the model's ``[check]``).
        tol_rot_rad: Rotation tolerance (default: the model's ``[check]``).
        timeout_s: Time limit of reading a recording (``poses:FILE``), as the check's
            ``--timeout`` limits it (at least :data:`~fkcheck.engine.stream.READ_MIN_S`,
            from before it is opened); ``None``: none.

    Returns:
        The diagnosis, explanations ranked most likely first.

    Raises:
        FrameError: An unknown frame name.
        ToleranceError: A tolerance out of its range (:mod:`fkcheck.core.tolerances`).
        BackendUnavailable, FrameUnavailable, FkcheckError: The reference cannot run.
        TimeLimitError: A recording's read did not finish within ``timeout_s``.
    """
    start = time.perf_counter()
    pair = (frame_from or model.check.frame_from, frame_to or model.check.frame_to)
    tol = pose_tolerances(
        tol_pos_m, tol_rot_rad, (model.check.tol_pos_m, model.check.tol_rot_rad), model.reach_m
    )
    if q is None and isinstance(backend, FixedConfigurations):
        from fkcheck.engine.stream import stream_recordings

        stream_recordings([backend], tol, timeout_s)  # a long one: its sample, its worst rows
        q = backend.configurations(model)
    configs = q if q is not None else diagnosis_configurations(model, samples, seed)
    problem = Problem.build(model, backend, configs, pair, tol)
    before = problem.residual(model)
    explanations: list[Explanation] = []
    tried: list[str] = []
    axes: tuple[AxisRow, ...] = ()
    known = _known(model, backend, pair, tol)
    if known is not None and not problem.exact(before):
        if before.within(known.max_position_m, known.max_angle_rad):
            explanations.append(_recorded(known, before, backend.name))
        else:
            problem = replace(problem, known=known)
    if not problem.exact(before):
        explanations, tried, axes = _steps(
            problem, explanations, reads_model_description(backend, model)
        )
    unsettled: tuple[Unsettled, ...] = ()
    if problem.exact(before) and backend.evidence == "table":  # agreement: what it leaves open
        unsettled = unsettled_numbers(model, pair, tol, configs)
    return Diagnosis(
        model=model,
        backend=backend.name,
        frame_from=pair[0],
        frame_to=pair[1],
        configurations=int(configs.shape[0]),
        before=before,
        tol_pos_m=tol[0],
        tol_rot_rad=tol[1],
        explanations=rank(explanations, before, tol),
        axes=axes,
        axes_note=axes_note(model, axes),
        tried=tuple(tried),
        duration_s=time.perf_counter() - start,
        unsettled=unsettled,
    )


def _steps(
    problem: Problem, explanations: list[Explanation], reads_urdf: bool
) -> tuple[list[Explanation], list[str], tuple[AxisRow, ...]]:
    """Every step on a disagreement, after ``explanations`` (the model's record, if any).

    Returns:
        The explanations (re-checked against the reference), what was tried, and the
        joint axes compared (only when the reference reads the URDF, ``reads_urdf``).
    """
    tried: list[str] = []
    axes: tuple[AxisRow, ...] = ()
    explanations += explain_offsets(problem)
    tried.append("constant base/tip frame offsets (least squares on SE(3))")
    found, hypotheses_tried = explain_hypotheses(problem)
    explanations += found
    tried += hypotheses_tried
    if reads_urdf:
        swaps, n_swaps = explain_swapped_mapping(problem)
        explanations += swaps
        tried.append(f"two URDF joints swapped in [urdf].joints ({n_swaps})")
        if not any(e.explains for e in explanations):
            explanations += explain_conventions(problem)
            tried.append(
                "reversed joints, quarter-turn zeros and the end frames together, "
                "from the URDF's chain"
            )
    # Re-checked against the backend before deciding on the fit: a black box can rule
    # out a fix (a frame offset) that looked like it explained everything.
    explanations = [_verified(problem, e) for e in explanations]
    # The general form, when nothing simpler leaves less than the tolerances (a
    # change that leaves the recorded known difference explains, but the fit is
    # still shown: it says where the recorded difference comes from).
    if not any(e.explains and problem.exact(e.residual) for e in explanations):
        explanations += [_verified(problem, e) for e in explain_parameter_fit(problem)]
        tried.append("all DH parameters + base + tool fitted together")
    if problem.known is not None:
        explanations = [_leaves_known(problem, problem.known, e) for e in explanations]
    if reads_urdf:
        axes = compare_axes(problem)
        tried.append("joint axes against the URDF")
    return explanations, tried, axes


def _verified(problem: Problem, e: Explanation) -> Explanation:
    """An explaining explanation, re-checked against the reference run on its own model."""
    if not e.explains or e.model is None:
        return e
    check = problem.verify(e.model)
    if problem.explained(check):
        return e
    return replace(
        e,
        explains=False,
        residual=check,
        fix_toml="",
        details=(
            *e.details,
            f"but the reference, run on the changed model, is still "
            f"{check.text()} away: it computes these frames from the table's own base and "
            "tool (a black box gives only the TCP), so this change cannot be the fix",
        ),
    )


def _known(
    model: Model, backend: Backend, pair: tuple[str, str], tol: tuple[float, float]
) -> KnownDifference | None:
    """The model's recorded difference with ``backend``, where the check would apply it.

    As :func:`fkcheck.engine.expected.apply_known_differences`: on the model's own
    frame pair and tolerances only.
    """
    if pair != (model.check.frame_from, model.check.frame_to) or tol != (
        model.check.tol_pos_m,
        model.check.tol_rot_rad,
    ):
        return None
    library = library_of(backend) if any(e.versions for e in model.known_differences) else None
    version = library[1] if library is not None else None
    return known_difference_for(model, backend.name, backend.reads, version)


def _bounds(known: KnownDifference) -> str:
    return f"{known.max_position_m:g} m, {known.max_angle_rad:g} rad"


def _recorded(known: KnownDifference, before: Residual, backend: str) -> Explanation:
    """The model's own record, as the first explanation of a disagreement within its bounds."""
    return Explanation(
        "known",
        f"the model file records this difference with {backend} ([[known_difference]]): "
        f"{known.finding}",
        before,
        True,
        (
            f"the disagreement, {before.text()}, is within the recorded bounds "
            f"({_bounds(known)}); the explanations below say where it comes from",
        ),
        numbers=0,
    )


def _leaves_known(problem: Problem, known: KnownDifference, e: Explanation) -> Explanation:
    """An explanation that leaves more than the tolerances, but no more than the record, says so."""
    if not e.explains or problem.exact(e.residual):
        return e
    return replace(
        e,
        details=(
            *e.details,
            f"it leaves {e.residual.text()}: within the difference the model file records "
            f"({known.finding}; bounds {_bounds(known)})",
        ),
    )
