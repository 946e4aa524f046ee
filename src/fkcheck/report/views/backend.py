"""The backends' table, their partings and each backend's detail: its worst cases and the arm drawn.

View models (:mod:`fkcheck.report.views`): plain text, numbers and nested views only.
"""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.report.views.cells import Image, JointValue, MatrixView, Measure, PoseForms

__all__ = [
    "ArmDrawing",
    "BackendDetail",
    "BackendRow",
    "FrameSide",
    "PartingRow",
    "PartingView",
    "WorstCase",
]


@dataclass(frozen=True)
class FrameSide:
    """One side of the compared frame pair and what it means.

    Attributes:
        role: ``"from"`` or ``"to"``.
        name: The named frame.
        placement: Where it sits on the DH chain, e.g. ``"DH frame 0"``.
        offset: Its fixed offset from there, or ``"none"``.
        urdf: Its URDF twin, e.g. ``"link base"``, or a note that it has none.
    """

    role: str
    name: str
    placement: str
    offset: str
    urdf: str


@dataclass(frozen=True)
class BackendRow:
    """One backend's line in the summary table.

    Attributes:
        name: Backend name.
        anchor: HTML id of its detail section (empty when it has none).
        status: ``pass``, ``fail``, ``error``, ``skipped``, ``xfail``, ``xpass``.
        label: The status as shown: the status, or ``fail (reader)`` for a
            reader finding (:func:`~fkcheck.engine.results.status_label`).
        method: The library call it used.
        duration: Wall time, formatted.
        message: Why it was skipped or errored, or the failure summary, in full.
        pos_max: Largest position error.
        pos_p99: 99th percentile of the position error.
        pos_median: Median position error.
        rot_max: Largest rotation error.
        rot_p99: 99th percentile of the rotation error.
        rot_median: Median rotation error.
        worst_q: The worst configuration, formatted (empty when it did not run).
        worst_origin: Where the worst configuration came from (``random``, ``pose:home`` …).
    """

    name: str
    anchor: str
    status: str
    label: str
    method: str
    duration: str
    message: str
    pos_max: Measure
    pos_p99: Measure
    pos_median: Measure
    rot_max: Measure
    rot_p99: Measure
    rot_median: Measure
    worst_q: str
    worst_origin: str


@dataclass(frozen=True)
class WorstCase:
    """One of a backend's worst configurations, both poses side by side.

    Attributes:
        rank: 1 for the worst.
        index: Index of the configuration in the check.
        origin: Where it came from (``random``, ``corner``, ``pose:home`` …).
        q: The joint values.
        position_error: Position error at this configuration.
        rotation_error: Rotation error at this configuration.
        ours: The in-house ``from_T_to``.
        theirs: The backend's ``from_T_to`` as the check compared it.
        difference: ``theirs − ours``.
    """

    rank: int
    index: int
    origin: str
    q: tuple[JointValue, ...]
    position_error: Measure
    rotation_error: Measure
    ours: PoseForms
    theirs: PoseForms
    difference: MatrixView


@dataclass(frozen=True)
class PartingRow:
    """One DH frame compared between two chains at one configuration.

    Attributes:
        frame: Label, e.g. ``"DH frame 2 (after joint shoulder_lift)"``.
        position_error: Distance between the two frames' origins.
        rotation_error: Angle between the two frames' orientations.
        differs: Beyond tolerance.
        first: This is the first frame that differs.
    """

    frame: str
    position_error: Measure
    rotation_error: Measure
    differs: bool
    first: bool


@dataclass(frozen=True)
class PartingView:
    """Where two chains part: every DH frame (or joint axis) compared at one configuration.

    Attributes:
        title: What is compared, e.g. ``"rtb-dh: DH frames T_0_i"``.
        verdict: One sentence naming the first frame that differs (or saying none does).
        parted: Some frame differs.
        short: Where they part, in a few words, for the page's first screen
            (empty when they do not).
        what: How the comparison is made.
        rows: One row per frame.
    """

    title: str
    verdict: str
    parted: bool
    short: str
    what: str
    rows: tuple[PartingRow, ...]


@dataclass(frozen=True)
class ArmDrawing:
    """The 3D stick drawing of the arm at a backend's worst configuration."""

    image: Image


@dataclass(frozen=True)
class BackendDetail:
    """Everything about one disagreeing backend.

    Attributes:
        name: Backend name.
        anchor: HTML id.
        summary: One line: how many configurations differ and by how much.
        worst_q: The worst configuration, formatted.
        arm: The stick drawing at the worst configuration.
        worst_cases: The worst few configurations with both poses.
    """

    name: str
    anchor: str
    summary: str
    worst_q: str
    arm: ArmDrawing | None
    worst_cases: tuple[WorstCase, ...]
