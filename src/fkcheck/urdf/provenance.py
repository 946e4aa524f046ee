"""Whether a model's URDF was written from the model's own table, so it cannot verify it.

``fkcheck urdf`` turns a DH table into a URDF. Checked against that table, the
URDF agrees whatever the table says — a wrong d1 is wrong in both — so it is no
evidence for the table. :func:`derived_from_table` tells such a URDF apart in
two independent ways, whatever the file is called and whatever comments it lost:

* **its mark**: the exporter writes an element, ``<fkcheck:written-from …
  table="sha256:…">`` (:mod:`fkcheck.urdf.marker`), that the screen keeps and
  the URDF readers skip. A mark whose ``table`` is this table's fingerprint
  decides it, even when the URDF was edited since (remove the mark from a URDF
  you made into an independent description).
* **its numbers**: without a mark (removed, or lost to a tool that rewrote the
  file), the URDF is compared with the table's own export, made again in
  memory: from the URDF's root, through the model's mapped joints, to the TCP,
  joint for joint — the fixed joint to DH frame 0, each row's joints, the fixed
  joint to the TCP — the same kinds of joint, origins and axes within the
  check's tolerances (at least 1e-9), and links that carry no inertia or
  geometry (the export writes none). Names do not matter.

The numbers find only the export itself, renamed or rewritten. A URDF derived
from the table another way — joints merged, geometry added, the mark removed —
is not found, and a URDF that is itself a DH table written out (a vendor's
modified-DH URDF with the same numbers, e.g. the Panda's) is not taken for a
copy: its links carry inertia and geometry, and its root and tool joints
differ from the export's.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Literal

import numpy as np

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.errors import FkcheckError
from fkcheck.io.numbers import show_text
from fkcheck.model.types import FrameSpec, Model
from fkcheck.urdf.chain import JointGeometry, UrdfKinematics, urdf_kinematics
from fkcheck.urdf.export import urdf_from_model
from fkcheck.urdf.marker import read_marker, table_fingerprint
from fkcheck.urdf.tree import UrdfInfo, chain_between, urdf_info_from_bytes

__all__ = ["NUMBERS_FLOOR", "Derivation", "derived_from_table"]

#: The tightest comparison of the numbers (m, rad): a URDF's decimal digits, not noise.
NUMBERS_FLOOR = 1e-9
#: What a link of fkcheck's export never holds.
_PHYSICAL = ("inertial", "visual", "collision")


@dataclass(frozen=True)
class Derivation:
    """How a URDF was found to be written from the model's own table.

    Attributes:
        via: ``"mark"`` (fkcheck's mark names this table) or ``"numbers"``
            (its chain is the table's own export).
        detail: What was found, in words.
    """

    via: Literal["mark", "numbers"]
    detail: str

    @property
    def message(self) -> str:
        """The sentence a URDF backend's result carries."""
        what = (
            "was written by fkcheck from this table"
            if self.via == "mark"
            else "is what fkcheck urdf writes from this table"
        )
        return (
            f"the URDF {what} ({self.detail}): it cannot verify the table, so its agreement "
            "counts as implementation evidence"
        )


def _table_only(model: Model) -> Model:
    """The model with only its table, base and tool: what the export's chain is made of."""
    frames = {"world": FrameSpec("world", "world"), "tcp": FrameSpec("tcp", "tcp")}
    return replace(model, frames=frames, urdf=None, known_differences=())


def _same(a: JointGeometry, b: JointGeometry, tol: tuple[float, float]) -> bool:
    """Same kind of joint, origin and axis within ``(position m, rotation rad)``."""
    kind = {"continuous": "revolute"}
    if kind.get(a.type, a.type) != kind.get(b.type, b.type):
        return False
    if float(position_error_m(a.origin, b.origin)) > tol[0]:
        return False
    if float(rotation_error_rad(a.origin, b.origin)) > tol[1]:
        return False
    if a.type == "fixed":
        return True
    cos = float(np.clip(np.dot(a.axis, b.axis), -1.0, 1.0))
    return float(np.arccos(cos)) <= tol[1]


def _tail(
    kin: UrdfKinematics, link: str, wanted: Sequence[JointGeometry], tol: tuple[float, float]
) -> list[JointGeometry] | None:
    """Fixed joints down from ``link`` that match ``wanted`` one by one, or ``None``."""
    if not wanted:
        return []
    for joint in kin.joints.values():
        if joint.parent == link and _same(joint, wanted[0], tol):
            rest = _tail(kin, joint.child, wanted[1:], tol)
            if rest is not None:
                return [joint, *rest]
    return None


def _path(
    kin: UrdfKinematics,
    movable: Sequence[str],
    tail: Sequence[JointGeometry],
    tol: tuple[float, float],
) -> list[JointGeometry] | None:
    """The joints from the root through ``movable`` (in order) and a match of ``tail``."""
    path: list[JointGeometry] = []
    link = kin.root
    for name in movable:
        joint = kin.joints.get(name)
        if joint is None:
            return None
        between = chain_between(kin.joints, link, joint.parent)
        if between is None or any(j.type != "fixed" for j in between):
            return None
        path += [*between, joint]
        link = joint.child
    rest = _tail(kin, link, tail, tol)
    return None if rest is None else path + rest


def _bare(root: ET.Element, links: set[str]) -> bool:
    """Whether none of ``links`` holds an inertial, a visual or a collision."""
    return not any(
        el.find(part) is not None
        for el in root.findall("link")
        if el.get("name") in links
        for part in _PHYSICAL
    )


def _is_export(
    model: Model, info: UrdfInfo, joints: Sequence[str], tol: tuple[float, float]
) -> int | None:
    """The number of joints compared when the URDF's chain is the table's export, else ``None``."""
    try:
        text = urdf_from_model(_table_only(model)).text
        own = urdf_kinematics(urdf_info_from_bytes(Path("export.urdf"), text.encode("utf-8")))
        theirs = urdf_kinematics(info)
    except FkcheckError:
        return None
    expected = chain_between(own.joints, own.root, "tcp")
    assert expected is not None  # the export's chain: world → … → tcp
    last = max(i for i, j in enumerate(expected) if j.type != "fixed")
    found = _path(theirs, joints, expected[last + 1 :], tol)
    if found is None or len(found) != len(expected):
        return None
    if not all(_same(a, b, tol) for a, b in zip(found, expected, strict=True)):
        return None
    links = {theirs.root, *(j.child for j in found)}
    return len(found) if _bare(ET.fromstring(info.text), links) else None


def derived_from_table(
    model: Model, info: UrdfInfo, tol: tuple[float, float] = (NUMBERS_FLOOR, NUMBERS_FLOOR)
) -> Derivation | None:
    """Whether ``info`` (the model's URDF) was written from the model's own table.

    Args:
        model: The model, with ``[urdf]`` mapping its joints onto the URDF's.
        info: Its URDF, read and screened (:func:`fkcheck.urdf.source.load_urdf`).
        tol: ``(position m, rotation rad)`` within which the URDF's numbers count as
            the export's (the check's tolerances; never below :data:`NUMBERS_FLOOR`).

    Returns:
        How it was found (see the module docstring), or ``None``: the URDF is not
        the table's own export as far as fkcheck can tell.
    """
    fingerprint = table_fingerprint(model)
    root = ET.fromstring(info.text)
    mark = read_marker(root)
    if mark is not None and mark.table == fingerprint:
        return Derivation(
            "mark",
            f"its fkcheck mark names model {show_text(mark.model)} and table {mark.table}, "
            "this table",
        )
    if model.urdf is None:
        return None
    floor = (max(tol[0], NUMBERS_FLOOR), max(tol[1], NUMBERS_FLOOR))
    compared = _is_export(model, info, model.urdf.joints, floor)
    if compared is None:
        return None
    return Derivation(
        "numbers",
        f"it has no fkcheck mark, but its {compared} joints from the root to the TCP are "
        "the export's, to the check's tolerance, on links without inertia or geometry",
    )
