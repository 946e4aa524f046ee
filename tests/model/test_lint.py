"""fkcheck lint: each rule on a table written to show it, and the bundled tables clean."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import pytest

from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.model.lint import lint_model
from fkcheck.model.published import KNOWN_VARIANTS
from fkcheck.model.types import Offset
from fkcheck.model.write import model_to_toml
from tests.helpers import BUNDLED


def with_joint(model, index, **changes):
    joints = list(model.joints)
    joints[index] = replace(joints[index], **changes)
    return replace(model, joints=tuple(joints))


def write(tmp_path, model, *, angle_unit=None, text_edit=None):
    text = model_to_toml(model, angle_unit=angle_unit)
    if text_edit is not None:
        text = text_edit(text)
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    return path


def lint(capsys, path):
    code = main(["lint", str(path), "--json"])
    return code, json.loads(capsys.readouterr().out)["findings"]


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_models_are_clean(name, capsys):
    assert main(["lint", name]) == 0
    assert "clean" in capsys.readouterr().out


def test_rtb_d1_is_flagged_as_a_variant_of_the_published_ur5(tmp_path, capsys):
    path = write(tmp_path, with_joint(load_model("ur5"), 0, d=0.089459))
    code, findings = lint(capsys, path)
    assert code == 1
    assert [f["rule"] for f in findings] == ["published"]
    assert findings[0]["field"] == "joint[0].d"
    message = findings[0]["message"]
    assert "d1 (joint[0].d, shoulder_pan) = 0.089459 is +0.300 mm from 0.089159" in message
    assert "published table ur5" in message
    assert "Robotics Toolbox for Python's packaged UR5" in message


def test_older_d1_without_a_known_source_is_flagged_too(tmp_path, capsys):
    path = write(tmp_path, with_joint(load_model("ur5"), 0, d=0.08946))
    code, findings = lint(capsys, path)
    assert code == 1
    assert "+0.301 mm from 0.089159" in findings[0]["message"]
    assert "Robotics Toolbox" not in findings[0]["message"]


def test_a_tiny_angle_difference_reads_as_its_digits_not_as_zero(tmp_path, capsys):
    # α1 of the UR5 written with 1.7e-6 rad less than the published π/2: was "-0.000 °".
    ur5 = load_model("ur5")
    path = write(tmp_path, with_joint(ur5, 0, alpha=ur5.joints[0].alpha - 1.7e-6))
    code, findings = lint(capsys, path)
    assert code == 1
    assert [f["rule"] for f in findings] == ["rounded-angle", "published"]
    finding = findings[1]
    assert finding["field"] == "joint[0].alpha"
    assert (
        " is -9.74e-05° from 1.5707963267948966 in the published table ur5" in (finding["message"])
    )


def test_degrees_declared_as_radians(tmp_path, capsys):
    path = write(
        tmp_path,
        load_model("ur5"),
        angle_unit="deg",
        text_edit=lambda t: t.replace('angle_unit = "deg"', 'angle_unit = "rad"'),
    )
    code, findings = lint(capsys, path)
    assert code == 1
    degrees = [f for f in findings if f["rule"] == "degrees"]
    assert {f["field"] for f in degrees} == {
        "joint[0].alpha",
        "joint[3].alpha",
        "joint[4].alpha",  # 90, 90, -90
        "frames.base_link.rpy[2]",
        "frames.ee_link.rpy[0]",
        "frames.ee_link.rpy[1]",
        "frames.flange.rpy[0]",
        "frames.flange.rpy[1]",
    }
    assert "looks like degrees" in degrees[0]["message"]
    assert any(f["rule"] == "limits" and "degrees in a file" in f["message"] for f in findings)


def test_radians_declared_as_degrees(tmp_path, capsys):
    path = write(
        tmp_path,
        load_model("panda"),
        text_edit=lambda t: t.replace('angle_unit = "rad"', 'angle_unit = "deg"'),
    )
    code, findings = lint(capsys, path)
    assert code == 1
    assert any(
        f["rule"] == "degrees" and "reads like π/2 in radians" in f["message"] for f in findings
    )


def test_rounded_and_odd_twists(tmp_path, capsys):
    model = with_joint(with_joint(load_model("ur5"), 0, alpha=1.5708), 3, alpha=0.3)
    code, findings = lint(capsys, write(tmp_path, model, angle_unit="rad"))
    assert code == 1
    by_field = {f["field"]: f for f in findings}
    assert by_field["joint[0].alpha"]["rule"] == "rounded-angle"
    assert "1.5707963267948966" in by_field["joint[0].alpha"]["message"]
    assert by_field["joint[3].alpha"]["rule"] == "twist"


def test_a_theta_offset_written_as_rounded_radians(tmp_path, capsys):
    # θ2 = -1.5708 in a radian file: 3.7e-6 rad off -π/2, passed lint when only α was looked at.
    model = with_joint(load_model("ur5"), 1, theta=-1.5708)
    path = write(tmp_path, model, angle_unit="rad")
    assert main(["lint", str(path)]) == 1
    assert capsys.readouterr().out.splitlines() == [
        f"{path}: joint[1].theta (shoulder_lift): warning [rounded-angle]: θ2 (joint[1].theta, "
        "shoulder_lift) = -1.5708 rad is -90° rounded (3.7e-06 rad off): write "
        "-1.5707963267948966 rad or -90 in a degree file"
    ]


@pytest.mark.parametrize("theta", [-math.pi / 2, math.pi, math.radians(0.01), -0.3])
def test_exact_small_and_odd_theta_offsets_are_clean(theta, tmp_path, capsys):
    # An exact quarter turn, a calibrated table's 0.01°, a θ offset of any size: not rounded
    # (0.01° from UR5's table is `published`'s: "close to the published table").
    _, findings = lint(capsys, write(tmp_path, with_joint(load_model("ur5"), 1, theta=theta)))
    assert [f["rule"] for f in findings] == (["published"] if abs(theta) < 1e-3 else [])


def test_a_theta_in_a_degree_file_converted_from_rounded_radians(tmp_path, capsys):
    model = with_joint(load_model("ur5"), 4, theta=math.radians(89.9999))
    code, findings = lint(capsys, write(tmp_path, model, angle_unit="deg"))
    assert code == 1
    assert [(f["rule"], f["field"]) for f in findings] == [("rounded-angle", "joint[4].theta")]
    assert "= 89.9999° is 90° rounded" in findings[0]["message"]


def test_limits_of_a_rounded_full_turn_are_not_degrees(tmp_path, capsys):
    # ±6.2832 rad (J6 of a vendor sheet) was "beyond ±360° (degrees in a file with
    # angle_unit = rad?)".
    model = with_joint(load_model("ur5"), 5, limits=(-6.2832, 6.2832))
    path = write(tmp_path, model, angle_unit="rad")
    assert main(["lint", str(path)]) == 1
    assert capsys.readouterr().out.splitlines() == [
        f"{path}: joint[5].limits (wrist_3): warning [rounded-angle]: revolute joint wrist_3 has "
        "limits [-6.2832 rad, 6.2832 rad]: ±360° rounded up (1.5e-05 rad beyond): write "
        "±6.283185307179586 rad or ±360 in a degree file"
    ]


@pytest.mark.parametrize(
    ("limits", "rules"),
    [
        ((-6.28318530718, 6.28318530718), []),  # a URDF's 2π: within float slack
        ((-3.1416, 6.2832), ["rounded-angle"]),  # one side rounded beyond a turn
        ((-6.2842, 6.2842), ["limits"]),  # 1.0e-3 beyond: more than rounding
        ((-6.3, 6.3), ["limits"]),
    ],
)
def test_limits_near_a_full_turn(limits, rules, tmp_path, capsys):
    model = with_joint(load_model("ur5"), 5, limits=limits)
    code, findings = lint(capsys, write(tmp_path, model, angle_unit="rad"))
    assert [f["rule"] for f in findings] == rules
    assert code == (1 if rules else 0)
    assert all("degrees" not in f["message"] for f in findings if f["rule"] == "rounded-angle")


def test_a_calibrations_measured_theta_and_limits_are_exempt():
    # What fkcheck.calibration.lint passes for a calibrated model that fits its nominal one.
    model = with_joint(with_joint(load_model("ur5"), 1, theta=-1.5708), 5, limits=(-6.2832, 6.2832))
    assert [(f.rule, f.field) for f in lint_model(model)] == [
        ("rounded-angle", "joint[1].theta"),
        ("rounded-angle", "joint[5].limits"),
    ]
    assert lint_model(model, measured=True) == []


def test_millimetres_in_a_metre_file(tmp_path, capsys):
    code, findings = lint(capsys, write(tmp_path, with_joint(load_model("ur5"), 1, a=-425.0)))
    assert code == 1
    assert findings[0]["rule"] == "length"
    assert findings[0]["field"] == "joint[1].a"
    assert "millimetres" in findings[0]["message"]


def test_long_base_tool_and_frame_offsets_are_named_by_field():
    ur5 = load_model("ur5")
    frames = dict(ur5.frames)
    frames["flange"] = replace(frames["flange"], offset=Offset((-7.0, 0.0, 0.0)))
    model = replace(
        ur5, base=Offset((0.0, 0.0, 89.159)), tool=Offset((0.0, 6.0, 0.0)), frames=frames
    )
    lengths = [f for f in lint_model(model) if f.rule == "length"]
    assert [f.field for f in lengths] == ["base.xyz[2]", "tool.xyz[1]", "frames.flange.xyz[0]"]
    assert "millimetres" in lengths[0].message
    assert "millimetres" not in lengths[1].message


def test_limits_beyond_a_full_turn(tmp_path, capsys):
    model = with_joint(load_model("ur5"), 2, limits=(-math.radians(400), math.radians(400)))
    code, findings = lint(capsys, write(tmp_path, model))
    assert code == 1
    assert [(f["rule"], f["field"]) for f in findings] == [("limits", "joint[2].limits")]


@pytest.mark.parametrize(
    ("model_name", "joint", "limits", "said"),
    [
        ("ur5", 2, (0.0, 0.0), "no range at all"),
        ("ur5", 2, (-math.radians(1e-7), math.radians(1e-7)), "a range under 0.057°"),
        ("ur5", 2, (-math.radians(0.02), math.radians(0.02)), "a range under 0.057°"),
        ("stanford", 2, (0.5, 0.5), "no range at all"),  # a prismatic joint held still
    ],
)
def test_a_joint_the_limits_freeze_is_flagged(tmp_path, capsys, model_name, joint, limits, said):
    model = with_joint(load_model(model_name), joint, limits=limits)
    code, findings = lint(capsys, write(tmp_path, model))
    assert code == 1
    assert [(f["rule"], f["field"]) for f in findings] == [("limits", f"joint[{joint}].limits")]
    assert said in findings[0]["message"]
    assert "is the joint meant to move?" in findings[0]["message"]


def test_a_range_of_a_tenth_of_a_degree_is_not_flagged():
    """Over NARROW_RANGE_RAD (1 mrad, 0.057°): a narrow axis, not one held still."""
    model = with_joint(load_model("ur5"), 2, limits=(-math.radians(0.05), math.radians(0.05)))
    assert lint_model(model) == []


def test_modified_table_declared_standard(tmp_path, capsys):
    path = write(
        tmp_path,
        load_model("panda"),
        text_edit=lambda t: t.replace('convention = "modified"', 'convention = "standard"'),
    )
    code, findings = lint(capsys, path)
    assert code == 1
    assert [f["rule"] for f in findings] == ["convention"]
    assert "shaped like a modified (Craig) one" in findings[0]["message"]


def test_standard_table_declared_modified(tmp_path, capsys):
    path = write(
        tmp_path,
        load_model("ur5"),
        text_edit=lambda t: t.replace('convention = "standard"', 'convention = "modified"'),
    )
    code, findings = lint(capsys, path)
    assert code == 1
    assert findings[0]["rule"] == "convention"
    assert "first row has a0 = 0, α0 = 90°" in findings[0]["message"]


def test_unreadable_model_is_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("name = \n")
    assert main(["lint", str(bad)]) == 2
    assert "not valid TOML" in capsys.readouterr().err


def test_lint_model_returns_findings_in_memory():
    findings = lint_model(with_joint(load_model("ur10"), 3, d=0.1639))  # 0.163941 rounded
    assert [(f.rule, f.field) for f in findings] == [("published", "joint[3].d")]


def test_known_variants_are_what_robotics_toolbox_ships():
    import roboticstoolbox as rtb

    for variant in KNOWN_VARIANTS:
        assert variant.model == "ur5"
        robot = rtb.models.DH.UR5()
        link = robot.links[variant.joint]
        assert getattr(link, variant.param) == variant.value
        # ...and that is the only number in which it differs from the published table.
        published = load_model("ur5")
        for i, (ours, theirs) in enumerate(zip(published.joints, robot.links, strict=True)):
            for param in ("a", "alpha", "d"):
                if (i, param) != (variant.joint, variant.param):
                    assert getattr(ours, param) == pytest.approx(getattr(theirs, param), abs=1e-15)


def test_a_joint_field_is_shown_with_its_joint_name(tmp_path, capsys):
    # lint counted from 0 (joint[3]) and diagnose from 1 (α4): the name settles which joint.
    path = write(tmp_path, with_joint(load_model("ur5"), 1, a=-425.0))
    assert main(["lint", str(path)]) == 1
    assert capsys.readouterr().out.splitlines() == [
        f"{path}: joint[1].a (shoulder_lift): warning [length]: -425 m is beyond 5 m — "
        "millimetres in a file that must be in metres?"
    ]


def test_a_model_error_in_a_joint_names_the_joint(tmp_path):
    from fkcheck.errors import ModelError

    text = model_to_toml(load_model("ur5")).replace("alpha = 0.0\n", 'alpha = "ninety"\n', 1)
    path = tmp_path / "arm.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(
        ModelError, match=r"arm\.toml: joint\[1\]\.alpha \(shoulder_lift\): "
    ) as exc:
        load_model(path)
    assert exc.value.field == "joint[1].alpha"  # the field path itself is unchanged
    assert exc.value.joint == "shoulder_lift"
