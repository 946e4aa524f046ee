"""An interrupted run says so, exits non-zero, and leaves no (truncated) report behind."""

from __future__ import annotations

import signal
import subprocess
import sys
import time

import pytest

from tests.processes import interruptible


@pytest.mark.parametrize(
    ("sig", "code", "word"),
    [(signal.SIGTERM, 143, "terminated"), (signal.SIGINT, 130, "interrupted")],
)
def test_signal_during_a_check_leaves_no_report(tmp_path, sig, code, word):
    report = tmp_path / "ur5.json"
    proc = subprocess.Popen(
        [sys.executable, "-m", "fkcheck.cli.main", "check", "ur5", "--samples", "300000",
         "--against", "yourdfpy-urdf", "--json", str(report)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=interruptible,
    )  # fmt: skip
    time.sleep(4.0)  # well into the run: 300 000 yourdfpy poses take minutes
    assert proc.poll() is None, proc.communicate()
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == code, (out, err)
    assert f"fkcheck: {word}" in err
    assert "no report written" in err
    assert list(tmp_path.iterdir()) == []  # neither the report nor a temporary file
