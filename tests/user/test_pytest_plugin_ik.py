"""The pytest plugin's IK items: ``[tool.fkcheck] ik_solvers``, one test per model and solver.

A throw-away user repository names the bundled UR5 and two solvers: ur-analytic-ik,
which is sound and complete on it, and the user's own ``wrongik:solve``, which
answers every pose with the zero configuration. pytest runs in a subprocess, as
a user runs it.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.user.test_pytest_plugin import _env, _outcomes
from tests.user.userrepo import make_user_repo

TOOL_FKCHECK = """\
models = ["robots/good.toml"]
samples = 50
against = ["rtb-dh"]
ik_solvers = ["ur-analytic-ik", "wrongik:solve"]
"""

WRONG_IK = """\
import numpy as np


def solve(pose):
    return np.zeros((1, 6))  # one answer, whatever the pose: wrong nearly everywhere
"""


@pytest.mark.slow
def test_each_named_solver_is_a_test_that_fails_when_the_solver_is_wrong(tmp_path: Path) -> None:
    pytest.importorskip("ur_analytic_ik")
    repo = make_user_repo(tmp_path / "repo", TOOL_FKCHECK)
    (repo / "robots" / "bad.toml").unlink()
    (repo / "wrongik.py").write_text(WRONG_IK, encoding="utf-8")
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-v", "-rA"],
        cwd=repo,
        env=_env(tmp_path),
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    out = result.stdout
    assert result.returncode == 1, out + result.stderr  # a test failed, not a usage error
    assert _outcomes(out) == {
        "robots/good.toml::fkcheck[rtb-dh]": "PASSED",
        "robots/good.toml::fkcheck[ik:ur-analytic-ik]": "PASSED",
        "robots/good.toml::fkcheck[ik:wrongik:solve]": "FAILED",
    }, out
    section = out.split("robots/good.toml::fkcheck[ik:wrongik:solve] _", 1)[1]
    assert "IK FAIL" in section
    assert "wrong solutions: " in section
    assert "wrong solutions: 0;" not in section
    assert "Traceback" not in out


def test_an_unknown_solver_fails_its_test_in_one_line(tmp_path: Path) -> None:
    repo = make_user_repo(tmp_path / "repo", TOOL_FKCHECK.replace("wrongik:solve", "no-such-ik"))
    (repo / "robots" / "bad.toml").unlink()
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-v", "-rA", "-k", "no-such"],
        cwd=repo,
        env=_env(tmp_path),
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    out = result.stdout
    assert _outcomes(out) == {"robots/good.toml::fkcheck[ik:no-such-ik]": "FAILED"}, out
    assert "good.toml: IK solver no-such-ik: " in out
    assert "Traceback" not in out
