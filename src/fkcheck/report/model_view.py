"""The report's model section: the DH table, A_i, base, tool and named frames as views.

Every number goes through :mod:`fkcheck.io.format`; text from a model
file or URDF passes through unchanged and is escaped by the templates.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from fkcheck.description.registry import model_format
from fkcheck.engine.results import CheckResult
from fkcheck.io.format import (
    format_constant,
    format_fixed,
)
from fkcheck.model.types import FrameSpec, Model, Offset
from fkcheck.report.views import (
    DhRow,
    FrameRow,
    FrameSide,
    ModelView,
    TransformView,
)

if TYPE_CHECKING:
    pass

from fkcheck.report.measures import matrix_view, xyz_rpy_text
from fkcheck.urdf.locate import display_path

__all__ = ["frame_sides", "model_view", "placement", "urdf_twin"]


_STANDARD_A = (
    ("cos θᵢ", "−sin θᵢ cos αᵢ", "sin θᵢ sin αᵢ", "aᵢ cos θᵢ"),
    ("sin θᵢ", "cos θᵢ cos αᵢ", "−cos θᵢ sin αᵢ", "aᵢ sin θᵢ"),
    ("0", "sin αᵢ", "cos αᵢ", "dᵢ"),
    ("0", "0", "0", "1"),
)


_MODIFIED_A = (
    ("cos θᵢ", "−sin θᵢ", "0", "aᵢ₋₁"),
    ("sin θᵢ cos αᵢ₋₁", "cos θᵢ cos αᵢ₋₁", "−sin αᵢ₋₁", "−dᵢ sin αᵢ₋₁"),
    ("sin θᵢ sin αᵢ₋₁", "cos θᵢ sin αᵢ₋₁", "cos αᵢ₋₁", "dᵢ cos αᵢ₋₁"),
    ("0", "0", "0", "1"),
)


_FORMULA = {
    "standard": "standard DH: Aᵢ = Rz(θᵢ) · Tz(dᵢ) · Tx(aᵢ) · Rx(αᵢ), mapping frame i−1 to frame i",
    "modified": "modified DH (Craig): Aᵢ = Rx(αᵢ₋₁) · Tx(aᵢ₋₁) · Rz(θᵢ) · Tz(dᵢ), mapping frame "
    "i−1 to frame i; row i of the table holds aᵢ₋₁ and αᵢ₋₁",
}


_VARIABLE_NOTE = (
    "Revolute joint: θᵢ = sᵢ·qᵢ + θ offset, dᵢ fixed; prismatic joint: dᵢ = sᵢ·qᵢ + d "
    "offset, θᵢ fixed; sᵢ = −1 for a flipped joint, else +1. "
    "world_T_tcp = base · A₁ ⋯ Aₙ · tool."
)


def placement(model: Model, spec: FrameSpec) -> str:
    """Where a named frame sits on the DH chain, in words."""
    if spec.dh == "world":
        return "the world frame (before the base transform)"
    if spec.dh == "tcp":
        return "the TCP (after the tool transform)"
    if spec.dh == 0:
        return "DH frame 0 (the DH base)"
    joint = model.joints[spec.dh - 1]
    last = ", the last DH frame" if spec.dh == model.dof else ""
    return f"DH frame {spec.dh} (after joint {spec.dh}, {joint.name}{last})"


def urdf_twin(model: Model, spec: FrameSpec) -> str:
    """A named frame's twin in the model's description, in words (or that it has none)."""
    fmt = model_format(model)
    twin = spec.urdf if fmt is None else fmt.frame(spec)
    language = "URDF" if fmt is None else fmt.language.upper()
    if twin is None:
        return f"no {language} twin: only backends built from the DH table compare it"
    where = f" of {fmt.written(model)}" if fmt is not None else ""
    return f"{language} link {twin}{where}"


def frame_sides(check: CheckResult) -> tuple[FrameSide, ...]:
    """The compared ``from`` and ``to`` frames, each placed and mapped."""
    model = check.model
    out = []
    for role, name in (("from", check.frame_from), ("to", check.frame_to)):
        spec = model.frames[name]
        out.append(
            FrameSide(
                role,
                name,
                placement(model, spec),
                xyz_rpy_text(spec.offset),
                urdf_twin(model, spec),
            )
        )
    return tuple(out)


def _transform_view(label: str, offset: Offset) -> TransformView:
    summary = "identity" if offset.is_identity else xyz_rpy_text(offset)
    return TransformView(
        label, summary, matrix_view(offset.matrix, fmt=lambda v: format_fixed(v, 6))
    )


def _limits(model: Model, i: int) -> str:
    joint = model.joints[i]
    if joint.limits is None:
        return "none"
    lo, hi = joint.limits
    if joint.type == "prismatic":
        return f"{format_constant(lo)} … {format_constant(hi)} m"
    return f"{format_constant(math.degrees(lo))} … {format_constant(math.degrees(hi))}°"


def model_view(check: CheckResult) -> ModelView:
    """The model section: the DH table, Aᵢ, base, tool and named frames."""
    model = check.model
    fmt = model_format(model)
    urdf_joints = fmt.mapped_joints(model) if fmt is not None else ()
    rows = tuple(
        DhRow(
            index=i + 1,
            joint=j.name,
            type=j.type,
            a=format_constant(j.a),
            alpha=format_constant(math.degrees(j.alpha)),
            d=format_constant(j.d),
            theta=format_constant(math.degrees(j.theta)),
            flip="yes" if j.flip else "",
            limits=_limits(model, i),
            urdf_joint=urdf_joints[i] if i < len(urdf_joints) else "",
            variable="d" if j.type == "prismatic" else "θ",
        )
        for i, j in enumerate(model.joints)
    )
    compared = {check.frame_from: "from", check.frame_to: "to"}
    frames = tuple(
        FrameRow(
            name=name,
            placement=placement(model, spec),
            offset=xyz_rpy_text(spec.offset),
            urdf=spec.urdf or "",
            compared=compared.get(name, ""),
        )
        for name, spec in model.frames.items()
    )
    source = model.source
    effect = check.calibration
    if effect is not None and effect.provenance is not None and effect.provenance.note:
        source = f"{source} — {effect.provenance.note}"  # the provenance no longer holds as said
    return ModelView(
        name=model.name,
        description=model.description,
        source=source,
        path=display_path(model.path) if model.path is not None else "(built in memory)",
        convention=model.convention,
        convention_formula=_FORMULA[model.convention],
        a_matrix=_STANDARD_A if model.convention == "standard" else _MODIFIED_A,
        variable_note=_VARIABLE_NOTE,
        rows=rows,
        base=_transform_view("base: world → DH frame 0", model.base),
        tool=_transform_view(f"tool: DH frame {model.dof} → TCP", model.tool),
        frames=frames,
        urdf=fmt.written(model) if fmt is not None else "",
    )
