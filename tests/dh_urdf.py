"""A URDF and a model file built by hand from a standard DH table, for evidence tests.

The URDF's links are the DH frames: joint i+1 sits at ``Tz(d_i)·Tx(a_i)·Rx(α_i)``
of link i, its axis along z (or −z: a reversed joint). It is written here, not
by fkcheck (``fkcheck urdf``'s export would be fkcheck's own evidence).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

__all__ = ["UR5E", "dh_model", "dh_urdf"]

#: UR5e's nominal DH table (standard): a (m), α (rad), d (m); θ offsets 0.
UR5E = (
    (0.0, math.pi / 2, 0.1625),
    (-0.425, 0.0, 0.0),
    (-0.3922, 0.0, 0.0),
    (0.0, math.pi / 2, 0.1333),
    (0.0, -math.pi / 2, 0.0997),
    (0.0, 0.0, 0.0996),
)
WHOLE_TURNS = (-360.0, 360.0)


def dh_urdf(rows: Sequence[tuple[float, float, float]], axes: Sequence[int] = ()) -> str:
    """A URDF of ``rows`` (a, α, d), links ``base``, ``l1``…, ``tool0``; ``axes``: ±1 each."""
    axes = tuple(axes) or (1,) * len(rows)
    out = ['<robot name="arm">', '<link name="base"/>']
    parent, origin = "base", (0.0, 0.0, 0.0)
    for i, (a, alpha, d) in enumerate(rows):
        out.append(f'<link name="l{i + 1}"/>')
        out.append(
            f'<joint name="j{i + 1}" type="revolute"><parent link="{parent}"/>'
            f'<child link="l{i + 1}"/><origin xyz="{origin[0]!r} 0 {origin[2]!r}" '
            f'rpy="{origin[1]!r} 0 0"/><axis xyz="0 0 {axes[i]}"/>'
            '<limit lower="-6.283185307179586" upper="6.283185307179586" effort="1" '
            'velocity="1"/></joint>'
        )
        parent, origin = f"l{i + 1}", (a, alpha, d)
    out.append('<link name="tool0"/>')
    out.append(
        f'<joint name="flange" type="fixed"><parent link="{parent}"/><child link="tool0"/>'
        f'<origin xyz="{origin[0]!r} 0 {origin[2]!r}" rpy="{origin[1]!r} 0 0"/></joint>'
    )
    return "\n".join([*out, "</robot>"])


def dh_model(
    directory: Path,
    urdf: str,
    rows: Sequence[tuple[float, float, float]] = UR5E,
    limits: Sequence[tuple[float, float]] = (),
) -> Path:
    """A model file of ``rows`` (no named poses), its URDF ``urdf``; ``limits`` in degrees.

    Its frames ``base`` and ``tool0`` are vouched for: the URDF's link ``l6`` sits where
    d6 = 0 would put the last DH frame, a choice among links only a vouch settles
    (:class:`fkcheck.model.coverage.Competitor`).
    """
    (directory / "arm.urdf").write_text(urdf, encoding="utf-8")
    limits = tuple(limits) or (WHOLE_TURNS,) * len(rows)
    joints = "".join(
        f'[[joint]]\nname = "j{i + 1}"\na = {a!r}\nalpha = {math.degrees(al)!r}\nd = {d!r}\n'
        f"theta = 0\nlimits = [{float(limits[i][0])!r}, {float(limits[i][1])!r}]\n\n"
        for i, (a, al, d) in enumerate(rows)
    )
    names = ", ".join(f'"j{i + 1}"' for i in range(len(rows)))
    path = directory / "arm.toml"
    path.write_text(
        'name = "arm"\nconvention = "standard"\nangle_unit = "deg"\n\n'
        f"{joints}"
        f'[urdf]\npath = "arm.urdf"\njoints = [{names}]\n\n'
        '[frames.base]\ndh = 0\nurdf = "base"\nsource = "the test URDF: base is DH frame 0"\n\n'
        f'[frames.tool0]\ndh = {len(rows)}\nurdf = "tool0"\n'
        'source = "the test URDF: tool0 is the last DH frame"\n\n'
        '[check]\nfrom = "base"\nto = "tool0"\n',
        encoding="utf-8",
    )
    return path
