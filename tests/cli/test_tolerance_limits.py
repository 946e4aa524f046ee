"""Limits without limits are refused wherever they come in: one line, exit 2 (issue 20, item 5).

``--tol-pos 1000 --tol-rot 10`` (or the same in a model's ``[check]`` or in
``[tool.fkcheck]``) accepted any table; a rotation tolerance of π or more
accepts every rotation; ``--tol-jacobian 1e300`` passed an all-zero Jacobian.
Each is refused before anything runs, naming the flag, field or file, the value
and the range (:mod:`fkcheck.core.tolerances`).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from fkcheck import check
from fkcheck.backends.registry import make_backend
from fkcheck.cli.main import main
from fkcheck.diagnose import diagnose
from fkcheck.engine.runner import run_check
from fkcheck.errors import FkcheckError, ToleranceError
from fkcheck.model.read import bundled_model_paths, load_model
from fkcheck.testing import assert_fk_matches

POS = r"must be > 0 and at most 0\.01 m \(1 cm: a looser check cannot tell a wrong link length "
POS += r"from a right one\)"
ROT = r"must be > 0 and at most 0\.1 rad \(5\.7°: a looser one lets a wrong joint offset through, "
ROT += r"and at π accepts every rotation\)"
JAC = r"must be > 0 and at most 0\.01 m/rad and rad/rad \(.*\)"


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    out, err = capsys.readouterr()
    assert out == ""  # nothing ran
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


@pytest.mark.parametrize(
    ("flags", "line"),
    [
        (["--tol-pos", "1000"], rf"--tol-pos: {POS}, got 1000"),
        (["--tol-pos", "0.0100001"], rf"--tol-pos: {POS}, got 0\.0100001"),
        (["--tol-pos", "nan"], rf"--tol-pos: {POS}, got nan"),
        (["--tol-pos", "0"], rf"--tol-pos: {POS}, got 0"),
        (["--tol-rot", "10"], rf"--tol-rot: {ROT}, got 10"),
        (["--tol-rot", "3.1416"], rf"--tol-rot: {ROT}, got 3\.1416"),
        (["--tol-rot", "inf"], rf"--tol-rot: {ROT}, got inf"),
        (["--tol-jacobian", "1e300"], rf"--tol-jacobian: {JAC}, got 1e\+300"),
    ],
)
def test_a_flag_beyond_its_bound_is_one_line_and_exit_2(capsys, flags, line):
    assert main(["check", "ur5", "--against", "rtb-dh", "--samples", "2", *flags]) == 2
    assert re.fullmatch(f"fkcheck: error: {line}", _one_line(capsys))


@pytest.mark.parametrize(
    ("flags", "line"),
    [
        (["--tol-pos", "1000"], rf"--tol-pos: {POS}, got 1000"),
        (["--tol-rot", "10"], rf"--tol-rot: {ROT}, got 10"),
    ],
)
def test_diagnose_flags_too(capsys, flags, line):
    assert main(["diagnose", "ur5", "--against", "rtb-dh", *flags]) == 2
    assert re.fullmatch(f"fkcheck: error: {line}", _one_line(capsys))


def test_the_loosest_allowed_flags_run(capsys):
    argv = ["check", "ur5", "--against", "rtb-dh", "--samples", "2", "--tol-pos", "0.01",
            "--tol-rot", "0.1", "--tol-jacobian", "0.01"]  # fmt: skip
    assert main(argv) == 0, capsys.readouterr().err


@pytest.mark.parametrize(
    ("line", "field", "pattern"),
    [
        ("tol_pos_m = 1000", "check.tol_pos_m", rf"{POS}, got 1000"),
        ("tol_rot_rad = 10", "check.tol_rot_rad", rf"{ROT}, got 10"),
        ("tol_jacobian = 1e300", "check.tol_jacobian", rf"{JAC}, got 1e\+300"),
    ],
)
def test_a_models_check_beyond_its_bound_is_one_line_and_exit_2(tmp_path, capsys, line, field,
                                                                pattern):  # fmt: skip
    path = tmp_path / "loose.toml"
    path.write_text(bundled_model_paths()["ur5"].read_text(encoding="utf-8") + line + "\n")
    assert main(["check", str(path), "--against", "rtb-dh", "--samples", "2"]) == 2
    expected = f"fkcheck: error: {re.escape(str(path))}: {re.escape(field)}: {pattern}"
    assert re.fullmatch(expected, _one_line(capsys))


@pytest.mark.parametrize(
    ("line", "pattern"),
    [
        ("tol_pos_m = 1000", rf"tool\.fkcheck\.tol_pos_m: {POS}, got 1000"),
        ("tol_rot_rad = 10", rf"tool\.fkcheck\.tol_rot_rad: {ROT}, got 10"),
        ("tol_jacobian = 1e300", rf"tool\.fkcheck\.tol_jacobian: {JAC}, got 1e\+300"),
    ],
)
def test_a_pyproject_in_a_parent_directory_beyond_its_bound_is_named(
    tmp_path, monkeypatch, capsys, line, pattern
):
    (tmp_path / "pyproject.toml").write_text(f"[tool.fkcheck]\n{line}\n", encoding="utf-8")
    deep = tmp_path / "a" / "b"
    deep.mkdir(parents=True)
    monkeypatch.chdir(deep)
    assert main(["check", "ur5", "--against", "rtb-dh", "--samples", "2"]) == 2
    where = re.escape(str((tmp_path / "pyproject.toml").resolve()))
    assert re.fullmatch(f"fkcheck: error: {where}: {pattern}", _one_line(capsys))


def test_a_bad_flag_over_a_good_pyproject_is_named_as_the_flag(tmp_path, monkeypatch, capsys):
    # A valid pyproject value is taken; a bad flag on top of it is named as the flag.
    (tmp_path / "pyproject.toml").write_text("[tool.fkcheck]\ntol_pos_m = 1e-5\n", "utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["check", "ur5", "--against", "rtb-dh", "--samples", "2", "--tol-rot", "4"]) == 2
    assert re.fullmatch(rf"fkcheck: error: --tol-rot: {ROT}, got 4", _one_line(capsys))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"tol_pos_m": 1000.0}, rf"^tol_pos_m: {POS}, got 1000$"),
        ({"tol_pos_m": 0.0}, rf"^tol_pos_m: {POS}, got 0$"),  # not silently the default
        ({"tol_rot_rad": 10.0}, rf"^tol_rot_rad: {ROT}, got 10$"),
        ({"tol_rot_rad": math.pi}, rf"^tol_rot_rad: {ROT}, got 3\.14159$"),
        ({"tol_jacobian": 1e300}, rf"^tol_jacobian: {JAC}, got 1e\+300$"),
        ({"tol_jacobian": 1e300, "jacobian": False}, r"^tol_jacobian: "),  # refused even unused
    ],
)
def test_the_python_api_refuses_them(kwargs, match):
    with pytest.raises(ToleranceError, match=match) as info:
        check("ur5", ["rtb-dh"], samples=2, diagnose=False, **kwargs)
    assert isinstance(info.value, FkcheckError)
    assert isinstance(info.value, ValueError)


def test_the_engine_and_the_diagnosis_refuse_them_too():
    ur5 = load_model("ur5")
    with pytest.raises(ToleranceError, match=rf"^tol_pos_m: {POS}, got 1000$"):
        run_check(ur5, [make_backend("rtb-dh")], samples=2, tol_pos_m=1000.0)
    with pytest.raises(ToleranceError, match=rf"^tol_rot_rad: {ROT}, got 10$"):
        run_check(ur5, [make_backend("rtb-dh")], samples=2, tol_rot_rad=10.0)
    with pytest.raises(ToleranceError, match=rf"^tol_rot_rad: {ROT}, got 4$"):
        diagnose(ur5, make_backend("rtb-dh"), samples=2, tol_rot_rad=4.0)


def test_assert_fk_matches_refuses_them():
    with pytest.raises(ToleranceError, match=rf"^tol_pos_m: {POS}, got 1000$"):
        assert_fk_matches("ur5", against="rtb-dh", samples=2, tol_pos_m=1000.0)
    with pytest.raises(ToleranceError, match=rf"^tol_rot_rad: {ROT}, got 10$"):
        assert_fk_matches("ur5", against="rtb-dh", samples=2, tol_rot_rad=10.0)


def test_the_loosest_check_still_fails_a_link_2_cm_off(tmp_path: Path):
    pytest.importorskip("pinocchio")
    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    wrong = tmp_path / "wrong.toml"
    wrong.write_text(text.replace("d = 0.089159", "d = 0.109159", 1), encoding="utf-8")
    assert wrong.read_text(encoding="utf-8") != text
    outcome = check(wrong, ["pinocchio-urdf"], samples=20, tol_pos_m=0.01, tol_rot_rad=0.1,
                    diagnose=False)  # fmt: skip
    assert outcome.verdict == "fail"


FLOOR = r"must be at least 1e-12 {unit} \(a tighter check judges the round-off of float "
FLOOR += r"arithmetic, not the table\), got {got}"


@pytest.mark.parametrize(
    ("flags", "line"),
    [
        (["--tol-pos", "5e-324"], "--tol-pos: " + FLOOR.format(unit="m", got=r"4\.94066e-324")),
        (["--tol-pos", "9.9e-13"], "--tol-pos: " + FLOOR.format(unit="m", got=r"9\.9e-13")),
        (["--tol-rot", "1e-300"], "--tol-rot: " + FLOOR.format(unit="rad", got=r"1e-300")),
        (["--tol-jacobian", "1e-300"],
         "--tol-jacobian: " + FLOOR.format(unit="m/rad and rad/rad", got=r"1e-300")),
    ],
)  # fmt: skip
def test_a_flag_below_the_round_off_is_one_line_and_exit_2(capsys, flags, line):
    # 5e-324 ended in "LinAlgError: SVD did not converge" (issue 31).
    assert main(["check", "ur5", "--against", "rtb-dh", "--samples", "2", *flags]) == 2
    assert re.fullmatch(f"fkcheck: error: {line}", _one_line(capsys))


def test_the_tightest_allowed_flags_run_and_a_right_table_passes(capsys):
    argv = ["check", "ur5", "--against", "rtb-dh", "--samples", "20", "--tol-pos", "1e-12",
            "--tol-rot", "1e-12"]  # fmt: skip
    assert main(argv) == 0, capsys.readouterr().err


@pytest.mark.parametrize(
    ("line", "field", "unit"),
    [("tol_pos_m = 1e-300", "check.tol_pos_m", "m"), ("tol_rot_rad = 1e-300", "check.tol_rot_rad",
                                                      "rad")],
)  # fmt: skip
def test_a_models_check_below_the_round_off_is_one_line(tmp_path, capsys, line, field, unit):
    path = tmp_path / "tight.toml"
    path.write_text(bundled_model_paths()["ur5"].read_text(encoding="utf-8") + line + "\n")
    assert main(["check", str(path), "--against", "rtb-dh", "--samples", "2"]) == 2
    floor = FLOOR.format(unit=unit, got="1e-300")
    assert re.fullmatch(f"fkcheck: error: {re.escape(str(path))}: {field}: {floor}",
                        _one_line(capsys))  # fmt: skip


def test_a_pyproject_below_the_round_off_is_named(tmp_path, monkeypatch, capsys):
    (tmp_path / "pyproject.toml").write_text("[tool.fkcheck]\ntol_pos_m = 1e-300\n", "utf-8")
    monkeypatch.chdir(tmp_path)
    assert main(["check", "ur5", "--against", "rtb-dh", "--samples", "2"]) == 2
    where = re.escape(str((tmp_path / "pyproject.toml").resolve()))
    floor = FLOOR.format(unit="m", got="1e-300")
    assert re.fullmatch(f"fkcheck: error: {where}: tool\\.fkcheck\\.tol_pos_m: {floor}",
                        _one_line(capsys))  # fmt: skip


def test_the_python_api_refuses_a_tolerance_below_the_round_off():
    with pytest.raises(ToleranceError, match=r"^tol_pos_m: must be at least 1e-12 m "):
        check("ur5", ["rtb-dh"], samples=2, diagnose=False, tol_pos_m=5e-324)
    with pytest.raises(ToleranceError, match=r"^tol_rot_rad: must be at least 1e-12 rad "):
        assert_fk_matches("ur5", against="rtb-dh", samples=2, tol_rot_rad=1e-300)


def test_the_floor_grows_with_the_models_reach(tmp_path, capsys):
    # A kilometre-long arm rounds off a hundred times more than a 10 m one.
    path = tmp_path / "long.toml"
    path.write_text('name = "long"\nconvention = "standard"\n[[joint]]\nname = "j1"\n'
                    'a = 600.0\nalpha = 0\nd = 300.0\n', encoding="utf-8")  # fmt: skip
    argv = ["check", str(path), "--against", "rtb-dh", "--samples", "20"]
    assert main([*argv, "--tol-pos", "8e-11"]) == 2
    err = capsys.readouterr().err  # after the check's header: the model's reach is known then
    assert err.splitlines() == [
        "fkcheck: error: tol_pos_m: must be at least 9e-11 m for a model whose lengths add up "
        "to 900 m (a tighter check judges the round-off of float arithmetic, not the table), "
        "got 8e-11"
    ]
    assert main([*argv, "--tol-pos", "9e-11"]) == 0, capsys.readouterr().err
