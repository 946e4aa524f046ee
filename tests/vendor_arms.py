"""Two arms written as a vendor's DH table and an independent, ROS-Industrial-style URDF.

The tables are typed from the public dimensions of a FANUC LR Mate 200iD (base
330 mm, J1–J2 offset 50 mm, upper arm 330 mm, J3–J4 offset 35 mm, forearm 335 mm,
flange 80 mm) and a KUKA KR 16-2 (base 675 mm, A1–A2 offset 260 mm, upper arm
680 mm, A3–A4 offset 35 mm, forearm 670 mm, flange 158 mm), standard DH. The
URDFs are written here from the same dimensions with numpy alone (never
fkcheck's exporter or DH core), the way ROS-Industrial writes them: every link
frame parallel to the base at zero, each joint on its axis, some axes the other
way round (the FANUC's J3–J6; the KUKA's A1, A4 and A6) and some zeros elsewhere
(the KUKA's A2 and A3 by 90°). A table and its URDF then agree once the table
toggles ``flip`` on the reversed joints and adds the zero offsets to θ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["FANUC", "KUKA", "VendorArm", "dh_row", "urdf_text", "write_arm"]


@dataclass(frozen=True)
class VendorArm:
    """A vendor's table and how its URDF differs.

    Attributes:
        name: Model name.
        rows: ``(name, a, alpha_deg, d, theta_deg)`` per joint, standard DH.
        reversed: Joints whose URDF axis is the other way round.
        zeros: Joint → degrees the URDF's zero is turned from the table's.
    """

    name: str
    rows: tuple[tuple[str, float, float, float, float], ...]
    reversed: tuple[str, ...]
    zeros: dict[str, float]


FANUC = VendorArm(
    "lrmate_like",
    (
        ("J1", 0.050, -90.0, 0.330, 0.0),
        ("J2", 0.330, 0.0, 0.0, -90.0),
        ("J3", 0.035, -90.0, 0.0, 0.0),
        ("J4", 0.0, 90.0, 0.335, 0.0),
        ("J5", 0.0, -90.0, 0.0, 0.0),
        ("J6", 0.0, 0.0, 0.080, 0.0),
    ),
    ("J3", "J4", "J5", "J6"),
    {},
)

KUKA = VendorArm(
    "kr16_like",
    (
        ("A1", 0.260, -90.0, 0.675, 0.0),
        ("A2", 0.680, 0.0, 0.0, 0.0),
        ("A3", 0.035, -90.0, 0.0, 0.0),
        ("A4", 0.0, 90.0, 0.670, 0.0),
        ("A5", 0.0, -90.0, 0.0, 0.0),
        ("A6", 0.0, 0.0, 0.158, 0.0),
    ),
    ("A1", "A4", "A6"),
    {"A2": -90.0, "A3": 90.0},
)


def dh_row(a: float, alpha: float, d: float, theta: float) -> np.ndarray:
    """Standard DH: Rz(θ)·Tz(d)·Tx(a)·Rx(α), written out."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array(
        [
            [ct, -st * ca, st * sa, a * ct],
            [st, ct * ca, -ct * sa, a * st],
            [0.0, sa, ca, d],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def urdf_text(arm: VendorArm) -> str:
    """The URDF: links parallel to ``base_link`` at the URDF's zero, joints on the axes."""
    frames = [np.eye(4)]
    for name, a, alpha, d, theta in arm.rows:
        zero = math.radians(theta + arm.zeros.get(name, 0.0))
        frames.append(frames[-1] @ dh_row(a, math.radians(alpha), d, zero))
    links = ["base_link", *(f"link_{k}" for k in range(1, len(arm.rows) + 1))]
    out = ['<?xml version="1.0"?>', f'<robot name="{arm.name}">']
    out += [f'  <link name="{link}"/>' for link in [*links, "flange", "tool0"]]
    previous = np.zeros(3)
    for k, (name, *_rest) in enumerate(arm.rows):
        point, axis = frames[k][:3, 3], frames[k][:3, 2]
        if name in arm.reversed:
            axis = -axis
        xyz = " ".join(repr(float(v)) for v in point - previous)
        ax = " ".join(repr(round(float(v), 15) + 0.0) for v in axis)
        out += [
            f'  <joint name="joint_{name.lower()}" type="revolute">',
            f'    <parent link="{links[k]}"/><child link="{links[k + 1]}"/>',
            f'    <origin xyz="{xyz}" rpy="0 0 0"/><axis xyz="{ax}"/>',
            '    <limit lower="-3.0" upper="3.0" effort="1" velocity="1"/>',
            "  </joint>",
        ]
        previous = point
    tip = " ".join(repr(float(v)) for v in frames[-1][:3, 3] - previous)
    out += [
        '  <joint name="flange_fixed" type="fixed">',
        f'    <parent link="{links[-1]}"/><child link="flange"/>',
        f'    <origin xyz="{tip}" rpy="0 0 0"/>',
        "  </joint>",
        '  <joint name="tool0_fixed" type="fixed">',
        '    <parent link="flange"/><child link="tool0"/>',
        f'    <origin xyz="0 0 0" rpy="0 {math.pi / 2!r} 0"/>',
        "  </joint>",
        "</robot>",
    ]
    return "\n".join(out) + "\n"


def _model(
    arm: VendorArm,
    urdf: str,
    tool_rpy_deg: tuple[float, float, float],
    unit: str = "deg",
    rounded: tuple[str, ...] = (),
) -> str:
    """The model file: the vendor's table as published, mapped onto the URDF.

    With ``unit = "rad"`` the angles are written in radians, exactly, except the
    θ of the joints in ``rounded``: to four decimals (``-1.5708``), as tables do.
    """

    def angle(value_deg: float, rounded_here: bool = False) -> str:
        if unit == "deg":
            return repr(value_deg)
        rad = math.radians(value_deg)
        return f"{rad:.4f}" if rounded_here else repr(rad)

    joints = ", ".join(f'"joint_{name.lower()}"' for name, *_ in arm.rows)
    out = [
        f'name = "{arm.name}"',
        'convention = "standard"',
        f'angle_unit = "{unit}"',
        "",
        "[urdf]",
        f'path = "{urdf}"',
        f"joints = [{joints}]",
        "",
        "[frames.base_link]",
        "dh = 0",
        'urdf = "base_link"',
        "",
        "[frames.tool0]",
        f"dh = {len(arm.rows)}",
        "rpy = [" + ", ".join(angle(v) for v in tool_rpy_deg) + "]",
        'urdf = "tool0"',
        "",
        "[check]",
        'from = "base_link"',
        'to = "tool0"',
    ]
    for name, a, alpha, d, theta in arm.rows:
        out += [
            "",
            "[[joint]]",
            f'name = "{name}"',
            f"a = {a!r}",
            f"alpha = {angle(alpha)}",
            f"d = {d!r}",
            f"theta = {angle(theta, name in rounded)}",
            f"limits = [{angle(-170.0)}, {angle(170.0)}]",
        ]
    return "\n".join(out) + "\n"


def write_arm(
    arm: VendorArm,
    directory: Path,
    tool_rpy_deg: tuple[float, float, float] = (0.0, 0.0, 0.0),
    unit: str = "deg",
    rounded: tuple[str, ...] = (),
) -> Path:
    """Write ``<name>.urdf`` and ``<name>.toml`` into ``directory``; return the model file.

    ``tool_rpy_deg``: the ``[frames.tool0]`` offset the user typed (the URDF's
    ``tool0`` is turned from the last DH frame by something else: the diagnosis
    names that too). ``unit``, ``rounded``: the file's ``angle_unit``, and the
    joints whose θ it writes rounded to four decimals of a radian.
    """
    urdf = directory / f"{arm.name}.urdf"
    urdf.write_text(urdf_text(arm), encoding="utf-8")
    model = directory / f"{arm.name}.toml"
    model.write_text(_model(arm, urdf.name, tool_rpy_deg, unit, rounded), encoding="utf-8")
    return model
