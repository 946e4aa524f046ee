"""What looks wrong in a DH table on its own, before anything is compared.

Each rule is a heuristic, so every finding is a *warning*: a real arm can have
a twist that is not a multiple of 90°, or a 6 m reach. The rules:

* ``degrees``: an angle beyond ±2π in a radian file (or one that reads like a
  radian value — π/2, π — in a degree file);
* ``rounded-angle``: α within 0.001 rad of a multiple of π/2 but not on it (1.5708),
  θ within 0.001 rad of a non-zero one (−1.5708; a small θ is an offset), or revolute
  limits up to 0.001 rad beyond ±2π (±6.2832, not degrees);
* ``twist``: α not a multiple of π/2;
* ``length``: a length beyond :data:`LONG_M` (millimetres in a metre file?);
* ``limits``: a revolute joint whose limits exceed ±2π by more than rounding, or
  whose range is under :data:`NARROW_RANGE_RAD` (a prismatic one: no range at all):
  within them no check can tell apart the numbers the joint's motion separates (a
  50 mm split of a2 and a3 around a frozen elbow passes);
* ``convention``: a modified table whose first row has a ≠ 0 or α ≠ 0 (usual for
  standard, unusual for modified), or a standard table shaped like a modified one
  (first row a = α = 0, last row a or α ≠ 0);
* ``published``: every number matches a published table (a bundled model) except
  a few that are close but not equal — a rounded or outdated value;
* ``calibration``: a calibrated model whose table moves its ``[check] to`` frame
  further from its nominal model's than a factory calibration can, or whose nominal
  model cannot be compared with it (:mod:`fkcheck.calibration.lint`);
* ``known-difference``: a ``[[known_difference]]`` naming several URDF readers one
  by one, which a check reads as ``reads = "urdf"``: the current form
  (:func:`fkcheck.engine.expected.known_difference_findings`).

A calibrated model (``[calibration]``, written by ``fkcheck calibration``) holds one
robot's measured table: α a few 1e-4 rad off a quarter turn, or d2/d3 of hundreds of
metres, θ of 7 rad in a linearised table, are what the calibration says, so the rules
about units and round or plausible values (:data:`MEASURED_RULES`) do not look at its
joints; ``fkcheck lint`` says so, and the nominal model is where those rules apply.
Only while the table fits its nominal model (:mod:`fkcheck.calibration.lint` decides,
and adds the ``calibration`` finding when it does not): one that does not (a
hand-written ``[calibration]``, a value edited in millimetres or degrees) is no
calibration of it, and its joints are held to every rule. :func:`lint_model` alone
exempts nothing.

A rule can be turned off per model (``[lint] ignore = ["limits"]`` in the model
file), per project (``lint_ignore`` in ``[tool.fkcheck]``) or per run
(``fkcheck lint --ignore limits``): a real ±400° axis is not a unit error.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Literal

from fkcheck.model.lint_rules import Rule
from fkcheck.model.names import PARAMS, field_text, param_field, param_symbol
from fkcheck.model.published import published_tables, variant_note
from fkcheck.model.types import Model

__all__ = [
    "LONG_M",
    "MEASURED_RULES",
    "NARROW_RANGE_RAD",
    "Finding",
    "Rule",
    "lint_lines",
    "lint_model",
]

#: Lengths beyond this look like a unit error (no arm in the bundled set exceeds 1.3 m).
LONG_M = 5.0
#: Limits within this of ±2π count as ±2π (URDFs write 6.28318530718).
_LIMIT_SLACK = 1e-6
#: A revolute joint's range under this (0.057°) looks like a joint held still by a
#: placeholder: a turn of it moves a point 1 m away by under 1 mm, and no arm's axis
#: is built to move so little. Within such limits a check cannot tell apart the
#: numbers the joint's turn separates (evidence per number says which, from the
#: tolerances: :mod:`fkcheck.model.coverage`). The bundled arms' least is 153° (Baxter).
NARROW_RANGE_RAD = 1e-3
#: "Rounded, not different": the largest differences treated as rounding or an old value.
NEAR_LENGTH_M = 1e-3
NEAR_ANGLE_RAD = 1e-3
_EXACT = 1e-12


#: Rules a calibrated model's joints are exempt from: its numbers are measured, not written
#: (radians and metres from UR's files; lint the nominal model for its own values).
MEASURED_RULES: frozenset[Rule] = frozenset(
    {"degrees", "rounded-angle", "twist", "length", "published"}
)


@dataclass(frozen=True)
class Finding:
    """One warning about a model.

    Attributes:
        rule: Which rule fired (see the module docstring).
        field: Where, as a file field (``joint[0].d``) or ``""`` for the whole table.
        message: What looks wrong and what it probably is.
    """

    rule: Rule
    field: str
    message: str


def _quarter_turns(angle: float) -> tuple[int, float]:
    k = round(angle / (math.pi / 2))
    return k, abs(angle - k * math.pi / 2)


def _angle_text(model: Model, value: float) -> str:
    return f"{math.degrees(value):g}°" if model.angle_unit == "deg" else f"{value:g} rad"


def _offset_fields(model: Model, part: Literal["xyz", "rpy"]) -> list[tuple[str, float]]:
    """Every ``xyz`` or ``rpy`` entry of the base, the tool and the named frames, by file field."""
    offsets = [("base", model.base), ("tool", model.tool)]
    offsets += [(f"frames.{name}", spec.offset) for name, spec in model.frames.items()]
    return [
        (f"{label}.{part}[{k}]", v)
        for label, offset in offsets
        for k, v in enumerate(getattr(offset, part))
    ]


def _angles(model: Model) -> list[Finding]:
    out: list[Finding] = []
    if model.angle_unit == "rad":
        written: list[tuple[str, float]] = []
        for i, joint in enumerate(model.joints):
            written += [(f"joint[{i}].alpha", joint.alpha), (f"joint[{i}].theta", joint.theta)]
        for field, value in written + _offset_fields(model, "rpy"):
            if abs(value) > 2 * math.pi + 1e-9:
                out.append(
                    Finding(
                        "degrees",
                        field,
                        f"{value:g} is beyond ±2π: it looks like "
                        'degrees in a file with angle_unit = "rad"',
                    )
                )
    else:
        for i, joint in enumerate(model.joints):
            for label in ("alpha", "theta"):
                number = math.degrees(getattr(joint, label))  # the number in the file
                for name, target in (("π/2", math.pi / 2), ("π", math.pi)):
                    if number != 0 and abs(abs(number) - target) < 1e-3:
                        out.append(
                            Finding(
                                "degrees",
                                f"joint[{i}].{label}",
                                f'{number:g} in a file with angle_unit = "deg" reads like '
                                f"{name} in radians",
                            )
                        )
    for i in range(model.dof):
        for param in ("alpha", "theta"):
            out += _rounded_or_odd(model, i, param)
    return out


def _rounded_or_odd(model: Model, i: int, param: Literal["alpha", "theta"]) -> list[Finding]:
    """``rounded-angle`` for α or θ near a quarter turn; ``twist`` for any other α."""
    value = getattr(model.joints[i], param)
    k, off = _quarter_turns(value)
    if off <= _EXACT or abs(value) > 2 * math.pi + 1e-9:
        return []
    if param == "theta" and k == 0:  # a small θ offset (0.01°) is a calibrated table's
        return []
    where = param_field(model, i, param)
    if off < NEAR_ANGLE_RAD:
        exact = k * math.pi / 2
        return [
            Finding(
                "rounded-angle",
                f"joint[{i}].{param}",
                f"{where} = {_angle_text(model, value)} is {k * 90}° rounded "
                f"({off:.2g} rad off): write {exact!r} rad or {k * 90} in a degree file",
            )
        ]
    if param == "theta":  # a θ offset of any size is common (Jaco's, a calibration's)
        return []
    return [
        Finding(
            "twist",
            f"joint[{i}].alpha",
            f"{where} = {_angle_text(model, value)} is not a multiple of 90° "
            "(some arms have such twists; most tables do not)",
        )
    ]


def _rounded_limits(model: Model) -> list[Finding]:
    """``rounded-angle`` for revolute limits just beyond ±2π: ±6.2832 is ±360° rounded.

    Within :data:`NEAR_ANGLE_RAD` of a full turn a limit is a rounded 2π (URDFs and
    vendor sheets write 6.2832, 6.28319), not degrees, and ``limits`` leaves it alone.
    """
    out: list[Finding] = []
    for i, joint in enumerate(model.joints):
        if joint.type != "revolute" or joint.limits is None:
            continue
        beyond = [
            v
            for v in joint.limits
            if 2 * math.pi + _LIMIT_SLACK < abs(v) <= 2 * math.pi + NEAR_ANGLE_RAD
        ]
        if not beyond:
            continue
        off = max(abs(v) - 2 * math.pi for v in beyond)
        lo, hi = joint.limits
        out.append(
            Finding(
                "rounded-angle",
                f"joint[{i}].limits",
                f"revolute joint {joint.name} has limits [{_angle_text(model, lo)}, "
                f"{_angle_text(model, hi)}]: ±360° rounded up ({off:.2g} rad beyond): write "
                f"±{2 * math.pi!r} rad or ±360 in a degree file",
            )
        )
    return out


def _lengths(model: Model) -> list[Finding]:
    out: list[Finding] = []
    values: list[tuple[str, float]] = []
    for i, joint in enumerate(model.joints):
        values += [(f"joint[{i}].a", joint.a), (f"joint[{i}].d", joint.d)]
    for field, value in values + _offset_fields(model, "xyz"):
        if abs(value) > LONG_M:
            hint = " — millimetres in a file that must be in metres?" if abs(value) > 50 else ""
            out.append(Finding("length", field, f"{value:g} m is beyond {LONG_M:g} m{hint}"))
    return out


def _limits(model: Model) -> list[Finding]:
    out: list[Finding] = []
    bound = 2 * math.pi + NEAR_ANGLE_RAD  # closer to ±2π is a rounded full turn
    for i, joint in enumerate(model.joints):
        if joint.limits is None:
            continue
        lo, hi = joint.limits
        narrow = NARROW_RANGE_RAD if joint.type == "revolute" else 0.0
        if hi - lo < narrow or hi == lo:
            shown = (
                f"[{_angle_text(model, lo)}, {_angle_text(model, hi)}]"
                if joint.type == "revolute"
                else f"[{lo:g} m, {hi:g} m]"
            )
            out.append(
                Finding(
                    "limits",
                    f"joint[{i}].limits",
                    f"{joint.type} joint {joint.name} has limits {shown}, "
                    + (
                        "no range at all"
                        if hi == lo
                        else f"a range under {math.degrees(NARROW_RANGE_RAD):.2g}°"
                    )
                    + ": within them no check can tell apart the numbers its motion "
                    "separates (evidence per number calls them not identifiable) — is the "
                    "joint meant to move?",
                )
            )
            continue
        if joint.type != "revolute":
            continue
        if lo < -bound or hi > bound:
            hint = (
                ' (degrees in a file with angle_unit = "rad"?)' if model.angle_unit == "rad" else ""
            )
            out.append(
                Finding(
                    "limits",
                    f"joint[{i}].limits",
                    f"revolute joint {joint.name} has limits [{_angle_text(model, lo)}, "
                    f"{_angle_text(model, hi)}], beyond ±360°{hint}",
                )
            )
    return out


def _convention(model: Model) -> list[Finding]:
    first, last = model.joints[0], model.joints[-1]
    if model.convention == "modified" and (abs(first.a) > _EXACT or abs(first.alpha) > _EXACT):
        return [
            Finding(
                "convention",
                "joint[0]",
                f"modified (Craig) table whose first row has a0 = {first.a:g}, α0 = "
                f"{_angle_text(model, first.alpha)}: usual in standard DH, unusual in modified "
                "(frame 0 normally lies on axis 1) — is it a standard table?",
            )
        ]
    if (
        model.convention == "standard"
        and model.dof > 1
        and abs(first.a) <= _EXACT
        and abs(first.alpha) <= _EXACT
        and (abs(last.a) > _EXACT or abs(last.alpha) > _EXACT)
    ):
        return [
            Finding(
                "convention",
                "",
                "standard table shaped like a modified (Craig) one: the first row has a = α = 0 "
                f"and the last has a = {last.a:g}, α = {_angle_text(model, last.alpha)} — in a "
                "modified table row i holds a_{i-1}, α_{i-1}",
            )
        ]
    return []


def _signed(value: float, unit: str) -> str:
    """``+0.300 mm``, ``-9.74e-05°``: three decimals, or three digits when they would read 0."""
    return f"{value:+.3f}{unit}" if abs(value) >= 5e-4 else f"{value:+.3g}{unit}"


def _published(model: Model) -> list[Finding]:
    out: list[Finding] = []
    for table in published_tables():
        if table.dof != model.dof or table.convention != model.convention:
            continue
        near: list[tuple[int, str, float, float]] = []
        matches = True
        for i, (ours, theirs) in enumerate(zip(model.joints, table.joints, strict=True)):
            for param in PARAMS:
                a, b = getattr(ours, param), getattr(theirs, param)
                diff = abs(a - b)
                limit = NEAR_ANGLE_RAD if param in ("alpha", "theta") else NEAR_LENGTH_M
                if diff <= _EXACT:
                    continue
                if diff <= limit:
                    near.append((i, param, a, b))
                else:
                    matches = False
        if not matches or not near:
            continue
        for i, pname, a, b in near:
            length = pname in ("a", "d")
            delta = _signed((a - b) * 1e3, " mm") if length else _signed(math.degrees(a - b), "°")
            others = [param_symbol(model, k, p) for k, p, _, _ in near if (k, p) != (i, pname)]
            rest = (
                "every other number matches"
                if not others
                else f"{', '.join(others)} {'is' if len(others) == 1 else 'are'} close too, "
                "every other number matches"
            )
            text = (
                f"{param_field(model, i, pname)} = {a!r} is {delta} from "
                f"{b!r} in the published table {table.name} ({table.description or table.name}); "
                f"{rest}: a rounded or outdated value?"
            )
            note = variant_note(table.name, i, pname, a)
            if note:
                text += f" {a!r} is the value in {note}."
            out.append(Finding("published", f"joint[{i}].{pname}", text))
    return out


def lint_model(
    model: Model,
    ignore: Iterable[str] = (),
    *,
    measured: bool = False,
    more: Iterable[Finding] = (),
) -> list[Finding]:
    """Every warning for ``model``, in the order of the rules above.

    Args:
        model: The model.
        ignore: Rules to leave out, on top of the model file's ``[lint] ignore``.
        measured: Its joints hold measured values (a calibration that fits its
            nominal model, as :func:`fkcheck.calibration.lint.lint_calibrated`
            decides): the :data:`MEASURED_RULES` do not look at them.
        more: Findings of rules decided elsewhere (``calibration``,
            ``known-difference``), added last.
    """
    skipped = {*model.lint_ignore, *ignore}
    findings = [
        *_angles(model),
        *_rounded_limits(model),
        *_lengths(model),
        *_limits(model),
        *_convention(model),
        *_published(model),
    ]
    if measured:
        findings = [
            f for f in findings if not (f.rule in MEASURED_RULES and f.field.startswith("joint["))
        ]
    findings += more
    return [f for f in findings if f.rule not in skipped]


def lint_lines(model: Model, findings: Iterable[Finding]) -> tuple[str, ...]:
    """``findings`` of ``model`` as one line each: ``field (joint): message [rule]``."""
    return tuple(
        f"{field_text(model, f.field) + ': ' if f.field else ''}{f.message} [{f.rule}]"
        for f in findings
    )
