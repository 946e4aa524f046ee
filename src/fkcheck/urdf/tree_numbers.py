"""A URDF's numbers: every numeric attribute the right count of finite decimals, axes usable.

What :func:`fkcheck.urdf.tree.read_urdf` checks of the numbers, as urdfdom reads
them (space-separated decimals: no ``inf``, ``nan`` or hexadecimal), before any
reader sees the file; a moving joint's axis must have a length every reader can
normalise (:data:`MIN_AXIS_LENGTH` … :data:`MAX_AXIS_LENGTH`).
"""

from __future__ import annotations

import math
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from fkcheck.errors import UrdfError
from fkcheck.urdf.screen import ScreenedUrdf

__all__ = ["MAX_AXIS_LENGTH", "MIN_AXIS_LENGTH", "at_line", "check_numbers"]

#: Shortest and longest ``<axis xyz>`` a reader can normalise: every one divides by
#: ``sqrt(x² + y² + z²)``, whose square must be a normal float (2.2e-308 … 1.8e308).
#: ``0 0 1e-300`` gave 0 (Pinocchio's and yourdfpy's poses were not rotations),
#: ``0 1e300 1e300`` gave infinity.
MIN_AXIS_LENGTH = math.sqrt(sys.float_info.min)
MAX_AXIS_LENGTH = math.sqrt(sys.float_info.max) / 2.0  # three components: room for the sum

#: A URDF number, as urdfdom reads it: decimal, optional sign and exponent (no
#: ``inf``, ``nan``, ``1_0``, hexadecimal or non-ASCII digits).
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
#: Numeric attributes urdfdom parses, by the element holding them under a
#: ``<joint>``, a ``<link>`` or the ``<robot>``: name → how many numbers.
_NUMERIC: tuple[tuple[str, str, dict[str, int]], ...] = (
    ("joint", "origin", {"xyz": 3, "rpy": 3}),
    ("joint", "axis", {"xyz": 3}),
    ("joint", "limit", {"lower": 1, "upper": 1, "effort": 1, "velocity": 1}),
    ("joint", "dynamics", {"damping": 1, "friction": 1}),
    ("joint", "mimic", {"multiplier": 1, "offset": 1}),
    (
        "joint",
        "safety_controller",
        {"soft_lower_limit": 1, "soft_upper_limit": 1, "k_position": 1, "k_velocity": 1},
    ),
    ("joint", "calibration", {"rising": 1, "falling": 1}),
    ("link", "inertial/origin", {"xyz": 3, "rpy": 3}),
    ("link", "inertial/mass", {"value": 1}),
    (
        "link",
        "inertial/inertia",
        {"ixx": 1, "ixy": 1, "ixz": 1, "iyy": 1, "iyz": 1, "izz": 1},
    ),
    *(
        entry
        for part in ("visual", "collision")
        for entry in (
            ("link", f"{part}/origin", {"xyz": 3, "rpy": 3}),
            ("link", f"{part}/geometry/box", {"size": 3}),
            ("link", f"{part}/geometry/cylinder", {"radius": 1, "length": 1}),
            ("link", f"{part}/geometry/capsule", {"radius": 1, "length": 1}),
            ("link", f"{part}/geometry/sphere", {"radius": 1}),
            ("link", f"{part}/geometry/mesh", {"scale": 3}),
        )
    ),
    ("link", "visual/material/color", {"rgba": 4}),
    ("robot", "material/color", {"rgba": 4}),
)


def at_line(doc: ScreenedUrdf, element: ET.Element) -> str:
    """``"line N: "`` for a message about ``element`` (empty when its line is unknown)."""
    line = doc.line(element)
    return f"line {line}: " if line is not None else ""


def check_numbers(path: Path, doc: ScreenedUrdf) -> None:
    """Every numeric URDF attribute is the right count of finite decimal numbers.

    Numbers are separated by spaces, as urdfdom splits them. A moving joint's
    axis must not be zero.
    """
    owners = {
        "robot": [doc.root],
        "link": doc.root.findall("link"),
        "joint": doc.root.findall("joint"),
    }
    for owner_tag, sub, attributes in _NUMERIC:
        for owner in owners[owner_tag]:
            for el in owner.findall(sub):
                for attr, count in attributes.items():
                    text = el.get(attr)
                    if text is not None:
                        _numbers(path, doc, owner, el, attr, text, count)
    for joint in owners["joint"]:
        axis = joint.find("axis")
        if axis is None or joint.get("type") not in ("revolute", "continuous", "prismatic"):
            continue
        values = _numbers(path, doc, joint, axis, "xyz", axis.get("xyz", "1 0 0"), 3)
        if not any(values):
            raise UrdfError(
                path,
                f"{at_line(doc, axis)}joint {joint.get('name')!r}: <axis xyz> is zero; a "
                f"{joint.get('type')} joint needs a direction",
            )
        length = math.sqrt(sum(v * v for v in values))  # as every reader normalises it
        if not MIN_AXIS_LENGTH <= length <= MAX_AXIS_LENGTH:
            raise UrdfError(
                path,
                f"{at_line(doc, axis)}joint {joint.get('name')!r}: <axis xyz> is "
                f"{axis.get('xyz')!r}, whose length no reader can take (its square is not a "
                f"normal float: {MIN_AXIS_LENGTH:.3g} … {MAX_AXIS_LENGTH:.3g}); write the "
                "direction as a unit vector",
            )


def _numbers(
    path: Path,
    doc: ScreenedUrdf,
    owner: ET.Element,
    el: ET.Element,
    attr: str,
    text: str,
    count: int,
) -> tuple[float, ...]:
    parts = [p for p in text.split(" ") if p]
    values = tuple(float(p) for p in parts if _NUMBER.fullmatch(p))
    if len(values) == count and len(parts) == count and all(map(math.isfinite, values)):
        return values
    field = f"<{el.tag} {attr}>"
    if owner is not doc.root:
        field = f"{owner.tag} {owner.get('name')!r}: {field}"
    expected = "a finite decimal number" if count == 1 else f"{count} finite decimal numbers"
    raise UrdfError(
        path,
        f"{at_line(doc, el)}{field} is {text!r}, expected {expected}"
        + (" separated by spaces" if count > 1 else ""),
    )
