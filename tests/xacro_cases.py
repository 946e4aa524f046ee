"""A small xacro description written by the tests, its hand-expanded twin and a DH model of it.

The description: a top file ``robot/arm.urdf.xacro`` that takes an argument
(``reach``, default 0.3), defines a property (``a = 0.25``), includes
``$(find arm_description)/urdf/parts.xacro`` and calls its ``revolute`` macro
three times, with ``${pi/2}`` and ``${a*2}`` in the origins. Standard DH of the
same chain: joint 1 (d = 0.2, α = π/2), joint 2 (a = 0.5), joint 3 (a = reach).
"""

from __future__ import annotations

from pathlib import Path

__all__ = [
    "PARTS",
    "TOP",
    "UR_COLORS",
    "UR_KINEMATICS",
    "UR_LIMITS",
    "UR_MACRO",
    "UR_TOP",
    "environ_job",
    "grow_macro",
    "twin_urdf",
    "write_description",
    "write_model",
    "write_ur_description",
]

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


def environ_job(
    data: bytes,
    path: str,
    args: dict[str, str],
    packages: dict[str, str],
    roots: list[str],
    files: list[str],
) -> tuple[str, tuple[str, list[str], list[str]]]:
    """In place of the expansion's job: what the child's environment is, as text.

    ``repr((its /proc/self/environ, its supervisor's /proc/PID/environ, os.environ's names))``
    — the kernel's record is what the process was executed with.
    """
    import os

    with open("/proc/self/environ", "rb") as f:
        own = f.read()
    with open(f"/proc/{os.getppid()}/environ", "rb") as f:
        supervisor = f.read()
    return "ok", (repr((own, supervisor, sorted(os.environ))), [], [])


def grow_macro(leaf: str, depth: int) -> str:
    """A macro that calls itself twice a level, called ``depth`` levels deep: 2**depth ``leaf``."""
    return (
        '<xacro:macro name="grow" params="n"><xacro:if value="${n > 0}">'
        '<xacro:grow n="${n - 1}"/><xacro:grow n="${n - 1}"/></xacro:if>'
        f'<xacro:unless value="${{n > 0}}">{leaf}</xacro:unless></xacro:macro>'
        f'<xacro:grow n="{depth}"/>'
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

# l3 sits where a3 = 0 would put DH frame 3: which link is the last DH frame is the
# description's word (its tip is a3 along x from l3).
[frames.tip]
dh = 3
urdf = "tip"
source = "the test description: tip is the last DH frame"

[check]
from = "base"
to = "tip"
"""
    )
    return path


# --- a UR-style description: load_yaml, units, namespaces, macros, conditionals, math ------

#: The kinematics of a UR5, as ur_description keeps them (``default_kinematics.yaml``).
UR_KINEMATICS = """\
kinematics:
  shoulder: {x: 0, y: 0, z: 0.089159, roll: 0, pitch: 0, yaw: 0}
  upper_arm: {x: 0, y: 0, z: 0, roll: 1.570796327, pitch: 0, yaw: 0}
  forearm: {x: -0.425, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}
  wrist_1: {x: -0.39225, y: 0, z: 0.10915, roll: 0, pitch: 0, yaw: 0}
  wrist_2: {x: 0, y: -0.09465, z: -1.9413039509e-11, roll: 1.570796327, pitch: 0, yaw: 0}
  wrist_3: {x: 0, y: 0.0823, z: -1.688001216e-11, roll: 1.570796326589793,
            pitch: 3.141592653589793, yaw: 3.141592653589793}
"""

#: Joint limits with xacro's yaml units (``!degrees``), as ur_description writes them.
UR_LIMITS = """\
joint_limits:
  shoulder_pan_joint: {max_position: !degrees 360.0, min_position: !degrees -360.0,
                       max_velocity: !degrees 180.0, max_effort: 150.0}
  shoulder_lift_joint: {max_position: !degrees 360.0, min_position: !degrees -360.0,
                        max_velocity: !degrees 180.0, max_effort: 150.0}
  elbow_joint: {max_position: !degrees 180.0, min_position: !degrees -180.0,
                max_velocity: !degrees 180.0, max_effort: 150.0}
  wrist_1_joint: {max_position: !degrees 360.0, min_position: !degrees -360.0,
                  max_velocity: !degrees 180.0, max_effort: 28.0}
  wrist_2_joint: {max_position: !degrees 360.0, min_position: !degrees -360.0,
                  max_velocity: !degrees 180.0, max_effort: 28.0}
  wrist_3_joint: {max_position: !radians 2*pi, min_position: !radians -2*pi,
                  max_velocity: !degrees 180.0, max_effort: 28.0}
"""

#: The macro file: a joint macro and the arm macro, reading both yaml files given to it.
UR_MACRO = f"""<?xml version="1.0"?>
<robot xmlns:xacro="{XACRO_NS}">
  <xacro:property name="margin" value="0.15"/>
  <xacro:macro name="ur_joint" params="name parent child sec lim safety_limits continuous:=false">
    <link name="${{child}}">
      <inertial><mass value="${{2.0 * (1 + 0.5 * (child == 'upper_arm_link'))}}"/>
        <origin xyz="0 0 ${{python.abs(sec['z']) / 2}}" rpy="0 0 0"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="${{max(0.01, sqrt(2) / 100)}}"/>
      </inertial>
    </link>
    <joint name="${{name}}" type="${{'continuous' if continuous else 'revolute'}}">
      <parent link="${{parent}}"/><child link="${{child}}"/>
      <origin xyz="${{sec['x']}} ${{sec['y']}} ${{sec['z']}}"
              rpy="${{sec.roll}} ${{sec.pitch}} ${{sec.yaw}}"/>
      <axis xyz="0 0 1"/>
      <xacro:unless value="${{continuous}}">
        <limit lower="${{lim['min_position']}}" upper="${{lim['max_position']}}"
               effort="${{lim['max_effort']}}" velocity="${{lim['max_velocity']}}"/>
      </xacro:unless>
      <xacro:if value="${{continuous}}">
        <limit effort="${{lim['max_effort']}}" velocity="${{lim['max_velocity']}}"/>
      </xacro:if>
      <xacro:if value="${{safety_limits and not continuous}}">
        <safety_controller soft_lower_limit="${{lim['min_position'] + margin}}"
                           soft_upper_limit="${{lim['max_position'] - margin}}"
                           k_position="20" k_velocity="0.0"/>
      </xacro:if>
    </joint>
  </xacro:macro>

  <xacro:macro name="ur_robot" params="prefix kinematics_file limits_file safety_limits:=false">
    <xacro:property name="kin" value="${{xacro.load_yaml(kinematics_file)['kinematics']}}"/>
    <xacro:property name="limits" value="${{load_yaml(limits_file).joint_limits}}"/>
    <link name="${{prefix}}base_link"/>
    <xacro:ur_joint name="${{prefix}}shoulder_pan_joint" parent="${{prefix}}base_link"
        child="${{prefix}}shoulder_link" sec="${{kin['shoulder']}}"
        lim="${{limits['shoulder_pan_joint']}}" safety_limits="${{safety_limits}}"/>
    <xacro:ur_joint name="${{prefix}}shoulder_lift_joint" parent="${{prefix}}shoulder_link"
        child="${{prefix}}upper_arm_link" sec="${{kin['upper_arm']}}"
        lim="${{limits['shoulder_lift_joint']}}" safety_limits="${{safety_limits}}"/>
    <xacro:ur_joint name="${{prefix}}elbow_joint" parent="${{prefix}}upper_arm_link"
        child="${{prefix}}forearm_link" sec="${{kin['forearm']}}"
        lim="${{limits['elbow_joint']}}" safety_limits="${{safety_limits}}"/>
    <xacro:ur_joint name="${{prefix}}wrist_1_joint" parent="${{prefix}}forearm_link"
        child="${{prefix}}wrist_1_link" sec="${{kin['wrist_1']}}"
        lim="${{limits['wrist_1_joint']}}" safety_limits="${{safety_limits}}"/>
    <xacro:ur_joint name="${{prefix}}wrist_2_joint" parent="${{prefix}}wrist_1_link"
        child="${{prefix}}wrist_2_link" sec="${{kin['wrist_2']}}"
        lim="${{limits['wrist_2_joint']}}" safety_limits="${{safety_limits}}"/>
    <xacro:ur_joint name="${{prefix}}wrist_3_joint" parent="${{prefix}}wrist_2_link"
        child="${{prefix}}wrist_3_link" sec="${{kin['wrist_3']}}"
        lim="${{limits['wrist_3_joint']}}" safety_limits="${{safety_limits}}" continuous="true"/>
    <link name="${{prefix}}flange"/>
    <joint name="${{prefix}}wrist_3-flange" type="fixed">
      <parent link="${{prefix}}wrist_3_link"/><child link="${{prefix}}flange"/>
      <origin xyz="0 0 0" rpy="0 ${{-pi/2.0}} ${{-pi/2.0}}"/>
    </joint>
    <link name="${{prefix}}tool0"/>
    <joint name="${{prefix}}flange-tool0" type="fixed">
      <origin xyz="0 0 0" rpy="${{pi/2.0}} 0 ${{pi/2.0}}"/>
      <parent link="${{prefix}}flange"/><child link="${{prefix}}tool0"/>
    </joint>
  </xacro:macro>
</robot>
"""

#: A file included into a namespace (``<xacro:include … ns="colors"/>``).
UR_COLORS = f"""<?xml version="1.0"?>
<robot xmlns:xacro="{XACRO_NS}">
  <xacro:property name="grey" value="${{' '.join(['0.5'] * 3)}} 1"/>
</robot>
"""

#: The top file, in the two ways a description names its files: ``$(find …)`` of a
#: declared package (which worked before fkcheck evaluated expressions itself), and
#: ``$(dirname)`` and paths relative to the xacro file (as xacro resolves them).
UR_TOP = {
    "find": f"""<?xml version="1.0"?>
<robot name="ur" xmlns:xacro="{XACRO_NS}">
  <xacro:arg name="ur_type" default="ur5"/>
  <xacro:arg name="prefix" default=""/>
  <xacro:arg name="safety_limits" default="false"/>
  <xacro:include filename="$(find ur_description)/urdf/ur_macro.xacro"/>
  <xacro:include filename="$(find ur_description)/urdf/colors.xacro" ns="colors"/>
  <xacro:property name="config" value="$(find ur_description)/config/$(arg ur_type)"/>
  <xacro:property name="is_ur5" value="${{'$(arg ur_type)' == 'ur5'}}"/>
  <xacro:property name="scale" value="$(eval 1.0 if ur_type == 'ur5' else 2.0)"/>
  <link name="world"><visual><geometry><box size="0.1 0.1 0.1"/></geometry>
    <material name="grey"><color rgba="${{colors.grey}}"/></material></visual></link>
  <joint name="world_joint" type="fixed">
    <parent link="world"/><child link="$(arg prefix)base_link"/>
    <origin xyz="0 0 ${{0.0 * scale}}" rpy="0 0 ${{radians(0) if is_ur5 else pi}}"/>
  </joint>
  <xacro:ur_robot prefix="$(arg prefix)" safety_limits="$(arg safety_limits)"
      kinematics_file="${{config}}/default_kinematics.yaml"
      limits_file="${{config + '/joint_limits.yaml'}}"/>
</robot>
""",
    "relative": f"""<?xml version="1.0"?>
<robot name="ur" xmlns:xacro="{XACRO_NS}">
  <xacro:arg name="ur_type" default="ur5"/>
  <xacro:arg name="prefix" default=""/>
  <xacro:arg name="safety_limits" default="false"/>
  <xacro:include filename="$(dirname)/ur_macro.xacro"/>
  <xacro:include filename="colors.xacro" ns="colors"/>
  <xacro:property name="config" value="../config/$(arg ur_type)"/>
  <xacro:property name="is_ur5" value="${{'$(arg ur_type)' == 'ur5'}}"/>
  <xacro:property name="scale" value="$(eval 1.0 if ur_type == 'ur5' else 2.0)"/>
  <link name="world"><visual><geometry><box size="0.1 0.1 0.1"/></geometry>
    <material name="grey"><color rgba="${{colors.grey}}"/></material></visual></link>
  <joint name="world_joint" type="fixed">
    <parent link="world"/><child link="$(arg prefix)base_link"/>
    <origin xyz="0 0 ${{0.0 * scale}}" rpy="0 0 ${{radians(0) if is_ur5 else pi}}"/>
  </joint>
  <xacro:ur_robot prefix="$(arg prefix)" safety_limits="$(arg safety_limits)"
      kinematics_file="${{config}}/default_kinematics.yaml"
      limits_file="${{config + '/joint_limits.yaml'}}"/>
</robot>
""",
}


def write_ur_description(root: Path, top: str = "find") -> tuple[Path, Path]:
    """Write the UR-style description under ``root``: ``(top file, the ur_description package)``.

    ``top`` is a key of :data:`UR_TOP` or the text of a top file.
    """
    package = root / "ur_description"
    (package / "urdf").mkdir(parents=True)
    (package / "config" / "ur5").mkdir(parents=True)
    (package / "config" / "ur5" / "default_kinematics.yaml").write_text(UR_KINEMATICS)
    (package / "config" / "ur5" / "joint_limits.yaml").write_text(UR_LIMITS)
    (package / "urdf" / "ur_macro.xacro").write_text(UR_MACRO)
    (package / "urdf" / "colors.xacro").write_text(UR_COLORS)
    top_file = package / "urdf" / "ur.urdf.xacro"
    top_file.write_text(UR_TOP.get(top, top))
    return top_file, package
