"""A plugin's module is found in the working directory, as pytest's ``pythonpath`` finds it.

``--against teamfk.fk:forward`` from the team's repository failed with "No module
named 'teamfk'" unless ``PYTHONPATH=.`` (issue 32). The program runs as the
installed ``fkcheck`` script does: ``python -P`` puts neither the current
directory nor the script's on ``sys.path``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.paths import PLUGINS_DIR, REPO_ROOT

#: The team's own FK, a package in its repository (UR5 in closed form).
TEAMFK = f"""
import sys
sys.path.insert(0, {str(PLUGINS_DIR)!r})
from ur5_closed_form import forward as _forward


def forward(q):
    return _forward(q)
"""


def _fkcheck(cwd: Path, *argv: str) -> subprocess.CompletedProcess[str]:
    paths = [str(REPO_ROOT), os.environ.get("PYTHONPATH", "")]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in paths if p)}
    return subprocess.run(
        [sys.executable, "-P", "-m", "fkcheck", *argv],
        cwd=cwd, env=env, capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip


def _repository(tmp_path: Path) -> Path:
    repo = tmp_path / "repo"
    (repo / "teamfk").mkdir(parents=True)
    (repo / "teamfk" / "__init__.py").write_text("")
    (repo / "teamfk" / "fk.py").write_text(TEAMFK)
    return repo


def test_a_plugin_module_in_the_working_directory_is_imported(tmp_path):
    repo = _repository(tmp_path)
    out = tmp_path / "r.json"
    done = _fkcheck(repo, "check", "ur5", "--samples", "8", "--against", "teamfk.fk:forward",
                    "--json", str(out))  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    (row,) = json.loads(out.read_text())["backends"]
    assert (row["name"], row["status"]) == ("teamfk.fk:forward", "pass")
    # Its module is among the check's inputs (no output may replace it).
    refused = _fkcheck(repo, "check", "ur5", "--against", "teamfk.fk:forward",
                       "--json", "teamfk/fk.py")  # fmt: skip
    assert refused.returncode == 2, refused.stdout + refused.stderr
    assert "teamfk/fk.py" in refused.stderr


def test_another_directory_s_module_is_not_found(tmp_path):
    _repository(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    done = _fkcheck(elsewhere, "check", "ur5", "--samples", "8", "--against",
                    "teamfk.fk:forward")  # fmt: skip
    assert done.returncode == 1, done.stdout + done.stderr
    assert "cannot import module 'teamfk.fk': No module named 'teamfk'" in done.stdout


def test_the_working_directory_never_shadows_what_fkcheck_imports(tmp_path):
    # It is searched last: a numpy.py there is not imported by the plugin's process.
    repo = _repository(tmp_path)
    marker = tmp_path / "shadowed"
    (repo / "numpy.py").write_text(f"open({str(marker)!r}, 'w').write('imported')\n")
    done = _fkcheck(repo, "check", "ur5", "--samples", "8", "--against", "teamfk.fk:forward")
    assert done.returncode == 0, done.stdout + done.stderr
    assert not marker.exists()
