"""Edits of a DH table's ``[[joint]]`` rows, as a model file would take them.

Where a table and a description of the same arm differ by conventions (a
vendor's table against a ROS-Industrial URDF: joints that turn the other way,
zeros a quarter turn apart), ``fkcheck map`` and ``fkcheck diagnose`` say which
rows to change. :class:`TableEdits` holds those changes, applies them to a
:class:`~fkcheck.model.Model` (:meth:`TableEdits.apply`) and says each as the
line a user types (:meth:`TableEdits.lines`), in the file's ``angle_unit``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from fkcheck.model.names import param_symbol
from fkcheck.model.types import Joint, Model

__all__ = ["TableEdits", "format_turn", "half_turns_as_signs"]

#: The parameters an edit may negate.
_NEGATABLE = ("alpha", "a")


@dataclass(frozen=True)
class TableEdits:
    """Changes to a table's rows, each by joint name.

    Attributes:
        flips: Joints whose ``flip`` is toggled (they turn the other way).
        thetas: ``(joint, radians)`` added to the joint's θ (its zero moved).
        negated: ``(joint, parameter)`` whose sign is changed (``"alpha"``, ``"a"``).
        values: ``(joint, parameter, value)`` set to another value (m or rad): a
            number that differs beyond the conventions.
    """

    flips: tuple[str, ...] = ()
    thetas: tuple[tuple[str, float], ...] = ()
    negated: tuple[tuple[str, str], ...] = ()
    values: tuple[tuple[str, str, float], ...] = ()

    def __post_init__(self) -> None:
        for _, param in self.negated:
            if param not in _NEGATABLE:
                raise ValueError(f"cannot negate {param!r}: only {', '.join(_NEGATABLE)}")

    @property
    def count(self) -> int:
        """How many numbers or settings of the model file the edits change."""
        return len(self.flips) + len(self.thetas) + len(self.negated) + len(self.values)

    def __bool__(self) -> bool:
        return self.count > 0

    def apply(self, model: Model) -> Model:
        """The model with the edits made (a new model; ``model`` is unchanged).

        Raises:
            KeyError: An edit names a joint the model does not have.
        """
        index = {j.name: k for k, j in enumerate(model.joints)}
        joints = list(model.joints)

        def edit(name: str, **changes: object) -> None:
            k = index[name]
            joints[k] = replace(joints[k], **changes)  # type: ignore[arg-type]

        for name in self.flips:
            edit(name, flip=not joints[index[name]].flip)
        for name, turn in self.thetas:
            edit(name, theta=joints[index[name]].theta + turn)
        for name, param in self.negated:
            edit(name, **{param: -getattr(joints[index[name]], param)})
        for name, param, value in self.values:
            edit(name, **{param: value})
        return replace(model, joints=tuple(joints))

    def lines(self, model: Model) -> list[str]:
        """One line per edit, in the model file's unit, joint order.

        ``[[joint]] J3: flip = true``, ``[[joint]] A2: theta = -90 (was 0: θ2's
        zero -90° away)``, ``[[joint]] wrist_1: alpha = 90 (was -90: α4's sign)``,
        ``[[joint]] A2: a = 0.68 (was 0.681: a2 differs)``.
        """
        edited = self.apply(model)
        out: list[tuple[int, str]] = []
        for k, (old, new) in enumerate(zip(model.joints, edited.joints, strict=True)):
            head = f"[[joint]] {old.name}:"
            if old.flip != new.flip:
                out.append((k, f"{head} flip = {'true' if new.flip else 'false'}"))
            set_here = {p for n, p, _ in self.values if n == old.name}
            for param in ("a", "alpha", "d", "theta"):
                a, b = getattr(old, param), getattr(new, param)
                if a == b:
                    continue
                symbol = param_symbol(model, k, param)
                if param in set_here:
                    why = f"{symbol} differs"
                elif param == "theta":
                    why = f"{symbol}'s zero {format_turn(b - a)} away"
                else:
                    why = f"{symbol}'s sign"
                shown = _angle if param in ("alpha", "theta") else _length
                out.append(
                    (k, f"{head} {param} = {shown(model, b)} (was {shown(model, a)}: {why})")
                )
        return [line for _, line in sorted(out, key=lambda x: x[0])]


def format_turn(rad: float) -> str:
    """A multiple of a quarter turn, as people say it: ``+90°``, ``-90°``, ``180°``."""
    deg = math.degrees(rad)
    if abs(abs(deg) - 180.0) < 1e-9:
        return "180°"
    return f"{deg:+.12g}°"


def _angle(model: Model, rad: float) -> str:
    value = math.degrees(rad) if model.angle_unit == "deg" else rad
    return _number(value)


def _length(model: Model, m: float) -> str:
    return _number(m)


def _number(value: float) -> str:
    """A number as a model file writes it: the shortest text that reads back the same."""
    rounded = round(value, 9)
    if math.isclose(rounded, value, rel_tol=0.0, abs_tol=1e-12):
        value = rounded + 0.0
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text


def half_turns_as_signs(
    joints: tuple[Joint, ...], convention: str, thetas: list[float]
) -> list[tuple[int, str]]:
    """Half turns on two neighbouring zeros, said as the sign of the row between them.

    ``θk + 180°`` and ``θk+1 + 180°`` together move the chain exactly as ``αk``
    (and ``ak``) with the other sign do: Rz(π) moved through ``Tx(a)·Rx(α)`` turns
    both round. A sign typed the other way is likelier than two zeros half a
    turn away, so the pair is said so. ``thetas`` (radians added, per joint) is
    changed in place: the pairs said as signs are set to 0.

    Returns:
        ``(joint index, parameter)`` to negate, for each pair.
    """
    out: list[tuple[int, str]] = []
    k = 0
    while k + 1 < len(thetas):
        if _half(thetas[k]) and _half(thetas[k + 1]) and joints[k].type == "revolute":
            row = k if convention == "standard" else k + 1
            out += [(row, p) for p in _NEGATABLE if getattr(joints[row], p) != 0.0]
            thetas[k] = thetas[k + 1] = 0.0
            k += 2
        else:
            k += 1
    return out


def _half(rad: float) -> bool:
    return abs(abs(rad) - math.pi) < 1e-12
