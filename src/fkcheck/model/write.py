"""Writing a :class:`~fkcheck.model.Model` back out as a model file (the TOML schema).

The inverse of :func:`fkcheck.model.model_from_dict`: what this writes loads back
into the same model (numbers as Python's shortest round-trip ``repr``, so
radians survive exactly; with ``angle_unit = "deg"`` angles go through one
multiplication each way, a few ulps). Comments can be attached to the header,
to each joint row and to each frame, so generated files explain themselves.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Literal

from fkcheck.io.text import terminal_text
from fkcheck.model.types import (
    CalibrationSpec,
    CheckSpec,
    FrameSpec,
    Joint,
    KnownDifference,
    Model,
    Offset,
    UrdfSpec,
)

__all__ = [
    "frame_toml",
    "model_to_toml",
    "offset_toml",
    "relocate_urdf_path",
    "toml_comment",
    "toml_key",
    "toml_number",
    "toml_string",
    "xacro_toml",
]

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def toml_number(value: float) -> str:
    """A finite float as TOML: the shortest text that reads back as the same float."""
    if not math.isfinite(value):
        raise ValueError(f"TOML model files hold finite numbers only, got {value}")
    text = repr(float(value))
    return "0.0" if text == "-0.0" else text


def toml_key(key: str) -> str:
    """A table key: bare when it can be, else a quoted string."""
    return key if _BARE_KEY.match(key) else toml_string(key)


def toml_string(text: str) -> str:
    """A TOML basic string: JSON's escapes are TOML's, and TOML escapes DEL too."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _numbers(values: Sequence[float]) -> str:
    return "[" + ", ".join(toml_number(v) for v in values) + "]"


def toml_comment(lines: str | Sequence[str] | None) -> list[str]:
    """Comment lines (``# …``); text from input shows its control characters escaped."""
    if not lines:
        return []
    items = lines.splitlines() if isinstance(lines, str) else list(lines)
    # A comment line holds no control character (TOML): names in it show them escaped.
    return [f"# {terminal_text(line)}".rstrip() for line in items]


def _angle(value: float, unit: Literal["rad", "deg"]) -> float:
    if unit == "rad":
        return value
    degrees = math.degrees(value)
    # 30° read as radians and written back is 29.999999999999996; print 30.0. The
    # snap moves a value by at most 1e-11° (2e-13 rad), far below any tolerance.
    rounded = round(degrees, 9)
    return rounded if abs(rounded - degrees) < 1e-11 else degrees


def _offset_lines(offset: Offset, unit: Literal["rad", "deg"]) -> list[str]:
    lines = []
    if any(offset.xyz):
        lines.append(f"xyz = {_numbers(offset.xyz)}")
    if any(offset.rpy):
        lines.append(f"rpy = {_numbers([_angle(v, unit) for v in offset.rpy])}")
    return lines


def offset_toml(label: str, offset: Offset, unit: Literal["rad", "deg"] = "rad") -> str:
    """The ``[base]`` or ``[tool]`` table (``label``) of ``offset``, angles in ``unit``."""
    return "\n".join([f"[{label}]", *_offset_lines(offset, unit)]) + "\n"


def frame_toml(
    spec: FrameSpec, unit: Literal["rad", "deg"] = "rad", comment: str | Sequence[str] | None = None
) -> str:
    """One ``[frames.NAME]`` table, angles in ``unit``."""
    lines = toml_comment(comment)
    lines.append(f"[frames.{toml_key(spec.name)}]")
    lines.append(f"dh = {spec.dh}" if isinstance(spec.dh, int) else f"dh = {toml_string(spec.dh)}")
    lines.extend(_offset_lines(spec.offset, unit))
    if spec.urdf is not None:
        lines.append(f"urdf = {toml_string(spec.urdf)}")
    if spec.mjcf is not None:
        lines.append(f"mjcf = {toml_string(spec.mjcf)}")
    if spec.source:
        lines.append(f"source = {toml_string(spec.source)}")
    return "\n".join(lines) + "\n"


def _joint_lines(joint: Joint, unit: Literal["rad", "deg"]) -> list[str]:
    lines = ["[[joint]]", f"name = {toml_string(joint.name)}"]
    if joint.type != "revolute":
        lines.append(f"type = {toml_string(joint.type)}")
    lines.append(f"a = {toml_number(joint.a)}")
    lines.append(f"alpha = {toml_number(_angle(joint.alpha, unit))}")
    lines.append(f"d = {toml_number(joint.d)}")
    lines.append(f"theta = {toml_number(_angle(joint.theta, unit))}")
    if joint.flip:
        lines.append("flip = true")
    if joint.limits is not None:
        lo, hi = joint.limits
        if joint.type == "revolute":
            lo, hi = _angle(lo, unit), _angle(hi, unit)
        lines.append(f"limits = {_numbers([lo, hi])}")
    return lines


def xacro_toml(urdf: UrdfSpec) -> list[str]:
    """The ``[urdf]`` lines of the xacro opt-in: ``xacro`` and its tables."""
    out = ["xacro = true"] if urdf.xacro else []
    tables = (
        ("xacro_args", urdf.xacro_args),
        ("packages", urdf.packages),
        ("xacro_files", urdf.xacro_files),
    )
    for key, table in tables:
        if table:
            items = ", ".join(f"{toml_string(k)} = {toml_string(v)}" for k, v in table.items())
            out.append(f"{key} = {{ {items} }}")
    return out


def _is_default_frame(spec: FrameSpec) -> bool:
    return (
        spec.name in ("world", "tcp")
        and spec.dh == spec.name
        and spec.offset.is_identity
        and spec.urdf is None
        and spec.mjcf is None
    )


def model_to_toml(
    model: Model,
    *,
    angle_unit: Literal["rad", "deg"] | None = None,
    header: str | Sequence[str] | None = None,
    joint_comments: Mapping[int, str | Sequence[str]] | None = None,
    frame_comments: Mapping[str, str | Sequence[str]] | None = None,
) -> str:
    """The model as a TOML model file.

    Args:
        model: The model to write.
        angle_unit: Unit of the written angles (default: the model's own).
        header: Comment lines at the top of the file.
        joint_comments: Comment lines before joint row ``i`` (0-based).
        frame_comments: Comment lines before ``[frames.NAME]``.

    Returns:
        The file's text; :func:`fkcheck.model.model_from_dict` reads it back.
    """
    unit: Literal["rad", "deg"] = angle_unit or model.angle_unit
    joint_comments = joint_comments or {}
    frame_comments = frame_comments or {}
    out: list[str] = toml_comment(header)
    if out:
        out.append("")
    out += _header_lines(model, unit)
    for i, joint in enumerate(model.joints):
        out.append("")
        out.extend(toml_comment(joint_comments.get(i)))
        out.extend(_joint_lines(joint, unit))
    for label, offset in (("base", model.base), ("tool", model.tool)):
        if not offset.is_identity:
            out.extend(["", offset_toml(label, offset, unit).rstrip("\n")])
    if model.poses:
        out += _poses_lines(model, unit)
    if model.urdf is not None:
        joints = ", ".join(toml_string(n) for n in model.urdf.joints)
        out.extend(["", "[urdf]", f"path = {toml_string(model.urdf.path)}", f"joints = [{joints}]"])
        out.extend(xacro_toml(model.urdf))
    if model.mjcf is not None:
        joints = ", ".join(toml_string(n) for n in model.mjcf.joints)
        out.extend(["", "[mjcf]", f"path = {toml_string(model.mjcf.path)}", f"joints = [{joints}]"])
    for name, spec in model.frames.items():
        if _is_default_frame(spec):
            continue
        out.append("")
        out.append(frame_toml(spec, unit, frame_comments.get(name)).rstrip("\n"))
    out += _check_lines(model.check)
    if model.lint_ignore:
        rules = ", ".join(toml_string(rule) for rule in model.lint_ignore)
        out.extend(["", "[lint]", f"ignore = [{rules}]"])
    for known in model.known_differences:
        out += _known_difference_lines(known)
    if model.calibration is not None:
        out += _calibration_lines(model.calibration)
    return "\n".join(out) + "\n"


def _calibration_lines(spec: CalibrationSpec) -> list[str]:
    """The ``[calibration]`` table."""
    out = [
        "",
        "[calibration]",
        f"nominal = {toml_string(spec.nominal)}",
        f"file = {toml_string(spec.file)}",
        f"form = {toml_string(spec.form)}",
        f"sha256 = {toml_string(spec.sha256)}",
    ]
    if spec.identity:
        out.append(f"identity = {toml_string(spec.identity)}")
    if spec.status is not None:
        out.append(f"status = {spec.status}")
    return out


def _header_lines(model: Model, unit: Literal["rad", "deg"]) -> list[str]:
    """``name``, ``description`` and ``source`` (when given), ``convention``, ``angle_unit``."""
    out = [f"name = {toml_string(model.name)}"]
    if model.description:
        out.append(f"description = {toml_string(model.description)}")
    if model.source:
        out.append(f"source = {toml_string(model.source)}")
    out.append(f"convention = {toml_string(model.convention)}")
    out.append(f"angle_unit = {toml_string(unit)}")
    return out


def _poses_lines(model: Model, unit: Literal["rad", "deg"]) -> list[str]:
    """``[poses]``, revolute values in ``unit``."""
    out = ["", "[poses]"]
    for pname, values in model.poses.items():
        shown = [
            _angle(v, unit) if j.type == "revolute" else v
            for v, j in zip(values, model.joints, strict=True)
        ]
        out.append(f"{toml_key(pname)} = {_numbers(shown)}")
    return out


def _check_lines(check: CheckSpec) -> list[str]:
    """``[check]``: always the frame pair and tolerances, the rest when not the default."""
    out = [
        "",
        "[check]",
        f"from = {toml_string(check.frame_from)}",
        f"to = {toml_string(check.frame_to)}",
    ]
    out.append(f"tol_pos_m = {toml_number(check.tol_pos_m)}")
    out.append(f"tol_rot_rad = {toml_number(check.tol_rot_rad)}")
    if check.require:
        out.append(f"require = [{', '.join(toml_string(k) for k in check.require)}]")
    if check.jacobian:
        out.append("jacobian = true")
    if check.jacobian or check.jacobian_reference != "world-aligned":
        out.append(f"jacobian_reference = {toml_string(check.jacobian_reference)}")
        out.append(f"tol_jacobian = {toml_number(check.tol_jacobian)}")
    return out


def _known_difference_lines(known: KnownDifference) -> list[str]:
    """One ``[[known_difference]]`` table."""
    names = ", ".join(toml_string(name) for name in known.backends)
    selected = [f"backends = [{names}]"] if known.backends else []
    if known.reads:
        selected.append(f"reads = {toml_string(known.reads)}")
    if known.versions:
        selected.append(f"versions = {toml_string(known.versions)}")
    return [
        "",
        "[[known_difference]]",
        *selected,
        f"finding = {toml_string(known.finding)}",
        f"max_position_m = {toml_number(known.max_position_m)}",
        f"max_angle_rad = {toml_number(known.max_angle_rad)}",
    ]


def relocate_urdf_path(model: Model, new_file: Path) -> Model:
    """The model with a relative ``[urdf].path`` rewritten for a file written at ``new_file``.

    A relative URDF path (and a relative ``[urdf] packages`` directory) is
    relative to the model file; a model written elsewhere must point at the same
    files (and ``xacro_files``). ``example-robot-data:``, ``fkcheck:`` and absolute
    paths are kept as they are.
    """
    if model.urdf is None or model.path is None:
        return model
    old_dir, new_dir = model.path.parent, Path(new_file).resolve().parent

    def moved(spec: str) -> str:
        if spec.startswith(("example-robot-data:", "fkcheck:")) or Path(spec).is_absolute():
            return spec
        return Path(os.path.relpath((old_dir / spec).resolve(), new_dir)).as_posix()

    packages = {name: moved(where) for name, where in model.urdf.packages.items()}
    files = {name: moved(where) for name, where in model.urdf.xacro_files.items()}
    urdf = replace(model.urdf, path=moved(model.urdf.path), packages=packages, xacro_files=files)
    return replace(model, urdf=urdf)
