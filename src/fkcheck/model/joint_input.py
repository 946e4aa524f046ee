"""Joint values at the boundary: parsing command-line and CSV input, units, limits.

Values are read with :func:`fkcheck.io.numbers.parse_number` (plain ASCII decimals,
no empty fields), files with :func:`fkcheck.io.files.read_lines` (a regular
file of at most 256 MiB, lines of at most 64 KiB, read one line at a time so
that memory holds the configurations only). Whatever the limits say, and with
``--ignore-limits`` too, a joint value beyond the physical bound of the model
file (:data:`fkcheck.model.MAX_JOINT_RAD`, :data:`fkcheck.model.MAX_LENGTH_M`)
is refused, so the forward kinematics never overflows.
"""

from __future__ import annotations

from array import array
from pathlib import Path

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.errors import JointInputError
from fkcheck.io.files import InputFileError, read_lines
from fkcheck.io.numbers import NumberError, parse_numbers
from fkcheck.model.types import MAX_JOINT_RAD, MAX_LENGTH_M, Model

__all__ = ["check_bounds", "check_limits", "parse_q", "read_q_file", "to_internal_units"]


#: Separators between joint values (``30,-60,90`` or ``30;-60;90``).
_SEPARATORS = ",;"


def _parse_numbers(text: str, where: str, *, columns: bool = False) -> list[float]:
    """The values of one configuration; ``where`` and the value's place name a bad one."""
    try:
        return parse_numbers(text, _SEPARATORS)
    except NumberError as exc:
        place = f"column {exc.column} (value {exc.index})" if columns else f"value {exc.index}"
        raise JointInputError(f"{where}: {place}: {exc.problem}") from None


def _row(values: list[float], model: Model, where: str) -> list[float]:
    if len(values) != model.dof:
        raise JointInputError(
            f"{where}: model {model.name} has {model.dof} joints, got {len(values)} values"
        )
    return values


def parse_q(text: str, model: Model, *, where: str = "--q") -> Float:
    """Parse ``"30,-60,90"`` into one configuration of ``model.dof`` values (file units).

    Raises:
        JointInputError: Not numbers (an empty field included), not finite, or
            the wrong count.
    """
    return np.array(_row(_parse_numbers(text, where), model, where))


def read_q_file(path: Path, model: Model) -> Float:
    """Read configurations from a CSV file: one per line, ``#`` comments allowed.

    Returns:
        ``(N, n)`` values in the file's units.

    Raises:
        JointInputError: Not a regular file, too large, not UTF-8, a bad number
            (named by line and column), or a line of the wrong length.
    """
    values = array("d")
    try:
        for lineno, line in read_lines(path):
            content = line.split("#", 1)[0]
            if content.strip():
                where = f"{path}: line {lineno}"
                values.extend(_row(_parse_numbers(content, where, columns=True), model, where))
    except InputFileError as exc:
        raise JointInputError(str(exc)) from None
    if not values:
        raise JointInputError(f"{path}: no configurations in file")
    return np.frombuffer(values, dtype=np.float64).reshape(-1, model.dof)


def to_internal_units(q: Float, model: Model, *, degrees: bool) -> Float:
    """Convert revolute joint values from degrees to radians when ``degrees`` is set.

    Prismatic joint values are metres either way.
    """
    if not degrees:
        return q
    revolute = np.array([j.type == "revolute" for j in model.joints])
    return np.where(revolute, np.deg2rad(q), q)


def check_bounds(q: Float, model: Model) -> None:
    """Raise when a value (radians / metres) is beyond the physical bound, limits or not.

    Raises:
        JointInputError: Names the first configuration and joint beyond
            ±:data:`~fkcheck.model.MAX_JOINT_RAD` rad (revolute) or
            ±:data:`~fkcheck.model.MAX_LENGTH_M` m (prismatic).
    """
    q2 = np.atleast_2d(q)
    prismatic = np.array([j.type == "prismatic" for j in model.joints])
    bound = np.where(prismatic, MAX_LENGTH_M, MAX_JOINT_RAD)
    bad = np.argwhere(np.abs(q2) > bound)
    if bad.size:
        row, col = (int(v) for v in bad[0])
        unit = "m" if prismatic[col] else "rad"
        prefix = f"configuration {row + 1}: " if q2.shape[0] > 1 else ""
        raise JointInputError(
            f"{prefix}joint {model.joints[col].name} = {q2[row, col]:.6g} {unit} is beyond "
            f"±{bound[col]:g} {unit}, more than any arm moves"
        )


def check_limits(q: Float, model: Model, *, degrees: bool = False) -> None:
    """Raise when any value is outside its joint's limits (radians / metres).

    Args:
        q: ``(n,)`` or ``(N, n)`` joint values, radians / metres.
        model: The model whose limits apply.
        degrees: Say revolute values and limits in degrees (the user gave degrees).

    Raises:
        JointInputError: Names the first configuration and joint out of range.
    """
    q2 = np.atleast_2d(q)
    lo, hi = model.limits[:, 0], model.limits[:, 1]
    bad = np.argwhere((q2 < lo) | (q2 > hi))
    if bad.size:
        row, col = (int(v) for v in bad[0])
        joint = model.joints[col]
        value, low, high = q2[row, col], lo[col], hi[col]
        unit = " rad" if joint.type == "revolute" else " m"
        if degrees and joint.type == "revolute":
            value, low, high, unit = *np.degrees([value, low, high]), "°"
        prefix = f"configuration {row + 1}: " if q2.shape[0] > 1 else ""
        raise JointInputError(
            f"{prefix}joint {joint.name} = {value:.6g}{unit} is outside its limits "
            f"[{low:.6g}, {high:.6g}]{unit} (use --ignore-limits to allow)"
        )
