"""A check says when lint flags its model (issue 24 point 6).

Degrees in a radian file agree with themselves: every backend reads the same
90 rad, so the check passes "implementation only" while ``fkcheck lint`` fails.
The verdict line, and every output (through the record's headline), says that
lint found something; the project's ``lint_ignore`` is honoured as lint's own.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from fkcheck.cli.main import main

TABLE = """name = "t"
convention = "standard"

[[joint]]
a = 0.2
alpha = {alpha}
d = 0.1

[[joint]]
a = 0.3
alpha = 0
d = 0.0
"""

LINE = (
    "joint[0].alpha (joint 1): 90 is beyond ±2π: it looks like degrees in a file with "
    'angle_unit = "rad" [degrees]'
)


def _check(tmp_path: Path, capsys: pytest.CaptureFixture[str], alpha: str, *extra: str):
    model = tmp_path / "t.toml"
    model.write_text(TABLE.format(alpha=alpha), encoding="utf-8")
    out_json = tmp_path / "out.json"
    md = tmp_path / "summary.md"
    code = main(["check", str(model), "--samples", "20", "--against", "rtb-dh", "--json",
                 str(out_json), "--summary", str(md), *extra])  # fmt: skip
    out = capsys.readouterr().out
    return code, out, json.loads(out_json.read_text()), md.read_text()


@pytest.fixture
def isolated_cwd(tmp_path: Path):
    old = Path.cwd()
    os.chdir(tmp_path)
    yield tmp_path
    os.chdir(old)


def test_degrees_in_a_radian_file_pass_but_the_verdict_says_lint_flags_them(
    isolated_cwd: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, data, md = _check(isolated_cwd, capsys, "90", "--isolated")
    assert code == 0
    note = "; lint: 1 warning (fkcheck lint names it)"
    verdict = [line for line in out.splitlines() if line.startswith("verdict:")]
    assert verdict == [
        "verdict: pass — implementation only; table not checked against anything "
        f"independent{note} (1 backend(s) answered)"
    ]
    assert data["lint"] == [LINE]
    assert data["headline"].endswith(note)
    assert note in md


def test_a_clean_table_says_nothing_of_lint(
    isolated_cwd: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, data, _ = _check(isolated_cwd, capsys, "1.5707963267948966", "--isolated")
    assert code == 0
    assert "lint" not in out
    assert data["lint"] == []


def test_the_projects_lint_ignore_is_lints_own(
    isolated_cwd: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (isolated_cwd / "pyproject.toml").write_text(
        '[tool.fkcheck]\nlint_ignore = ["degrees"]\n', encoding="utf-8"
    )
    code, out, data, _ = _check(isolated_cwd, capsys, "90")
    assert code == 0
    assert data["lint"] == []
    assert "lint:" not in out
