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
  memory: from the URDF's root, through the model's mapped joints, to a link
  where the TCP is — as the robot moves: each movable joint seen from the one
  before it (the fixed joints between composed, so fixed joints added, merged
  or split change nothing), the same kinds of joint, origins and axes within
  the check's tolerances (at least 1e-9). Only the kinematic chain counts:
  names, comments, whitespace, how the numbers are written, and what the links
  hold (inertia, geometry: a copy given them is still the export) do not.

The numbers find the export however it was renamed, rewritten, re-jointed or
dressed. A vendor's URDF that is itself its DH table written out joint for
joint (the Panda's) has the export's numbers too: numbers cannot tell it from a
copy. One read from a package fkcheck resolves (``example-robot-data:``,
``fkcheck:``, see :mod:`fkcheck.urdf.locate`) is the package's, not a file
written from this table, and is not taken for a copy; the same file copied
beside the model is (its agreement proves the transcription, as a copy's would).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Literal

import numpy as np

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.errors import FkcheckError
from fkcheck.io.numbers import show_text
from fkcheck.model.types import Model, default_frames
from fkcheck.urdf.chain import UrdfKinematics, urdf_kinematics
from fkcheck.urdf.export import urdf_from_model
from fkcheck.urdf.locate import ERD_PREFIX, FKCHECK_PREFIX
from fkcheck.urdf.marker import read_marker, table_fingerprint
from fkcheck.urdf.tree import UrdfInfo, chain_between, urdf_info_from_bytes

__all__ = ["NUMBERS_FLOOR", "Derivation", "derived_from_table"]

#: The tightest comparison of the numbers (m, rad): a URDF's decimal digits, not noise.
NUMBERS_FLOOR = 1e-9
#: Where a URDF comes from a package fkcheck resolves, not from the user's files.
_PACKAGED = (ERD_PREFIX, FKCHECK_PREFIX)


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
    return replace(model, frames=default_frames(), urdf=None, known_differences=())


@dataclass(frozen=True)
class _Step:
    """A movable joint seen from the one before it: fixed joints composed, then its own origin.

    Attributes:
        origin: The previous movable joint's child (the root at first) → this joint.
        axis: Its axis, in its own frame.
        kind: ``revolute`` (continuous too) or ``prismatic``.
    """

    origin: Float
    axis: Float
    kind: str


def _steps(kin: UrdfKinematics, movable: Sequence[str]) -> tuple[list[_Step], str] | None:
    """The chain as steps from the root through ``movable``, and its last link (``None``: none)."""
    steps: list[_Step] = []
    link = kin.root
    for name in movable:
        joint = kin.joints.get(name)
        if joint is None:
            return None
        between = chain_between(kin.joints, link, joint.parent)
        if between is None or any(j.type != "fixed" for j in between):
            return None
        origin = np.eye(4)
        for fixed in between:
            origin = origin @ fixed.origin
        kind = "revolute" if joint.type == "continuous" else joint.type
        steps.append(_Step(origin @ joint.origin, joint.axis, kind))
        link = joint.child
    return steps, link


def _near(a: Float, b: Float, tol: tuple[float, float]) -> bool:
    return float(position_error_m(a, b)) <= tol[0] and float(rotation_error_rad(a, b)) <= tol[1]


def _same(a: _Step, b: _Step, tol: tuple[float, float]) -> bool:
    """Same kind of joint, composed origin and axis within ``(position m, rotation rad)``."""
    if a.kind != b.kind or not _near(a.origin, b.origin, tol):
        return False
    cos = float(np.clip(np.dot(a.axis, b.axis), -1.0, 1.0))
    return float(np.arccos(cos)) <= tol[1]


def _fixed_below(kin: UrdfKinematics, link: str) -> list[tuple[Float, tuple[str, ...]]]:
    """Every link hanging from ``link`` by fixed joints only: its pose there, the links passed."""
    out: list[tuple[Float, tuple[str, ...]]] = [(np.eye(4), (link,))]
    todo: list[tuple[str, Float, tuple[str, ...]]] = [(link, np.eye(4), (link,))]
    while todo:
        here, pose, passed = todo.pop()
        for joint in kin.joints.values():
            if joint.parent == here and joint.type == "fixed" and joint.child not in passed:
                step = (pose @ joint.origin, (*passed, joint.child))
                out.append(step)
                todo.append((joint.child, *step))
    return out


def _is_export(
    model: Model, info: UrdfInfo, joints: Sequence[str], tol: tuple[float, float]
) -> int | None:
    """The joints compared when the URDF's chain is the table's export, else ``None``.

    Compared as the robot moves, not joint for joint: between two movable joints
    the fixed ones are composed, so an identity joint added above the root, or
    fixed joints merged or split, do not hide the export.
    """
    try:
        text = urdf_from_model(_table_only(model)).text
        own = urdf_kinematics(urdf_info_from_bytes(Path("export.urdf"), text.encode("utf-8")))
        theirs = urdf_kinematics(info)
    except FkcheckError:
        return None
    expected = chain_between(own.joints, own.root, "tcp")
    assert expected is not None  # the export's chain: world → … → tcp
    own_movable = [j.name for j in expected if j.type != "fixed"]
    mine, theirs_found = _steps(own, own_movable), _steps(theirs, joints)
    if mine is None or theirs_found is None or len(mine[0]) != len(theirs_found[0]):
        return None
    (want, own_last), (found, last) = mine, theirs_found
    if not all(_same(a, b, tol) for a, b in zip(found, want, strict=True)):
        return None
    tail = chain_between(own.joints, own_last, "tcp") or []
    tcp = np.eye(4)
    for fixed in tail:
        tcp = tcp @ fixed.origin
    if not any(_near(pose, tcp, tol) for pose, _ in _fixed_below(theirs, last)):
        return None
    return len(found)


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
    if model.urdf is None or model.urdf.path.startswith(_PACKAGED):
        return None
    floor = (max(tol[0], NUMBERS_FLOOR), max(tol[1], NUMBERS_FLOOR))
    compared = _is_export(model, info, model.urdf.joints, floor)
    if compared is None:
        return None
    return Derivation(
        "numbers",
        f"it has no fkcheck mark, but its {compared} joints from the root to the TCP are "
        "the export's, to the check's tolerance, whatever its names, comments and links' "
        "inertia or geometry",
    )
