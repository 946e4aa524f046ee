"""Model files: every bundled model loads; units; the seed CSV; every rejected input."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from fkcheck import ModelError, load_model
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.errors import ToleranceError
from fkcheck.model.read import bundled_model_paths
from fkcheck.model.types import MAX_JOINTS
from tests.helpers import BUNDLED, assert_pose_close, random_q
from tests.paths import DATA_DIR

DATA = DATA_DIR

UR_NOMINAL = {  # Universal Robots' published table: d1, a2, a3, d4, d5, d6 (m)
    "ur3": (0.1519, -0.24365, -0.21325, 0.11235, 0.08535, 0.0819),
    "ur5": (0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823),
    "ur10": (0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922),
    "ur3e": (0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921),
    "ur5e": (0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
    "ur10e": (0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655),
    "ur16e": (0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655),
    "ur20": (0.2363, -0.862, -0.7287, 0.201, 0.1593, 0.1543),
    "ur30": (0.2363, -0.637, -0.5037, 0.201, 0.1593, 0.1543),
}


def test_bundled_set_is_complete():
    expected = {*UR_NOMINAL, "panda", "puma560", "stanford", "planar2", "planar3"}
    assert expected <= set(bundled_model_paths())


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_model_loads_with_source_and_no_warnings(name):
    model = load_model(name)
    assert model.name == name
    assert model.source.strip()
    assert model.warnings == ()
    assert model.dof == len(model.joint_names) >= 2
    for pose in model.poses.values():
        assert len(pose) == model.dof


@pytest.mark.parametrize("name", sorted(UR_NOMINAL))
def test_ur_tables_are_the_published_numbers(name):
    m = load_model(name)
    d1, a2, a3, d4, d5, d6 = UR_NOMINAL[name]
    assert [j.a for j in m.joints] == [0.0, a2, a3, 0.0, 0.0, 0.0]
    assert [j.d for j in m.joints] == [d1, 0.0, 0.0, d4, d5, d6]
    half_pi = math.pi / 2
    assert [j.alpha for j in m.joints] == [half_pi, 0.0, 0.0, half_pi, -half_pi, 0.0]
    assert all(j.theta == 0.0 for j in m.joints)


def test_panda_is_modified_with_flange_tool():
    m = load_model("panda")
    assert m.convention == "modified"
    assert m.dof == 7
    assert m.tool.xyz == (0.0, 0.0, 0.107)
    assert [j.a for j in m.joints] == [0.0, 0.0, 0.0, 0.0825, -0.0825, 0.0, 0.088]


def test_stanford_has_a_prismatic_joint():
    m = load_model("stanford")
    assert [j.type for j in m.joints].count("prismatic") == 1
    j3 = m.joints[2]
    assert j3.limits == (0.3048, 1.27)  # metres, not converted by angle_unit
    assert j3.theta == pytest.approx(-math.pi / 2, abs=1e-15)


def test_degree_file_equals_its_radian_twin(tmp_path, rng):
    deg = load_model("ur5")
    text = (bundled_model_paths()["ur5"]).read_text()
    text = text.replace('angle_unit = "deg"', 'angle_unit = "rad"')
    for value in ("90", "-90"):
        text = text.replace(f"alpha = {value}\n", f"alpha = {math.radians(float(value))!r}\n")
    text = text.replace("limits = [-360.0, 360.0]", f"limits = [{-2 * math.pi!r}, {2 * math.pi!r}]")
    text = text.replace("limits = [-180.0, 180.0]", f"limits = [{-math.pi!r}, {math.pi!r}]")
    text = text.replace("rpy = [0, 0, 180]", f"rpy = [0, 0, {math.pi!r}]")
    text = text.replace("rpy = [90, -90, 0]", f"rpy = [{math.pi / 2!r}, {-math.pi / 2!r}, 0]")
    text = text.replace("rpy = [-90, -90, 0]", f"rpy = [{-math.pi / 2!r}, {-math.pi / 2!r}, 0]")
    lines = [ln for ln in text.splitlines() if not ln.startswith(("home", "worked_example"))]
    (tmp_path / "ur5_rad.toml").write_text("\n".join(lines))
    rad = load_model(tmp_path / "ur5_rad.toml")
    assert rad.warnings == ()
    q = random_q(deg, rng, 200)
    np.testing.assert_array_equal(rad.fk(q), deg.fk(q))
    np.testing.assert_array_equal(rad.limits, deg.limits)
    assert rad.frames == deg.frames


def test_seed_csv_table_is_read_as_standard_dh_in_radians(rng):
    csv = load_model(DATA / "ur5_seed001.csv")
    toml = load_model("ur5")
    assert csv.name == "ur5_seed001"
    assert csv.convention == "standard"
    assert csv.joint_names == toml.joint_names
    q = random_q(toml, rng, 200)
    assert_pose_close(csv.fk(q), toml.fk(q), SAME_CHAIN)


def test_too_many_joints_refused_quickly(tmp_path):
    rows = "".join("[[joint]]\na = 0.1\nalpha = 0.0\nd = 0.0\n" for _ in range(10_000))
    path = tmp_path / "huge.toml"
    path.write_text(f'name = "huge"\nconvention = "standard"\n{rows}')
    with pytest.raises(ModelError, match=rf"10000 joints is more than the limit of {MAX_JOINTS}"):
        load_model(path)


def test_degrees_in_a_radian_file_warn_but_load(tmp_path):
    path = tmp_path / "degish.toml"
    path.write_text(
        'name = "x"\nconvention = "standard"\n[[joint]]\na = 0.3\nalpha = 90\nd = 0.1\n'
    )
    model = load_model(path)
    assert len(model.warnings) == 1
    assert "joint[0].alpha = 90" in model.warnings[0]  # not named in the file: no name
    assert "looks like degrees" in model.warnings[0]


GOOD_HEAD = 'name = "m"\nconvention = "standard"\n'
JOINT = "[[joint]]\na = 0.1\nalpha = 0.0\nd = 0.2\n"

BAD_FILES = {
    "not_toml": ("name = \n[[[", r"not valid TOML"),
    "truncated": (GOOD_HEAD + "[[joint]]\na = 0.1\nalpha = ", r"not valid TOML"),
    "empty": ("", r"empty model file"),
    "no_joints": (GOOD_HEAD, r"joint: missing"),
    "empty_joint_list": (GOOD_HEAD + "joint = []\n", r"joint: no joints"),
    "missing_name": ('convention = "standard"\n' + JOINT, r"name: missing \(required\)"),
    "missing_convention": ('name = "m"\n' + JOINT, r"convention: missing"),
    "missing_alpha": (GOOD_HEAD + "[[joint]]\na = 0.1\nd = 0.2\n", r"joint\[0\]\.alpha: missing"),
    "string_number": (
        GOOD_HEAD + '[[joint]]\na = "0.1"\nalpha = 0.0\nd = 0.2\n',
        r"joint\[0\]\.a: expected a number, got a string",
    ),
    "bool_number": (
        GOOD_HEAD + "[[joint]]\na = true\nalpha = 0.0\nd = 0.2\n",
        r"joint\[0\]\.a: expected a number, got a boolean",
    ),
    "unknown_key": (
        GOOD_HEAD + JOINT + "offset = 3\n",
        r"joint\[0\]\.offset: unknown key; allowed",
    ),
    "unknown_top_key": ('colour = "red"\n' + GOOD_HEAD + JOINT, r"colour: unknown key"),
    "unknown_convention": (
        'name = "m"\nconvention = "craig"\n' + JOINT,
        r"convention: 'craig' is not one of: standard, modified",
    ),
    "unknown_joint_type": (
        GOOD_HEAD + JOINT + 'type = "spherical"\n',
        r"joint\[0\]\.type: 'spherical' is not one of: revolute, prismatic",
    ),
    "unknown_angle_unit": (GOOD_HEAD + 'angle_unit = "grad"\n' + JOINT, r"angle_unit: 'grad'"),
    "duplicate_names": (
        GOOD_HEAD + JOINT + 'name = "j"\n' + JOINT + 'name = "j"\n',
        r"joint\[1\]\.name: duplicate joint name 'j' \(also joint\[0\]\)",
    ),
    "nan": (
        GOOD_HEAD + "[[joint]]\na = nan\nalpha = 0.0\nd = 0.2\n",
        r"joint\[0\]\.a: must be a finite number, got nan",
    ),
    "inf": (
        GOOD_HEAD + "[[joint]]\na = 0.1\nalpha = 0.0\nd = -inf\n",
        r"joint\[0\]\.d: must be a finite number, got -inf",
    ),
    "limits_reversed": (
        GOOD_HEAD + JOINT + "limits = [1.0, -1.0]\n",
        r"joint\[0\]\.limits: lower 1.0 is greater than upper -1.0",
    ),
    "limits_length": (GOOD_HEAD + JOINT + "limits = [1.0]\n", r"joint\[0\]\.limits: expected 2"),
    "pose_length": (
        GOOD_HEAD + JOINT + "[poses]\nzero = [0, 0]\n",
        r"poses\.zero: expected 1 numbers, got 2",
    ),
    "pose_nan": (
        GOOD_HEAD + JOINT + "[poses]\nzero = [nan]\n",
        r"poses\.zero\[0\]: must be a finite",
    ),
    "flip_not_bool": (
        GOOD_HEAD + JOINT + "flip = 1\n",
        r"joint\[0\]\.flip: expected true or false",
    ),
    "base_xyz_short": (GOOD_HEAD + JOINT + "[base]\nxyz = [0, 0]\n", r"base\.xyz: expected 3"),
    "joint_not_table": (GOOD_HEAD + "joint = [1, 2]\n", r"joint\[0\]: expected a table"),
    "urdf_path_empty": (
        GOOD_HEAD + JOINT + '[urdf]\npath = ""\njoints = ["a"]\n',
        r"urdf\.path: '' names no file: give the URDF's path \(relative to this file\), "
        r"example-robot-data:<subpath> or fkcheck:<subpath>$",
    ),
    "urdf_path_blank": (
        GOOD_HEAD + JOINT + '[urdf]\npath = "  "\njoints = ["a"]\n',
        r"urdf\.path: '  ' names no file",
    ),
    "urdf_path_bare_prefix": (
        GOOD_HEAD + JOINT + '[urdf]\npath = "example-robot-data:"\njoints = ["a"]\n',
        r"urdf\.path: 'example-robot-data:' names no file",
    ),
    "urdf_path_bare_fkcheck_prefix": (
        GOOD_HEAD + JOINT + '[urdf]\npath = "fkcheck:"\njoints = ["a"]\n',
        r"urdf\.path: 'fkcheck:' names no file",
    ),
    "urdf_joint_count": (
        GOOD_HEAD + JOINT + '[urdf]\npath = "x.urdf"\njoints = ["a", "b"]\n',
        r"urdf\.joints: names 2 URDF joints but the DH table has 1",
    ),
    "frame_bad_dh": (
        GOOD_HEAD + JOINT + "[frames.f]\ndh = 5\n",
        r"frames\.f\.dh: expected 0…1, \"tcp\" or \"world\", got 5",
    ),
    "check_unknown_frame": (
        GOOD_HEAD + JOINT + '[check]\nfrom = "base"\n',
        r"check\.from: frame 'base' is not defined; frames are: world, tcp",
    ),
    "check_negative_tol": (
        GOOD_HEAD + JOINT + "[check]\ntol_pos_m = -1.0\n",
        r"check\.tol_pos_m: must be > 0 and at most 0\.01 m .*, got -1$",
    ),
    # Limits without limits: each tolerance has an upper bound (fkcheck.core.tolerances).
    "check_huge_tol_pos": (
        GOOD_HEAD + JOINT + "[check]\ntol_pos_m = 1000\n",
        r"check\.tol_pos_m: must be > 0 and at most 0\.01 m \(1 cm: a looser check cannot tell a "
        r"wrong link length from a right one\), got 1000$",
    ),
    "check_huge_tol_rot": (
        GOOD_HEAD + JOINT + "[check]\ntol_rot_rad = 3.1416\n",
        r"check\.tol_rot_rad: must be > 0 and at most 0\.1 rad \(5\.7°: .*\), got 3\.1416$",
    ),
    "check_huge_tol_jacobian": (
        GOOD_HEAD + JOINT + "[check]\ntol_jacobian = 1e300\n",
        r"check\.tol_jacobian: must be > 0 and at most 0\.01 m/rad and rad/rad .*, got 1e\+300$",
    ),
    "check_zero_tol_rot": (
        GOOD_HEAD + JOINT + "[check]\ntol_rot_rad = 0\n",
        r"check\.tol_rot_rad: must be > 0 .*, got 0$",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_model_file_is_one_clear_error(tmp_path, case):
    text, match = BAD_FILES[case]
    path = tmp_path / f"{case}.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match=match) as info:
        load_model(path)
    message = str(info.value)
    assert message.startswith(str(path))
    assert "\n" not in message


def test_a_check_spec_built_in_memory_is_bounded_too():
    # Not only files: a model changed in memory cannot carry a limit without limits.
    check = load_model("ur5").check
    for key, value, match in [
        ("tol_pos_m", 1000.0, r"^CheckSpec\.tol_pos_m: must be > 0 and at most 0\.01 m"),
        ("tol_rot_rad", math.pi, r"^CheckSpec\.tol_rot_rad: must be > 0 and at most 0\.1 rad"),
        ("tol_jacobian", 1e300, r"^CheckSpec\.tol_jacobian: must be > 0 and at most 0\.01"),
        ("tol_pos_m", 0.0, r"^CheckSpec\.tol_pos_m: .*, got 0$"),
    ]:
        with pytest.raises(ToleranceError, match=match):
            replace(check, **{key: value})
    assert replace(check, tol_pos_m=0.01, tol_rot_rad=0.1, tol_jacobian=0.01).tol_rot_rad == 0.1


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("j1,0.1,0.0,0.2\n", r"line 1: expected 5 comma-separated fields"),
        ("# header\nj1,0.1,abc,0.2,0\n", r"line 2\.alpha \(column 8\): not a number: 'abc'"),
        ("j1,0.1,0.0,inf,0\n", r"line 1\.d \(column 12\): must be finite"),
        ("# only a comment\n", r"joint: no joints"),
    ],
)
def test_bad_csv_is_one_clear_error(tmp_path, text, match):
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(ModelError, match=match):
        load_model(path)


def test_unknown_model_name_lists_bundled():
    with pytest.raises(
        ModelError, match=r"no bundled model of that name; bundled models are: .*ur5"
    ):
        load_model("ur7")


def test_missing_file():
    with pytest.raises(ModelError, match=r"nope\.toml: no such file"):
        load_model("models/nope.toml")


def test_binary_file(tmp_path):
    path = tmp_path / "bin.toml"
    path.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(ModelError, match="not UTF-8"):
        load_model(path)


def test_degrees_in_radian_file_warn_then_the_check_fails(tmp_path, capsys):
    # The UR5 file with its unit line changed: 90 and 180 are now read as radians.
    from fkcheck.cli.main import main

    text = (
        bundled_model_paths()["ur5"].read_text().replace('angle_unit = "deg"', 'angle_unit = "rad"')
    )
    path = tmp_path / "ur5_units.toml"
    path.write_text(text)
    model = load_model(path)  # loads: a warning, not an error
    assert any(
        "joint[0].alpha (shoulder_pan) = 90" in w and "looks like degrees" in w
        for w in model.warnings
    )
    code = main(["check", str(path), "--samples", "50", "--against", "pinocchio-urdf"])
    out, err = capsys.readouterr()
    assert code == 1, out + err
    assert "fkcheck: warning: joint[0].alpha (shoulder_pan) = 90 is beyond ±2π" in err
    assert "verdict: fail" in out
