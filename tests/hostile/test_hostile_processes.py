"""Code fkcheck runs — plugins, cmd: programs, isolated backends — cannot hang it, end
it with success, or outlive it (issue 15: processes, time limits and hangs).

Each case runs ``fkcheck check`` as a user would and asserts the exit code, the one
line that says what happened, a bound on the wall time, and that no process it
started is left running afterwards.
"""

from __future__ import annotations

import functools
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import textwrap
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from fkcheck.backends.command import CommandBackend
from fkcheck.backends.plugin import PluginBackend
from fkcheck.backends.registry import BackendOptions
from fkcheck.cli.main import TERMINATE_BACKSTOP_S
from fkcheck.engine.runner import run_check
from fkcheck.model.read import load_model
from fkcheck.process.isolation import run_isolated
from fkcheck.process.supervise import (
    MAX_TIMEOUT_S,
    STDERR_TAIL_BYTES,
    TERMINATE_GRACE_S,
    IsolatedDied,
    IsolatedTimeout,
    run_supervised,
)
from tests.paths import TESTS_DIR
from tests.processes import (
    LINUX_ONLY,
    alive,
    assert_gone,
    descendants,
    interruptible,
    wait_for_pids,
)

pytestmark = LINUX_ONLY

TESTS = TESTS_DIR
SRC = TESTS.parent / "src"
PLUGINS = TESTS / "plugins"
#: A CLI run on a loaded machine: interpreter start, imports, sampling, report.
CLI_OVERHEAD_S = 15.0

#: A program that hangs after starting a sleeper in a session of its own.
HANG = 'setsid sh -c \'echo $$ > "$0.tmp"; mv "$0.tmp" "$0"; exec sleep 600\' {pids} & sleep 600'


def _env(tmp_path: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(SRC), str(PLUGINS)])
    env["FKCHECK_TEST_PIDS"] = str(tmp_path / "pids")
    env["COLUMNS"] = "400"  # one table row per backend: the message is never folded
    return env


_STARTED: list[subprocess.Popen[str]] = []


@pytest.fixture(autouse=True)
def _none_left_running() -> Iterator[None]:
    """A test that fails half-way does not leave its fkcheck running into the next ones."""
    yield
    while _STARTED:
        proc = _STARTED.pop()
        if proc.poll() is None:
            proc.kill()  # its supervisors hear of it from the kernel (PR_SET_PDEATHSIG)
        proc.communicate()


def _popen(argv: list[str], tmp_path: Path) -> subprocess.Popen[str]:
    proc = subprocess.Popen(
        argv, cwd=tmp_path, env=_env(tmp_path), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, preexec_fn=interruptible,
    )  # fmt: skip
    _STARTED.append(proc)
    return proc


def _start(tmp_path: Path, against: str, *extra: str) -> subprocess.Popen[str]:
    """``fkcheck check ur5 --against AGAINST`` in ``tmp_path``, writing ``out.json``."""
    argv = [sys.executable, "-m", "fkcheck.cli.main", "check", "ur5", "--samples", "5",
            "--against", against, "--json", str(tmp_path / "out.json"), *extra]  # fmt: skip
    return _popen(argv, tmp_path)


def _message(tmp_path: Path) -> str:
    (backend,) = json.loads((tmp_path / "out.json").read_text())["backends"]
    message: str = backend["message"]
    return message


# ---------------------------------------------------------------- plugins through the CLI


def test_plugin_calling_os_exit_0_is_an_error_with_a_report(tmp_path: Path) -> None:
    proc = _start(tmp_path, "hostile:exit_zero")
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 1, (out, err)
    line = "plugin hostile:exit_zero: its process exited with code 0 without an answer"
    assert line in _message(tmp_path)
    assert line in out
    assert "verdict: error" in out


def test_plugin_leaving_a_non_daemon_thread_does_not_keep_fkcheck_alive(tmp_path: Path) -> None:
    start = time.monotonic()
    proc = _start(tmp_path, "hostile:thread_left")
    out, err = proc.communicate(timeout=60)
    assert time.monotonic() - start < CLI_OVERHEAD_S  # the thread sleeps 600 s
    assert proc.returncode == 0, (out, err)
    assert "verdict: pass — implementation only" in out
    assert "(1 backend(s) answered)" in out


def test_plugin_holding_the_gil_is_killed_at_the_timeout(tmp_path: Path) -> None:
    start = time.monotonic()
    proc = _start(tmp_path, "hostile:holds_gil", "--timeout", "2")
    (worker,) = wait_for_pids(tmp_path / "pids")
    running = time.monotonic()  # the plugin runs: its 2 s started a moment earlier
    out, err = proc.communicate(timeout=60)
    assert time.monotonic() - running < 2.0 + TERMINATE_GRACE_S + 2.0
    assert time.monotonic() - start < 2.0 + CLI_OVERHEAD_S
    assert proc.returncode == 1, (out, err)
    assert _message(tmp_path) == "timed out after 2 s"
    assert re.search(r"hostile:holds_gil \(error\): timed out after 2 s", out), out
    assert_gone([worker], within_s=1.0)


def test_plugin_process_is_found_where_fkcheck_imports_from(tmp_path: Path) -> None:
    # A module in the current directory, on sys.path via `python -m`, as today.
    (tmp_path / "here_fk.py").write_text("from ur5_closed_form import forward\n")
    proc = _start(tmp_path, "here_fk:forward")
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, (out, err)
    assert "verdict: pass" in out


# ---------------------------------------------------------------- signals and kill -9


def _hang_spec(tmp_path: Path) -> str:
    return "cmd:" + shlex.join(["sh", "-c", HANG.format(pids=shlex.quote(str(tmp_path / "pids")))])


SIGNALS = [(signal.SIGTERM, 143, "terminated"), (signal.SIGINT, 130, "interrupted")]


@pytest.mark.parametrize("kind", ["plugin", "cmd"])
@pytest.mark.parametrize(("sig", "code", "word"), SIGNALS, ids=["SIGTERM", "SIGINT"])
def test_a_signal_ends_fkcheck_at_once_and_leaves_no_process(
    tmp_path: Path, kind: str, sig: int, code: int, word: str
) -> None:
    against = "hostile:holds_gil" if kind == "plugin" else _hang_spec(tmp_path)
    proc = _start(tmp_path, against, "--timeout", "300")
    wait_for_pids(tmp_path / "pids")
    tree = descendants(proc.pid)  # supervisor, program, and what it started
    assert len(tree) >= 2, tree
    sent = time.monotonic()
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=60)
    assert time.monotonic() - sent < 1.0 + TERMINATE_GRACE_S
    assert proc.returncode == code, (out, err)
    assert f"fkcheck: {word}" in err
    assert_gone(tree, within_s=0.5)  # killed before fkcheck exited


def test_sigterm_during_an_isolated_backend_leaves_no_child(tmp_path: Path) -> None:
    # The case: yourdfpy's process ran on for 5-10 s after fkcheck exited.
    pytest.importorskip("yourdfpy")
    proc = _start(tmp_path, "yourdfpy-urdf", "--samples", "300000", "--full")
    deadline = time.monotonic() + 60
    while not (tree := descendants(proc.pid)) or len(tree) < 2:
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.05)
    time.sleep(0.5)  # into the job
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, (out, err)
    assert_gone(tree, within_s=0.5)


#: Stands in for llvmlite's ``__del__`` (numba compiling the kernels) or a library's
#: ``except BaseException``: where the signal's exception lands, it is swallowed.
SWALLOWER = """
    import sys, time
    import fkcheck.cli.main as cli

    def swallow_everything(args_list):
        open(sys.argv[1], "w").close()  # ready for the signal
        while True:
            try:
                time.sleep(0.01)
            except BaseException:
                pass

    cli._run = swallow_everything
    sys.exit(cli.main())
"""


def test_sigterm_whose_exception_is_swallowed_still_ends_fkcheck(tmp_path: Path) -> None:
    # CI's case: SIGTERM landed in llvmlite's __del__ during a cold numba compile,
    # Python printed "Exception ignored in …" and the check ran on to its end.
    script = tmp_path / "swallow.py"
    script.write_text(textwrap.dedent(SWALLOWER), encoding="utf-8")
    ready = tmp_path / "ready"
    proc = _popen([sys.executable, str(script), str(ready)], tmp_path)
    deadline = time.monotonic() + 60
    while not ready.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.02)
    sent = time.monotonic()
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=60)
    took = time.monotonic() - sent
    assert proc.returncode == 143, (out, err)
    assert err.strip() == "fkcheck: terminated (SIGTERM): results incomplete, no report written"
    assert TERMINATE_BACKSTOP_S <= took < TERMINATE_BACKSTOP_S + TERMINATE_GRACE_S + 2.0


def test_kill_9_of_fkcheck_still_leaves_no_process(tmp_path: Path) -> None:
    proc = _start(tmp_path, _hang_spec(tmp_path), "--timeout", "300")
    wait_for_pids(tmp_path / "pids")
    tree = descendants(proc.pid)
    proc.kill()  # no atexit, no handler: the supervisor hears of it from the kernel
    proc.communicate(timeout=60)
    assert_gone(tree, within_s=TERMINATE_GRACE_S + 1.0)


# ---------------------------------------------------------------- cmd: programs through the CLI


def test_program_flooding_stdout_is_an_error_in_bounded_time(tmp_path: Path) -> None:
    start = time.monotonic()
    proc = _start(tmp_path, "cmd:yes 1.0")
    out, err = proc.communicate(timeout=60)
    assert time.monotonic() - start < CLI_OVERHEAD_S
    assert proc.returncode == 1, (out, err)
    assert (
        "cmd:yes 1.0: printed more than 1110 lines for 86 configurations (the program was killed)"
        in _message(tmp_path)
    )


def test_program_leaving_a_sleeper_in_its_own_session_times_out_and_it_dies(
    tmp_path: Path,
) -> None:
    proc = _start(tmp_path, _hang_spec(tmp_path), "--timeout", "2")
    pids = wait_for_pids(tmp_path / "pids")
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 1, (out, err)
    # The check's limit and the program's own (the same 2 s) race: either one says so.
    assert _message(tmp_path) in (
        "timed out after 2 s",
        f"{_hang_spec(tmp_path)}: timed out after 2 s (the program was killed)",
    )
    assert_gone(pids, within_s=1.0)


# ---------------------------------------------------------------- the engine and the supervisor


def test_run_check_returns_at_the_timeout_and_the_plugin_dies_right_after(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.syspath_prepend(PLUGINS)
    monkeypatch.setenv("FKCHECK_TEST_PIDS", str(tmp_path / "pids"))
    # The plugin's own limit is the default 120 s: the check's 2 s must win.
    backend = PluginBackend("hostile:holds_gil", BackendOptions())
    start = time.monotonic()
    check = run_check(load_model("ur5"), [backend], samples=5, timeout_s=2.0)
    assert time.monotonic() - start < 2.0 + 3.0  # + loading the model, sampling
    assert (check.verdict, check.backends[0].message) == ("error", "timed out after 2 s")
    assert_gone(wait_for_pids(tmp_path / "pids", 1.0), within_s=0.5)


def test_every_process_a_program_started_dies_with_it(tmp_path: Path) -> None:
    # 20 sleepers, each double-forked into a session of its own: orphans all.
    pids = tmp_path / "pids"
    script = (
        f"for i in $(seq 20); do (setsid sleep 600 & echo $! >> {shlex.quote(str(pids))}) ; done;"
        " sleep 600"
    )
    start = time.monotonic()
    with pytest.raises(IsolatedTimeout):
        run_supervised(["sh", "-c", script], b"", 1.5, max_stdout_bytes=1000)
    assert time.monotonic() - start < 1.5 + TERMINATE_GRACE_S + 1.0
    sleepers = [int(p) for p in pids.read_text().split()]
    assert len(sleepers) == 20
    assert_gone(sleepers, within_s=0.5)


def test_stderr_is_kept_as_a_bounded_tail() -> None:
    shell = "head -c 30000000 /dev/zero | tr '\\0' e >&2; echo ' the end' >&2; echo out"
    done = run_supervised(["sh", "-c", shell], b"", 60, max_stdout_bytes=10)
    assert (done.returncode, done.stdout) == (0, b"out\n")
    assert len(done.stderr_tail) == STDERR_TAIL_BYTES
    assert done.stderr_tail.endswith(b"eee the end\n")


def test_an_isolated_answer_past_its_limit_is_refused_in_bounded_time() -> None:
    start = time.monotonic()
    with pytest.raises(IsolatedDied, match=r"^its answer was larger than 1000000 bytes"):
        run_isolated(functools.partial(bytes, 50_000_000), 60, max_answer_bytes=1_000_000)
    assert time.monotonic() - start < 10.0


def test_an_isolated_job_that_prints_still_answers() -> None:
    got = run_isolated(functools.partial(print, "noise on stdout"), 60)
    assert got is None
    q = np.arange(6.0)
    np.testing.assert_array_equal(run_isolated(functools.partial(np.copy, q), 60), q)


def test_the_supervisor_itself_is_gone_after_a_run() -> None:
    before = set(descendants(os.getpid()))
    done = run_supervised(["sh", "-c", "sleep 600 & echo started"], b"", 60, max_stdout_bytes=100)
    assert done.stdout == b"started\n"
    left = [p for p in descendants(os.getpid()) if p not in before and alive(p)]
    assert not left


def test_a_module_in_the_current_directory_is_not_imported_by_the_child(tmp_path: Path) -> None:
    # fkcheck run without the current directory on sys.path (as the `fkcheck` script
    # is): its child processes must not pick up a numpy.py lying there either.
    (tmp_path / "numpy.py").write_text("open('pwned', 'w').close()\nraise SystemExit(9)\n")
    argv = [sys.executable, "-P", "-m", "fkcheck.cli.main", "check", "ur5", "--samples", "5",
            "--against", "ur5_closed_form:forward"]  # fmt: skip
    run = subprocess.run(
        argv, cwd=tmp_path, env=_env(tmp_path), capture_output=True, text=True, timeout=60
    )
    assert run.returncode == 0, (run.stdout, run.stderr)
    assert not (tmp_path / "pwned").exists()


def test_a_time_limit_too_large_for_the_clock_means_no_limit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # 1e10 s overflows thread joins and select(); it must simply never fire. A check's
    # own limit is at most a day (fkcheck.model.options), but a backend built
    # directly may be given any number.
    monkeypatch.syspath_prepend(PLUGINS)
    options = BackendOptions(timeout_s=1e10)
    program = shlex.join([sys.executable, str(PLUGINS / "fk_stdio.py"), "ok"])
    backends = [PluginBackend("ur5_closed_form:forward", options), CommandBackend(program, options)]
    check = run_check(load_model("ur5"), backends, samples=5, timeout_s=MAX_TIMEOUT_S)
    assert [b.status for b in check.backends] == ["pass", "pass"]
    assert check.verdict == "pass"


def test_a_thread_the_check_gave_up_on_starts_no_new_program() -> None:
    """After terminate_all(started_by=thread), that thread's next program is refused at once.

    An abandoned backend's thread may still be looping over batches (a plugin with
    more than 65 536 configurations): its next batch must not start a process
    that runs on until its own time limit.
    """
    import threading

    from fkcheck.process.supervise import IsolatedTimeout, run_supervised, terminate_all

    outcome: list[BaseException | None] = []

    def backend_thread() -> None:
        terminate_all(started_by=threading.current_thread())
        start = time.monotonic()
        try:
            run_supervised([sys.executable, "-c", "import time; time.sleep(30)"], b"", 30.0,
                           max_stdout_bytes=1024)  # fmt: skip
        except IsolatedTimeout as exc:
            outcome.append(exc)
        else:
            outcome.append(None)
        assert time.monotonic() - start < 5.0

    thread = threading.Thread(target=backend_thread)
    thread.start()
    thread.join(60)
    (exc,) = outcome
    assert isinstance(exc, IsolatedTimeout)
    assert "gave this backend up" in str(exc)
    # Another thread is not affected.
    done = run_supervised([sys.executable, "-c", "print(1)"], b"", 30.0, max_stdout_bytes=1024)
    assert done.stdout.strip() == b"1"


def test_a_backend_left_at_its_time_limit_ends_the_run_in_its_own_lines(tmp_path):
    """No interpreter finalization under a thread still in C++: nanobind's leak report
    (dozens of lines) used to follow the one that said "timed out"; the exit code stays."""
    done = subprocess.run(
        [sys.executable, "-m", "fkcheck", "check", "ur5", "--samples", "300000", "--full",
         "--timeout", "1", "--against", "pinocchio-dh,rtb-urdf"],
        capture_output=True, text=True, timeout=300, cwd=tmp_path, check=False,
    )  # fmt: skip
    assert "verdict: error — no backend gave an answer" in done.stdout  # both timed out
    assert done.returncode == 1
    assert "nanobind" not in done.stderr
    assert "leaked" not in done.stderr
