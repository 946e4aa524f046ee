"""A check's first stage: read and screen its inputs once, and decide what runs.

:func:`prepare` takes a :class:`~fkcheck.engine.request.CheckRequest` and returns
a :class:`PreparedCheck`: the known differences checked against the backends,
the calibration file screened, the model's descriptions read once
(:func:`_read_descriptions`: ``urdf:LINK`` frames placed, the URDF read and its
links checked, a xacro expansion kept with the model), the frame pair and the
tolerances resolved, the configurations sampled (or a measured-poses backend's),
what a calibration changes, what the frame pair can verify
(:mod:`fkcheck.model.coverage`) and the plan (:mod:`fkcheck.engine.plan`). Bad
input ends here, before any backend starts; the command line prepares before
it prints its header, so it is one line.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from fkcheck.backends.base import Backend, FixedConfigurations, reads_format
from fkcheck.backends.registry import check_known_differences
from fkcheck.calibration.description import screen_kinematics
from fkcheck.calibration.effect import CalibrationEffect, calibration_effect, nominal_model
from fkcheck.calibration.provenance import calibration_provenance
from fkcheck.core.tolerances import pose_tolerances
from fkcheck.core.typing import Float
from fkcheck.description.registry import load_description, model_format, model_formats
from fkcheck.description.types import Description, DescriptionFormat
from fkcheck.engine.jacobian import JacobianSpec, check_fixed_from
from fkcheck.engine.plan import Plan, plan_check
from fkcheck.engine.request import CheckRequest
from fkcheck.engine.stream import stream_recordings
from fkcheck.engine.verdict import KINDS, Kind
from fkcheck.errors import BackendUnavailable, FkcheckError, FrameError
from fkcheck.model.coverage import Competitor, Coverage, coverage
from fkcheck.model.frames import resolve_frame
from fkcheck.model.options import jacobian_for
from fkcheck.model.sampling import Samples, sample_configurations
from fkcheck.model.types import URDF_FRAME_PREFIX, Model
from fkcheck.urdf.chain import competing_links

if TYPE_CHECKING:
    from fkcheck.urdf.mapping import LinkFit

__all__ = ["EVIDENCE_MIN_S", "PreparedCheck", "numbers_of", "prepare"]

#: The per-number evidence's time limit is the check's ``timeout_s``, but never less
#: than this, seconds: it costs a few seconds even at 256 joints (about 5 s of one
#: core), and a ``--timeout`` short enough for a hanging backend (0.5 s) must not end
#: a six-joint check on a busy machine.
EVIDENCE_MIN_S = 10.0


@dataclass(frozen=True, eq=False)
class PreparedCheck:
    """A request with its inputs read and everything decided that the run needs.

    Attributes:
        request: The request, unchanged.
        model: The model as the backends get it: with the ``urdf:LINK`` frames it
            placed and its xacro expansion (run once).
        placed: The links placed from the URDF (only URDF backends compare them).
        pair: The compared frames, resolved: ``(from, to)``.
        tol: Position (m) and rotation (rad) tolerance, resolved.
        jacobian: The Jacobian comparison asked for, or ``None``.
        samples: The configurations and where each came from.
        required: Kinds of evidence that must be verified (the model's and the options').
        competitors: URDF links a choice among which could hide a number (coverage's).
        numbers: What the frame pair can verify over all configurations.
        calibration: What a calibrated model's calibration changes, else ``None``.
        plan: How many configurations each backend compares.
        created: ISO 8601 UTC time the check started.
        started_s: ``time.perf_counter()`` when it started (for its duration).
    """

    request: CheckRequest
    model: Model
    placed: Mapping[str, LinkFit]
    pair: tuple[str, str]
    tol: tuple[float, float]
    jacobian: JacobianSpec | None
    samples: Samples
    required: tuple[Kind, ...]
    competitors: Mapping[str, list[Competitor]]
    numbers: Coverage
    calibration: CalibrationEffect | None
    plan: Plan
    created: str
    started_s: float


def prepare(request: CheckRequest) -> PreparedCheck:
    """Read and screen the request's inputs once; sample, plan and analyse the frame pair.

    Raises:
        FrameError: An unknown frame name.
        UrdfError: The model's URDF is missing, unsafe or does not fit the model.
        ModelError: A calibrated model's nominal model is missing or invalid.
        TimeLimitError: A recording's read (:data:`~fkcheck.engine.stream.READ_MIN_S`
            at least) or the per-number evidence did not finish within the check's
            time limit (or :data:`EVIDENCE_MIN_S`, when longer).
        FkcheckError: Other bad input (a known difference naming no backend,
            measured poses at different configurations, ``require table`` on a
            frame pair that spans no joint).
    """
    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    started_s = time.perf_counter()
    options, backends = request.options, request.backends
    check_known_differences(request.model, backends)
    screen_kinematics(request.model)  # a calibration YAML is read as fkcheck calibration reads it
    model, placed, pair, competitors = _read_descriptions(request)
    tol = pose_tolerances(
        options.tol_pos_m,
        options.tol_rot_rad,
        (model.check.tol_pos_m, model.check.tol_rot_rad),
        model.reach_m,
    )
    asked = jacobian_for(options, model)
    jacobian = JacobianSpec(*asked) if asked is not None else None
    if jacobian is not None:
        check_fixed_from(model, pair[0])
    q = _fixed_configurations(model, backends, tol, options.timeout_s) or sample_configurations(
        model, options.samples, options.seed, options.sampler
    )
    required = tuple(k for k in KINDS if k in (*model.check.require, *options.require))
    # What it exercises, and what a choice among links could hide, within the check's
    # time limit (at least EVIDENCE_MIN_S).
    numbers = numbers_of(model, pair, tol, q.q, competitors, options.timeout_s)
    if "table" in required and numbers.spans_no_joint:
        raise FkcheckError(
            f"require table: the frame pair {pair[0]} → {pair[1]} spans no joint of model "
            f"{model.name}, so it cannot verify the table; compare a pair with joints "
            "between them (e.g. the model's [check] from/to)"
        )
    plan = plan_check(backends, q.origin, dof=model.dof, timeout_s=options.timeout_s,
                      jacobian=jacobian is not None, full=options.full)  # fmt: skip
    return PreparedCheck(
        request=request,
        model=model,
        placed=placed,
        pair=pair,
        tol=tol,
        jacobian=jacobian,
        samples=q,
        required=required,
        competitors=competitors,
        numbers=numbers,
        calibration=_calibration_effect(model, q.q, pair),
        plan=plan,
        created=created,
        started_s=started_s,
    )


def numbers_of(
    model: Model,
    pair: tuple[str, str],
    tol: tuple[float, float],
    q: Float,
    competitors: Mapping[str, list[Competitor]],
    timeout_s: float,
) -> Coverage:
    """What the frame pair can verify at ``q``, in ``timeout_s`` (≥ :data:`EVIDENCE_MIN_S`)."""
    return coverage(
        model, pair[0], pair[1], *tol, q=q, competitors=dict(competitors),
        time_limit_s=max(timeout_s, EVIDENCE_MIN_S),
    )  # fmt: skip


def _read_descriptions(
    request: CheckRequest,
) -> tuple[Model, dict[str, LinkFit], tuple[str, str], dict[str, list[Competitor]]]:
    """The model's descriptions read once: ``(model, placed links, frame pair, competitors)``.

    ``urdf:LINK`` frames placed, the frame pair resolved, each of the model's
    descriptions read once (one that runs code, a xacro file, only when a backend
    reads it), the compared frames' links checked against each description a
    backend reads, the links that could compete found, and what a format carries
    (a xacro expansion) kept with the model.

    Raises:
        FrameError: An unknown frame, or a compared frame's link not in the URDF.
        UrdfError: A description is missing, unsafe or does not fit the model.
    """
    from fkcheck.urdf.xacro import XACRO_TIMEOUT_S

    model, backends, options = request.model, request.backends, request.options
    timeout_s = options.timeout_s
    frame_from, frame_to = options.frame_from, options.frame_to
    asked = (frame_from or model.check.frame_from, frame_to or model.check.frame_to)
    # ``urdf:LINK`` resolves to the declared frame mapped onto that link; a link no
    # frame declares is placed from the URDF, and only URDF backends compare it.
    xacro_timeout_s = min(timeout_s, XACRO_TIMEOUT_S)  # the check's limit, when shorter
    model, placed = _place_urdf_links(model, asked, xacro_timeout_s)
    pair = (resolve_frame(model, asked[0]).name, resolve_frame(model, asked[1]).name)
    competitors: dict[str, list[Competitor]] = {}
    for fmt in model_formats(model):
        read = any(reads_format(b, fmt.name) for b in backends)
        if fmt.executes and not read:  # code in a description (xacro) runs only when read
            continue
        # Bad description input is exit 2 before anything runs; a missing
        # example-robot-data is not: each reader then reports itself skipped.
        with contextlib.suppress(BackendUnavailable):
            described = load_description(model, xacro_timeout_s, language=fmt.language)
            if read:
                _check_twins(model, pair, fmt, described)
                for name, found in competing_links(model, pair, described.tree, fmt.frame).items():
                    competitors.setdefault(name, []).extend(found)
            model = fmt.carry(model, described)  # an expansion travels: run the file once
    return model, placed, pair, competitors


def _place_urdf_links(
    model: Model, asked: Sequence[str], xacro_timeout_s: float
) -> tuple[Model, dict[str, LinkFit]]:
    """The model with ``urdf:LINK`` frames for the undeclared links ``asked`` names.

    ``xacro_timeout_s`` is the time limit of a xacro expansion.

    Raises:
        FkcheckError: The URDF cannot be read (example-robot-data missing included),
            the link is not in it, or it is at no constant offset from any DH frame.
    """
    wanted = [
        name
        for name in asked
        if name.startswith(URDF_FRAME_PREFIX)
        and not any(s.urdf == name[len(URDF_FRAME_PREFIX) :] for s in model.frames.values())
    ]
    if not wanted or model_format(model, "urdf") is None:
        return model, {}  # resolve_frame says what is wrong, if anything
    from fkcheck.urdf.mapping import with_link_frames  # scipy.optimize: only when needed

    try:
        kin = load_description(model, xacro_timeout_s, language="urdf").tree
    except BackendUnavailable as exc:
        raise FkcheckError(f"{wanted[0]}: the URDF cannot be read here: {exc}") from None
    return with_link_frames(model, kin, wanted)


def _check_twins(
    model: Model, pair: Sequence[str], fmt: DescriptionFormat, described: Description
) -> None:
    """The description's frames of the compared frames exist (one not compared may lack its own).

    Raises:
        FrameError: A compared frame names a frame the description does not have (listing them).
    """
    links = described.frames
    for name in pair:
        link = fmt.frame(resolve_frame(model, name))
        if link is not None and link not in links:
            where = f"{described.language.upper()} {described.path.name} (frame {name})"
            raise FrameError(link, where, links)


def _fixed_configurations(
    model: Model, backends: Sequence[Backend], tol: tuple[float, float], timeout_s: float
) -> Samples | None:
    """The configurations a measured-poses backend dictates, if one takes part.

    A long recording is compared as it is read, its rows beyond ``tol`` counted,
    within ``timeout_s`` (at least :data:`~fkcheck.engine.stream.READ_MIN_S`).
    """
    fixed = [b for b in backends if isinstance(b, FixedConfigurations)]
    if not fixed:
        return None
    stream_recordings(fixed, tol, timeout_s)  # a long recording is compared as it is read
    q = np.asarray(fixed[0].configurations(model), dtype=np.float64)
    for other in fixed[1:]:
        if not np.array_equal(np.asarray(other.configurations(model)), q):
            raise FkcheckError(
                f"{fixed[0].name} and {other.name} hold poses at different configurations; "
                "check them one at a time"
            )
    return Samples(q=q, origin=(f"file:{fixed[0].name}",) * q.shape[0])


def _calibration_effect(model: Model, q: Float, pair: tuple[str, str]) -> CalibrationEffect | None:
    """What a calibrated model's calibration changes at ``q`` (``None`` for other models).

    The nominal model must load (a bad ``[calibration] nominal`` is bad input);
    a frame pair the nominal model does not have is not compared.

    Raises:
        ModelError: The nominal model is missing, invalid or has other joints.
    """
    if model.calibration is None:
        return None
    nominal = nominal_model(model)
    try:
        name = Path(model.calibration.file).name
        effect = calibration_effect(model, nominal, q, pair[0], pair[1], name)
    except FrameError:
        return None
    # Said with the effect: whether the file and the table are still as calibrated.
    return replace(effect, provenance=calibration_provenance(model, nominal))
