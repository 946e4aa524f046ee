"""``fkcheck check`` shows its progress: a live display on a terminal, plain lines in a pipe."""

from __future__ import annotations

import io
import os
import select
import subprocess
import sys
import threading
import time

import pytest

from fkcheck.cli.progress import check_progress, plain_line

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


def test_a_pipe_sees_periodic_plain_lines_and_quiet_sees_none():
    run = subprocess.run([*_ARGV, "--progress-interval", "0.2"], capture_output=True,
                         text=True, env=_ENV, timeout=300, check=False)  # fmt: skip
    assert run.returncode == 0, run.stderr
    lines = [x for x in run.stderr.splitlines() if x.startswith("fkcheck: rtb-dh ")]
    assert len(lines) >= 2, run.stderr
    for line in lines:
        done, total = line.split()[2].split("/")
        assert 0 < int(done) < int(total) == 200081
        assert line.endswith(" s")
    assert "\x1b" not in run.stderr  # no terminal codes in a log
    # In a log stdout holds the result only: the description opens the table.
    assert run.stdout.startswith(
        "fkcheck ur5: base → tool0, 200081 configurations (200000 sobol samples, seed 0), "
        "tolerance 1e-06 m / 1e-06 rad\n"
    )
    quiet = subprocess.run([*_ARGV[:-3], "20000", "--against", "rtb-dh", "--quiet",
                            "--progress-interval", "0.05"],
                           capture_output=True, text=True, env=_ENV, timeout=300,
                           check=False)  # fmt: skip
    assert quiet.returncode == 0, quiet.stderr
    assert "configurations," not in quiet.stderr
    assert "verdict: pass" in quiet.stdout


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
