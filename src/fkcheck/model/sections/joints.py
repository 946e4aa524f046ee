"""The ``[[joint]]`` rows: the DH table, lengths in metres, angles in the file's ``angle_unit``."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from fkcheck.errors import ModelError
from fkcheck.io.numbers import show_text
from fkcheck.model.sections.header import Header
from fkcheck.model.sections.reader import Reader, kind
from fkcheck.model.types import MAX_JOINT_RAD, MAX_JOINTS, MAX_LENGTH_M, Joint

__all__ = ["JOINT_KEYS", "JOINT_TYPES", "joint_value", "read_joints"]

JOINT_KEYS = {"name", "type", "a", "alpha", "d", "theta", "flip", "limits"}
JOINT_TYPES = ("revolute", "prismatic")


def read_joints(
    r: Reader, top: Mapping[str, Any], header: Header, *, linearised: bool = False
) -> tuple[tuple[Joint, ...], tuple[str, ...]]:
    """The DH table and the warnings it deserves (degrees in a radian file).

    Joint names are unique; a row without one is ``joint<i+1>``. In a
    ``linearised`` table (a UR controller's calibration, ``[calibration]``
    status 2) a θ beyond ±2π is the controller's own number, not degrees.
    """
    rows = _rows(r, top.get("joint"))
    joints: list[Joint] = []
    seen: dict[str, int] = {}
    warnings: list[str] = []
    for i, raw in enumerate(rows):
        joint, row_warnings = _read_joint(r, raw, i, header, seen, linearised)
        joints.append(joint)
        warnings += row_warnings
    return tuple(joints), tuple(warnings)


def joint_value(r: Reader, value: float, field_: str, jtype: str) -> float:
    """A limit or pose value in radians / metres, within the physical bound."""
    if jtype == "prismatic":
        return r.bounded(value, field_, MAX_LENGTH_M, "m")
    return r.bounded(value, field_, MAX_JOINT_RAD, "rad")


def _rows(r: Reader, raw_joints: Any) -> list[Any]:
    """The ``joint`` array: present, an array, not empty and not too long."""
    if raw_joints is None:
        raise r.fail("joint", "missing: the model needs at least one [[joint]]")
    if not isinstance(raw_joints, list):
        raise r.fail("joint", f"expected an array of tables [[joint]], got {kind(raw_joints)}")
    if not raw_joints:
        raise r.fail("joint", "no joints: the model needs at least one [[joint]]")
    if len(raw_joints) > MAX_JOINTS:
        raise r.fail("joint", f"{len(raw_joints)} joints is more than the limit of {MAX_JOINTS}")
    return raw_joints


def _read_joint(
    r: Reader, raw: Any, i: int, header: Header, seen: dict[str, int], linearised: bool
) -> tuple[Joint, list[str]]:
    """Row ``i`` (its name recorded in ``seen``) and its warnings."""
    where = f"joint[{i}]"
    row = r.table(raw, where, JOINT_KEYS)
    for required in ("a", "alpha", "d"):
        if required not in row:
            raise r.fail(f"{where}.{required}", "missing (required)")
    jname = r.string(row.get("name", f"joint{i + 1}"), f"{where}.name")
    if jname in seen:
        raise r.fail(
            f"{where}.name",
            f"duplicate joint name {show_text(jname)} (also joint[{seen[jname]}])",
        )
    seen[jname] = i
    # From here on, an error names the joint after its field (fkcheck.model.names) — when
    # the file names it: a default joint1, joint2, … beside a 0-based path would mislead.
    shown = jname if "name" in row else ""
    try:
        return _read_named_joint(r, row, where, jname, shown, header, linearised)
    except ModelError as exc:
        if not shown or exc.joint or not exc.field.startswith(where):
            raise
        raise ModelError(exc.path, exc.field, exc.problem, joint=shown) from None


def _read_named_joint(
    r: Reader,
    row: Mapping[str, Any],
    where: str,
    jname: str,
    shown: str,
    header: Header,
    linearised: bool,
) -> tuple[Joint, list[str]]:
    """The rest of row ``where`` named ``jname``; warnings show ``shown`` (``""``: no name).

    A ``linearised`` table's θ beyond ±2π is the controller's number, not degrees.
    """
    jtype = r.choice(row.get("type", "revolute"), f"{where}.type", JOINT_TYPES)
    flip = r.flag(row.get("flip", False), f"{where}.flip")
    alpha = r.number(row["alpha"], f"{where}.alpha")
    theta = r.number(row.get("theta", 0.0), f"{where}.theta")
    limits = _limits(r, row, where, jtype, header.to_rad)
    warnings = []
    if header.angle_unit == "rad":
        warnings = _degree_warnings(where, shown, alpha, 0.0 if linearised else theta)
    to_rad = header.to_rad
    joint = Joint(
        name=jname,
        type=jtype,  # type: ignore[arg-type]
        a=r.length(row["a"], f"{where}.a"),
        alpha=alpha * to_rad,
        d=r.length(row["d"], f"{where}.d"),
        theta=theta * to_rad,
        flip=flip,
        limits=limits,
    )
    return joint, warnings


def _limits(
    r: Reader, row: Mapping[str, Any], where: str, jtype: str, to_rad: float
) -> tuple[float, float] | None:
    """``limits = [lower, upper]`` in radians / metres, or ``None`` when absent."""
    if "limits" not in row:
        return None
    lo, hi = r.numbers(row["limits"], f"{where}.limits", 2)
    if lo > hi:
        raise r.fail(f"{where}.limits", f"lower {lo} is greater than upper {hi}")
    scale = to_rad if jtype == "revolute" else 1.0
    return (
        joint_value(r, lo * scale, f"{where}.limits[0]", jtype),
        joint_value(r, hi * scale, f"{where}.limits[1]", jtype),
    )


def _degree_warnings(where: str, shown: str, alpha: float, theta: float) -> list[str]:
    """A warning for each fixed angle beyond ±2π in a radian file: degrees, most likely."""
    name = f" ({shown})" if shown else ""
    return [
        f"{where}.{label}{name} = {value:g} is beyond ±2π: it looks like degrees "
        'in a file with angle_unit = "rad"'
        for label, value in (("alpha", alpha), ("theta", theta))
        if abs(value) > 2 * math.pi + 1e-9
    ]
