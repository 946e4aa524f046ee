"""A small xacro description written by the tests, its hand-expanded twin and a DH model of it.

The description: a top file ``robot/arm.urdf.xacro`` that takes an argument
(``reach``, default 0.3), defines a property (``a = 0.25``), includes
``$(find arm_description)/urdf/parts.xacro`` and calls its ``revolute`` macro
three times, with ``${pi/2}`` and ``${a*2}`` in the origins. Standard DH of the
same chain: joint 1 (d = 0.2, α = π/2), joint 2 (a = 0.5), joint 3 (a = reach).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["PARTS", "TOP", "twin_urdf", "write_description", "write_model"]

XACRO_NS = "http://www.ros.org/wiki/xacro"

PARTS = f"""<?xml version="1.0"?>
<robot xmlns:xacro="{XACRO_NS}">
  <xacro:macro name="revolute" params="name parent child xyz rpy:='0 0 0'">
    <link name="${{child}}"/>
    <joint name="${{name}}" type="revolute">
      <parent link="${{parent}}"/><child link="${{child}}"/>
      <origin xyz="${{xyz}}" rpy="${{rpy}}"/><axis xyz="0 0 1"/>
      <limit lower="-3" upper="3" effort="1" velocity="1"/>
    </joint>
  </xacro:macro>
</robot>
"""

TOP = f"""<?xml version="1.0"?>
<robot name="xarm" xmlns:xacro="{XACRO_NS}">
  <xacro:arg name="reach" default="0.3"/>
  <xacro:property name="a" value="0.25"/>
  <xacro:include filename="$(find arm_description)/urdf/parts.xacro"/>
  <link name="base"/>
  <xacro:revolute name="j1" parent="base" child="l1" xyz="0 0 0"/>
  <xacro:revolute name="j2" parent="l1" child="l2" xyz="0 0 0.2" rpy="${{pi/2}} 0 0"/>
  <xacro:revolute name="j3" parent="l2" child="l3" xyz="${{a*2}} 0 0"/>
  <link name="tip"/>
  <joint name="tip_joint" type="fixed">
    <parent link="l3"/><child link="tip"/>
    <origin xyz="$(arg reach) 0 0" rpy="0 0 0"/>
  </joint>
</robot>
"""


def twin_urdf(reach: str = "0.3") -> str:
    """:data:`TOP` expanded by hand, with the argument ``reach``."""
    joints = [("j1", "base", "l1", "0 0 0", "0 0 0"),
              ("j2", "l1", "l2", "0 0 0.2", "1.5707963267948966 0 0"),
              ("j3", "l2", "l3", "0.5 0 0", "0 0 0")]  # fmt: skip
    body = "".join(
        f'<link name="{child}"/><joint name="{name}" type="revolute"><parent link="{parent}"/>'
        f'<child link="{child}"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="0 0 1"/>'
        '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>\n'
        for name, parent, child, xyz, rpy in joints
    )
    return (
        f'<?xml version="1.0"?>\n<robot name="xarm">\n<link name="base"/>\n{body}'
        '<link name="tip"/><joint name="tip_joint" type="fixed"><parent link="l3"/>'
        f'<child link="tip"/><origin xyz="{reach} 0 0" rpy="0 0 0"/></joint>\n</robot>\n'
    )


def write_description(root: Path, top: str = TOP) -> tuple[Path, Path]:
    """Write the description under ``root``: ``(top file, the arm_description package)``."""
    package = root / "arm_description"
    (package / "urdf").mkdir(parents=True)
    (package / "urdf" / "parts.xacro").write_text(PARTS)
    (root / "robot").mkdir()
    top_file = root / "robot" / "arm.urdf.xacro"
    top_file.write_text(top)
    return top_file, package


def write_model(root: Path, reach: str, urdf_extra: str) -> Path:
    """A DH model file of the description in ``root/robot/``; ``urdf_extra`` ends its [urdf]."""
    path = root / "robot" / "xarm.toml"
    path.write_text(
        f"""name = "xarm"
convention = "standard"

[[joint]]
name = "j1"
a = 0.0
alpha = 1.5707963267948966
d = 0.2
limits = [-3.0, 3.0]

[[joint]]
name = "j2"
a = 0.5
alpha = 0.0
d = 0.0
limits = [-3.0, 3.0]

[[joint]]
name = "j3"
a = {reach}
alpha = 0.0
d = 0.0
limits = [-3.0, 3.0]

[urdf]
path = "arm.urdf.xacro"
joints = ["j1", "j2", "j3"]
{urdf_extra}

[frames.base]
dh = 0
urdf = "base"

[frames.tip]
dh = 3
urdf = "tip"

[check]
from = "base"
to = "tip"
"""
    )
    return path
