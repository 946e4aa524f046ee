"""The pytest plugin with ``[check] jacobian = true``: a wrong Jacobian is a failing test."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.paths import PLUGINS_DIR
from tests.user.test_pytest_plugin import _env
from tests.user.userrepo import good_ur5_text, make_user_repo

TOOL_FKCHECK = (
    'models = ["robots/jac.toml"]\nsamples = 20\nagainst = ["ur5_jacobians:end_effector"]\n'
)


@pytest.mark.slow
def test_a_jacobian_that_disagrees_fails_its_test_with_the_diagnosis(tmp_path: Path) -> None:
    repo = make_user_repo(tmp_path / "repo", TOOL_FKCHECK)
    text = good_ur5_text()
    head, _, _ = text.partition("[check]")
    (repo / "robots" / "jac.toml").write_text(
        head + '[check]\nfrom = "world"\nto = "tcp"\njacobian = true\n', encoding="utf-8"
    )
    env = _env(tmp_path)
    env["PYTHONPATH"] = os.pathsep.join([str(PLUGINS_DIR), env["PYTHONPATH"]])
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA", "-v"],
        cwd=repo, env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    assert "FAILED robots/jac.toml::fkcheck[ur5_jacobians:end_effector]" in out
    assert "ur5_jacobians:end_effector: pass — max position error" in out  # the poses agree
    assert "  Jacobian fail: Jacobian (world-aligned)" in out
    assert "  Jacobian diagnosis: the backend's Jacobian is in the frame's own axes (local" in out
    assert "Traceback" not in out
