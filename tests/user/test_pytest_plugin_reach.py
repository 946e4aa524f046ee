"""The pytest plugin says what it left out, and says a table error once.

* ``[tool.fkcheck] models`` outside what pytest collects (``testpaths = ["tests"]``,
  models in ``robots/``) gave ``1 passed``, silently: now a warning in pytest's
  summary names them and the way in (a run given paths chose, and is not warned);
* one α of the wrong sign failed each URDF backend and the required evidence,
  with the diagnosis printed in every one of them: now it is written out once.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.user.test_pytest_plugin import _env, _outcomes
from tests.user.userrepo import WRONG_ALPHA, make_user_repo

#: Where pytest runs, as far as its summary goes: ``CI`` set makes pytest print
#: each failure's message whole in the short summary; unset, cut to the width.
WHERE = {"terminal": {"COLUMNS": "200"}, "ci": {"CI": "true"}}


def _pytest(
    repo: Path, tmp_path: Path, *args: str, env: dict[str, str] | None = None
) -> subprocess.CompletedProcess[str]:
    run_env = {k: v for k, v in _env(tmp_path).items() if k not in ("CI", "BUILD_NUMBER")}
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA", *args],
        cwd=repo, env=run_env | (env or {}), capture_output=True, text=True, timeout=300,
        check=False,
    )  # fmt: skip


def _repo_with_testpaths(tmp_path: Path) -> Path:
    repo = make_user_repo(tmp_path / "repo", 'models = ["robots/*.toml"]\nsamples = 10\n')
    with (repo / "pyproject.toml").open("a", encoding="utf-8") as f:
        f.write('\n[tool.pytest.ini_options]\ntestpaths = ["tests"]\n')
    (repo / "tests").mkdir()
    (repo / "tests" / "test_units.py").write_text(
        "def test_units():\n    assert 1000 * 0.001 == 1.0\n", encoding="utf-8"
    )
    return repo


def test_models_outside_testpaths_are_a_warning_naming_them(tmp_path: Path) -> None:
    done = _pytest(_repo_with_testpaths(tmp_path), tmp_path)
    out = done.stdout
    assert done.returncode == 0, out + done.stderr
    assert re.search(r"\b1 passed, 1 warning\b", out), out
    assert (
        "FkcheckCollectionWarning: fkcheck: 2 of 2 [tool.fkcheck] models lie outside what "
        "pytest collects (testpaths = ['tests']) and were not checked: robots/bad.toml, "
        "robots/good.toml; add robots to testpaths, or run pytest robots"
    ) in out
    # Located at the line that names the models.
    assert re.search(r"^pyproject\.toml:6$", out, re.MULTILINE), out


def test_a_run_given_paths_is_not_warned(tmp_path: Path) -> None:
    done = _pytest(_repo_with_testpaths(tmp_path), tmp_path, "tests")
    assert done.returncode == 0, done.stdout + done.stderr
    assert re.search(r"\b1 passed in\b", done.stdout), done.stdout
    assert "FkcheckCollectionWarning" not in done.stdout


@pytest.mark.slow
@pytest.mark.parametrize("where", WHERE)
def test_one_table_error_is_one_failure_per_backend_and_one_diagnosis(
    tmp_path: Path, where: str
) -> None:
    pytest.importorskip("pinocchio")
    tool = (
        'models = ["robots/bad.toml"]\nsamples = 10\nrequire = ["table"]\n'
        'against = ["pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf"]\n'
    )
    repo = make_user_repo(tmp_path / "repo", tool)
    done = _pytest(repo, tmp_path, "-v", env=WHERE[where])
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    assert _outcomes(out) == {
        f"robots/bad.toml::fkcheck[{name}]": "FAILED"
        for name in ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "require:table")
    }, out
    assert out.count(f"diagnosis: {WRONG_ALPHA}") == 1, out
    section = out.split("robots/bad.toml::fkcheck[pinocchio-urdf] _", 1)[1]
    assert section.index(f"diagnosis: {WRONG_ALPHA}") < section.index("fkcheck[yourdfpy-urdf]")
    assert (
        out.count(
            "diagnosis: as for pinocchio-urdf (one for pinocchio-urdf, yourdfpy-urdf, rtb-urdf)"
        )
        == 2
    ), out
    # The short summary gives each failure its headline, in CI as on a terminal.
    summary = out.split("short test summary info", 1)[1]
    assert (
        "FAILED robots/bad.toml::fkcheck[rtb-urdf] - fkcheck ur5: base → tool0: fail — "
        "table disagrees\n"
    ) in summary, out
