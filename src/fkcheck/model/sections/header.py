"""The file's header: ``name``, ``convention`` and ``angle_unit`` (and the free texts)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

from fkcheck.core import dh
from fkcheck.model.sections.reader import Reader

__all__ = ["ANGLE_UNITS", "CONVENTIONS", "Header", "read_free_text", "read_header"]

CONVENTIONS = ("standard", "modified")
ANGLE_UNITS = ("rad", "deg")


@dataclass(frozen=True)
class Header:
    """What the other sections need from the header.

    Attributes:
        name: The model's name (not blank).
        convention: ``"standard"`` or ``"modified"`` DH.
        angle_unit: The unit the file's angles are written in.
    """

    name: str
    convention: dh.Convention
    angle_unit: Literal["rad", "deg"]

    @property
    def to_rad(self) -> float:
        """The factor that turns the file's angles into radians."""
        return math.pi / 180.0 if self.angle_unit == "deg" else 1.0


def read_header(r: Reader, top: Mapping[str, Any]) -> Header:
    """``name`` and ``convention`` (both required) and ``angle_unit`` (``"rad"`` by default)."""
    for required in ("name", "convention"):
        if required not in top:
            raise r.fail(required, "missing (required)")
    name = r.string(top["name"], "name")
    if not name.strip():
        raise r.fail("name", "must not be empty")
    convention = r.choice(top["convention"], "convention", CONVENTIONS)
    unit = r.choice(top.get("angle_unit", "rad"), "angle_unit", ANGLE_UNITS)
    return Header(name, convention, unit)  # type: ignore[arg-type]


def read_free_text(r: Reader, top: Mapping[str, Any], key: str) -> str:
    """A free-text top-level key (``description``, ``source``), ``""`` when absent."""
    return r.string(top.get(key, ""), key)
