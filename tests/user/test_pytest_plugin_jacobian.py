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


def _run(tmp_path: Path, tool: str, check: str) -> subprocess.CompletedProcess[str]:
    repo = make_user_repo(tmp_path / "repo", TOOL_FKCHECK + tool)
    head, _, _ = good_ur5_text().partition("[check]")
    (repo / "robots" / "jac.toml").write_text(
        head + f'[check]\nfrom = "world"\nto = "tcp"\n{check}', encoding="utf-8"
    )
    env = _env(tmp_path)
    env["PYTHONPATH"] = os.pathsep.join([str(PLUGINS_DIR), env["PYTHONPATH"]])
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA", "-v"],
        cwd=repo, env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize(
    ("tool", "check"),
    [("", "jacobian = true\n"), ("jacobian = true\n", "")],
    ids=["model-check", "tool-fkcheck"],
)
def test_a_jacobian_that_disagrees_fails_its_test_with_the_diagnosis(
    tmp_path: Path, tool: str, check: str
) -> None:
    done = _run(tmp_path, tool, check)
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    assert "FAILED robots/jac.toml::fkcheck[ur5_jacobians:end_effector]" in out
    assert "ur5_jacobians:end_effector: pass — max position error" in out  # the poses agree
    assert "  Jacobian fail: Jacobian (world-aligned)" in out
    assert "  Jacobian diagnosis: the backend's Jacobian is in the frame's own axes (local" in out
    assert "Traceback" not in out


@pytest.mark.slow
def test_the_projects_jacobian_reference_is_the_one_compared(tmp_path: Path) -> None:
    """``jacobian_reference`` alone turns the comparison on (as ``--jacobian-reference``).

    The plugin's ``_jacobian`` promises world-aligned (the plugin contract) and
    answers in the frame's own axes: re-expressed in ``local`` it still disagrees.
    """
    done = _run(tmp_path, 'jacobian_reference = "local"\n', "")
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    assert "  Jacobian fail: Jacobian (local): 101 of 101 configurations differ" in out


@pytest.mark.slow
def test_the_projects_jacobian_false_wins_over_the_models_check(tmp_path: Path) -> None:
    done = _run(tmp_path, "jacobian = false\n", "jacobian = true\n")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "PASSED robots/jac.toml::fkcheck[ur5_jacobians:end_effector]" in done.stdout
    assert "Jacobian" not in done.stdout
