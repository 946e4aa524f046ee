"""``fkcheck diagnose``: a reference that cannot answer is one line and exit 2, never a traceback.

A check reports such a backend as ``skipped`` or ``error`` and goes on with the
others; a diagnosis has one reference only, so the same words end the command.
Each case is a common first-hour mistake (issue 32).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from tests.paths import REPO_ROOT


def _without_frames(tmp_path: Path) -> Path:
    """The UR5 with its ``[urdf]`` but none of its ``[frames.*]``: nothing is mapped."""
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
    kept = text[: text.index("[frames.")]
    assert "[urdf]" in kept
    path = tmp_path / "unmapped.toml"
    path.write_text(kept, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["puma560", "--against", "pinocchio-urdf"],
            r"cannot diagnose against pinocchio-urdf: it cannot run here: model has no \[urdf\]",
        ),
        (
            ["UNMAPPED"],
            r"cannot diagnose against pinocchio-urdf: it failed: frame 'world' .* has no URDF "
            r"twin",
        ),
        (
            ["ur5", "--against", "nosuchmod_backends.fk:forward"],
            r"cannot diagnose against nosuchmod_backends\.fk:forward: it failed: plugin "
            r"nosuchmod_backends\.fk:forward: cannot import module 'nosuchmod_backends\.fk'",
        ),
    ],
    ids=["backend-unavailable", "unmapped-frame", "plugin-import"],
)
def test_a_reference_that_cannot_answer_is_one_line_and_exit_2(
    tmp_path, monkeypatch, capsys, argv, message
):
    monkeypatch.chdir(tmp_path)
    argv = [str(_without_frames(tmp_path)) if a == "UNMAPPED" else a for a in argv]
    assert main(["diagnose", *argv, "--samples", "8"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "Traceback" not in captured.err
    assert captured.err.count("\n") == 1, captured.err
    assert re.match(r"fkcheck: error: " + message, captured.err), captured.err


def test_check_reports_the_same_failure_as_the_backend_s_error(tmp_path, monkeypatch, capsys):
    # The words diagnose ends with are the ones check gives the backend's result.
    monkeypatch.chdir(tmp_path)
    model = str(_without_frames(tmp_path))
    assert main(["check", model, "--against", "pinocchio-urdf", "--samples", "8"]) == 1
    out = capsys.readouterr().out
    assert "has no URDF twin, so pinocchio-urdf cannot compare the model with its URDF" in out
