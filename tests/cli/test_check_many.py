"""fkcheck check over many models: files, directories, [tool.fkcheck], one table, one exit code."""

from __future__ import annotations

import json
import shutil

import pytest

from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths

#: One fast URDF backend: enough to verify the table and to catch a wrong α.
FAST = ["--against", "pinocchio-urdf", "--samples", "4"]


@pytest.fixture
def repo(tmp_path, monkeypatch):
    """A user's repository: robots/good.toml (the bundled UR5), robots/bad.toml (α4 flipped)."""
    robots = tmp_path / "robots"
    robots.mkdir()
    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    (robots / "good.toml").write_text(text, encoding="utf-8")
    lines = text.splitlines(keepends=True)
    wrist_1 = lines.index('name = "wrist_1"\n')
    assert lines[wrist_1 + 2] == "alpha = 90\n"
    lines[wrist_1 + 2] = "alpha = -90\n"
    (robots / "bad.toml").write_text("".join(lines), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_a_directory_is_one_run_one_table_one_exit_code(repo, capsys):
    out = repo / "reports"
    summary = repo / "summary.md"
    argv = ["check", "robots", *FAST, "--out-dir", str(out), "--summary", str(summary)]
    assert main(argv) == 1
    stdout = capsys.readouterr().out
    table = [line for line in stdout.splitlines() if line.startswith("│ robots/")]
    assert len(table) == 2
    assert table[0].startswith("│ robots/bad.toml  │ fail ")
    assert table[1].startswith("│ robots/good.toml │ pass ")
    assert "robots/bad.toml: pinocchio-urdf: " in stdout
    assert "fkcheck: 1 of 2 models pass; reports in" in stdout
    tally = stdout[stdout.index("fkcheck: 1 of 2 models pass") :].splitlines()[1:]
    assert tally == [
        "fkcheck: table verified independently: 1 (robots/good.toml)",
        "fkcheck: table FAILED against independent evidence: 1 (robots/bad.toml)",
        "fkcheck: implementation only, table not checked: 0",
    ]
    assert {p.name for p in out.iterdir()} == {
        "index.html", "bad.html", "bad.json", "bad.junit.xml",
        "good.html", "good.json", "good.junit.xml",
    }  # fmt: skip
    assert json.loads((out / "bad.json").read_text())["verdict"] == "fail"
    good = json.loads((out / "good.json").read_text())
    assert good["verdict"] == "pass"
    assert good["samples"] == 4
    index = (out / "index.html").read_text(encoding="utf-8")
    assert '<a href="good.html">' in index
    assert '<a href="bad.html">' in index
    assert summary.read_text(encoding="utf-8").startswith("## fkcheck: 2 models")


def test_only_good_files_pass(repo, capsys):
    assert main(["check", "robots/good.toml", "ur3", *FAST, "--out-dir", "r"]) == 0
    assert "fkcheck: 2 of 2 models pass" in capsys.readouterr().out


def test_one_file_is_today_s_single_model_output(repo, capsys):
    assert main(["check", "robots/good.toml", *FAST]) == 0
    out = capsys.readouterr().out
    assert "verdict: pass" in out
    assert "models pass" not in out


def test_project_gives_the_models_and_defaults_and_flags_win(repo, capsys):
    (repo / "pyproject.toml").write_text(
        '[tool.fkcheck]\nmodels = ["robots/good.toml"]\nsamples = 3\nseed = 5\n'
        'against = ["pinocchio-urdf"]\n',
        encoding="utf-8",
    )
    assert main(["check", "--out-dir", "r"]) == 0
    doc = json.loads((repo / "r" / "good.json").read_text())
    assert (doc["samples"], doc["seed"]) == (3, 5)
    assert [b["name"] for b in doc["backends"]] == ["pinocchio-urdf"]
    assert main(["check", "--out-dir", "r2", "--samples", "2"]) == 0
    doc = json.loads((repo / "r2" / "good.json").read_text())
    assert (doc["samples"], doc["seed"]) == (2, 5)
    assert "--samples 2 --seed 5" in doc["command"]


def test_a_bags_settings_from_the_project_are_in_each_models_command_line(repo, capsys):
    # Against a recording (here an RTDE CSV, which they leave alone), as they were given.
    import numpy as np

    from fkcheck import load_model
    from tests.rtde_cases import write_rtde_csv

    q = np.random.default_rng(7).uniform(-2.0, 2.0, (5, 6))
    write_rtde_csv(repo / "rec.csv", load_model(str(repo / "robots" / "good.toml")), q)
    (repo / "pyproject.toml").write_text(
        '[tool.fkcheck]\nmodels = ["robots/good.toml"]\nsamples = 3\n'
        'against = ["poses:rec.csv"]\nbag_tf = "/ur/tf"\nbag_stamp_tolerance = 0.002\n',
        encoding="utf-8",
    )
    assert main(["check", "--out-dir", "r", "--bag-tf-static", "/ur/tf_static"]) == 0, (
        capsys.readouterr()
    )
    command = json.loads((repo / "r" / "good.json").read_text())["command"]
    assert command.endswith(
        " --against poses:rec.csv --bag-tf /ur/tf --bag-tf-static /ur/tf_static "
        "--bag-stamp-tolerance 0.002"
    ), command


def test_project_jacobian_keys_are_defaults_the_flags_override(repo, capsys):
    (repo / "pyproject.toml").write_text(
        '[tool.fkcheck]\nmodels = ["robots/good.toml"]\nsamples = 3\n'
        'against = ["pinocchio-urdf"]\njacobian_reference = "local"\ntol_jacobian = 1e-5\n',
        encoding="utf-8",
    )

    def jacobian(out: str, *flags: str) -> tuple[dict | None, str | None]:
        """The check's Jacobian settings and the backend's Jacobian status."""
        assert main(["check", "--out-dir", out, *flags]) == 0, capsys.readouterr()
        doc = json.loads((repo / out / "good.json").read_text())
        (backend,) = doc["backends"]
        return doc.get("jacobian"), backend.get("jacobian", {}).get("status")

    spec, status = jacobian("r")
    assert spec is not None
    assert (spec["reference"], spec["tolerance"], status) == ("local", 1e-5, "pass")
    assert jacobian("r2", "--no-jacobian") == (None, None)
    spec, status = jacobian("r3", "--jacobian-reference", "world")
    assert spec is not None
    assert (spec["reference"], spec["tolerance"], status) == ("world", 1e-5, "pass")


def test_bad_input_in_any_file_is_exit_2_before_anything_runs(repo, capsys):
    (repo / "robots" / "broken.toml").write_text("name = 'x'\n", encoding="utf-8")
    assert main(["check", "robots", *FAST, "--out-dir", "r"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1
    assert "broken.toml: convention: missing (required)" in err
    assert not (repo / "r").exists()


def test_two_models_with_one_stem_are_refused_not_overwritten(repo, capsys):
    (repo / "other").mkdir()
    shutil.copy(repo / "robots" / "good.toml", repo / "other" / "good.toml")
    assert main(["check", "robots", "other", *FAST, "--out-dir", "r"]) == 2
    err = capsys.readouterr().err
    assert "other/good.toml and robots/good.toml would both write good.json" in err
    assert not (repo / "r").exists()


def test_outputs_never_overwrite_an_input(repo, capsys):
    assert main(["check", "robots/good.toml", "robots/bad.toml", *FAST, "--summary",
                 "robots/good.toml"]) == 2  # fmt: skip
    assert "robots/good.toml" in capsys.readouterr().err


def test_no_model_and_no_project_says_what_to_give(repo, capsys):
    assert main(["check"]) == 2
    err = capsys.readouterr().err
    assert "give a MODEL (e.g. ur5) or --all, or list models in [tool.fkcheck]" in err


def test_each_models_recorded_command_reproduces_its_frames(repo, capsys):
    argv = ["check", "robots/good.toml", "robots/good2.toml", "--from", "world", "--to", "tcp",
            "--samples", "2", "--against", "rtb-dh", "--out-dir", "r"]  # fmt: skip
    (repo / "robots" / "good2.toml").write_text(
        (repo / "robots" / "good.toml")
        .read_text(encoding="utf-8")
        .replace('name = "ur5"', 'name = "ur5b"'),
        encoding="utf-8",
    )
    assert main(argv) == 0, capsys.readouterr()
    doc = json.loads((repo / "r" / "good.json").read_text())
    assert (doc["from"], doc["to"]) == ("world", "tcp")
    assert "--from world --to tcp" in doc["command"]


def test_names_after_double_dash_are_files_and_every_command_line_keeps_them_files(repo, capsys):
    """``--`` ends the options: a file named like an option is a model; reproductions say ``./``."""
    hostile = "--against=cmd:x.toml"
    shutil.copyfile(repo / "robots" / "bad.toml", repo / hostile)
    argv = ["check", *FAST, "--out-dir", "r", "--", hostile, "robots/good.toml"]
    assert main(argv) == 1
    out = capsys.readouterr().out
    assert f"│ {hostile} │ fail " in out
    command = json.loads((repo / "r" / "--against=cmd:x.json").read_text())["command"]
    assert command.startswith(f"fkcheck check ./{hostile} --samples 4 "), command
    assert main(["check", *FAST, "--", hostile]) == 1
    out = capsys.readouterr().out
    assert f"hint: explain it: fkcheck diagnose ./{hostile} --against pinocchio-urdf" in out


def test_a_models_max_errors_leave_out_its_recorded_expected_failures(
    tmp_path, capsys, monkeypatch
):
    """ur5e_menagerie's MJCF readers differ as recorded (xfail): its row shows rtb-dh's errors."""
    from fkcheck.io.format import format_angle_console, format_length_console

    monkeypatch.setenv("COLUMNS", "200")  # each row on one line, whatever the terminal

    against = "rtb-dh,mujoco-mjcf,pinocchio-mjcf"
    argv = ["check", "ur5", "ur5e_menagerie", "--samples", "4", "--against", against,
            "--out-dir", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr().out
    rows = json.loads((tmp_path / "ur5e_menagerie.json").read_text(encoding="utf-8"))["backends"]
    status = {r["name"]: r["status"] for r in rows}
    assert status["rtb-dh"] == "pass"
    assert status["mujoco-mjcf"] == "xfail"  # Menagerie's rounding: up to 1.49 mm
    counted = [r for r in rows if r["status"] != "xfail"]
    expected = [r for r in rows if r["status"] == "xfail"]
    worst = max(r["max_position_error_m"] for r in expected)
    assert worst > 1e-3 > max(r["max_position_error_m"] for r in counted)
    row = next(line for line in out.splitlines() if line.startswith("│ ur5e_menagerie "))
    cells = [c.strip() for c in row.strip("│").split("│")]
    assert cells[3] == format_length_console(max(r["max_position_error_m"] for r in counted))
    assert cells[4] == format_angle_console(max(r["max_rotation_error_rad"] for r in counted))
    assert (
        "max errors: of the backends that count for the verdict, not of a recorded expected "
        "failure (a row's xfail: its own check and report give their errors)"
    ) in " ".join(out.split())
    assert f"{len(expected)} xfail" in cells[2]  # the row counts them
