"""Evidence for a report, recomputed after a check at a failing backend's worst configurations.

The engine keeps per-configuration errors, not poses (a run of 10 000 samples
would otherwise hold every backend's 10 000 matrices). To show *both* matrices
side by side, :func:`collect_worst_poses` runs each failing backend again on
its few worst configurations only — backends are deterministic, so these are
the poses the check compared. :func:`dh_parting` compares every DH frame of a
backend built from the DH table with the in-house frames, to find where the
two chains part.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from fkcheck.backends.base import Backend
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.model.frames import reference_poses, relative_pose

__all__ = [
    "WORST_CASES",
    "DhParting",
    "WorstPoses",
    "collect_worst_poses",
    "dh_parting",
    "require_aligned",
    "worst_indices",
]


#: How many of a failing backend's worst configurations a report shows in full.
WORST_CASES = 3


@dataclass(frozen=True, eq=False)
class WorstPoses:
    """A backend's ``from_T_to`` next to the in-house one at its worst configurations.

    Attributes:
        indices: Configuration indices into ``CheckResult.q``, worst first.
        ours: In-house ``from_T_to``, shape ``(K, 4, 4)``.
        theirs: The backend's ``from_T_to``, shape ``(K, 4, 4)``, or ``None`` when
            recomputing failed.
        note: Why ``theirs`` is missing, if it is.
    """

    indices: tuple[int, ...]
    ours: Float
    theirs: Float | None
    note: str = ""


@dataclass(frozen=True, eq=False)
class DhParting:
    """Every DH frame of two chains compared at one configuration.

    Attributes:
        index: The configuration's index in ``CheckResult.q``.
        ours: In-house ``world_T_i``, shape ``(n+1, 4, 4)``.
        theirs: The backend's ``world_T_i``, shape ``(n+1, 4, 4)``.
        position_error_m: Distance between frame origins, per frame.
        rotation_error_rad: Angle between frame orientations, per frame.
        first: Index of the first frame beyond tolerance, or ``None``.
    """

    index: int
    ours: Float
    theirs: Float
    position_error_m: Float
    rotation_error_rad: Float
    first: int | None


def worst_indices(check: CheckResult, result: BackendResult, k: int = WORST_CASES) -> list[int]:
    """The ``k`` configurations with the largest error relative to tolerance, worst first.

    Ranked like the engine ranks its worst configuration: by
    ``max(position / tol_pos, rotation / tol_rot)``, ties to the earlier index.
    """
    if result.position_error_m is None or result.rotation_error_rad is None:
        return []
    score = np.maximum(
        result.position_error_m / check.tol_pos_m, result.rotation_error_rad / check.tol_rot_rad
    )
    order = np.argsort(-score, kind="stable")
    return [int(i) for i in order[:k]]


def require_aligned(check: CheckResult, backends: Sequence[Backend]) -> None:
    """Check that ``backends`` can be the objects behind ``check.backends``, one each.

    Raises:
        ValueError: Their counts differ.
    """
    if len(backends) != len(check.backends):
        raise ValueError(
            f"{len(backends)} backend objects for {len(check.backends)} results: "
            "pass the backends the check ran, in order"
        )


def _in_house_relative(check: CheckResult, q: Float) -> Float:
    ref = reference_poses(check.model, q, (check.frame_from, check.frame_to))
    return relative_pose(ref[0], ref[1])


def collect_worst_poses(
    check: CheckResult, backends: Sequence[Backend], k: int = WORST_CASES
) -> tuple[WorstPoses | None, ...]:
    """Recompute each failing backend's ``from_T_to`` at its ``k`` worst configurations.

    Args:
        check: The finished check.
        backends: The backend objects the check ran, in the same order as
            ``check.backends``.
        k: How many configurations per backend.

    Returns:
        One entry per backend result, aligned with ``check.backends``: ``None``
        for backends that did not fail. A backend that raises now is recorded
        with a note instead of poses; it never stops the report.

    Raises:
        ValueError: ``backends`` does not match ``check.backends``.
    """
    require_aligned(check, backends)
    out: list[WorstPoses | None] = []
    pair = (check.frame_from, check.frame_to)
    for backend, result in zip(backends, check.backends, strict=True):
        indices = worst_indices(check, result, k) if result.status == "fail" else []
        if not indices:
            out.append(None)
            continue
        q = check.q[indices]
        ours = _in_house_relative(check, q)
        try:
            poses = np.asarray(backend.frame_poses(check.model, q, pair), dtype=np.float64)
            theirs = relative_pose(poses[0], poses[1])
        except Exception as exc:  # the report shows what it can; the check already judged
            note = f"recomputing the poses failed: {type(exc).__name__}: {exc}"
            out.append(WorstPoses(tuple(indices), ours, None, note))
            continue
        out.append(WorstPoses(tuple(indices), ours, theirs))
    return tuple(out)


def dh_parting(check: CheckResult, result: BackendResult) -> DhParting | None:
    """Compare the in-house DH frames with a backend's at its worst configuration.

    Only for backends that share DH frames (``BackendResult.worst_dh_frames`` is
    set by the engine for those that failed). Both sets of frames are in the
    world frame (the model's base transform included), so frame 0 differs only
    when the base does.

    Returns:
        The comparison, or ``None`` when the backend has no DH frames to compare.
    """
    if result.worst_dh_frames is None or result.worst_index is None:
        return None
    q = check.q[result.worst_index]
    ours = np.asarray(check.model.fk(q, all_frames=True))
    theirs = np.asarray(result.worst_dh_frames, dtype=np.float64)
    if theirs.shape != ours.shape:
        return None
    pos = position_error_m(ours, theirs)
    rot = rotation_error_rad(ours, theirs)
    beyond = np.flatnonzero((pos > check.tol_pos_m) | (rot > check.tol_rot_rad))
    first = int(beyond[0]) if beyond.size else None
    return DhParting(result.worst_index, ours, theirs, pos, rot, first)
