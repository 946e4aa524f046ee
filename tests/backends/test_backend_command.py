"""The command backend: an external FK program over stdin/stdout, and the C++/Eigen example."""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from fkcheck.backends import command
from fkcheck.backends.base import Backend, FrameUnavailable
from fkcheck.backends.command import CommandBackend, CommandError, CommandSpecError
from fkcheck.backends.registry import BackendOptions, make_backend, parse_against
from fkcheck.core.tolerances import SAME_CHAIN, SIX_DECIMALS
from fkcheck.errors import FkcheckError, JointInputError
from fkcheck.model.frames import frame_poses_from_dh
from fkcheck.model.read import load_model
from fkcheck.model.types import Model
from fkcheck.process.supervise import TERMINATE_GRACE_S
from tests import seed_ur5
from tests.helpers import assert_pose_close, assert_se3, random_q
from tests.paths import PLUGINS_DIR, REPO_ROOT
from tests.processes import LINUX_ONLY, assert_gone, wait_for_pids

ROOT = REPO_ROOT
SCRIPT = PLUGINS_DIR / "fk_stdio.py"
EXAMPLE = ROOT / "examples" / "cpp_eigen"
UR5_FRAMES = ["world", "tcp", "base", "base_link", "tool0", "flange"]


@pytest.fixture(scope="module")
def ur5() -> Model:
    return load_model("ur5")


def script(*args: str, timeout_s: float = 60.0) -> CommandBackend:
    """The Python FK fixture program as a backend, run with this interpreter."""
    spec = shlex.join([sys.executable, str(SCRIPT), *args])
    return CommandBackend(spec, BackendOptions(timeout_s=timeout_s))


# ---------------------------------------------------------------- a working program


@pytest.mark.parametrize("mode", ["ok", "comma"])
def test_program_poses_agree_with_core_on_every_ur5_frame(
    ur5: Model, rng: np.random.Generator, mode: str
) -> None:
    q = random_q(ur5, rng, 300)
    poses = script(mode).frame_poses(ur5, q, UR5_FRAMES)
    assert poses.shape == (len(UR5_FRAMES), 300, 4, 4)
    expected = frame_poses_from_dh(ur5, ur5.fk(q, all_frames=True), ur5.fk(q), UR5_FRAMES)
    for name, got, want in zip(UR5_FRAMES, poses, expected, strict=True):
        assert_pose_close(got, want, SAME_CHAIN, what=name)


def test_batches_are_split_and_reassembled_in_order(
    ur5: Model, rng: np.random.Generator, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(command, "BATCH_SIZE", 7)  # 23 configurations → 4 runs, last one short
    q = random_q(ur5, rng, 23)
    (tcp,) = script("ok").frame_poses(ur5, q, ["tcp"])
    assert_pose_close(tcp, ur5.fk(q), SAME_CHAIN)


def test_no_configurations_runs_nothing(ur5: Model) -> None:
    backend = CommandBackend("./fkcheck-no-such-program", BackendOptions())
    poses = backend.frame_poses(ur5, np.zeros((0, 6)), ["tcp", "base"])
    assert poses.shape == (2, 0, 4, 4)


def test_registry_builds_a_command_backend_with_the_rest_of_the_value() -> None:
    line = f"{shlex.quote(sys.executable)} {shlex.quote(str(SCRIPT))} ok, with comma"
    (backend,) = parse_against([f"cmd:{line}"])
    assert isinstance(backend, CommandBackend)
    assert isinstance(backend, Backend)
    assert backend.name == f"cmd:{line}"
    assert backend.argv == [sys.executable, str(SCRIPT), "ok,", "with", "comma"]
    assert make_backend("cmd: ./fk_tool --flag").name == "cmd:./fk_tool --flag"


def test_arguments_are_split_like_a_posix_shell_and_run_without_one(ur5: Model) -> None:
    backend = script("echo-argv", "two words", "$HOME;|*")
    with pytest.raises(
        CommandError, match=re.escape("status 4: argv=echo-argv|two words|$HOME;|*")
    ):
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])


# ---------------------------------------------------------------- failing programs

FAILURES = [
    ("garbage", "configuration 1: 'zero' is not a number in line"),
    ("arabic-digits", "configuration 1: '\u0661.\u0660' is not a number in line"),
    ("short", "configuration 0: expected 16 numbers (row-major 4×4), got 15"),
    ("missing", "printed 4 pose lines for 5 configurations (configurations 0…4)"),
    ("exit", "exited with status 3: fk_stdio: cannot handle 5 lines"),
]


def test_nan_printed_by_a_program_is_an_answer_the_engine_fails(ur5: Model) -> None:
    """NaN is a wrong answer, not no answer: the poses reach the engine, which fails them."""
    from fkcheck.engine.runner import run_check

    check = run_check(ur5, [script("nan")], samples=2, frame_from="world", frame_to="tcp")
    (row,) = check.backends
    assert row.status == "fail"
    assert re.search(r"returned NaN or inf at 1 of \d+ configurations", row.message), row.message
    assert check.verdict == "fail"


@pytest.mark.parametrize(("mode", "message"), FAILURES, ids=[m for m, _ in FAILURES])
def test_failing_program_raises_a_command_error_naming_the_problem(
    ur5: Model, mode: str, message: str
) -> None:
    backend = script(mode)
    q = np.outer(np.arange(5) / 10.0, np.ones(6))
    with pytest.raises(CommandError, match=re.escape(f"{backend.name}: {message}")):
        backend.frame_poses(ur5, q, ["tcp"])


def test_missing_program_is_reported_not_skipped(ur5: Model) -> None:
    backend = CommandBackend("./no/such/fk_tool --x", BackendOptions())
    assert backend.unavailable_reason(ur5) is None
    with pytest.raises(CommandError, match=re.escape("program './no/such/fk_tool' not found")):
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])


def test_missing_program_on_path_says_so(ur5: Model) -> None:
    backend = CommandBackend("fkcheck-no-such-program-xyz", BackendOptions())
    with pytest.raises(CommandError, match="'fkcheck-no-such-program-xyz' not found on PATH"):
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])


def test_non_executable_program_is_reported(ur5: Model, tmp_path: Path) -> None:
    program = tmp_path / "fk.sh"
    program.write_text("#!/bin/sh\n")
    program.chmod(0o644)
    backend = CommandBackend(shlex.quote(str(program)), BackendOptions())
    with pytest.raises(CommandError, match="is not executable"):
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])


def _alive(pid: int) -> bool:
    """Whether a process exists and is not a zombie (PID 1 may not reap in containers)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


@pytest.mark.skipif(sys.platform != "linux", reason="reads /proc to see the processes died")
def test_hanging_program_is_killed_with_its_children_at_the_time_limit(
    ur5: Model, tmp_path: Path
) -> None:
    pidfile = tmp_path / "pids"
    backend = script("hang", str(pidfile), timeout_s=2.0)
    start = time.monotonic()
    with pytest.raises(CommandError, match=r"timed out after 2 s \(the program was killed\)"):
        backend.frame_poses(ur5, np.zeros((3, 6)), ["tcp"])
    assert time.monotonic() - start < 10.0
    pids = [int(p) for p in pidfile.read_text().split()]
    assert len(pids) == 2
    deadline = time.monotonic() + 5.0
    while any(_alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not any(_alive(p) for p in pids), f"still running: {pids}"


ABANDON = """
import sys, threading, time
from pathlib import Path
import numpy as np
from fkcheck.backends.command import CommandBackend
from fkcheck.backends.registry import BackendOptions
from fkcheck.model import load_model

spec, pidfile = sys.argv[1], Path(sys.argv[2])
backend = CommandBackend(spec, BackendOptions(timeout_s=300.0))
args = (load_model("ur5"), np.zeros((1, 6)), ["tcp"])
threading.Thread(target=backend.frame_poses, args=args, daemon=True).start()
while not pidfile.exists():
    time.sleep(0.02)
"""


@pytest.mark.skipif(sys.platform != "linux", reason="reads /proc to see the processes died")
def test_program_abandoned_by_an_exiting_interpreter_is_killed(tmp_path: Path) -> None:
    # The check gives up on a backend thread at its time limit and may exit first.
    pidfile = tmp_path / "pids"
    spec = shlex.join([sys.executable, str(SCRIPT), "hang", str(pidfile)])
    subprocess.run([sys.executable, "-c", ABANDON, spec, str(pidfile)], check=True, timeout=60)
    pids = [int(p) for p in pidfile.read_text().split()]
    assert len(pids) == 2
    deadline = time.monotonic() + 5.0
    while any(_alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not any(_alive(p) for p in pids), f"still running: {pids}"


def test_unbalanced_quotes_are_bad_input() -> None:
    with pytest.raises(CommandSpecError, match="cannot split command line: No closing quotation"):
        CommandBackend("./fk 'oops", BackendOptions())
    assert issubclass(CommandSpecError, FkcheckError)
    assert not issubclass(CommandError, FkcheckError)


def test_empty_command_is_bad_input() -> None:
    with pytest.raises(CommandSpecError, match="empty command line"):
        CommandBackend("   ", BackendOptions())


def test_mid_chain_frame_is_unavailable_before_anything_runs() -> None:
    panda = load_model("panda")
    backend = CommandBackend("./fkcheck-no-such-program", BackendOptions())
    with pytest.raises(FrameUnavailable, match="'panda_link3' sits at DH frame 3, mid-chain"):
        backend.frame_poses(panda, np.zeros((1, panda.dof)), ["panda_link3"])


def test_q_of_the_wrong_width_is_refused(ur5: Model) -> None:
    with pytest.raises(JointInputError, match=r"expected 6 joint values .* got shape \(2, 7\)"):
        script("ok").frame_poses(ur5, np.zeros((2, 7)), ["tcp"])


def test_non_finite_q_is_refused_before_anything_runs(ur5: Model) -> None:
    q = np.zeros((2, 6))
    q[1, 0] = np.inf
    backend = CommandBackend("./fkcheck-no-such-program", BackendOptions())
    with pytest.raises(JointInputError, match="configuration 1 joint 1 is inf"):
        backend.frame_poses(ur5, q, ["tcp"])


# ---------------------------------------------------------------- the C++/Eigen example

_NO_TOOLCHAIN = "no C++ compiler / cmake / Eigen3 found: "


def missing_tool(cmake_output: str) -> str | None:
    """cmake's own error when a configure failed for want of a compiler or Eigen3, else ``None``.

    The error's heading (``CMake Error at CMakeLists.txt:14 (find_package):``) and its
    first paragraph, on one line: the lines cmake printed before it (``The CXX compiler
    identification is GNU 12.2.0``) say what it found, not what is missing.
    """
    lines = cmake_output.splitlines()
    for i, line in enumerate(lines):
        if not line.startswith("CMake Error"):
            continue
        paragraph = []
        for more in lines[i + 1 :]:
            if not more.strip():
                break
            paragraph.append(more.strip())
        text = " ".join(paragraph)
        if 'provided by "Eigen3"' in text:
            text = text.split(" with any of the following names", 1)[0]
            return f"{line.strip()} {text} (Debian: apt-get install libeigen3-dev)"
        if "No CMAKE_CXX_COMPILER" in text:
            return f"{line.strip()} {text}"
    return None


@pytest.fixture(scope="module")
def fk_tool(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """examples/cpp_eigen built from source into a fresh directory."""
    if shutil.which("cmake") is None:
        pytest.skip(_NO_TOOLCHAIN + "cmake is not on PATH")
    if not any(shutil.which(cxx) for cxx in ("c++", "g++", "clang++")):
        pytest.skip(_NO_TOOLCHAIN + "no c++/g++/clang++ on PATH")
    build = tmp_path_factory.mktemp("cpp_eigen_build")
    configure = subprocess.run(
        ["cmake", "-S", str(EXAMPLE), "-B", str(build)],
        capture_output=True,
        text=True,
        check=False,
    )
    if configure.returncode != 0:
        output = configure.stdout + configure.stderr
        missing = missing_tool(output)
        if missing is not None:
            pytest.skip(_NO_TOOLCHAIN + missing)
        pytest.fail(f"cmake configure failed:\n{output}")
    compiled = subprocess.run(
        ["cmake", "--build", str(build)], capture_output=True, text=True, check=False
    )
    assert compiled.returncode == 0, compiled.stdout + compiled.stderr
    return build / "fk_tool"


def test_cpp_example_agrees_with_core_on_random_configurations(
    fk_tool: Path, ur5: Model, rng: np.random.Generator
) -> None:
    q = random_q(ur5, rng, 5000)  # two batches
    backend = CommandBackend(shlex.quote(str(fk_tool)), BackendOptions(timeout_s=60.0))
    tcp, flange = backend.frame_poses(ur5, q, ["tcp", "flange"])
    assert_pose_close(tcp, ur5.fk(q), SAME_CHAIN)
    assert_se3(tcp, SAME_CHAIN)
    expected_flange = frame_poses_from_dh(ur5, ur5.fk(q, all_frames=True), ur5.fk(q), ["flange"])
    assert_pose_close(flange, expected_flange[0], SAME_CHAIN)


def test_cpp_example_reproduces_seed_hand_computation(fk_tool: Path, ur5: Model) -> None:
    backend = CommandBackend(shlex.quote(str(fk_tool)), BackendOptions())
    (tcp,) = backend.frame_poses(ur5, np.deg2rad([seed_ur5.Q_DEG]), ["tcp"])
    np.testing.assert_allclose(
        tcp[0, :3, 3], [-0.505612, -0.417951, 0.178795], rtol=0, atol=SIX_DECIMALS
    )
    np.testing.assert_allclose(tcp[0], seed_ur5.T0[6], rtol=0, atol=SIX_DECIMALS)


def test_cpp_example_rejects_a_model_with_the_wrong_joint_count(fk_tool: Path) -> None:
    planar2 = load_model("planar2")
    backend = CommandBackend(shlex.quote(str(fk_tool)), BackendOptions())
    with pytest.raises(
        CommandError,
        match=re.escape("exited with status 1: fk_tool: line 1: expected 6 comma-separated"),
    ):
        backend.frame_poses(planar2, np.zeros((1, planar2.dof)), ["tcp"])


@pytest.mark.parametrize(
    ("line", "problem"),
    [
        ("0,0,0,0,0", "expected 6 comma-separated numbers, got 5"),
        ("0,0,0,0,0,0,0", "expected 6 comma-separated numbers, got more (or trailing text)"),
        ("0,0,0,0,0,0 rad", "expected 6 comma-separated numbers, got more (or trailing text)"),
        ("0,0,x,0,0,0", "field 3 is not a number"),
        ("0,0,0,nan,0,0", "field 4 is not a finite number"),
    ],
)
def test_cpp_example_reports_a_bad_line_on_stderr(fk_tool: Path, line: str, problem: str) -> None:
    run = subprocess.run(
        [str(fk_tool)], input=f"0,0,0,0,0,0\n\n{line}\n", capture_output=True, text=True
    )
    assert run.returncode == 1
    assert run.stderr == f"fk_tool: line 3: {problem}: '{line}'\n"
    assert len(run.stdout.split()) == 16  # the good first line was answered


# ---------------------------------------------------------------- hostile programs (issue 15)

LEAVER = """
import os, subprocess, sys, time
from pathlib import Path

mode, pidfile = sys.argv[1], Path(sys.argv[2])
if mode.startswith("daemon"):  # double fork: the sleeper is orphaned in a session of its own
    pid = os.fork()
    if pid == 0:
        os.setsid()
        sleeper = subprocess.Popen(["sleep", "600"])
        pidfile.with_suffix(".tmp").write_text(f"{os.getpid()} {sleeper.pid}")
        pidfile.with_suffix(".tmp").replace(pidfile)
        os._exit(0)
    os.waitpid(pid, 0)
else:  # setsid sleep 600 &, holding our stdout
    sleeper = subprocess.Popen(["sleep", "600"], start_new_session=True)
    pidfile.with_suffix(".tmp").write_text(f"{os.getpid()} {sleeper.pid}")
    pidfile.with_suffix(".tmp").replace(pidfile)
if mode.endswith("hang"):
    time.sleep(600)
os.execv(sys.executable, [sys.executable, sys.argv[3], "ok"])
"""


@LINUX_ONLY
@pytest.mark.parametrize("mode", ["session-hang", "daemon-hang"])
def test_hanging_program_is_killed_with_what_left_its_session(
    ur5: Model, tmp_path: Path, mode: str
) -> None:
    program, pidfile = tmp_path / "leaver.py", tmp_path / "pids"
    program.write_text(LEAVER)
    spec = shlex.join([sys.executable, str(program), mode, str(pidfile), str(SCRIPT)])
    backend = CommandBackend(spec, BackendOptions(timeout_s=2.0))
    start = time.monotonic()
    with pytest.raises(CommandError, match=r"timed out after 2 s \(the program was killed\)$"):
        backend.frame_poses(ur5, np.zeros((3, 6)), ["tcp"])
    assert time.monotonic() - start < 2.0 + TERMINATE_GRACE_S + 1.0
    assert_gone(wait_for_pids(pidfile, 1.0), within_s=1.0)


@LINUX_ONLY
@pytest.mark.parametrize("mode", ["session", "daemon"])
def test_program_that_answers_and_leaves_a_process_behind_passes_and_the_process_dies(
    ur5: Model, tmp_path: Path, mode: str
) -> None:
    # The sleeper keeps the program's stdout open: the run must not wait for it.
    program, pidfile = tmp_path / "leaver.py", tmp_path / "pids"
    program.write_text(LEAVER)
    spec = shlex.join([sys.executable, str(program), mode, str(pidfile), str(SCRIPT)])
    q = np.full((5, 6), 0.7)
    start = time.monotonic()
    (tcp,) = CommandBackend(spec, BackendOptions(timeout_s=60.0)).frame_poses(ur5, q, ["tcp"])
    assert time.monotonic() - start < 15.0
    assert_pose_close(tcp, ur5.fk(q), SAME_CHAIN)
    assert_gone(wait_for_pids(pidfile, 1.0), within_s=1.0)


FLOODS = [
    ("yes 0", f"printed more than {5 + command.EXTRA_LINES} lines for 5 configurations"),
    (
        "tr -d '\\n' < /dev/zero",
        f"printed a line longer than {command.MAX_LINE_BYTES} bytes for 5 configurations",
    ),
]


@pytest.mark.parametrize(("shell", "problem"), FLOODS, ids=["many-lines", "endless-line"])
def test_program_flooding_stdout_is_stopped_at_the_output_limit(
    ur5: Model, shell: str, problem: str
) -> None:
    backend = CommandBackend(shlex.join(["sh", "-c", shell]), BackendOptions(timeout_s=60.0))
    start = time.monotonic()
    with pytest.raises(CommandError) as caught:
        backend.frame_poses(ur5, np.zeros((5, 6)), ["tcp"])
    assert time.monotonic() - start < 10.0
    assert str(caught.value) == f"{backend.name}: {problem} (the program was killed)"


def test_program_flooding_stderr_keeps_only_the_tail(ur5: Model) -> None:
    # 50 MB on one stderr line, then the line that says what went wrong.
    shell = "head -c 50000000 /dev/zero | tr '\\0' x; echo; echo 'fk: the last word'"
    shell = f"({shell}) >&2; exit 5"
    backend = CommandBackend(shlex.join(["sh", "-c", shell]), BackendOptions(timeout_s=60.0))
    with pytest.raises(CommandError) as caught:
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])
    assert str(caught.value) == f"{backend.name}: exited with status 5: fk: the last word"


def test_a_very_long_last_stderr_line_is_shortened(ur5: Model) -> None:
    shell = "head -c 100000 /dev/zero | tr '\\0' x >&2; exit 1"
    backend = CommandBackend(shlex.join(["sh", "-c", shell]), BackendOptions(timeout_s=60.0))
    with pytest.raises(CommandError, match=r"exited with status 1: x{300}…$") as caught:
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])
    assert len(str(caught.value)) < 400


def test_program_killed_by_a_signal_says_which(ur5: Model) -> None:
    backend = CommandBackend("sh -c 'kill -SEGV $$'", BackendOptions(timeout_s=60.0))
    with pytest.raises(CommandError, match=r"was killed by SIGSEGV \(nothing on stderr\)$"):
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])


def test_program_that_does_not_read_its_input_is_stopped_at_the_time_limit(ur5: Model) -> None:
    # 4096 configurations (~500 kB) fill the pipe: writing must not block past the limit.
    backend = CommandBackend("sleep 600", BackendOptions(timeout_s=1.0))
    start = time.monotonic()
    with pytest.raises(CommandError, match=r"timed out after 1 s"):
        backend.frame_poses(ur5, np.zeros((4096, 6)), ["tcp"])
    assert time.monotonic() - start < 1.0 + TERMINATE_GRACE_S + 1.0


#: What cmake 3.25 prints configuring examples/cpp_eigen without Eigen3 (stdout + stderr).
_NO_EIGEN = """\
-- The CXX compiler identification is GNU 12.2.0
-- Detecting CXX compiler ABI info
-- Detecting CXX compiler ABI info - done
-- Check for working CXX compiler: /usr/bin/c++ - skipped
-- Detecting CXX compile features
-- Detecting CXX compile features - done
-- Configuring incomplete, errors occurred!
CMake Error at CMakeLists.txt:14 (find_package):
  Could not find a package configuration file provided by "Eigen3" with any
  of the following names:

    Eigen3Config.cmake
    eigen3-config.cmake

"""

#: ... and without a C++ compiler.
_NO_COMPILER = """\
-- Configuring incomplete, errors occurred!
CMake Error at CMakeLists.txt:4 (project):
  No CMAKE_CXX_COMPILER could be found.

  Tell CMake where to find the compiler by setting either the environment
  variable "CXX" or the CMake cache entry CMAKE_CXX_COMPILER to the full path
  to the compiler executable or the compiler name if it is in the PATH.

"""


def test_the_skip_reason_quotes_cmakes_error_not_its_first_line() -> None:
    # It quoted "-- The CXX compiler identification is GNU 12.2.0": what cmake found.
    assert missing_tool(_NO_EIGEN) == (
        "CMake Error at CMakeLists.txt:14 (find_package): Could not find a package "
        'configuration file provided by "Eigen3" (Debian: apt-get install libeigen3-dev)'
    )
    assert missing_tool(_NO_COMPILER) == (
        "CMake Error at CMakeLists.txt:4 (project): No CMAKE_CXX_COMPILER could be found."
    )
    # Any other failure is the example's own: the fixture fails the test, it does not skip.
    assert missing_tool("CMake Error at CMakeLists.txt:9 (add_executable):\n  bad\n") is None
