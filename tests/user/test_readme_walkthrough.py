"""The README's "Bring your own robot" walk-through, run as written.

The commands are read from README.md's code block (the lines starting ``$ ``),
so the README and this test cannot drift apart: a command the README shows
that no longer works fails here.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import fkcheck
from tests.paths import REPO_ROOT

SECTION = "## Bring your own robot"


def _walkthrough() -> tuple[list[str], str]:
    """The section's first code block: its ``$`` commands and the verdict line it shows."""
    text = (REPO_ROOT / "README.md").read_text(encoding="utf-8")
    section = text[text.index(SECTION) :]
    block = section.split("```", 2)[1]
    commands = [line[2:] for line in block.splitlines() if line.startswith("$ ")]
    verdict = next(line for line in block.splitlines() if line.startswith("verdict: "))
    return commands, verdict


def _myarm_text() -> str:
    """This repository's UR5 numbers, named myarm, without its [urdf], [frames] or [check]."""
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
    table = text.split("\n[urdf]")[0]
    while table.rstrip().splitlines()[-1].startswith("#"):  # the comments before [urdf]
        table = table.rstrip().rsplit("\n", 1)[0] + "\n"
    for section in ("[urdf]", "[frames", "[check]"):
        assert section not in table
    return table.replace('name = "ur5"', 'name = "myarm"', 1)


def test_the_commands_are_read_from_the_readme():
    commands, verdict = _walkthrough()
    assert [c.split()[:2] for c in commands] == [
        ["fkcheck", "lint"],
        ["fkcheck", "map"],
        ["sed", "-n"],
        ["cat", "mapping.toml"],
        ["fkcheck", "check"],
    ]
    assert verdict.startswith("verdict: pass — table verified independently")


def test_bring_your_own_robot_runs_as_the_readme_shows(tmp_path):
    commands, verdict = _walkthrough()
    (tmp_path / "myarm.toml").write_text(_myarm_text(), encoding="utf-8")
    src = str(Path(fkcheck.__file__).resolve().parents[1])
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(p for p in (src, os.environ.get("PYTHONPATH")) if p),
        "COLUMNS": "200",
        "FKCHECK_PYTHON": sys.executable,
    }
    shown = verdict.split("(…", 1)[0]  # the README elides the count of backends
    for command in commands:
        # `fkcheck` is this interpreter's fkcheck, whatever is on PATH.
        script = f'fkcheck() {{ "$FKCHECK_PYTHON" -m fkcheck "$@"; }}\n{command}\n'
        done = subprocess.run(
            ["bash", "-c", script],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=300,
            check=False,
        )
        assert done.returncode == 0, f"$ {command}\n{done.stdout}\n{done.stderr}"
    # The last command is the check: it passes with the verdict the README shows.
    assert commands[-1].startswith("fkcheck check myarm.toml")
    assert shown in done.stdout, done.stdout
    assert re.search(r"\(\d+ backend\(s\) answered\)", done.stdout)
