"""`fkcheck calibration` as a UR user runs it, and what `fkcheck check` then shows."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from fkcheck.model.read import load_model
from fkcheck.report.markdown import escape_markdown
from tests.calibration.ur_test_data import composed, write_conf, write_kinematics_info


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_calibration_writes_the_model_and_says_what_it_changes(tmp_path, capsys):
    conf = write_conf(tmp_path / "calibration.conf", "ur10-test")
    out_file = tmp_path / "models" / "robot.toml"
    out_file.parent.mkdir()
    code, out, err = run(capsys, "calibration", "ur10", conf, "-o", out_file, "--name", "cell3")
    assert code == 0, err
    first = out.splitlines()[0]
    assert first.startswith(
        "fkcheck calibration: calibration calibration.conf vs nominal ur10 "
        "(DH frame 0 → DH frame 6, "
    )
    assert "position max 7.8" in first
    assert "95th percentile" in first
    assert "largest at q = [" in first
    assert f"wrote {out_file}; check it: fkcheck check {out_file}" in out
    model = load_model(out_file)
    assert model.name == "cell3"
    assert model.calibration is not None
    assert model.calibration.file == "../calibration.conf"
    assert model.calibration.status == 2
    assert model.urdf is None  # the nominal description would differ by the calibration


def test_check_of_a_calibrated_model_shows_the_effect_in_every_format(tmp_path, capsys):
    nominal = load_model("ur10e")
    info = write_kinematics_info(tmp_path / "info.log", composed(nominal.joints, "ur10e-test-b"), 2)
    model = tmp_path / "robot.toml"
    assert run(capsys, "calibration", "ur10e", info, "-o", model)[0] == 0
    outputs = {k: tmp_path / f"r.{k}" for k in ("json", "html", "junit")}
    summary = tmp_path / "summary.md"
    code, out, err = run(
        capsys, "check", model, "--samples", "64", "--against", "rtb-dh",
        "--json", outputs["json"], "--html", outputs["html"], "--junit", outputs["junit"],
        "--summary", summary,
    )  # fmt: skip
    assert code == 0, err
    line = next(x for x in out.splitlines() if x.startswith("calibration info.log vs nominal"))
    assert "position max 3." in line
    data = json.loads(outputs["json"].read_text())["calibration"]
    assert data["nominal"] == "ur10e"
    assert data["line"] == line
    assert 3e-3 < data["position_m"]["max"] < 4e-3
    assert data["position_m"]["median"] <= data["position_m"]["p95"] <= data["position_m"]["max"]
    assert line in outputs["html"].read_text().replace("&gt;", ">")
    assert line in outputs["junit"].read_text()
    assert escape_markdown(line) in summary.read_text()
    # A linearised table (d2 of 439 m, α a few 1e-4 off 90°) is no lint finding.
    verdict = next(x for x in out.splitlines() if x.startswith("verdict:"))
    assert "lint" not in verdict
    assert json.loads(outputs["json"].read_text())["lint"] == []


def test_lint_of_a_calibrated_model_says_which_rules_its_joints_are_not_held_to(tmp_path, capsys):
    conf = write_conf(tmp_path / "calibration.conf", "ur10e-test-a")  # θ3 of 7.1 rad
    model = tmp_path / "robot.toml"
    assert run(capsys, "calibration", "ur10e", conf, "-o", model)[0] == 0
    code, out, _ = run(capsys, "lint", model)
    assert code == 0
    assert out.splitlines() == [
        f"{model}: clean (6 joints, standard DH)",
        f"{model}: calibrated from ur10e: its joints' measured values are not held to the "
        "degrees, length, published, rounded-angle, twist rules (lint ur10e for those)",
    ]


def test_a_calibrated_model_edited_in_millimetres_is_no_calibration_and_lint_says_so(
    tmp_path, capsys
):
    conf = write_conf(tmp_path / "calibration.conf", "ur10e-test-a")
    model = tmp_path / "robot.toml"
    assert run(capsys, "calibration", "ur10e", conf, "-o", model)[0] == 0
    # wrist_2's d (~0.1198 m) typed in millimetres: [calibration] must not hide it.
    text = model.read_text()
    d5 = load_model(model).joints[4].d
    assert text.count(f"d = {d5!r}\n") == 1
    model.write_text(text.replace(f"d = {d5!r}\n", f"d = {d5 * 1000!r}\n"))
    code, out, _ = run(capsys, "lint", model)
    assert code == 1
    assert f"{model}: joint[4].d (wrist_2): warning [length]: " in out
    assert f"{model}: warning [calibration]: the table moves DH frame 6 up to " in out
    assert "not held to" not in out
    code, out, _ = run(capsys, "check", model, "--samples", "20")
    verdict = next(x for x in out.splitlines() if x.startswith("verdict:"))
    assert "lint: " in verdict


def test_a_hand_written_calibration_whose_nominal_does_not_load_exempts_nothing(tmp_path):
    from fkcheck.calibration.lint import lint_calibrated

    text = Path(load_model("ur5").path).read_text()
    text += (
        '\n[calibration]\nnominal = "no-such-model"\nfile = "calibration.conf"\n'
        f'form = "calibration.conf"\nsha256 = "{"0" * 64}"\n'
    )
    model = tmp_path / "robot.toml"
    model.write_text(text.replace("d = 0.089159", "d = 89.159", 1))
    findings, measured = lint_calibrated(load_model(model))
    assert not measured
    assert [(f.rule, f.field) for f in findings if f.rule == "length"] == [("length", "joint[0].d")]
    assert [f.rule for f in findings][-1] == "calibration"


def test_a_calibrated_model_naming_itself_as_its_nominal_exempts_nothing(tmp_path, capsys):
    conf = write_conf(tmp_path / "calibration.conf", "ur10e-test-a")
    model = tmp_path / "robot.toml"
    assert run(capsys, "calibration", "ur10e", conf, "-o", model)[0] == 0
    text = model.read_text().replace('nominal = "ur10e"', 'nominal = "robot.toml"')
    d5 = load_model(model).joints[4].d
    model.write_text(text.replace(f"d = {d5!r}\n", f"d = {d5 * 1000!r}\n"))
    code, out, _ = run(capsys, "lint", model)
    assert code == 1
    assert f"{model}: joint[4].d (wrist_2): warning [length]: " in out
    assert "warning [calibration]: [calibration] nominal 'robot.toml' is a calibrated" in out


def test_a_calibrated_model_is_no_nominal_model_to_calibrate_again(tmp_path, capsys):
    conf = write_conf(tmp_path / "calibration.conf", "ur5e-small")  # 3.4 mm: twice still fits
    once = tmp_path / "once.toml"
    assert run(capsys, "calibration", "ur5e", conf, "-o", once)[0] == 0
    code, out, err = run(capsys, "calibration", once, conf, "-o", tmp_path / "twice.toml")
    assert (code, out) == (2, "")
    assert "it is calibrated already (from ur5e, calibration.conf); give its nominal" in err
    assert not (tmp_path / "twice.toml").exists()


@pytest.mark.parametrize(
    ("files", "match"),
    [
        (["missing.conf"], "missing.conf: "),
        (["a.conf", "b.conf"], "b.conf: a second calibration table"),
        (["bad.conf"], r"bad.conf: \[mounting\] has no delta_a"),
    ],
)
def test_bad_calibration_input_is_one_line_and_exit_2(tmp_path, capsys, monkeypatch, files, match):
    monkeypatch.chdir(tmp_path)
    write_conf(tmp_path / "a.conf", "ur10-test")
    write_conf(tmp_path / "b.conf", "ur10-test")
    (tmp_path / "bad.conf").write_text("[mounting]\ndelta_theta = [0,0,0,0,0,0]\n")
    code, _out, err = run(capsys, "calibration", "ur10", *files, "-o", "out.toml")
    assert code == 2
    assert len(err.strip().splitlines()) == 1, err
    assert __import__("re").search(match, err), err
    assert not Path("out.toml").exists()


def test_a_calibration_of_another_type_is_refused_and_nothing_written(tmp_path, capsys):
    conf = write_conf(tmp_path / "calibration.conf", "ur10e-test-a")
    code, _out, err = run(capsys, "calibration", "ur3e", conf, "-o", tmp_path / "out.toml")
    assert code == 2
    assert "does not fit ur3e" in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out.toml").exists()
