"""``fkcheck ik`` from the command line: exit codes, the JSON's fields, the user's function."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from fkcheck.cli.main import main

HERE = Path(__file__).parent
pytest.importorskip("ur_analytic_ik")


def _run(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "fkcheck", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ},
        check=False,
    )


def test_ur_analytic_ik_passes_on_ur5e_with_json(tmp_path, capsys):
    out = tmp_path / "ik.json"
    page = tmp_path / "ik.html"
    code = main(["ik", "ur5e", "--solver", "ur-analytic-ik", "--samples", "200",
                 "--json", str(out), "--html", str(page)])  # fmt: skip
    printed = capsys.readouterr().out
    assert code == 0, printed
    assert printed.startswith("IK PASS")
    assert '<h1>IK <span class="pass">pass</span>: ur5e / ur-analytic-ik</h1>' in page.read_text()
    assert "Warning" not in printed  # the library's own printing is kept out of ours
    data = json.loads(out.read_text())
    assert data["schema"] == "fkcheck-ik/1"
    assert data["verdict"] == "pass"
    for field in ("wrong_solutions", "missed", "garbage", "raised", "poses", "singular_poses",
                  "own_fk_disagreements"):  # fmt: skip
        assert type(data[field]) is int, field
    assert (data["wrong_solutions"], data["missed"]) == (0, 0)
    assert (data["frame_from"], data["frame_to"]) == ("base", "tool0")
    assert data["own_fk"] is True
    assert data["worst"] == []


def test_wrong_function_fails_with_worst_cases_and_markdown(tmp_path):
    shutil.copy(HERE / "ur_ik.py", tmp_path / "myik.py")
    (tmp_path / "wrongik.py").write_text(
        "from myik import UR5E, solve_with, fk_with\n"
        "P = {**UR5E, 'd4': UR5E['d4'] + 1e-4}\n"
        "def solve(pose):\n    return solve_with(P, pose)\n"
        "def fk(q):\n    return fk_with(P, q)\n"
    )
    proc = _run(
        [
            "ik",
            "ur5e",
            "--solver",
            "wrongik:solve",
            "--samples",
            "50",
            "--json",
            "out.json",
            "--markdown",
            "out.md",
            "--junit",
            "out.xml",
        ],
        tmp_path,
    )
    assert proc.returncode == 1, proc.stderr
    data = json.loads((tmp_path / "out.json").read_text())
    assert data["verdict"] == "fail"
    assert data["wrong_solutions"] == data["solutions"] > 0
    assert data["own_fk_disagreements"] == data["poses"]
    worst = data["worst"][0]
    assert {"kind", "q", "q_deg", "branch", "returned", "explanation"} <= set(worst)
    assert "forward model" in proc.stdout
    assert "IK fail" in (tmp_path / "out.md").read_text()
    suite = ET.parse(tmp_path / "out.xml").getroot()[0]
    assert (suite.get("tests"), suite.get("failures")) == ("4", "3")  # singular behaviour passes
    failed = {c.get("name"): c.find("failure") for c in suite.iter("testcase")}
    assert failed["singular behaviour"] is None
    assert failed["soundness"].get("message").startswith(f"{data['wrong_solutions']} wrong")


def test_honest_function_from_the_working_directory_passes(tmp_path):
    shutil.copy(HERE / "ur_ik.py", tmp_path / "myik.py")
    proc = _run(["ik", "ur5e", "--solver", "myik:solve", "--samples", "50"], tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "own FK: 0 disagreements" in proc.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["puma560", "--solver", "ur-analytic-ik"], "not one of its robots"),
        (["puma560", "--solver", "ur-analytic-ik:ur5e"], "not a UR-shaped table"),
        (["ur5e", "--solver", "nope"], "unknown IK solver 'nope'; solvers are: ur-analytic-ik"),
        (["ur5e", "--solver", "ur-analytic-ik", "--to", "nowhere"], "nowhere"),
        (["ur5e", "--solver", "ur-analytic-ik", "--samples", "-1"], "--samples"),
        (
            ["ur5e", "--solver", "ur-analytic-ik", "--from", "tool0", "--to", "base"],
            "solves DH frame 0 (base) to DH frame 6 (tool0)",
        ),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, message, capsys):
    assert main(["ik", *args]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert "Traceback" not in err
    assert err.count("\n") == 1


def test_a_function_that_raises_is_a_failure_not_a_traceback(tmp_path):
    (tmp_path / "badik.py").write_text(
        "def solve(pose):\n    raise RuntimeError('boom <script>alert(1)</script>')\n"
    )
    proc = _run(
        ["ik", "ur5e", "--solver", "badik:solve", "--samples", "5", "--html", "ik.html"], tmp_path
    )
    assert proc.returncode == 1
    assert "raised RuntimeError: boom" in proc.stdout
    assert "Traceback" not in proc.stderr
    page = (tmp_path / "ik.html").read_text()
    assert "boom &lt;script&gt;alert(1)&lt;/script&gt;" in page  # what the solver said, escaped
    assert "<script>" not in page


def test_json_may_not_replace_the_model_or_the_solver_module(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    shutil.copy(HERE / "ur_ik.py", tmp_path / "myik.py")
    model = tmp_path / "ur5e.toml"
    model.write_bytes((HERE.parents[1] / "models" / "ur5e.toml").read_bytes())
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    for target in ("ur5e.toml", "myik.py"):
        code = main(["ik", "ur5e.toml", "--solver", "myik:solve", "--samples", "1",
                     "--json", target])  # fmt: skip
        err = capsys.readouterr().err
        assert code == 2, err
        assert "an input of this run" in err
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


def test_a_function_that_hangs_is_stopped_at_its_time_limit(tmp_path):
    (tmp_path / "slowik.py").write_text("def solve(pose):\n    while True:\n        pass\n")
    proc = _run(["ik", "ur5e", "--solver", "slowik:solve", "--samples", "1", "--timeout", "3"],
                tmp_path)  # fmt: skip
    assert proc.returncode == 1
    assert "timed out after 3 s (its process was killed)" in proc.stdout
    assert "Traceback" not in proc.stderr
