"""A pytest without fkcheck's plugin stops, when the project says it needs the plugin.

The plugin is a ``pytest11`` entry point of the fkcheck distribution: a pytest from
another environment (a global one) never loads it, and cannot run any of fkcheck's
code to say so. What such a pytest does read is the project's own configuration:
``required_plugins = ["fkcheck"]`` under ``[tool.pytest.ini_options]`` (pytest's
own option, pytest >= 6) makes it stop before collecting, "Missing required plugins:
fkcheck", instead of checking none of the models and passing. ``-p no:fkcheck``
stands in for that pytest here: the entry point is not loaded, as there.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.user.test_pytest_plugin import _env
from tests.user.userrepo import make_user_repo

TOOL_FKCHECK = 'models = ["robots/*.toml"]\nsamples = 20\nagainst = ["rtb-dh"]\n'
REQUIRED = '\n[tool.pytest.ini_options]\nrequired_plugins = ["fkcheck"]\n'


def _collect(tmp_path: Path, *args: str) -> subprocess.CompletedProcess[str]:
    repo = make_user_repo(tmp_path / "repo", TOOL_FKCHECK)
    with (repo / "pyproject.toml").open("a", encoding="utf-8") as f:
        f.write(REQUIRED)
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "--collect-only", "-q", *args],
        cwd=repo, env=_env(tmp_path), capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


def test_a_pytest_without_the_plugin_stops_naming_it(tmp_path: Path) -> None:
    done = _collect(tmp_path, "-p", "no:fkcheck")
    output = done.stdout + done.stderr
    assert done.returncode == 4, output  # pytest's usage error: nothing ran, nothing passed
    assert "Missing required plugins: fkcheck" in output
    assert "fkcheck[" not in done.stdout  # not one model test collected


def test_with_the_plugin_the_same_project_collects_its_models(tmp_path: Path) -> None:
    done = _collect(tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.splitlines()[:2] == [
        "robots/bad.toml::fkcheck[rtb-dh]",
        "robots/good.toml::fkcheck[rtb-dh]",
    ]
