"""The fkcheck program writing to a reader that goes away (``fkcheck check --all | head -1``)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="POSIX pipes")


def test_a_closed_pipe_mid_run_neither_stops_the_models_nor_hides_their_verdict(tmp_path: Path):
    out = tmp_path / "reports"
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2] / "src")}
    proc = subprocess.Popen(
        [sys.executable, "-m", "fkcheck", "check", "planar2", "planar3", "--samples", "2",
         "--against", "rtb-dh", "--require", "table", "--out-dir", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path, env=env,
    )  # fmt: skip
    assert proc.stdout is not None
    assert proc.stderr is not None
    proc.stdout.readline()  # the first model's header, then the reader goes away
    proc.stdout.close()
    with proc.stderr:
        err = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == 1, err  # both unverified: exit 1, not 0
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(
        ["index.html"] + [f"{m}{ext}" for m in ("planar2", "planar3")
                          for ext in (".html", ".json", ".junit.xml")]
    )  # fmt: skip
    assert "Traceback" not in err
