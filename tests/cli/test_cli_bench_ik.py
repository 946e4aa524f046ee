"""`fkcheck bench --ik`: solvers timed on the same poses, their library bare, the check's cost.

No timing is asserted (times depend on the machine): what was timed, on how many
poses, that the solutions reproduce their poses, and that a wrong solver fails.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from fkcheck.bench.ik import IK_POSES
from fkcheck.cli.main import main

HERE = Path(__file__).parents[1] / "ik"


def test_bench_ik_rows_per_solver(capsys, tmp_path, monkeypatch):
    pytest.importorskip("ur_analytic_ik")
    monkeypatch.chdir(tmp_path)
    shutil.copy(HERE / "ur_ik.py", tmp_path / "myik.py")
    argv = ["bench", "ur5e", "--ik", "ur-analytic-ik,myik:solve", "--n", "300", "--repeat", "1",
            "--json", "b.json"]  # fmt: skip
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "Warning" not in out  # the library's printing stays off the table
    data = json.loads((tmp_path / "b.json").read_text())
    assert (data["quantity"], data["n"]) == ("ik", 300)
    rows = [(t["solver"], t["part"]) for t in data["timings"]]
    assert rows == [
        ("ur-analytic-ik", "solve"),
        ("ur-analytic-ik", "library"),
        ("ur-analytic-ik", "check"),
        ("myik:solve", "solve"),
        ("myik:solve", "check"),
    ]
    for t in data["timings"]:
        assert t["seconds"] > 0
        assert t["solves_per_s"] == pytest.approx(t["n"] / t["seconds"])
    solves = [t for t in data["timings"] if t["part"] == "solve"]
    assert all(t["max_position_error_m"] < 1e-12 for t in solves)
    assert data["failed"] == data["unsound"] == []


def test_bench_ik_caps_the_poses_and_fails_an_unsound_solver(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    source = (HERE / "ur_ik.py").read_text()
    (tmp_path / "offik.py").write_text(source.replace('"d4": 0.1333', '"d4": 0.1334'))
    code = main(["bench", "ur5e", "--ik", "offik:solve", "--repeat", "1", "--json", "b.json"])
    err = capsys.readouterr().err
    assert code == 1
    assert "off their pose by more than 1e-06 m: offik:solve" in err
    data = json.loads((tmp_path / "b.json").read_text())
    assert data["n"] == IK_POSES  # --n's default (a million) capped
    assert data["unsound"] == ["offik:solve"]
    assert data["timings"][0]["max_position_error_m"] == pytest.approx(1e-4, rel=0.05)


def test_bench_ik_unknown_solver_is_one_line(capsys):
    assert main(["bench", "ur5e", "--ik", "nope"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("fkcheck: error: unknown IK solver 'nope'")
    assert err.count("\n") == 1
