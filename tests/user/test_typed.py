"""A user's strict mypy sees fkcheck's types: ``py.typed`` ships, the public API is annotated."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.paths import REPO_ROOT

USER_SCRIPT = """\
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

import fkcheck
from fkcheck.testing import assert_fk_matches, assert_pose_close


def tcp(path: Path) -> NDArray[np.float64]:
    model: fkcheck.Model = fkcheck.load_model(path)
    return model.fk([0.0] * model.dof)


def verdict(name: str) -> str:
    try:
        outcome = fkcheck.check(name, against=["rtb-dh"], samples=10)
    except fkcheck.FkcheckError as exc:
        return f"bad input: {exc}"
    worst: list[float | None] = [b.max_position_error_m for b in outcome.backends]
    print(worst, outcome.headline)
    return outcome.verdict


def in_tests(pose: NDArray[np.float64]) -> None:
    outcome: fkcheck.Outcome = assert_fk_matches("ur5", against="rtb-dh", samples=10)
    assert outcome.check.evidence.table.status in ("verified", "failed", "not-checked")
    assert_pose_close(pose, pose, tol_pos_m=1e-9)
"""

#: A mistake mypy can only see with fkcheck's types: a verdict is a string.
WRONG_SCRIPT = """\
import fkcheck

outcome = fkcheck.check("ur5", samples=10)
count: int = outcome.verdict
model = fkcheck.load_model("ur5")
model.fk("zero", all_frames="yes")
"""


def _mypy(tmp_path: Path, name: str, text: str) -> subprocess.CompletedProcess[str]:
    script = tmp_path / name
    script.write_text(text, encoding="utf-8")
    # PYTHONPATH puts this checkout's src/ on the interpreter's path, where mypy treats
    # fkcheck as an installed package: typed only if it ships py.typed (PEP 561).
    env = {**os.environ, "PYTHONPATH": str(REPO_ROOT / "src")}
    env.pop("MYPYPATH", None)
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental",
         "--python-executable", sys.executable, str(script)],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


def test_package_ships_py_typed() -> None:
    assert (REPO_ROOT / "src" / "fkcheck" / "py.typed").is_file()


@pytest.mark.slow
def test_users_strict_mypy_passes_on_the_public_api(tmp_path: Path) -> None:
    pytest.importorskip("mypy")
    result = _mypy(tmp_path, "user_script.py", USER_SCRIPT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Success: no issues found in 1 source file" in result.stdout


@pytest.mark.slow
def test_users_strict_mypy_reports_a_type_error(tmp_path: Path) -> None:
    pytest.importorskip("mypy")
    result = _mypy(tmp_path, "wrong_script.py", WRONG_SCRIPT)
    out = result.stdout
    assert result.returncode == 1, out + result.stderr
    assert "missing library stubs or py.typed marker" not in out
    assert (
        "wrong_script.py:4: error: Incompatible types in assignment (expression has type "
        "\"Literal['pass', 'fail', 'error', 'unverified']\", variable has type \"int\")"
    ) in out
    assert (
        'wrong_script.py:6: error: Argument "all_frames" to "fk" of "Model" has incompatible '
        'type "str"; expected "bool"' in out
    )
