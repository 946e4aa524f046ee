"""The pieces every section shows: a measure, a fact, an image, a 4×4 matrix, a pose, a joint value.

View models (:mod:`fkcheck.report.views`): plain text, numbers and nested views only.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "Fact",
    "Image",
    "JointValue",
    "MatrixCell",
    "MatrixView",
    "Measure",
    "PoseForms",
]


@dataclass(frozen=True)
class Measure:
    """A number shown two ways, with its exact value kept for machines.

    Attributes:
        value: The exact value in SI units (m or rad), or ``None`` when absent.
        primary: The human reading, e.g. ``"0.300 mm"`` or ``"6.88e-15°"``.
        secondary: The SI value, e.g. ``"3.00e-04 m"`` or ``"1.20e-16 rad"``.
    """

    value: float | None
    primary: str
    secondary: str


@dataclass(frozen=True)
class Fact:
    """One line of a key/value list.

    Attributes:
        label: What it is.
        value: The value as text.
        volatile: Non-empty when the value changes from run to run or machine to
            machine (``"date"``, ``"version"``, ``"path"``, ``"duration"``); the
            template marks it ``data-volatile`` so gold tests can scrub it.
        code: Show the value as code.
    """

    label: str
    value: str
    volatile: str = ""
    code: bool = False


@dataclass(frozen=True)
class Image:
    """A picture embedded in the page.

    Attributes:
        src: A ``data:`` URI (PNG, base64): no file or network access is needed.
        alt: Text alternative.
        caption: What is drawn and how to read it.
    """

    src: str
    alt: str
    caption: str


@dataclass(frozen=True)
class MatrixCell:
    """One entry of a 4×4 matrix.

    Attributes:
        text: The value as shown.
        marked: The two matrices differ here by more than the tolerance.
    """

    text: str
    marked: bool = False


@dataclass(frozen=True)
class MatrixView:
    """A 4×4 matrix: four rows of four cells."""

    rows: tuple[tuple[MatrixCell, ...], ...]


@dataclass(frozen=True)
class PoseForms:
    """A pose as a matrix and in compact forms.

    Attributes:
        matrix: The 4×4 homogeneous transform.
        xyz: Translation, metres.
        quaternion: Unit quaternion ``(x, y, z, w)`` (scalar last, w ≥ 0).
        rpy: Fixed-axis roll, pitch, yaw (URDF convention), degrees.
    """

    matrix: MatrixView
    xyz: str
    quaternion: str
    rpy: str


@dataclass(frozen=True)
class JointValue:
    """One joint value of a configuration.

    Attributes:
        joint: Joint name.
        rad: The value in radians (or metres for a prismatic joint).
        deg: The value in degrees (empty for a prismatic joint).
    """

    joint: str
    rad: str
    deg: str
