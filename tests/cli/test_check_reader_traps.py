"""The issue's reader traps through ``fkcheck check``: a reader error row or a reader finding.

Never a traceback, never a silent pass. A two-joint planar arm whose MJCF MuJoCo
reads exactly as the table (standard DH: a1 0.4, a2 0.25, θ2 offset 90°), with
one trap each: ``eulerseq="XYZ"`` with an unnormalised ``axisangle`` (Pinocchio
4.1.0 returns a matrix that is not a rotation, metres off), and ``<include>``d
defaults (Pinocchio 4.1.0 crashes on the include itself; fkcheck expands includes,
held to the model's folder, before any reader sees the text).
"""

from __future__ import annotations

import json
from importlib import metadata
from pathlib import Path

import numpy as np

from fkcheck.cli.main import main
from fkcheck.mjcf import mujoco_poses, pinocchio_poses, read_mjcf

ARM = """<mujoco model="arm">
  <compiler {compiler}/>
  {defaults}
  <worldbody>
    <body name="b1">
      <joint name="j1" axis="0 0 1"/>
      <body name="b2" pos="0.4 0 0" {b2}>
        <joint name="j2" {j2}/>
        <site name="tip" pos="0.25 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
MODEL = """name = "arm"
source = "two joints, drawn for this test"
convention = "standard"
angle_unit = "deg"

[[joint]]
a = 0.4
alpha = 0
d = 0
theta = 0

[[joint]]
a = 0.25
alpha = 0
d = 0
theta = 90

[mjcf]
path = "arm.xml"
joints = ["j1", "j2"]

[frames.base]
dh = 0
mjcf = "world"

[frames.tip]
dh = 2
mjcf = "tip"

[check]
from = "base"
to = "tip"
"""
PIN = metadata.version("pin")
Q = np.random.default_rng(7).uniform(-np.pi, np.pi, (20, 2))


def arm(tmp_path: Path, *, compiler="", defaults="", b2="", j2='axis="0 0 1"') -> Path:
    xml = ARM.format(compiler=compiler, defaults=defaults, b2=b2, j2=j2)
    (tmp_path / "arm.xml").write_text(xml, encoding="utf-8")
    path = tmp_path / "arm.toml"
    path.write_text(MODEL, encoding="utf-8")
    return path


def check(tmp_path: Path, model: Path, capsys) -> tuple[int, str, dict[str, dict]]:
    out = tmp_path / "check.json"
    argv = ["check", str(model), "--samples", "20", "--against", "mujoco-mjcf,pinocchio-mjcf",
            "--json", str(out)]  # fmt: skip
    code = main(argv)
    said = capsys.readouterr()
    assert "Traceback" not in said.out + said.err
    rows = {b["name"]: b for b in json.loads(out.read_text(encoding="utf-8"))["backends"]}
    return code, said.out, rows


def readers_agree(tmp_path: Path) -> bool:
    desc = read_mjcf(tmp_path / "arm.xml")
    return bool(
        np.allclose(pinocchio_poses(desc, ["tip"], Q), mujoco_poses(desc, ["tip"], Q), atol=1e-9)
    )


def test_eulerseq_with_an_unnormalised_axisangle_is_a_reader_finding(tmp_path, capsys):
    model = arm(tmp_path, compiler='eulerseq="XYZ"', b2='axisangle="0 0 2 90"')
    code, out, rows = check(tmp_path, model, capsys)
    assert rows["mujoco-mjcf"]["status"] == "pass"  # MuJoCo reads it as the table
    if readers_agree(tmp_path):  # a Pinocchio that reads it right
        assert (code, rows["pinocchio-mjcf"]["status"]) == (0, "pass")
        return
    assert code == 1
    assert rows["pinocchio-mjcf"]["status"] == "fail"
    assert rows["pinocchio-mjcf"]["reader_finding"].startswith(
        f"pinocchio-mjcf (pinocchio {PIN}) disagrees with mujoco-mjcf"
    )
    assert rows["pinocchio-mjcf"]["max_position_error_m"] > 0.1  # metres off, not round-off
    assert "table FAILED" not in out
    assert "a finding about the reader, not the table" in out


def test_the_trap_has_teeth_a_table_that_differs_fails_in_both_readers(tmp_path, capsys):
    model = arm(tmp_path, compiler='eulerseq="XYZ"', b2='axisangle="0 0 2 90"')
    model.write_text(MODEL.replace("theta = 90", "theta = 89"), encoding="utf-8")
    code, out, rows = check(tmp_path, model, capsys)
    assert code == 1
    assert rows["mujoco-mjcf"]["status"] == "fail"
    assert rows["pinocchio-mjcf"]["reader_finding"] is None  # no reader agrees: the table's
    assert "table FAILED" in out


#: θ2's 90°, as a w x y z quaternion (which every reader reads alike).
QUARTER = 'quat="0.7071067811865476 0 0 0.7071067811865476"'
DEFAULTS = '<default><default class="arm"><joint axis="0 0 1"/></default></default>'


def test_included_defaults_are_read_by_both_readers(tmp_path, capsys):
    (tmp_path / "defaults.xml").write_text(f"<mujoco>{DEFAULTS}</mujoco>", encoding="utf-8")
    model = arm(tmp_path, defaults='<include file="defaults.xml"/>', b2=QUARTER, j2='class="arm"')
    code, _, rows = check(tmp_path, model, capsys)
    assert rows["mujoco-mjcf"]["status"] == "pass"
    # fkcheck expands the include before a reader sees it: Pinocchio gets the defaults.
    assert (code, rows["pinocchio-mjcf"]["status"]) == (0, "pass"), rows["pinocchio-mjcf"]


def test_an_include_outside_the_models_folder_is_one_line(tmp_path, capsys):
    inner = tmp_path / "inner"
    inner.mkdir()
    (tmp_path / "defaults.xml").write_text(f"<mujoco>{DEFAULTS}</mujoco>", encoding="utf-8")
    model = arm(inner, defaults='<include file="../defaults.xml"/>', b2=QUARTER, j2='class="arm"')
    argv = ["check", str(model), "--samples", "5", "--against", "mujoco-mjcf,pinocchio-mjcf"]
    assert main(argv) == 2  # refused before any reader sees it
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert err.count("\n") == 1
    said = "<include file='../defaults.xml'>: '..' leads out of the folder includes are held to"
    assert said in err
