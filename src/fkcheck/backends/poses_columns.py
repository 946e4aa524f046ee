"""The columns of a measured-poses CSV: which header names hold what, in which units.

Part of :mod:`fkcheck.backends.measured`: :class:`_Layout` reads fkcheck's poses CSV
by its header (joints ``q1 … qn``, position ``x, y, z``, one of the rotation formats,
each with its unit's suffix); UR's RTDE recordings are :mod:`.poses_rtde`'s.
:class:`PosesFileError` is the one line a bad file ends in.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import chain
from pathlib import Path

import numpy as np

from fkcheck.errors import FkcheckError
from fkcheck.io.numbers import NumberError, parse_numbers, show_text, split_fields
from fkcheck.model.types import MAX_JOINT_RAD, MAX_LENGTH_M, Model

__all__ = ["CSV_METHOD", "MAX_ROTATION_NUMBER", "PosesFileError"]

#: How the report names a poses CSV's reading (:attr:`MeasuredPoses.method
#: <fkcheck.backends.measured.MeasuredPoses.method>`).
CSV_METHOD = "measured poses (CSV)"
#: Largest rotation number (a quaternion component or an angle in radians).
MAX_ROTATION_NUMBER = 1e3
_ROTATIONS: dict[str, tuple[str, ...]] = {
    "quat": ("qx", "qy", "qz", "qw"),
    "rotvec": ("rx", "ry", "rz"),
    "rpy": ("roll", "pitch", "yaw"),
    "zyx": ("A", "B", "C"),
}


class PosesFileError(FkcheckError):
    """A measured-poses file that cannot be read.

    Attributes:
        path: The file.
        problem: What is wrong (with the line number where there is one).
    """

    def __init__(self, path: Path, problem: str) -> None:
        self.path = path
        self.problem = problem
        super().__init__(f"{path}: {problem}")


#: The unit suffixes a column may carry, per quantity, with their factors to SI: a
#: suffix is valid only for what it measures (``q1_mm`` on a revolute joint was read
#: as milliradians, ``x_deg`` as a position, ``rx_mm`` as a rotation).
_ANGLE: dict[str, float] = {"": 1.0, "_deg": math.pi / 180}
_LENGTH: dict[str, float] = {"": 1.0, "_mm": 1e-3}
_PLAIN: dict[str, float] = {"": 1.0}
_SUFFIXES = ("_deg", "_mm")
_MEASURES = {"_deg": "an angle", "_mm": "a length"}


def _column(
    header: list[str], name: str, units: dict[str, float], what: str, path: Path
) -> tuple[int, float] | None:
    """The index and factor to SI of column ``name`` (with one of ``units``' suffixes).

    ``None`` when no such column is there. ``what`` says what the column measures
    (``joint 2 (shoulder), revolute``) for the messages.

    Raises:
        PosesFileError: The column carries a suffix for another quantity, or is
            there twice with different suffixes.
    """
    found = [(header.index(name + u), f) for u, f in units.items() if name + u in header]
    wrong = [name + u for u in _SUFFIXES if u not in units and name + u in header]
    if wrong:
        allowed = " or ".join(name + u for u in units)
        suffix = wrong[0][len(name) :]
        raise PosesFileError(
            path,
            f"column {wrong[0]}: {suffix} is for {_MEASURES[suffix]}, but {name} is {what}; "
            f"name it {allowed}",
        )
    if len(found) > 1:
        names = " and ".join(header[i] for i, _ in found)
        raise PosesFileError(path, f"columns {names} are the same number; keep one")
    return found[0] if found else None


def _columns(
    header: list[str], names: Sequence[str], units: Sequence[dict[str, float]],
    whats: Sequence[str], path: Path,
) -> tuple[list[int], list[float]] | None:  # fmt: skip
    """:func:`_column` of each name; ``None`` when none of them is there.

    Raises:
        PosesFileError: Some are there and some are not, or one carries a wrong suffix.
    """
    found = [_column(header, n, u, w, path) for n, u, w in zip(names, units, whats, strict=True)]
    if all(f is None for f in found):
        return None
    missing = [n for n, f in zip(names, found, strict=True) if f is None]
    if missing:
        raise PosesFileError(
            path,
            f"header needs columns {', '.join(names)} (each with its unit's suffix, if any); "
            f"it lacks {', '.join(missing)}; it has: {_names(header)}",
        )
    return [f[0] for f in found if f], [f[1] for f in found if f]


def _needed(
    header: list[str], names: Sequence[str], units: Sequence[dict[str, float]],
    whats: Sequence[str], path: Path,
) -> tuple[list[int], list[float]]:  # fmt: skip
    """:func:`_columns`, which must be there.

    Raises:
        PosesFileError: They are not, or one carries a wrong suffix.
    """
    found = _columns(header, names, units, whats, path)
    if found is None:
        raise PosesFileError(
            path,
            f"header needs columns {', '.join(names)} (or with their unit's suffix: _deg "
            f"for angles, _mm for lengths); it has: {_names(header)}",
        )
    return found


def _show(name: str) -> str:
    """A header name as it goes into a message: as is when short and printable."""
    return name if name.isprintable() and len(name) <= 40 else show_text(name)


def _names(header: list[str]) -> str:
    return ", ".join(_show(h) for h in header)


def _read_header(text: str, lineno: int, path: Path) -> list[str]:
    seen: dict[str, int] = {}
    for column, raw in split_fields(text):
        name = raw.strip()
        where = f"line {lineno}, column {column}"
        if not name:
            raise PosesFileError(path, f"{where}: a header field without a name")
        if name in seen:
            raise PosesFileError(
                path,
                f"{where}: column {show_text(name)} is named twice (also field {seen[name] + 1}); "
                "each column needs its own name",
            )
        seen[name] = len(seen)
    return list(seen)


class _Layout:
    """Which header columns hold what, and their factors to metres / radians."""

    def __init__(self, header: list[str], model: Model, path: Path) -> None:
        self.header = header
        revolute = [j.type == "revolute" for j in model.joints]
        joints = _needed(
            header,
            [f"q{i + 1}" for i in range(model.dof)],
            [_ANGLE if rev else _LENGTH for rev in revolute],
            [f"joint {i + 1} ({j.name}), {j.type}" for i, j in enumerate(model.joints)],
            path,
        )
        position = _needed(header, ["x", "y", "z"], [_LENGTH] * 3, ["a position"] * 3, path)
        rotation = None
        for fmt, names in _ROTATIONS.items():
            suffixes = [_PLAIN if fmt == "quat" else _ANGLE] * len(names)
            what = "a quaternion component" if fmt == "quat" else "an angle"
            rotation = _columns(header, names, suffixes, [what] * len(names), path)
            if rotation is not None:
                self.fmt = fmt
                break
        if rotation is None:
            raise PosesFileError(
                path,
                "header needs a rotation: qx,qy,qz,qw or rx,ry,rz or "
                f"roll,pitch,yaw or A,B,C; it has: {_names(header)}",
            )
        self.columns = [*joints[0], *position[0], *rotation[0]]
        self.n = model.dof
        # Per kept column: factor to SI and the bound after it.
        self.factor = np.array([*joints[1], *position[1], *rotation[1]])
        self.bound = np.array(
            [MAX_JOINT_RAD if rev else MAX_LENGTH_M for rev in revolute]
            + [MAX_LENGTH_M] * 3
            + [MAX_ROTATION_NUMBER] * len(rotation[0])
        )
        units = [" rad" if rev else " m" for rev in revolute] + [" m"] * 3
        self.unit = units + [" rad" if self.fmt != "quat" else ""] * len(rotation[0])
        self.method = CSV_METHOD

    def rows(self, lines: list[str], linenos: list[int], path: Path) -> list[float]:
        """The kept numbers of data lines, in file units, one row after another."""
        return list(chain.from_iterable(map(self.row, lines, linenos, [path] * len(lines))))

    def row(self, line: str, lineno: int, path: Path) -> list[float]:
        """The kept numbers of one data line, in file units."""
        try:
            numbers = parse_numbers(line)
        except NumberError as exc:
            header = self.header
            name = (
                f" ({_show(header[exc.index - 1])})"
                if exc.index and exc.index <= len(header)
                else ""
            )
            raise PosesFileError(
                path, f"line {lineno}, column {exc.column}{name}: {exc.problem}"
            ) from None
        if len(numbers) != len(self.header):
            raise PosesFileError(
                path,
                f"line {lineno}: {len(numbers)} fields, but the header names {len(self.header)}",
            )
        return [numbers[c] for c in self.columns]
