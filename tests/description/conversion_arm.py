"""One small arm written twice, as a URDF and as its MJCF conversion, and faults to seed in it.

Three revolute joints (one turning the other way), a quarter turn and a 0.5 rad
turn between links, and a tool frame (a URDF fixed joint, an MJCF site): what a
URDF → MJCF conversion must carry over. Each fault is a string replacement that
must change the MJCF (:func:`seeded`).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["FAULTS", "MJCF", "URDF", "seeded", "write_pair"]

URDF = """<?xml version="1.0"?>
<robot name="arm3">
  <link name="base_link"/>
  <link name="link1"/>
  <link name="link2"/>
  <link name="link3"/>
  <link name="tool0"/>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="link1"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="0 0.05 0.2" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="j3" type="revolute">
    <parent link="link2"/><child link="link3"/>
    <origin xyz="0.3 0 0" rpy="0 0 0.5"/><axis xyz="0 0 -1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="tool" type="fixed">
    <parent link="link3"/><child link="tool0"/>
    <origin xyz="0.1 0 0.02" rpy="0 1.5707963267948966 0"/>
  </joint>
</robot>
"""

MJCF = """<mujoco model="arm3">
  <compiler angle="radian"/>
  <worldbody>
    <body name="base_link">
      <body name="link1" pos="0 0 0.1">
        <joint name="j1" axis="0 0 1" range="-3 3"/>
        <body name="link2" pos="0 0.05 0.2" euler="1.5707963267948966 0 0">
          <joint name="j2" axis="0 0 1" range="-3 3"/>
          <body name="link3" pos="0.3 0 0" euler="0 0 0.5">
            <joint name="j3" axis="0 0 -1" range="-3 3"/>
            <site name="tool0" pos="0.1 0 0.02" euler="0 1.5707963267948966 0"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

#: Seeded conversion faults: name → (text in the right MJCF, its faulty replacement).
FAULTS = {
    # link3 1 mm further along link2's x: the table's a2.
    "body 1 mm off": ('<body name="link3" pos="0.3 0 0"', '<body name="link3" pos="0.301 0 0"'),
    "axis sign flipped": ('<joint name="j2" axis="0 0 1"', '<joint name="j2" axis="0 0 -1"'),
    # MuJoCo's default unit is the degree: the radians written are read as degrees.
    "radians read as degrees": ('  <compiler angle="radian"/>\n', ""),
}


def seeded(fault: str) -> str:
    """The MJCF with ``fault`` seeded (asserting the replacement changed it)."""
    old, new = FAULTS[fault]
    assert old in MJCF
    return MJCF.replace(old, new)


def write_pair(folder: Path, mjcf: str = MJCF) -> tuple[Path, Path]:
    """``(arm.urdf, arm.xml)`` written into ``folder``."""
    urdf, xml = folder / "arm.urdf", folder / "arm.xml"
    urdf.write_text(URDF, encoding="utf-8")
    xml.write_text(mjcf, encoding="utf-8")
    return urdf, xml
