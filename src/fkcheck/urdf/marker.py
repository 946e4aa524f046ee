"""The mark ``fkcheck urdf`` leaves in every URDF it writes: which DH table it was written from.

The mark is an element, not a comment, so that stripping comments (or the
screen, :mod:`fkcheck.urdf.screen`, which drops them) keeps it::

    <robot name="ur5">
      <fkcheck:written-from xmlns:fkcheck="urn:fkcheck:urdf-provenance"
          by="fkcheck urdf 0.1.0" model="ur5" convention="standard"
          table="sha256:0123456789abcdef" />

An element in a namespace of its own is an extension every URDF reader skips
(urdfdom, yourdfpy and Robotics Toolbox's reader read ``<link>``, ``<joint>``,
``<material>`` and ``<transmission>`` only), and the screen keeps it (it refuses
xacro and XInclude namespaces only). ``table`` is :func:`table_fingerprint`: a
hash of the numbers the export turns into the URDF's chain — the convention,
each row's type, a, α, d, θ and flip, ``[base]`` and ``[tool]`` — not of names,
limits or frames, so that renaming a joint or changing a limit keeps it.
"""

from __future__ import annotations

import hashlib
import xml.etree.ElementTree as ET
from dataclasses import dataclass

from fkcheck._version import __version__
from fkcheck.model.types import Model, Offset

__all__ = [
    "MARKER_TAG",
    "PROVENANCE_NAMESPACE",
    "Marker",
    "marker_element",
    "read_marker",
    "table_fingerprint",
]

#: The namespace of fkcheck's mark (a URN: a name, never fetched).
PROVENANCE_NAMESPACE = "urn:fkcheck:urdf-provenance"
#: The mark's tag, as ElementTree spells a namespaced name.
MARKER_TAG = f"{{{PROVENANCE_NAMESPACE}}}written-from"

ET.register_namespace("fkcheck", PROVENANCE_NAMESPACE)


@dataclass(frozen=True)
class Marker:
    """What a URDF's mark says.

    Attributes:
        by: The tool and version that wrote it (``fkcheck urdf 0.1.0``).
        model: The name of the model it was written from.
        convention: That model's DH convention.
        table: That model's :func:`table_fingerprint`.
    """

    by: str
    model: str
    convention: str
    table: str


def _number(value: float) -> str:
    return repr(float(value) + 0.0)  # shortest round trip; -0.0 and 0.0 alike


def _offset(offset: Offset) -> str:
    return " ".join(_number(v) for v in (*offset.xyz, *offset.rpy))


def table_fingerprint(model: Model) -> str:
    """``sha256:`` and 16 hex digits of the table's numbers (see the module docstring)."""
    lines = [f"convention {model.convention}", f"base {_offset(model.base)}"]
    for j in model.joints:
        numbers = " ".join(_number(v) for v in (j.a, j.alpha, j.d, j.theta))
        lines.append(f"{j.type} {numbers} {'flip' if j.flip else 'noflip'}")
    lines.append(f"tool {_offset(model.tool)}")
    digest = hashlib.sha256("\n".join(lines).encode("utf-8")).hexdigest()
    return f"sha256:{digest[:16]}"


def marker_element(model: Model) -> ET.Element:
    """The mark for a URDF written from ``model``."""
    return ET.Element(
        MARKER_TAG,
        by=f"fkcheck urdf {__version__}",
        model=model.name,
        convention=model.convention,
        table=table_fingerprint(model),
    )


def read_marker(root: ET.Element) -> Marker | None:
    """The first mark anywhere in a URDF's tree, or ``None`` without one."""
    found = next(root.iter(MARKER_TAG), None)
    if found is None:
        return None
    return Marker(
        by=found.get("by", ""),
        model=found.get("model", ""),
        convention=found.get("convention", ""),
        table=found.get("table", ""),
    )
