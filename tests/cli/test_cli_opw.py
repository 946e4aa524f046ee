"""`fkcheck opw` as a user runs it: the YAML MoveIt reads, and exit 2 on an arm that is not OPW.

The KR 6 R700 sixx's published set is kuka_experimental's
``kuka_kr6_support/config/opw_kinematics_kr6r700sixx.yaml`` at commit
e78bbd15edb2b39c9053ff3b963ef2947e10a531, which this reads back from the printed YAML.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
import yaml

from fkcheck.cli.main import main
from fkcheck.ik import opw_params
from fkcheck.model.read import bundled_model_paths

pytest.importorskip("py_opw_kinematics")

#: kuka_experimental's YAML, as published (its keys are what MoveIt's plugin reads).
KR6_PUBLISHED_YAML = """
opw_kinematics_geometric_parameters:
  a1:  0.025
  a2: -0.035
  b:   0.000
  c1:  0.400
  c2:  0.315
  c3:  0.365
  c4:  0.080
opw_kinematics_joint_offsets: [0.0, -1.57079632679, 0, 0, 0, 0]
opw_kinematics_joint_sign_corrections: [-1, 1, 1, -1, 1, -1]
"""


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_kr6_prints_the_published_yaml(capsys):
    code, out, err = run(capsys, "opw", "kr6r700sixx")
    assert code == 0, err
    assert err == ""
    printed = yaml.safe_load(out)
    published = yaml.safe_load(KR6_PUBLISHED_YAML)
    assert printed == published  # the 12 significant digits print -π/2 as published
    assert out.splitlines()[1].startswith(
        "# the FK of py-opw-kinematics against the table over 1080 configurations: at most "
    )


def test_the_printed_agreement_is_measured(capsys):
    code, out, _ = run(capsys, "opw", "puma560", "--samples", "64", "--seed", "9")
    assert code == 0
    line = out.splitlines()[1]
    numbers = [float(x) for x in line.split("at most ")[1].rstrip(" rad.").split(" m, ")]
    assert 0.0 <= numbers[0] < 1e-12
    assert 0.0 <= numbers[1] < 1e-12
    assert "over 145 configurations" in line  # 64 random + the structured ones


@pytest.mark.parametrize(
    ("model", "reason"),
    [
        ("ur5e", "axes 4, 5, 6 do not meet in one point (no spherical wrist): axes 4, 5 "
                 "meet 0.0997 m from where axes 5, 6 meet (the table's joint[4].d (wrist_2) = "
                 "0.0997 m)"),
        ("panda", "OPW arms have 6 joints, this table has 7"),
    ],
)  # fmt: skip
def test_an_arm_that_is_not_opw_shaped_exits_2_with_the_reason(capsys, model, reason):
    code, out, err = run(capsys, "opw", model)
    assert code == 2
    assert out == ""
    assert err == f"fkcheck: error: model {model}: not OPW-shaped: {reason}\n"


def test_frames_that_are_not_opws_are_said(capsys, tmp_path):
    text = bundled_model_paths()["kr6r700sixx"].read_text(encoding="utf-8")
    text = text.replace(
        'angle_unit = "deg"\n',
        'angle_unit = "deg"\n\n[base]\nxyz = [0.1, 0, 0]\n'
        "rpy = [0, 0, 0]\n\n[tool]\nxyz = [0.03, 0, 0.1]\nrpy = [0, 0, 0]\n",
        1,
    )
    path = tmp_path / "moved.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = run(capsys, "opw", str(path))
    assert code == 0, err
    comments = [line for line in out.splitlines() if line.startswith("# OPW's")]
    assert comments == [
        "# OPW's base frame is not the model's world: world_T_opw_base = xyz [0.1, 0.0, 0.0] "
        "rpy [0.0, 0.0, 0.0] (rad)",
        "# OPW's tool frame is not the model's TCP: opw_tool_T_tcp = xyz [0.03, 0.0, 0.0] "
        "rpy [0.0, 0.0, 0.0] (rad)",
    ]
    assert yaml.safe_load(out)["opw_kinematics_geometric_parameters"]["c4"] == pytest.approx(0.18)


def test_wrong_parameters_exit_1(capsys, monkeypatch):
    real = opw_params.derive_opw

    def off_by_a_millimetre(model):
        from dataclasses import replace

        p = real(model)
        return replace(p, c3=p.c3 + 1e-3)

    monkeypatch.setattr(opw_params, "derive_opw", off_by_a_millimetre)
    code, out, err = run(capsys, "opw", "kr6r700sixx", "--samples", "16")
    assert code == 1
    assert "c3: 0.366" in out
    assert err.startswith("fkcheck: opw: kr6r700sixx: py-opw-kinematics' FK with these parameters")
    assert "the parameters are wrong" in err


def test_without_py_opw_kinematics_it_says_which_extra(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "py_opw_kinematics", None)
    code, out, err = run(capsys, "opw", "kr6r700sixx")
    assert code == 2
    assert out == ""
    assert err == (
        "fkcheck: error: opw: py-opw-kinematics is not installed (no module "
        "'py_opw_kinematics'); it comes with fkcheck's 'ik' extra: pip install 'fkcheck[ik]'\n"
    )


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["opw", "kr6r700sixx", "--samples", "-1"], r"--samples: must be an integer"),
        (["opw", "kr6r700sixx", "--seed", "-3"], r"--seed: must be"),
        (["opw", "no_such_robot"], r"no model file 'no_such_robot'"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(capsys, argv, match):
    import re

    code, _, err = run(capsys, *argv)
    assert code == 2
    assert re.search(match, err), err
    assert len(err.splitlines()) == 1


def test_offsets_print_as_radians_to_twelve_digits(capsys):
    _, out, _ = run(capsys, "opw", "puma560", "--samples", "0")
    offsets = yaml.safe_load(out)["opw_kinematics_joint_offsets"]
    assert offsets == [3.14159265359, 1.57079632679, -1.57079632679, 0.0, 0.0, 3.14159265359]
    assert np.allclose(offsets, [math.pi, math.pi / 2, -math.pi / 2, 0, 0, math.pi], atol=1e-11)
