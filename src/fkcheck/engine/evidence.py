"""Evidence of a failure, gathered by the engine during the check, for every report.

A report formats what the check saw; it never runs a backend, the core or a
parser again. So while a backend is compared, the engine keeps, besides the
per-configuration errors, what a reader needs to see *why* it failed
(:class:`FailureDetail`, attached to a failing :class:`~fkcheck.engine.results.BackendResult`):

* its few worst configurations with both ``from_T_to`` side by side
  (:class:`WorstCases`, tracked chunk by chunk by :class:`WorstTracker`, so a
  run of a million samples holds three pairs of matrices, not a million);
* the in-house chain at the worst configuration (:class:`ArmPose`), to draw it;
* for a backend built from the DH table, every DH frame of both chains there
  (:class:`DhParting`): the first frame beyond tolerance is where they part;
* otherwise, when the model has a URDF, each joint's axis from the table and
  from the URDF there (:class:`UrdfAxes`, computed by :mod:`fkcheck.engine.axes`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.description.registry import model_format
from fkcheck.engine.axes import AxisLines, AxisRow, axis_lines, axis_rows
from fkcheck.errors import FkcheckError, Skip
from fkcheck.model.frames import reference_poses
from fkcheck.model.types import Model

__all__ = [
    "WORST_CASES",
    "ArmPose",
    "DhParting",
    "FailureDetail",
    "UrdfAxes",
    "WorstCases",
    "WorstTracker",
    "arm_pose",
    "dh_parting",
    "urdf_axes",
]

#: How many of a failing backend's worst configurations are kept in full.
WORST_CASES = 3


@dataclass(frozen=True, eq=False)
class WorstCases:
    """A backend's ``from_T_to`` next to the in-house one at its worst configurations.

    Attributes:
        indices: Configuration indices into ``CheckResult.q``; the first is the
            backend's ``worst_index``, the others the next largest errors relative
            to tolerance (``max(position / tol_pos, rotation / tol_rot)``, ties to
            the earlier index).
        ours: In-house ``from_T_to``, shape ``(K, 4, 4)``.
        theirs: The backend's ``from_T_to`` as it was compared, ``(K, 4, 4)``
            (NaN where the backend returned NaN or inf).
    """

    indices: tuple[int, ...]
    ours: Float
    theirs: Float


class WorstTracker:
    """The ``k`` rows with the largest score seen so far, over chunks of one run."""

    def __init__(self, k: int = WORST_CASES) -> None:
        self.k = k
        self._index = np.empty(0, dtype=np.int64)
        self._score = np.empty(0)
        self._ours = np.empty((0, 4, 4))
        self._theirs = np.empty((0, 4, 4))
        self._extra: dict[int, tuple[Float, Float]] = {}

    def add(self, first: int, score: Float, ours: Float, theirs: Float) -> None:
        """Offer a chunk's rows.

        Args:
            first: Index of the chunk's first row in the whole run.
            score: ``(M,)`` error relative to tolerance (``inf`` for a non-finite row).
            ours: ``(M, 4, 4)`` in-house ``from_T_to``.
            theirs: ``(M, 4, 4)`` the backend's ``from_T_to``.
        """
        top = np.argsort(-score, kind="stable")[: self.k]
        index = np.concatenate([self._index, first + top])
        merged = np.concatenate([self._score, score[top]])
        order = np.lexsort((index, -merged))[: self.k]
        self._index = index[order]
        self._score = merged[order]
        self._ours = np.concatenate([self._ours, ours[top]])[order]
        self._theirs = np.concatenate([self._theirs, theirs[top]])[order]

    def keep(self, index: int, ours: Float, theirs: Float) -> None:
        """Keep one row whatever its score (the engine's worst when a defect decides it)."""
        self._extra = {index: (ours.copy(), theirs.copy())}

    def cases(self, worst_index: int) -> WorstCases:
        """The kept rows, ``worst_index`` first, at most ``k``."""
        rows = {
            int(i): (o, t) for i, o, t in zip(self._index, self._ours, self._theirs, strict=True)
        }
        if worst_index not in rows:
            rows[worst_index] = self._extra[worst_index]
        order = [worst_index] + [int(i) for i in self._index if int(i) != worst_index]
        order = order[: self.k]
        return WorstCases(
            indices=tuple(order),
            ours=np.stack([rows[i][0] for i in order]),
            theirs=np.stack([rows[i][1] for i in order]),
        )


@dataclass(frozen=True, eq=False)
class ArmPose:
    """The in-house chain at one configuration, in the world frame.

    Attributes:
        world_T_dh: DH frames ``0…n``, ``(n+1, 4, 4)``.
        world_T_tcp: The TCP, ``(4, 4)``.
        world_T_from: The compared ``from`` frame, ``(4, 4)``.
        world_T_to: The compared ``to`` frame, ``(4, 4)``.
    """

    world_T_dh: Float
    world_T_tcp: Float
    world_T_from: Float
    world_T_to: Float


def arm_pose(model: Model, q: Float, pair: tuple[str, str]) -> ArmPose:
    """The in-house chain and the compared frames at one configuration ``(n,)``."""
    named = reference_poses(model, q[None], pair)[:, 0]
    return ArmPose(
        world_T_dh=np.asarray(model.fk(q, all_frames=True)),
        world_T_tcp=np.asarray(model.fk(q)),
        world_T_from=named[0],
        world_T_to=named[1],
    )


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


def dh_parting(
    index: int, ours: Float, theirs: Float, tol: tuple[float, float]
) -> DhParting | None:
    """Compare two chains' DH frames (both ``world_T_i``); ``None`` when the shapes differ.

    Both sets of frames are in the world frame (the model's base transform
    included), so frame 0 differs only when the base does.
    """
    theirs = np.asarray(theirs, dtype=np.float64)
    if theirs.shape != ours.shape:
        return None
    pos = position_error_m(ours, theirs)
    rot = rotation_error_rad(ours, theirs)
    beyond = np.flatnonzero((pos > tol[0]) | (rot > tol[1]))
    first = int(beyond[0]) if beyond.size else None
    return DhParting(index, ours, theirs, pos, rot, first)


@dataclass(frozen=True, eq=False)
class UrdfAxes:
    """The table's joint axes against the URDF's at one configuration of the check.

    Attributes:
        index: The configuration's index in ``CheckResult.q``.
        lines: Both sets of axes as lines in the ``from`` frame.
        rows: Per joint, the angle and distance between them and whether they agree.
        urdf_joints: The URDF joints mapped onto the DH joints, in DH order.
    """

    index: int
    lines: AxisLines
    rows: tuple[AxisRow, ...]
    urdf_joints: tuple[str, ...]

    @property
    def first(self) -> int | None:
        """0-based index of the first joint whose axis differs, or ``None``."""
        return next((r.joint for r in self.rows if not r.agrees), None)


def urdf_axes(
    model: Model, index: int, q: Float, frame_from: str, tol: tuple[float, float]
) -> UrdfAxes | None:
    """Joint axes against the model's URDF at one configuration ``(n,)``.

    Returns:
        ``None`` when the model has no URDF, the ``from`` frame has no URDF twin,
        or the URDF cannot be read: this is evidence for a report, never part of
        the verdict (a URDF backend that could not read it has said so already).
    """
    fmt = model_format(model)
    if fmt is None:
        return None
    try:
        lines = axis_lines(model, q, frame_from)
    except (FkcheckError, Skip, KeyError, ValueError):
        # Skip too: a URDF that cannot be read here (example-robot-data missing) must
        # not turn the failing backend this evidence is for into a skipped one.
        return None
    if lines is None:
        return None
    rows = axis_rows(model, [lines], tol[0], tol[1])
    return UrdfAxes(index, lines, rows, fmt.mapped_joints(model))


@dataclass(frozen=True, eq=False)
class FailureDetail:
    """What the engine kept about a failing backend, for reports.

    Attributes:
        worst: Both poses at its worst configurations.
        arm: The in-house chain at its worst configuration.
        dh_parting: Its DH frames against the in-house ones there (backends built
            from the DH table only).
        urdf_axes: The table's joint axes against the URDF's there (other
            backends, when the model has a URDF and the ``from`` frame a twin).
    """

    worst: WorstCases
    arm: ArmPose
    dh_parting: DhParting | None = None
    urdf_axes: UrdfAxes | None = None
