"""Joint values at the boundary: parsing command-line and CSV input, units, limits."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from fkcheck.errors import JointInputError
from fkcheck.model import Model

__all__ = ["check_limits", "parse_q", "read_q_file", "to_internal_units"]

Float = NDArray[np.float64]


def _parse_numbers(text: str, where: str) -> list[float]:
    values = []
    for item in text.replace(";", ",").split(","):
        item = item.strip()
        if not item:
            continue
        try:
            value = float(item)
        except ValueError:
            raise JointInputError(f"{where}: {item!r} is not a number") from None
        if not math.isfinite(value):
            raise JointInputError(f"{where}: joint values must be finite, got {item}")
        values.append(value)
    return values


def parse_q(text: str, model: Model, *, where: str = "--q") -> Float:
    """Parse ``"30,-60,90"`` into one configuration of ``model.dof`` values (file units).

    Raises:
        JointInputError: Not numbers, not finite, or the wrong count.
    """
    values = _parse_numbers(text, where)
    if len(values) != model.dof:
        raise JointInputError(
            f"{where}: model {model.name} has {model.dof} joints, got {len(values)} values"
        )
    return np.array(values)


def read_q_file(path: Path, model: Model) -> Float:
    """Read configurations from a CSV file: one per line, ``#`` comments allowed.

    Raises:
        JointInputError: Unreadable file, a bad number, or a line of the wrong length.
    """
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise JointInputError(f"{path}: cannot read: {exc}") from None
    rows = []
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.split("#", 1)[0].strip()
        if stripped:
            rows.append(parse_q(stripped, model, where=f"{path}: line {lineno}"))
    if not rows:
        raise JointInputError(f"{path}: no configurations in file")
    return np.stack(rows)


def to_internal_units(q: Float, model: Model, *, degrees: bool) -> Float:
    """Convert revolute joint values from degrees to radians when ``degrees`` is set.

    Prismatic joint values are metres either way.
    """
    if not degrees:
        return q
    revolute = np.array([j.type == "revolute" for j in model.joints])
    return np.where(revolute, np.deg2rad(q), q)


def check_limits(q: Float, model: Model) -> None:
    """Raise when any value is outside its joint's limits (radians / metres).

    Raises:
        JointInputError: Names the first configuration and joint out of range.
    """
    q2 = np.atleast_2d(q)
    lo, hi = model.limits[:, 0], model.limits[:, 1]
    bad = np.argwhere((q2 < lo) | (q2 > hi))
    if bad.size:
        row, col = (int(v) for v in bad[0])
        joint = model.joints[col]
        unit = "rad" if joint.type == "revolute" else "m"
        prefix = f"configuration {row + 1}: " if q2.shape[0] > 1 else ""
        raise JointInputError(
            f"{prefix}joint {joint.name} = {q2[row, col]:.6g} {unit} is outside its limits "
            f"[{lo[col]:.6g}, {hi[col]:.6g}] {unit} (use --ignore-limits to allow)"
        )
