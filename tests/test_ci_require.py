"""The CI plugin: with FKCHECK_REQUIRE_BACKENDS=1 a skip is a failure, without it a skip."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).parent

CASES = {
    "module_importorskip": "import pytest\npytest.importorskip('no_such_module_xyz')\n"
    "def test_x():\n    assert 1 + 1 == 2\n",
    "test_skip": "import pytest\ndef test_x():\n    pytest.skip('no toolchain here')\n",
    "xfail_is_not_a_skip": "import pytest\n@pytest.mark.xfail(strict=True)\n"
    "def test_x():\n    assert 1 + 1 == 3\n",
}


def run_pytest(tmp_path: Path, source: str, required: bool) -> subprocess.CompletedProcess[str]:
    test = tmp_path / "test_case.py"
    test.write_text(source)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(TESTS.parent), *sys.path])}
    env.pop("FKCHECK_REQUIRE_BACKENDS", None)
    env.pop("PYTEST_ADDOPTS", None)  # CI's --junitxml belongs to the outer run
    if required:
        env["FKCHECK_REQUIRE_BACKENDS"] = "1"
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "tests.ci_require", "-q", "-p", "no:cacheprovider",
         "-o", "addopts=", str(test)],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=120,
    )  # fmt: skip


@pytest.mark.parametrize("name", ["module_importorskip", "test_skip"])
def test_a_skip_is_a_failure_when_required(tmp_path, name):
    done = run_pytest(tmp_path, CASES[name], required=True)
    assert done.returncode in (1, 2), done.stdout  # 1: a failed test; 2: a collection error
    assert "FKCHECK_REQUIRE_BACKENDS=1 forbids skips" in done.stdout
    done = run_pytest(tmp_path, CASES[name], required=False)
    assert done.returncode in (0, 5), done.stdout  # 5: the module's only test was skipped
    assert "1 skipped" in done.stdout


def test_xfail_is_left_alone(tmp_path):
    done = run_pytest(tmp_path, CASES["xfail_is_not_a_skip"], required=True)
    assert done.returncode == 0, done.stdout
    assert "1 xfailed" in done.stdout
