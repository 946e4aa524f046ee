"""The model section: the DH table, the base and tool transforms, the frames.

View models (:mod:`fkcheck.report.views`): plain text, numbers and nested views only.
"""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.report.views.cells import MatrixView

__all__ = [
    "DhRow",
    "FrameRow",
    "ModelView",
    "TransformView",
]


@dataclass(frozen=True)
class DhRow:
    """One row of the DH table as shown (lengths m, angles degrees).

    Attributes:
        index: Row number, 1-based.
        joint: Joint name.
        type: ``revolute`` or ``prismatic``.
        a: Link length.
        alpha: Link twist.
        d: Link offset.
        theta: Joint angle offset.
        flip: ``yes`` when the joint turns the other way.
        limits: Joint limits.
        urdf_joint: The URDF joint mapped to it, if any.
        variable: Which of θ or d the joint value drives.
    """

    index: int
    joint: str
    type: str
    a: str
    alpha: str
    d: str
    theta: str
    flip: str
    limits: str
    urdf_joint: str
    variable: str


@dataclass(frozen=True)
class TransformView:
    """A fixed transform (the base or tool).

    Attributes:
        label: ``"base (world → DH frame 0)"`` or similar.
        summary: xyz (m) and rpy (degrees), or ``"identity"``.
        matrix: The 4×4 matrix.
    """

    label: str
    summary: str
    matrix: MatrixView


@dataclass(frozen=True)
class FrameRow:
    """One named frame of the model's mapping.

    Attributes:
        name: Frame name.
        placement: DH frame it is attached to.
        offset: Fixed offset from there.
        urdf: URDF twin, if any.
        compared: ``from`` / ``to`` when this check compares it.
    """

    name: str
    placement: str
    offset: str
    urdf: str
    compared: str


@dataclass(frozen=True)
class ModelView:
    """The model as the report shows it.

    Attributes:
        name: Model name.
        description: Free text from the model file.
        source: Where its numbers come from.
        path: The model file.
        convention: ``standard`` or ``modified``.
        convention_formula: ``A_i`` as a product of elementary motions.
        a_matrix: ``A_i`` written out, 4 rows of 4 symbolic entries.
        variable_note: How θ and d depend on the joint value.
        rows: The DH table.
        base: Base transform.
        tool: Tool transform.
        frames: Named frames.
        urdf: The reference URDF as written in the model file, or empty.
    """

    name: str
    description: str
    source: str
    path: str
    convention: str
    convention_formula: str
    a_matrix: tuple[tuple[str, ...], ...]
    variable_note: str
    rows: tuple[DhRow, ...]
    base: TransformView
    tool: TransformView
    frames: tuple[FrameRow, ...]
    urdf: str
