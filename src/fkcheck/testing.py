"""Assertions for hand-written tests, in the style of :mod:`numpy.testing`.

Example:
    >>> from fkcheck.testing import assert_fk_matches, assert_pose_close
    >>> outcome = assert_fk_matches("robots/arm.toml", against="pinocchio-urdf", samples=200)
    >>> assert_pose_close(model.fk(q), expected, tol_pos_m=1e-6, tol_rot_rad=1e-6)

Both raise :class:`AssertionError` with a message a person can act on: for a
check, the verdict, each backend's largest errors in mm and degrees, the worst
configuration and the diagnosis's headline (each backend's record,
:mod:`fkcheck.report.record`: the text every report shows); for two poses, the differences in mm
and degrees and the index of the worst pose (and a matrix that is not a rigid
transform is refused, naming its defect). :func:`check_message` is that text
for any finished check (the pytest plugin, :mod:`fkcheck.pytest_plugin`, shows
the same). Nothing here imports pytest.

Under pytest-xdist, :func:`assert_fk_matches` first sizes the process's thread
pools to its share of the cores
(:func:`fkcheck.process.threads.share_xdist_cores`), so that the workers'
checks do not wait on each other's threads.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.api import Outcome, check
from fkcheck.backends.base import Backend
from fkcheck.core.metrics import position_error_m, rotation_error_rad, se3_defect
from fkcheck.core.tolerances import check_limit
from fkcheck.core.typing import Float
from fkcheck.engine.compare import SE3_TOLERANCE
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.io.format import format_deg, format_mm, format_pair
from fkcheck.io.text import terminal_text
from fkcheck.model.require import Kind
from fkcheck.model.types import Model
from fkcheck.process.threads import share_xdist_cores
from fkcheck.report.record import BackendRecord, backend_record, check_record

__all__ = [
    "assert_fk_matches",
    "assert_pose_close",
    "backend_message",
    "backend_ok",
    "check_message",
    "diagnosis_headline",
    "worst_q_text",
]


def worst_q_text(check_result: CheckResult, result: BackendResult) -> str:
    """The backend's worst configuration, ``[30.00°, -60.00°, 0.1000 m]``; empty if none."""
    return backend_record(check_result, result).worst_q_text


def diagnosis_headline(outcome: Outcome, backend: str) -> str:
    """What the diagnosis says about one backend's disagreement, one line; empty if none.

    A diagnosis that stands for several backends (two libraries reading one
    URDF) answers for each of them.
    """
    c = outcome.check
    result = next((b for b in c.backends if b.name == backend), None)
    if result is None:
        return ""
    return backend_record(c, result, outcome.diagnoses).diagnosis_short


def backend_message(outcome: Outcome, result: BackendResult, *, once: bool = False) -> str:
    """One backend's lines: status, largest errors (mm, degrees), worst q, diagnosis.

    Args:
        outcome: What :func:`fkcheck.check` returned.
        result: One of its backends.
        once: A diagnosis that stands for several failing backends is written out
            only for the first of them; the others' line names that one (one
            table error, one diagnosis, however many backends it fails).
    """
    return _backend_lines(backend_record(outcome.check, result, outcome.diagnoses), once=once)


def _backend_lines(record: BackendRecord, *, once: bool = False) -> str:
    """A backend's lines, from its record (:mod:`fkcheck.report.record`)."""
    name = terminal_text(record.name)
    lines = [f"{name}: {record.status} — {terminal_text(record.summary)}"]
    if not record.ran:
        return lines[0]
    if record.status == "fail":
        lines.append(f"  {terminal_text(record.message)}")
        if record.worst_q_text:
            lines.append(f"  worst q: {record.worst_q_text}")
        if record.diagnosis_short:
            first = record.diagnosed_with[0] if record.diagnosed_with else record.name
            if once and first != record.name:
                group = ", ".join(terminal_text(b) for b in record.diagnosed_with)
                lines.append(f"  diagnosis: as for {terminal_text(first)} (one for {group})")
            else:
                lines.append(f"  diagnosis: {terminal_text(record.diagnosis_short)}")
    jac = record.jacobian
    if jac is not None and jac.status in ("fail", "error"):
        lines.append(f"  Jacobian {jac.status}: {terminal_text(jac.message)}")
        if jac.diagnosis:
            lines.append(f"  Jacobian diagnosis: {terminal_text(jac.diagnosis)}")
    return "\n".join(lines)


def backend_ok(result: BackendResult) -> bool:
    """Whether a backend's result lets a test pass.

    It agreed, or disagreed as the model file records (``xfail``), and its
    Jacobian, when compared, did too (or did not apply, e.g. measured poses).
    """
    jac = result.jacobian
    jacobian_ok = jac is None or jac.status in ("pass", "xfail", "skipped")
    return result.status in ("pass", "xfail") and jacobian_ok


def check_message(
    outcome: Outcome, backends: Sequence[str] | None = None, *, details: bool = True
) -> str:
    """The text of a finished check: headline, each backend's lines, the model's numbers.

    A diagnosis that stands for several backends is written out once, under the
    first of them. The whole check's text (every backend, with details) also says
    what each required kind of evidence lacks, naming the numbers (``d1 not
    identifiable (the offset of [frames.base] could absorb it)``), as ``fkcheck
    check`` does.

    Args:
        outcome: What :func:`fkcheck.check` returned.
        backends: Only these backends' lines (default: every backend).
        details: Each backend's errors, worst q and diagnosis; ``False``: its
            status line only (where each backend's details are shown elsewhere).
    """
    record = check_record(outcome.check, outcome.diagnoses)
    head = (
        f"fkcheck {terminal_text(record.model)}: {terminal_text(record.frame_from)} → "
        f"{terminal_text(record.frame_to)}: {record.headline}"
    )
    shown = [b for b in record.backends if backends is None or b.name in backends]
    lines = [head]
    for b in shown:
        text = _backend_lines(b, once=True)
        lines.append(text if details else text.split("\n", 1)[0])
    if details and backends is None:  # what a required kind lacks, by number (d1 not identifiable)
        lines += [terminal_text(e.sentence) for e in record.evidence if e.required]
    if record.numbers_line:  # which numbers of the model the pair verified
        lines.append(terminal_text(record.numbers_line))
    if record.calibration_line:  # what the calibration changes against the nominal table
        lines.append(terminal_text(record.calibration_line))
    return "\n".join(lines)


def assert_fk_matches(
    model_or_path: Model | str | Path,
    against: str | Backend | Sequence[str | Backend] = "pinocchio-urdf",
    frames: tuple[str, str] | None = None,
    *,
    samples: int = 200,
    seed: int = 0,
    require: Sequence[Kind] = (),
    tol_pos_m: float | None = None,
    tol_rot_rad: float | None = None,
    diagnose: bool = True,
) -> Outcome:
    """Assert that a model's forward kinematics matches one or more reference backends.

    Runs :func:`fkcheck.check` and passes only when its verdict is ``pass`` and
    every backend asked answered and agreed (:func:`backend_ok`: or disagreed as
    the model file's ``[[known_difference]]`` records; its Jacobian too, when the
    model's ``[check] jacobian`` compares it): a backend that was skipped
    (library missing, frame out of its reach) fails the assertion, since it
    proved nothing.

    Args:
        model_or_path: A loaded model, a bundled model's name or a model file.
        against: One backend (name or object) or several.
        frames: ``(from, to)`` frame pair compared; default the model's ``[check]``.
        samples: Random samples, on top of named poses, zero, mid-range and limit corners.
        seed: Seed of the random samples.
        require: Kinds of evidence that must be verified (``"table"``, ``"implementation"``).
        tol_pos_m: Position tolerance, metres (default: the model's ``[check]``).
        tol_rot_rad: Rotation tolerance, radians (default: the model's ``[check]``).
        diagnose: Diagnose a failure, for the message (about a second per backend).

    Returns:
        The outcome, for further assertions.

    Raises:
        AssertionError: The verdict is not ``pass``, or a backend did not agree;
            the message is :func:`check_message`.
        FkcheckError: Bad input (unknown model, backend or frame, bad file…).
    """
    __tracebackhide__ = True  # pytest shows the caller's line and the message, not this code
    share_xdist_cores()
    backends = [against] if isinstance(against, str | Backend) else list(against)
    frame_from, frame_to = frames if frames is not None else (None, None)
    outcome = check(
        model_or_path,
        backends,
        samples=samples,
        seed=seed,
        frame_from=frame_from,
        frame_to=frame_to,
        tol_pos_m=tol_pos_m,
        tol_rot_rad=tol_rot_rad,
        require=require,
        diagnose=diagnose,
    )
    if outcome.verdict != "pass" or not all(backend_ok(b) for b in outcome.backends):
        raise AssertionError(check_message(outcome))
    return outcome


def _index(flat: int, shape: tuple[int, ...]) -> str:
    return str(tuple(int(i) for i in np.unravel_index(flat, shape))) if shape else "()"


def _defect_text(T: Float) -> str:
    """What keeps one ``(4, 4)`` matrix from being a rigid transform, a few words."""
    last = T[3]
    if np.abs(last - np.array([0.0, 0.0, 0.0, 1.0])).max() > SE3_TOLERANCE:
        return f"its bottom row is [{', '.join(f'{v:g}' for v in last)}], not [0, 0, 0, 1]"
    R = T[:3, :3]
    det = float(np.linalg.det(R))
    if det < 0:
        return f"its 3×3 part has det {det:.3g}: a reflection, not a rotation"
    s = np.linalg.svd(R, compute_uv=False)
    if s[0] - s[-1] <= SE3_TOLERANCE:
        return f"its 3×3 part is a rotation scaled by {float(s.mean()):.6g}"
    values = ", ".join(f"{float(v):.4g}" for v in s)
    return f"its 3×3 part is sheared or unevenly scaled (singular values {values}), not a rotation"


def _refuse_non_rigid(name: str, x: Float, tol_rot_rad: float, head: str) -> None:
    """Raise AssertionError for the first pose of ``x`` that is not a rigid transform.

    The bottom row must be ``0 0 0 1`` to :data:`~fkcheck.engine.compare.SE3_TOLERANCE`
    (it is exact in any printed form); the 3×3 part orthonormal with det +1 to
    ``tol_rot_rad`` (at least ``SE3_TOLERANCE``): a rotation angle read from a
    matrix that far from a rotation is off by about as much, so the comparison
    would mean nothing at that tolerance. Matrices typed with six decimals are
    within 2e-6, with four within 2e-4.
    """
    __tracebackhide__ = True
    flat = x.reshape(-1, 4, 4)
    last = np.abs(flat[:, 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max(axis=1)
    bad = (last > SE3_TOLERANCE) | (se3_defect(flat) > max(SE3_TOLERANCE, tol_rot_rad))
    if not bad.any():
        return
    k = int(np.argmax(bad))
    where = f" at index {_index(k, x.shape[:-2])}" if x.ndim > 2 else ""
    raise AssertionError(
        f"{head}Poses not comparable: {name} is not a rigid transform{where}: "
        f"{_defect_text(flat[k])}"
    )


def assert_pose_close(
    actual: ArrayLike,
    desired: ArrayLike,
    tol_pos_m: float = 1e-6,
    tol_rot_rad: float = 1e-6,
    err_msg: str = "",
) -> None:
    """Assert that poses agree in position and rotation within tolerances.

    Compares the distance between the origins (metres) and the angle of
    ``R_aᵀ R_b`` (radians, accurate near 0 and π) of each pose. Both must be
    rigid transforms for the angle to mean anything: a matrix whose bottom row is
    not ``0 0 0 1``, or whose 3×3 part is scaled, sheared or a reflection beyond
    ``tol_rot_rad`` (at least :data:`~fkcheck.engine.compare.SE3_TOLERANCE`), is
    refused as not comparable, like NaN.

    Args:
        actual: One pose ``(4, 4)`` or a batch ``(..., 4, 4)``.
        desired: The same shape.
        tol_pos_m: Largest allowed position difference, metres: more than 0, at
            most :data:`~fkcheck.core.tolerances.MAX_TOL_POS_M` (1 cm).
        tol_rot_rad: Largest allowed rotation difference, radians: more than 0,
            at most :data:`~fkcheck.core.tolerances.MAX_TOL_ROT_RAD` (0.1 rad).
        err_msg: Text put first in the message.

    Raises:
        AssertionError: Shapes differ, a value is NaN or infinite, a matrix is not
            a rigid transform (the message names which input, the index and the
            defect), or a pose is beyond a tolerance; the message then gives the
            number of mismatched poses, the largest differences in mm and degrees,
            and the index of each.
        ToleranceError: A tolerance out of its range; it is a ``ValueError``.
    """
    __tracebackhide__ = True  # pytest shows the caller's line and the message, not this code
    check_limit(tol_pos_m, "tol_pos", "tol_pos_m")
    check_limit(tol_rot_rad, "tol_rot", "tol_rot_rad")
    a = np.asarray(actual, dtype=np.float64)
    b = np.asarray(desired, dtype=np.float64)
    head = f"{err_msg}\n" if err_msg else ""
    if a.shape != b.shape or a.shape[-2:] != (4, 4):
        raise AssertionError(
            f"{head}Poses not comparable: shapes {a.shape} and {b.shape} "
            "(each must be (4, 4) or (..., 4, 4), the same)"
        )
    for name, x in (("actual", a), ("desired", b)):
        if not np.isfinite(x).all():
            bad = int(np.argmax(~np.isfinite(x).reshape(-1, 16).all(axis=1)))
            raise AssertionError(
                f"{head}Poses not comparable: {name} has NaN or infinite values at index "
                f"{_index(bad, x.shape[:-2])}"
            )
    for name, x in (("actual", a), ("desired", b)):
        _refuse_non_rigid(name, x, tol_rot_rad, head)
    pos = np.atleast_1d(position_error_m(a, b))
    rot = np.atleast_1d(rotation_error_rad(a, b))
    bad_mask = (pos > tol_pos_m) | (rot > tol_rot_rad)
    if not bad_mask.any():
        return
    batch = a.shape[:-2]
    i_pos, i_rot = int(np.argmax(pos)), int(np.argmax(rot))
    worst_pos = format_pair(format_mm(float(pos[i_pos])), f"{pos[i_pos]:.3e} m")
    worst_rot = format_pair(format_deg(float(rot[i_rot])), f"{rot[i_rot]:.3e} rad")
    lines = [
        f"{head}Poses not close (tol_pos_m={tol_pos_m:g}, tol_rot_rad={tol_rot_rad:g} = "
        f"{format_mm(tol_pos_m)}, {format_deg(tol_rot_rad)})",
        f"Mismatched poses: {int(bad_mask.sum())} / {bad_mask.size}"
        f" ({100.0 * bad_mask.mean():.3g}%)",
        f"Max position difference: {worst_pos}"
        + (f" at index {_index(i_pos, batch)}" if batch else ""),
        f"Max rotation difference: {worst_rot}"
        + (f" at index {_index(i_rot, batch)}" if batch else ""),
    ]
    raise AssertionError("\n".join(lines))
