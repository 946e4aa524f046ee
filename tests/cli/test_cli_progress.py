"""``fkcheck check`` shows its progress: a live display on a terminal, plain lines in a pipe."""

from __future__ import annotations

import io
import os
import re
import select
import subprocess
import sys
import threading
import time

import pytest

from fkcheck.cli.progress import check_progress, plain_line
from fkcheck.core.dh import JIT_MIN_POSES

pytest.importorskip("roboticstoolbox")

_ENV = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path), "COLUMNS": "120"}
_ENV.pop("FORCE_COLOR", None)
_ENV.pop("GITHUB_ACTIONS", None)
_ENV.pop("GITHUB_STEP_SUMMARY", None)
_ARGV = [sys.executable, "-m", "fkcheck", "check", "ur5", "--samples", "200000",
         "--against", "rtb-dh"]  # fmt: skip


def _read_pty_until(fd: int, needle: bytes, limit_s: float) -> tuple[bytes, float | None]:
    """Read a pty until ``needle`` appears (time from now) or ``limit_s`` passes."""
    start, screen = time.monotonic(), b""
    while time.monotonic() - start < limit_s:
        ready, _, _ = select.select([fd], [], [], 0.05)
        if ready:
            try:
                chunk = os.read(fd, 65536)
            except OSError:
                break
            if not chunk:
                break
            screen += chunk
            if needle in screen:
                return screen, time.monotonic() - start
    return screen, None


def test_a_terminal_sees_the_header_and_a_progress_bar_within_two_seconds():
    pty = pytest.importorskip("pty")
    primary, secondary = pty.openpty()
    started = time.monotonic()
    proc = subprocess.Popen(_ARGV, stdin=secondary, stdout=secondary, stderr=secondary,
                            env=_ENV, close_fds=True)  # fmt: skip
    os.close(secondary)
    try:
        # The interpreter and fkcheck import first; the clock starts when fkcheck is running.
        screen, _ = _read_pty_until(primary, b"fkcheck ur5: base", 60)
        assert b"200000 sobol samples (seed 0)" in screen, screen[-500:]
        since_header = time.monotonic()
        screen2, seen = _read_pty_until(primary, b"configurations", 2.0)
        screen += screen2
        assert seen is not None, f"no progress within 2 s of the header: {screen[-800:]!r}"
        assert time.monotonic() - since_header < 2.5
        assert b"rtb-dh" in screen2
    finally:
        proc.kill()
        proc.wait()
        os.close(primary)
    assert time.monotonic() - started < 90


def test_a_pipe_sees_the_header_first_then_plain_lines_with_rate_and_eta_and_quiet_sees_none():
    run = subprocess.run([*_ARGV, "--progress-interval", "0.2"], capture_output=True,
                         text=True, env=_ENV, timeout=300, check=False)  # fmt: skip
    assert run.returncode == 0, run.stderr
    lines = [x for x in run.stderr.splitlines() if x.startswith("fkcheck: rtb-dh ")]
    assert len(lines) >= 2, run.stderr
    for line in lines:
        done, total = line.split()[2].split("/")
        assert 0 < int(done) < int(total) == 200081
        assert re.search(r", [\d,]+/s, ETA (\d+ s|\d+:\d\d)$", line), line
    assert "\x1b" not in run.stderr  # no terminal codes in a log
    assert "nanobind" not in run.stderr
    # The header is stdout's first line (flushed before anything runs), the result follows.
    first, second = run.stdout.splitlines()[:2]
    assert first.startswith("fkcheck ur5: base → tool0, 200000 sobol samples (seed 0), ")
    assert second == "200081 configurations compared"
    quiet = subprocess.run([*_ARGV[:-3], "20000", "--against", "rtb-dh", "--quiet",
                            "--progress-interval", "0.05"],
                           capture_output=True, text=True, env=_ENV, timeout=300,
                           check=False)  # fmt: skip
    assert quiet.returncode == 0, quiet.stderr
    assert "configurations," not in quiet.stderr
    assert "verdict: pass" in quiet.stdout


@pytest.mark.slow
def test_a_log_on_a_cold_numba_cache_opens_with_the_header_then_the_kernels_phase(tmp_path):
    """A fresh NUMBA_CACHE_DIR: the first compile is its own phase, said, after the header.

    stdout and stderr go to one pipe, as in a CI log: the order is the order written.
    """
    env = {**_ENV, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    run = subprocess.run([*_ARGV[:-3], "200000", "--against", "rtb-dh,pinocchio-dh"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                         timeout=600, check=False)  # fmt: skip
    assert run.returncode == 0, run.stdout
    lines = run.stdout.splitlines()
    assert lines[0].startswith("fkcheck ur5: base → tool0, 200000 sobol samples"), lines[:3]
    assert lines[1] == "fkcheck: compiling the core's kernels (first run only: 8–30 s)…"
    assert re.fullmatch(r"fkcheck: kernels ready \(\d+\.\d s\)", lines[2]), lines[2]
    assert any((tmp_path / "numba").rglob("*.nbi")), "numba cached nothing there"
    assert "nanobind" not in run.stdout


@pytest.mark.slow
def test_a_check_below_the_jits_size_loads_no_kernels_on_a_cold_cache(tmp_path):
    """10⁴ samples: the core's NumPy path takes milliseconds, numba would take seconds."""
    env = {**_ENV, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    samples = JIT_MIN_POSES - 100  # with the 81 structured configurations: still below
    run = subprocess.run([*_ARGV[:-3], str(samples), "--against", "rtb-dh,pinocchio-dh"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                         timeout=600, check=False)  # fmt: skip
    assert run.returncode == 0, run.stdout
    assert "kernels" not in run.stdout
    assert "verdict: pass" in run.stdout
    assert not any((tmp_path / "numba").rglob("*.nbi")), "numba compiled for a small check"


def test_plain_progress_is_thread_safe_and_lists_only_running_backends():
    stream = io.StringIO()
    with check_progress(["a", "b", "c"], interval_s=0.05, stream=stream) as update:
        assert update is not None

        def work(name: str) -> None:
            for k in range(1, 201):
                update(name, k, 400)

        threads = [threading.Thread(target=work, args=(n,)) for n in ("a", "b")]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        update("c", 10, 10)  # finished: never listed
        time.sleep(0.2)
    lines = stream.getvalue().splitlines()
    assert lines
    assert {line.split()[1] for line in lines} == {"a", "b"}
    assert all(" 200/400 configurations, " in line for line in lines)


def test_quiet_gives_no_callback():
    with check_progress(["a"], quiet=True) as update:
        assert update is None


def test_plain_line_escapes_control_characters():
    assert plain_line("x\x1b[2Jy", 5, 10, 1.25) == "fkcheck: x\\x1b[2Jy 5/10 configurations, 1.2 s"


def test_plain_line_gives_rate_and_eta_and_says_when_the_eta_passes_the_limit():
    line = plain_line("yourdfpy-urdf", 65_536, 1_000_081, 20.0, rate=3_276.8, limit_s=120.0)
    assert line == (
        "fkcheck: yourdfpy-urdf 65536/1000081 configurations, 20.0 s, 3,277/s, ETA 4:45, "
        "beyond its 120 s limit"
    )
    assert plain_line("a", 50, 100, 1.0, rate=50.0, limit_s=120.0).endswith(", 50/s, ETA 1 s")
