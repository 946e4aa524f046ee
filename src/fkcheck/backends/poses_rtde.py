"""UR RTDE recordings as measured poses: the columns UR's recorder writes, read fast.

Part of :mod:`fkcheck.backends.measured`: :class:`_RtdeLayout` reads a recording of
``record.py`` (UR's RTDE client library, without ``--binary``) by its header line:
the joints ``actual_q_0 … actual_q_5`` and the pose ``actual_TCP_pose_0 … 5``; every
other column is ignored; a binary recording is refused in one line.
"""

from __future__ import annotations

import csv
import math
import operator
import re
from itertools import chain
from pathlib import Path

import numpy as np

from fkcheck.backends.poses_columns import MAX_ROTATION_NUMBER, PosesFileError
from fkcheck.io.numbers import MAX_NUMBER_CHARS, NumberError, parse_number, parse_numbers
from fkcheck.model.types import MAX_JOINT_RAD, MAX_LENGTH_M, Model

__all__ = ["RTDE_COLUMNS"]

#: A character none of an RTDE recording's read fields may hold to be read in one go:
#: with these characters alone, ``float()`` accepts exactly the plain numbers of
#: :func:`fkcheck.io.numbers.parse_number` (and the spaces and tabs around them).
_NOT_PLAIN = re.compile(r"[^0-9+\-.eE \t\n]")
#: The columns of an RTDE recording that are read: joints, then TCP pose (UR's recorder
#: names the elements of a vector output ``name_0 … name_5``).
RTDE_COLUMNS = tuple(f"actual_q_{i}" for i in range(6)) + tuple(
    f"actual_TCP_pose_{i}" for i in range(6)
)
#: The type names of UR's binary recorder (``record.py --binary``), written as its second line.
_RTDE_TYPES = frozenset(
    {"BOOL", "UINT8", "UINT32", "UINT64", "INT32", "INT64", "DOUBLE", "VECTOR3D", "VECTOR6D",
     "VECTOR6INT32", "VECTOR6UINT32"}
)  # fmt: skip


class _RtdeLayout:
    """The columns of a UR RTDE recording that are read (:data:`RTDE_COLUMNS`), SI units."""

    fmt = "rotvec"

    def __init__(self, line: str, lineno: int, model: Model, path: Path) -> None:
        self.delimiter = "," if "," in line else "\t" if "\t" in line else " "
        self.header = [name.strip() for name in self._fields(line, lineno, path)]
        where: dict[str, list[int]] = {}
        for k, name in enumerate(self.header):
            where.setdefault(name, []).append(k + 1)
        twice = [(n, where[n]) for n in RTDE_COLUMNS if len(where.get(n, ())) > 1]
        if twice:
            name, fields = twice[0]
            raise PosesFileError(
                path,
                f"line {lineno}: column {name} is named twice (fields "
                f"{' and '.join(map(str, fields[:2]))}); the RTDE recording's column to read "
                "is ambiguous",
            )
        missing = [n for n in RTDE_COLUMNS if n not in where]
        if missing:
            raise PosesFileError(
                path,
                f"line {lineno}: an RTDE recording (its header names actual_q_0) needs columns "
                f"{', '.join(missing)}; record the outputs actual_q and actual_TCP_pose",
            )
        if model.dof != 6:
            raise PosesFileError(
                path,
                f"an RTDE recording holds 6 joints (actual_q_0 … actual_q_5); model "
                f"{model.name} has {model.dof}",
            )
        self.columns = [where[n][0] - 1 for n in RTDE_COLUMNS]
        self.n = 6
        self.factor = np.ones(12)
        revolute = [j.type == "revolute" for j in model.joints]
        self.bound = np.array(
            [MAX_JOINT_RAD if rev else MAX_LENGTH_M for rev in revolute]
            + [MAX_LENGTH_M] * 3
            + [MAX_ROTATION_NUMBER] * 3
        )
        self.unit = [" rad" if rev else " m" for rev in revolute] + [" m"] * 3 + [" rad"] * 3
        others = len(self.header) - len(RTDE_COLUMNS)
        separated = {",": "comma", "\t": "tab"}.get(self.delimiter, "space")
        self.method = (
            f"UR RTDE recording ({separated}-separated): joints actual_q_0…actual_q_5 (rad), "
            "pose actual_TCP_pose_0…actual_TCP_pose_5 (x, y, z in m, rotation vector in rad); "
            f"{others} other column{'s' if others != 1 else ''} ignored"
        )

    def _fields(self, line: str, lineno: int, path: Path) -> list[str]:
        try:
            return next(csv.reader((line,), delimiter=self.delimiter, skipinitialspace=True))
        except csv.Error as exc:
            raise PosesFileError(path, f"line {lineno}: {exc}") from None

    @staticmethod
    def _refuse_binary(fields: list[str], lineno: int, path: Path) -> None:
        """Refuse the type names UR's binary recorder writes after the header line."""
        if fields and all(f.strip() in _RTDE_TYPES for f in fields):
            raise PosesFileError(
                path,
                f"line {lineno}: a binary RTDE recording (record.py --binary: a line of "
                "type names, then packed numbers); record it without --binary",
            )

    def rows(self, lines: list[str], linenos: list[int], path: Path) -> list[float]:
        """The 12 numbers read of each data line, one row after another.

        Quick when the lines are as UR's recorder writes them (every field split at the
        delimiter, the read ones plain numbers); otherwise each line is read by
        :meth:`row`, which accepts and refuses exactly as this does and says where.
        """
        text = "\n".join(lines)
        spaced = self.delimiter == " " and "  " in text  # csv's skipinitialspace joins them
        if '"' not in text and "\x00" not in text and not spaced:
            width = len(self.header)
            fields = [line.split(self.delimiter) for line in lines]
            if all(len(f) == width for f in fields):
                pick = operator.itemgetter(*self.columns)
                used = list(chain.from_iterable(map(pick, fields)))
                if max(map(len, used)) <= MAX_NUMBER_CHARS and not _NOT_PLAIN.search(
                    "\n".join(used)
                ):
                    try:
                        values = list(map(float, used))
                    except ValueError:  # e.g. "1e", "-": row says which and where
                        values = [math.inf]
                    if all(map(math.isfinite, values)):
                        return values
        return list(chain.from_iterable(map(self.row, lines, linenos, [path] * len(lines))))

    def row(self, line: str, lineno: int, path: Path) -> list[float]:
        """The 12 numbers read of one data line: q (rad), position (m), rotation vector (rad)."""
        fields = self._fields(line, lineno, path)
        if len(fields) != len(self.header):
            self._refuse_binary(fields, lineno, path)
            raise PosesFileError(
                path,
                f"line {lineno}: {len(fields)} fields, but the header names {len(self.header)}",
            )
        used = [fields[c] for c in self.columns]
        try:
            numbers = parse_numbers(",".join(used))
        except NumberError:
            numbers = []
        if len(numbers) == len(used):
            return numbers
        self._refuse_binary(fields, lineno, path)
        for column, text in zip(self.columns, used, strict=True):  # name the first bad field
            try:
                parse_number(text)
            except NumberError as exc:
                raise PosesFileError(
                    path,
                    f"line {lineno}, field {column + 1} ({self.header[column]}): {exc.problem}",
                ) from None
        raise PosesFileError(path, f"line {lineno}: the read columns are not 12 numbers")
