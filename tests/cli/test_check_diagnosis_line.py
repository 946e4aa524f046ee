"""A failing check says its diagnosis in one line on the terminal, one model or many.

The reports (pytest, HTML, Markdown, JUnit) carry the diagnosis's headline ("…
differs in one number, d1 (shoulder_pan)"); the terminal run says the same, under
the verdict, and a run over many models says it under each failing model's
messages.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from fkcheck.cli.main import main
from tests.paths import REPO_ROOT

UR5 = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
FAST = ["--samples", "16", "--against", "pinocchio-urdf,rtb-dh"]
#: The diagnosis's headline: the reference matches UR's nominal table, but for d1.
LINE = (
    "diagnosis (pinocchio-urdf): the reference matches the published table ur5 (Universal "
    "Robots UR5 (CB-series), nominal DH); this table differs in one number, d1 (shoulder_pan)"
)


def _ur5(path: Path, d1: str = "0.089159") -> Path:
    """The bundled UR5 file (its URDF is fkcheck's own, found from anywhere), with d1 as given."""
    text = UR5.replace("d = 0.089159", f"d = {d1}")
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def wrong_ur5(tmp_path: Path) -> Path:
    return _ur5(tmp_path / "ur5_d1.toml", "0.0901")


def test_a_failing_check_prints_its_diagnosis_in_one_line(wrong_ur5, capsys, monkeypatch):
    monkeypatch.chdir(wrong_ur5.parent)
    assert main(["check", str(wrong_ur5), *FAST]) == 1
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert LINE in lines
    verdict = next(k for k, line in enumerate(lines) if line.startswith("verdict: fail"))
    assert lines.index(LINE) == verdict + 1  # right under the verdict, before the hint
    assert lines[verdict + 2].startswith("hint: explain it: fkcheck diagnose ")


def test_no_diagnose_leaves_it_out(wrong_ur5, capsys, monkeypatch):
    monkeypatch.chdir(wrong_ur5.parent)
    assert main(["check", str(wrong_ur5), *FAST, "--no-diagnose"]) == 1
    out = capsys.readouterr().out
    assert "diagnosis (" not in out
    assert "hint: explain it: fkcheck diagnose " in out  # the way to it stays


def test_a_passing_check_prints_no_diagnosis(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["check", str(_ur5(tmp_path / "ur5.toml")), *FAST]) == 0
    assert "diagnosis" not in capsys.readouterr().out


def test_a_run_over_many_models_says_each_failing_models_diagnosis(tmp_path, capsys, monkeypatch):
    robots = tmp_path / "robots"
    robots.mkdir()
    _ur5(robots / "a_good.toml")
    _ur5(robots / "b_wrong.toml", "0.0901")
    monkeypatch.chdir(tmp_path)
    assert main(["check", "robots", *FAST]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert f"robots/b_wrong.toml: {LINE}" in lines
    assert not any(line.startswith("robots/a_good.toml: diagnosis") for line in lines)
    # Under the failing model's own messages, before the tally.
    at = lines.index(f"robots/b_wrong.toml: {LINE}")
    assert lines[at - 1].startswith("robots/b_wrong.toml: pinocchio-urdf: ")
    assert lines[at + 1].startswith("fkcheck: 1 of 2 models pass")


def test_the_hint_reproduces_the_checks_seed_tolerance_and_time_limit(
    wrong_ur5, capsys, monkeypatch
):
    # The hint is the report's reproducing line: a seed, a tolerance or a time limit
    # other than the defaults is carried, else the diagnosis would run another check.
    monkeypatch.chdir(wrong_ur5.parent)
    argv = ["check", wrong_ur5.name, *FAST, "--no-diagnose", "--seed", "3",
            "--tol-pos", "2e-06", "--timeout", "60"]  # fmt: skip
    assert main(argv) == 1
    (hint,) = (line for line in capsys.readouterr().out.splitlines() if "explain it" in line)
    assert hint == (
        f"hint: explain it: fkcheck diagnose {wrong_ur5.name} --against pinocchio-urdf "
        "--from base --to tool0 --seed 3 --tol-pos 2e-06 --timeout 60.0"
    )
