"""``[base]``, ``[tool]`` and a named frame's offset: ``xyz`` (m) and ``rpy`` (the file's unit)."""

from __future__ import annotations

from typing import Any

from fkcheck.model.sections.reader import Reader
from fkcheck.model.types import MAX_LENGTH_M, Offset

__all__ = ["OFFSET_KEYS", "read_offset"]

OFFSET_KEYS = {"xyz", "rpy"}


def read_offset(r: Reader, value: Any, where: str, to_rad: float) -> Offset:
    """A fixed transform: ``xyz`` in metres (bounded), ``rpy`` turned into radians."""
    tbl = r.table(value, where, OFFSET_KEYS)
    xyz = r.numbers(tbl.get("xyz", [0.0, 0.0, 0.0]), f"{where}.xyz", 3)
    for i, v in enumerate(xyz):
        r.bounded(v, f"{where}.xyz[{i}]", MAX_LENGTH_M, "m")
    rpy = r.numbers(tbl.get("rpy", [0.0, 0.0, 0.0]), f"{where}.rpy", 3)
    return Offset(xyz=(xyz[0], xyz[1], xyz[2]),
                  rpy=(rpy[0] * to_rad, rpy[1] * to_rad, rpy[2] * to_rad))  # fmt: skip
