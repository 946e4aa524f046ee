"""Hostile calibration files (issue 31) and calibrations that are not what they claim (issue 30).

* ur_calibration's YAML costs work in proportion to what it is worth: a 600-byte
  alias bomb took 56 s and 1.4 GB (the message built the repr of a
  1.26-billion-character value before cutting it); 60,000 nested ``[`` or 30,000
  nested ``{a:`` ended in RecursionError, a 4000-digit integer in OverflowError.
  Each is now one line, exit 2, in well under a second — run in a child process
  under an address-space limit, so that a regression fails the test, not the machine;
* a key given twice in the YAML is refused, as the conf and KinematicsInfo readers
  refuse theirs;
* a calibration's fit is measured from DH frame 0 to the last DH frame, never between
  the nominal model's ``[check]`` pair, in ``fkcheck calibration`` and in lint.
"""

from __future__ import annotations

import re
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fkcheck.calibration.ur_files import (
    MAX_YAML_DEPTH,
    MAX_YAML_NODES,
    CalibrationError,
    read_ur_calibration,
)
from fkcheck.cli.main import main
from fkcheck.model.read import load_model
from tests.calibration.ur_test_data import Table, composed, fk, write_kinematics_info, write_yaml
from tests.helpers import deadline

#: Address space of the child that reads a hostile file: the reader needs ~60 MB;
#: the alias bomb needed 1.4 GB resident before the fix.
LIMIT_BYTES = 512 << 20
#: Every case ends well within this (measured after the fix: under 1 s each).
TIME_BOUND_S = 20.0


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (LIMIT_BYTES, LIMIT_BYTES))


def alias_bomb() -> str:
    """Nine levels of nine aliases each, under ``kinematics.shoulder.x``: 540 bytes."""
    lines = ["a0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]" for i in range(1, 9)]
    lines += ["kinematics:", "  shoulder: {x: *a8, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}"]
    return "\n".join(lines) + "\n"


def _shoulder(x: str) -> str:
    return f"kinematics:\n  shoulder: {{x: {x}, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}}\n"


HOSTILE_YAML = {
    # id: (text, the refusal)
    "alias_bomb": (alias_bomb(), r"line 1: an anchor or alias \(&name, \*name\)"),
    "alias_to_a_link": (
        "kinematics:\n  shoulder: &s {x: 0, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}\n"
        "  upper_arm: *s\n",
        r"line 2: an anchor or alias",
    ),
    "nested_60000_lists": (
        _shoulder("[" * 60_000 + "]" * 60_000),
        rf"line 2: nested more than {MAX_YAML_DEPTH} levels deep",
    ),
    "nested_30000_mappings": (
        _shoulder("{a: " * 30_000 + "1" + "}" * 30_000),
        rf"line 2: nested more than {MAX_YAML_DEPTH} levels deep",
    ),
    "integer_4000_digits": (_shoulder("9" * 4000), r"line 2: number too long: 4000 characters"),
    "integer_5000_digits": (_shoulder("9" * 5000), r"line 2: number too long: 5000 characters"),
    "float_4000_digits": (_shoulder("0." + "1" * 4000), r"number too long: 4002 characters"),
    "sexagesimal_200_parts": (_shoulder(":".join(["59"] * 200)), r"number too long"),
    "merge_key": (
        "kinematics:\n  shoulder:\n    <<: {x: 0, y: 0, z: 0, roll: 0, pitch: 0, yaw: 0}\n",
        r"line 3: a merge key \(<<\)",
    ),
    "a_list_of_a_million_characters": (
        _shoulder("[" + "1, " * 300_000 + "1]"),
        rf"line 2: more than {MAX_YAML_NODES} values",
    ),
    "a_list_of_500_items": (
        _shoulder("[" + "1, " * 500 + "1]"),
        r"kinematics\.shoulder\.x: expected a number, got a list of 501 items$",
    ),
    "a_string_of_a_million_characters": (
        _shoulder('"' + "x" * 1_000_000 + '"'),
        r"kinematics\.shoulder\.x: expected a number, got 'x{30,}'… \(1000000 characters\)$",
    ),
    "a_tag_of_a_million_characters": (
        _shoulder("!" + "t" * 1_000_000 + " 1"),
        r"line 2: could not determine a constructor for the tag .{0,120}…$",
    ),
}


@pytest.mark.parametrize("case", sorted(HOSTILE_YAML))
def test_a_hostile_yaml_is_one_line_in_bounded_time_and_memory(tmp_path: Path, case: str):
    text, refusal = HOSTILE_YAML[case]
    path = tmp_path / "robot_calibration.yaml"
    path.write_text(text, encoding="utf-8")
    assert path.stat().st_size <= 1 << 20  # every case fits the reader's size limit
    code = (
        "import sys; from fkcheck.calibration.ur_files import read_ur_calibration as r\n"
        "try:\n    r(sys.argv[1])\n"
        "except Exception as exc:\n    print(type(exc).__name__, exc, sep='|')\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(path)],
        capture_output=True, text=True, preexec_fn=_limited, timeout=TIME_BOUND_S,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    kind, _, message = done.stdout.rstrip("\n").partition("|")
    assert kind == "CalibrationError", done.stdout[-2000:]
    assert "\n" not in message
    assert len(message) < 400 + len(str(path)), message[:600]
    assert message.startswith(f"{path}: ")
    assert re.search(refusal, message), message


def test_the_alias_bomb_is_one_line_and_exit_2_on_the_command_line(tmp_path: Path, capfd):
    path = tmp_path / "robot_calibration.yaml"
    path.write_text(alias_bomb(), encoding="utf-8")
    assert len(alias_bomb()) < 600
    with deadline(TIME_BOUND_S):
        code = main(["calibration", "ur5e", str(path), "-o", str(tmp_path / "robot.toml")])
    _, err = capfd.readouterr()
    assert code == 2
    assert err.count("\n") == 1, err
    assert "anchor or alias" in err
    assert not (tmp_path / "robot.toml").exists()


# --------------------------------------------------------------------------- keys given twice


def _robot_yaml(tmp_path: Path) -> Path:
    table = composed(load_model("ur10e").joints, "ur10e-test-b")
    return write_yaml(tmp_path / "robot_calibration.yaml", table)


def test_the_robot_yaml_is_read(tmp_path: Path):
    cal = read_ur_calibration(_robot_yaml(tmp_path))
    assert cal.links is not None
    assert len(cal.links) == 6


@pytest.mark.parametrize(
    ("edit", "refusal"),
    [
        # `shoulder: z` twice: the second, a centimetre more, was taken silently
        (lambda t: t.replace("    z: ", "    z: 0.01\n    z: ", 1),
         r"line 6: key 'z' given twice \(first on line 5\)"),
        # a link mapping twice: the second shoulder was taken silently
        (lambda t: t.replace("  hash:", "  shoulder: {x: 0, y: 0, z: 0, roll: 0, pitch: 0, "
                                        "yaw: 0}\n  hash:"),
         r"line 44: key 'shoulder' given twice \(first on line 2\)"),
        (lambda t: t + "kinematics: {}\n", r"key 'kinematics' given twice \(first on line 1\)"),
        (lambda t: t.replace("  hash: calib_12345", "  hash: calib_1\n  hash: calib_2"),
         r"key 'hash' given twice"),
        # equal as values, though written differently
        (lambda t: t.replace("    x: ", "    0x1: 0\n    1: 0\n    x: ", 1),
         r"key '1' given twice"),
    ],
    ids=["a_number", "a_link", "the_top_key", "the_hash", "equal_values"],
)  # fmt: skip
def test_a_key_given_twice_is_refused(tmp_path: Path, edit, refusal):
    path = _robot_yaml(tmp_path)
    path.write_text(edit(path.read_text(encoding="utf-8")), encoding="utf-8")
    with pytest.raises(CalibrationError, match=refusal) as info:
        read_ur_calibration(path)
    assert "\n" not in str(info.value)


# --------------------------------------------------------------------------- the fit's frames
# (issue 30, item 6) The fit was measured between the nominal model's own [check] pair:
# with `tool0 → tool0`, or a pair spanning joint 1 only, a UR10 table onto a UR5 and a
# table in millimetres "fitted" by 0 mm, were written, and lint of them was clean.


def _nominal_with_pair(tmp_path: Path, frame_from: str, frame_to: str) -> Path:
    from fkcheck.model.read import bundled_model_paths

    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    old = '[check]\nfrom = "base"\nto = "tool0"'
    assert old in text
    path = tmp_path / "ur5-nominal.toml"
    path.write_text(text.replace(old, f'[check]\nfrom = "{frame_from}"\nto = "{frame_to}"'))
    return path


def _ur10_table() -> Table:
    return composed(load_model("ur10").joints, "ur10-test")


def _ur5_in_millimetres() -> Table:
    js = load_model("ur5").joints
    return Table(
        tuple(j.theta for j in js), tuple(j.a * 1e3 for j in js), tuple(j.d * 1e3 for j in js),
        tuple(j.alpha for j in js),
    )  # fmt: skip


PAIRS = {"tool0_to_tool0": ("tool0", "tool0"), "joint_1_only": ("world", "base_link")}
TABLES = {
    "ur10_onto_ur5": (_ur10_table, r"431 mm"),
    "millimetres": (_ur5_in_millimetres, r"1\.03e\+03 m"),
}


@pytest.mark.parametrize("pair", sorted(PAIRS))
@pytest.mark.parametrize("table", sorted(TABLES))
def test_a_table_that_does_not_fit_is_refused_whatever_the_nominal_pair(
    tmp_path: Path, capfd, pair: str, table: str
):
    nominal = _nominal_with_pair(tmp_path, *PAIRS[pair])
    make, size = TABLES[table]
    info = write_kinematics_info(tmp_path / "info.log", make(), 2)
    out = tmp_path / "robot.toml"
    with deadline(TIME_BOUND_S):
        code = main(["calibration", str(nominal), str(info), "-o", str(out)])
    _, err = capfd.readouterr()
    assert code == 2, err
    assert err.count("\n") == 1, err
    assert re.search(
        rf"does not fit ur5: the calibrated DH frame 6 is up to {size} .* relative to DH frame 0",
        err,
    ), err
    assert not out.exists()


@pytest.mark.parametrize("pair", sorted(PAIRS))
@pytest.mark.parametrize("table", sorted(TABLES))
def test_lint_measures_the_fit_between_the_dh_frames_whatever_the_pair(
    tmp_path: Path, pair: str, table: str
):
    """A calibrated model made before the fix (or by hand) is no calibration to lint."""
    from dataclasses import replace

    from fkcheck.calibration.lint import lint_calibrated
    from fkcheck.model.types import CalibrationSpec

    nominal_path = _nominal_with_pair(tmp_path, *PAIRS[pair])
    nominal = load_model(nominal_path)
    values = TABLES[table][0]()
    joints = tuple(
        replace(j, theta=values.theta[i], a=values.a[i], d=values.d[i], alpha=values.alpha[i])
        for i, j in enumerate(nominal.joints)
    )
    spec = CalibrationSpec(
        nominal=nominal_path.name, file="info.log", form="KinematicsInfo", sha256="0" * 64,
        identity="", status=2,
    )  # fmt: skip
    model = replace(nominal, joints=joints, calibration=spec, path=tmp_path / "robot.toml")
    findings, measured = lint_calibrated(model)
    assert not measured
    misfit = [f for f in findings if f.rule == "calibration"]
    assert len(misfit) == 1, findings
    assert re.search(r"moves DH frame 6 up to .* relative to DH frame 0", misfit[0].message)
    assert {f.rule for f in findings} - {"calibration"}  # the unit rules apply again


def test_the_dh_chain_effect_is_the_tables_composed_by_hand():
    """DH frame 0 → 6 of both tables, against the test's own composition of them."""
    from dataclasses import replace

    from fkcheck.calibration.effect import dh_chain_effect

    nominal = load_model("ur5")
    ur10 = _ur10_table()
    calibrated = replace(
        nominal,
        joints=tuple(
            replace(j, theta=ur10.theta[i], a=ur10.a[i], d=ur10.d[i], alpha=ur10.alpha[i])
            for i, j in enumerate(nominal.joints)
        ),
    )
    q = np.random.default_rng(11).uniform(-np.pi, np.pi, (50, 6))
    effect = dh_chain_effect(calibrated, nominal, q)
    ours, theirs = fk(ur10, q), fk(_table_of(nominal), q)
    position = np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=1)
    assert effect.max_position_m == pytest.approx(position.max(), abs=1e-12)
    assert (effect.frame_from, effect.frame_to) == ("DH frame 0", "DH frame 6")


def _table_of(model) -> Table:
    js = model.joints
    return Table(
        tuple(j.theta for j in js), tuple(j.a for j in js), tuple(j.d for j in js),
        tuple(j.alpha for j in js),
    )  # fmt: skip


# --------------------------------------------------------------------------- [calibration] nominal
# It named any path (absolute, ../), and the first key of that file was echoed in the
# error. It is held to the calibrated model's folder now, and nothing of a file outside
# it is read or quoted.

SECRET = "s3cr3t_first_key_of_a_foreign_file"
CONF = Path(__file__).parents[1] / "data" / "calibration" / "ur10e-test-b" / "calibration.conf"


@pytest.fixture
def calibrated_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capfd) -> Path:
    """``m/robot.toml`` calibrated from ur10e, and a foreign file beside ``m/``."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "m").mkdir()
    (tmp_path / "foreign.toml").write_text(f"{SECRET} = 1\n", encoding="utf-8")
    (tmp_path / "m" / "plain").write_text(f"{SECRET} = 1\n", encoding="utf-8")
    assert main(["calibration", "ur10e", str(CONF), "-o", "m/robot.toml"]) == 0
    capfd.readouterr()
    return tmp_path


RELATIVE = r"named relative to the calibrated model's folder"
NOMINALS = {
    "climbs_out": ("../foreign.toml", RELATIVE + r", without '\.\.'"),
    "absolute": ("{tmp}/foreign.toml", RELATIVE),
    "symbolic_link_out": ("link.toml", r"leads outside the calibrated model's folder"),
    "a_file_named_like_a_model": ("plain", r"'plain' is no bundled model \(.*\) and no model"),
    "bundled_climbing_out": ("fkcheck:../../foreign.toml", r"fkcheck: path names a file bundled"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(NOMINALS))
@pytest.mark.parametrize("command", ["check", "lint"])
def test_a_nominal_outside_the_models_folder_is_refused_unread(
    calibrated_dir, capfd, case, command
):
    ref, refusal = NOMINALS[case]
    (calibrated_dir / "m" / "link.toml").symlink_to(calibrated_dir / "foreign.toml")
    model = calibrated_dir / "m" / "robot.toml"
    text = model.read_text(encoding="utf-8")
    assert 'nominal = "ur10e"' in text
    edited = calibrated_dir / "m" / "edited.toml"
    ref = ref.replace("{tmp}", str(calibrated_dir))
    edited.write_text(text.replace('nominal = "ur10e"', f'nominal = "{ref}"'), encoding="utf-8")
    with deadline(60.0):
        code = main([command, str(edited)])
    out, err = capfd.readouterr()
    assert SECRET not in out + err
    assert "Traceback" not in err
    if command == "check":
        assert code == 2
        assert err.count("\n") == 1, err
        assert re.search(rf"edited\.toml: calibration\.nominal: .*{refusal}", err), err
    else:  # lint says it, and holds the joints to every rule
        assert code == 1
        assert re.search(rf"warning \[calibration\]: .*{refusal}", out), out


def test_a_nominal_in_the_models_folder_is_read(calibrated_dir, capfd):
    import shutil

    from fkcheck.model.read import bundled_model_paths

    shutil.copy(bundled_model_paths()["ur10e"], calibrated_dir / "m" / "nominal.toml")
    model = calibrated_dir / "m" / "robot.toml"
    text = model.read_text(encoding="utf-8").replace(
        'nominal = "ur10e"', 'nominal = "nominal.toml"'
    )
    model.write_text(text, encoding="utf-8")
    assert main(["lint", str(model)]) == 0
    out, _ = capfd.readouterr()
    assert "calibrated from nominal.toml" in out


def test_calibration_refuses_to_write_a_nominal_it_could_not_read_back(calibrated_dir, capfd):
    import shutil

    from fkcheck.model.read import bundled_model_paths

    shutil.copy(bundled_model_paths()["ur10e"], calibrated_dir / "nominal.toml")
    code = main(["calibration", "nominal.toml", str(CONF), "-o", "m/again.toml"])
    _, err = capfd.readouterr()
    assert code == 2
    assert err.count("\n") == 1, err
    assert "the nominal model is outside m, where the calibrated model goes" in err
    assert not (calibrated_dir / "m" / "again.toml").exists()
    # beside it, the same call writes the model, and its check reads the nominal model
    assert main(["calibration", "nominal.toml", str(CONF), "-o", "again.toml"]) == 0
    assert 'nominal = "nominal.toml"' in (calibrated_dir / "again.toml").read_text()


# --------------------------------------------------------------------------- one screen, two places
# A calibrated model's YAML holding "${…}" (which `fkcheck calibration` refuses) was
# evaluated as an expression at check time by the description's xacro: a YAML z of
# "${0.18053981171425867 + 0.001}" moved the shoulder by 1 mm and the check compared that.

YAML = CONF.parent / "robot_calibration.yaml"
Z1 = "    z: 0.18053981171425867\n"


@pytest.fixture
def with_yaml(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capfd) -> Path:
    """``robot.toml``: ur10e with calibration.conf; its description reads robot_calibration.yaml."""
    import shutil

    monkeypatch.chdir(tmp_path)
    for source in (CONF, YAML):
        shutil.copy(source, tmp_path / source.name)
    argv = [
        "calibration",
        "ur10e",
        "calibration.conf",
        "robot_calibration.yaml",
        "-o",
        "robot.toml",
    ]
    assert main(argv) == 0
    capfd.readouterr()
    assert '"kinematics_params" = "robot_calibration.yaml"' in (tmp_path / "robot.toml").read_text()
    return tmp_path


@pytest.mark.parametrize(
    "value",
    ['"${0.18053981171425867 + 0.001}"', '"${0.5}"', "'$(eval 0.5)'", "[0.18]", "{a: 1}"],
)
def test_the_check_screens_the_description_yaml_as_calibration_does(with_yaml: Path, capfd, value):
    yaml = with_yaml / "robot_calibration.yaml"
    text = yaml.read_text(encoding="utf-8")
    assert text.count(Z1) == 1
    yaml.write_text(text.replace(Z1, f"    z: {value}\n"), encoding="utf-8")
    with deadline(120.0):
        refused = main(["calibration", "ur10e", "robot_calibration.yaml"])
    _, at_calibration = capfd.readouterr()
    assert refused == 2
    with deadline(120.0):
        code = main(["check", "robot.toml", "--against", "pinocchio-urdf"])
    out, err = capfd.readouterr()
    assert code == 2, out
    assert err.count("\n") == 1, err
    # the same refusal, naming the same field, at both places
    problem = at_calibration.strip().removeprefix("fkcheck: error: ")
    assert problem.startswith("robot_calibration.yaml: kinematics.shoulder.z: expected a number")
    assert err.strip() == (
        f"fkcheck: error: {problem} (the kinematics_params of ur10e-calibrated's description)"
    )


def test_the_check_screens_it_in_the_api_too(with_yaml: Path):
    from fkcheck.backends.registry import make_backend
    from fkcheck.engine.runner import run_check

    yaml = with_yaml / "robot_calibration.yaml"
    yaml.write_text(yaml.read_text().replace(Z1, '    z: "${0.5}"\n'), encoding="utf-8")
    model = load_model(with_yaml / "robot.toml")
    with pytest.raises(
        CalibrationError, match=r"kinematics\.shoulder\.z: expected a number, got '\$\{0\.5\}'"
    ):
        run_check(model, [make_backend("rtb-dh")], samples=8)


def test_a_right_yaml_is_still_read_and_compared(with_yaml: Path, capfd):
    with deadline(180.0):
        code = main(["check", "robot.toml", "--against", "pinocchio-urdf", "--tol-pos", "1e-4",
                     "--tol-rot", "1e-4"])  # fmt: skip
    out, err = capfd.readouterr()
    assert code == 0, out + err
    assert "pinocchio-urdf" in out
