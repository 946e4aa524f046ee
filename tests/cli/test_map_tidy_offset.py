"""A half turn of θn that map's fitted offset makes tidy: neither table "verified".

A 3-joint modified-DH arm whose description has its last link ``l3`` a quarter
turn about x of DH frame 3, and a ``tool0`` link fixed to it 0.2 m across z of
DH frame 3, turned half a turn about z (an offset flange, as a vendor may define
one). The right table maps onto ``base → l3`` (offset: the quarter turn, which
carries no table number) and every number is verified. A table with θ3 off by
180° maps onto ``base → tool0``, whose fitted offset is now ``xyz (0, -0.2, 0)``
alone — a translation across z, which the rule treats as innocent — and the
check says "table verified" too. Poses cannot tell the two tables apart through
tool0: the half turn went into the offset, and choosing the link whose offset
looks tidiest is a fit, as a choice among links is.
"""

from __future__ import annotations

import json
import math

from fkcheck.cli.main import main

TABLE = """\
name = "arm3"
convention = "modified"
angle_unit = "deg"

[[joint]]
name = "j1"
a = 0.0
alpha = 0
d = 0.3
limits = [-170, 170]

[[joint]]
name = "j2"
a = 0.0
alpha = 90
d = 0.0
limits = [-170, 170]

[[joint]]
name = "j3"
a = 0.4
alpha = 0
d = 0.1
{theta}limits = [-170, 170]
"""

HALF, QUARTER = repr(math.pi), repr(math.pi / 2)

# DH frames: 1 = Tz(0.3)·Rz(q1); 2 = 1·Rx(90°)·Rz(q2); 3 = 2·Tx(0.4)·Rz(q3)·Tz(0.1).
# l3 is DH frame 3 turned a quarter turn about x (its axis then reads 0 1 0); tool0 is
# DH frame 3 · T(0, 0.2, 0) · Rz(180°), written from l3: Rx(-90°)·T(0, 0.2, 0)·Rz(180°).
URDF = f"""\
<?xml version="1.0"?>
<robot name="arm3">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="tool0"/>
  <joint name="j1" type="revolute"><origin xyz="0 0 0.3" rpy="0 0 0"/><parent link="base"/>
    <child link="l1"/><axis xyz="0 0 1"/><limit effort="0" lower="-3" upper="3" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute"><origin xyz="0 0 0" rpy="{QUARTER} 0 0"/><parent link="l1"/>
    <child link="l2"/><axis xyz="0 0 1"/><limit effort="0" lower="-3" upper="3" velocity="1"/>
  </joint>
  <joint name="j3" type="revolute"><origin xyz="0.4 0 0.1" rpy="{QUARTER} 0 0"/>
    <parent link="l2"/><child link="l3"/><axis xyz="0 1 0"/>
    <limit effort="0" lower="-3" upper="3" velocity="1"/>
  </joint>
  <joint name="l3-tool0" type="fixed"><origin xyz="0 0 -0.2" rpy="{QUARTER} 0 {HALF}"/>
    <parent link="l3"/><child link="tool0"/>
  </joint>
</robot>
"""


def _map_then_check(tmp_path, capsys, theta: str) -> tuple[str, dict]:
    (tmp_path / "arm.urdf").write_text(URDF, encoding="utf-8")
    model = tmp_path / "arm.toml"
    table = TABLE.format(theta=theta)
    model.write_text(table, encoding="utf-8")
    block = tmp_path / "block.toml"
    assert main(["map", str(model), str(tmp_path / "arm.urdf"), "-o", str(block)]) == 0
    model.write_text(table + "\n" + block.read_text(encoding="utf-8"), encoding="utf-8")
    report = tmp_path / "r.json"
    capsys.readouterr()
    main(["check", str(model), "--samples", "16", "--against", "pinocchio-urdf",
          "--require", "table", "--json", str(report)])  # fmt: skip
    printed = " ".join(capsys.readouterr().out.split())
    numbers = json.loads(report.read_text(encoding="utf-8"))["numbers"]["numbers"]
    return printed, {n["name"]: n for n in numbers}


def test_the_right_table_leaves_theta3_to_the_choice_of_link(tmp_path, capsys):
    # Through this description the right table and the one with θ3 off by 180° cannot
    # be told apart: l3 is tidy under the one, tool0 under the other.
    printed, numbers = _map_then_check(tmp_path, capsys, "")
    assert numbers["θ3"]["pair_can"] == "not-identifiable"
    assert numbers["θ3"]["competing"] == ["tool0"]
    assert "carries none of it" in numbers["θ3"]["absorbed_by"]
    assert "numbers (base → l3)" in printed
    assert "verdict: unverified" in printed


def test_theta3_off_by_a_half_turn_is_never_verified(tmp_path, capsys):
    printed, numbers = _map_then_check(tmp_path, capsys, "theta = 180\n")
    assert numbers["θ3"]["status"] != "verified"
    assert numbers["θ3"]["pair_can"] == "not-identifiable"
    assert "table verified independently" not in printed
    assert "verdict: unverified" in printed
