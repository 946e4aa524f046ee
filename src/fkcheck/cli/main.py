"""The ``fkcheck`` command line: argparse subcommands, ``main(argv) -> int``.

Each subcommand lives in its own module under :mod:`fkcheck.cli` with
``add_parser(subparsers)`` and ``run(args) -> int``; those modules import heavy
libraries only inside ``run``, so ``fkcheck --help`` stays fast.

Exit codes: 0 ok, 1 a check disagreed or errored, 2 bad input, an output that
cannot be written, or a command that needs a library of the ``reference`` extra
that is not installed (one line on stderr, naming the library and
``pip install 'fkcheck[reference]'``), 130/143 interrupted by Ctrl-C/SIGTERM.
A run that ends without a verdict never exits 0: code it calls ending it with
``sys.exit(0)`` is exit 1 with one line. Code fkcheck did not write (third-party
backends, plugins, ``cmd:`` programs) runs in processes of its own, so its
``os._exit(0)`` ends only that process: the backend's *error*.

Whatever the input, what reaches the terminal is safe (:mod:`fkcheck.io.text`):
the error line escapes control characters, and standard output replaces a
character its encoding cannot carry by a backslash escape (``PYTHONIOENCODING=ascii``
prints ``\u2192`` for ``→``) instead of failing. When standard output cannot be
written (``> /dev/full``), the run ends with one line on stderr and exit 2;
a closed pipe (``| head``) ends it quietly with the run's own exit code.
A closed stream (``>&-``) is given ``/dev/null``: the run goes on with its own
exit code. A command that writes files keeps its :class:`~fkcheck.io.output_paths.OutputPlan`
on ``args.output_plan``, so that an interrupted run says which of them it wrote.
"""

from __future__ import annotations

import argparse
import atexit
import contextlib
import errno
import importlib
import io
import os
import signal
import sys
import threading
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NoReturn, TextIO

from fkcheck._version import __version__
from fkcheck.errors import FkcheckError, Skip, missing_extra
from fkcheck.io.text import terminal_text
from fkcheck.process.threads import one_blas_thread

if TYPE_CHECKING:
    from _typeshed import SupportsWrite

__all__ = ["COMMANDS", "MAIN_JOB", "main"]

#: Subcommand modules under fkcheck.cli, in the order ``--help`` lists them.
COMMANDS = ("check", "fk", "models", "convert", "table_from", "map", "urdf", "expand", "lint",
            "diagnose", "calibration", "bench", "ik", "opw")  # fmt: skip

#: What plain ``fkcheck`` runs: the same check wherever it runs, so ``--isolated``
#: (a project's ``[tool.fkcheck]`` is for its own models: ``fkcheck check``).
MAIN_JOB = (
    "check", "ur5", "--isolated", "--json", "reports/ur5.json", "--html", "reports/ur5.html",
)  # fmt: skip

EXIT_OK = 0
EXIT_FAIL = 1
EXIT_BAD_INPUT = 2

#: Errors of a write that found no room or no device (``> /dev/full``, a full disk).
_WRITE_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EIO)


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line and exit 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {terminal_text(message)}\n")

    def _print_message(self, message: str, file: SupportsWrite[str] | None = None) -> None:
        """As argparse's, without swallowing a failed write (``--help > /dev/full``)."""
        if message:
            (file or sys.stderr).write(message)


def build_parser() -> argparse.ArgumentParser:
    """The full ``fkcheck`` parser with every subcommand."""
    parser = _Parser(
        prog="fkcheck",
        description="Cross-validate robot-arm forward kinematics: an in-house DH core "
        "checked pose by pose against reference libraries.",
    )
    parser.add_argument("--version", action="version", version=f"fkcheck {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        importlib.import_module(f"fkcheck.cli.{name}").add_parser(sub)
    return parser


def _join_negative_values(argv: list[str]) -> list[str]:
    """Let ``--q -30,60`` through: argparse would take ``-30,60`` for an option."""
    out: list[str] = []
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in ("--q",) and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            out.append(f"{arg}={argv[i + 1]}")
            i += 2
            continue
        out.append(arg)
        i += 1
    return out


class _Terminated(BaseException):
    """SIGTERM, turned into an exception so the run unwinds and says so.

    A ``BaseException``, as ``KeyboardInterrupt`` is: an ``except Exception`` on the
    way (a library's fallback, the kernels' loader) must not swallow it.
    """


#: Seconds a SIGTERM's unwinding may take before the process ends anyway. The
#: exception is raised wherever the main thread is; where that is a ``__del__``
#: (llvmlite's, while numba compiles the kernels) or a library's ``except
#: BaseException``, Python swallows it and the run would go on to its end.
TERMINATE_BACKSTOP_S = 3.0

_terminating = threading.Event()
_terminated_said = threading.Event()
#: The running command's arguments, for the backstop's line (what was written).
_current_args: list[argparse.Namespace] = []


def _on_sigterm(signum: int, frame: object) -> None:
    if not _terminating.is_set():
        _terminating.set()
        backstop = threading.Timer(TERMINATE_BACKSTOP_S, _terminate_now)
        backstop.daemon = True
        backstop.start()
    raise _Terminated


def _terminate_now() -> None:
    """The SIGTERM backstop: stop the supervised programs, say so, and end with 143.

    Runs only when the raised :class:`_Terminated` did not end the run within
    :data:`TERMINATE_BACKSTOP_S` (it was swallowed on the way).
    """
    from fkcheck.process.supervise import terminate_all

    if _terminated_said.is_set():  # unwound and said so: the exit is under way
        return
    with contextlib.suppress(Exception):
        terminate_all()
    written = _written(_current_args[-1]) if _current_args else "no report written"
    with contextlib.suppress(Exception):
        print(f"fkcheck: terminated (SIGTERM): results incomplete, {written}", file=sys.stderr)
    _exit_now(143)


def _open_closed_streams() -> None:
    """Give a closed stdin, stdout or stderr (``>&-``) ``/dev/null``, as if redirected there.

    Python starts with ``sys.stdout = None`` when descriptor 1 is closed, and the
    next file opened would take descriptor 1: a report, or a backend's child
    inheriting it as its stdout. With ``/dev/null`` there, the run goes on and
    ends with its own exit code, its output going nowhere, as nobody reads it.
    """
    for fd, name, mode in ((0, "stdin", "r"), (1, "stdout", "w"), (2, "stderr", "w")):
        try:
            os.fstat(fd)
        except OSError:  # closed: the lowest free descriptor is this one
            null = os.open(os.devnull, os.O_RDONLY if fd == 0 else os.O_WRONLY)
            if null != fd:
                os.dup2(null, fd)
                os.close(null)
        if getattr(sys, name) is None:
            setattr(sys, name, open(fd, mode, encoding="utf-8", closefd=False))  # noqa: SIM115


def _tolerant_streams() -> None:
    r"""Let stdout and stderr write any text: what their encoding lacks becomes ``\uXXXX``."""
    for stream in (sys.stdout, sys.stderr):
        if isinstance(stream, io.TextIOWrapper):
            stream.reconfigure(errors="backslashreplace")


class _ClosedPipeTolerant:
    """The program's stdout, except that a reader that went away (``| head``) silences it.

    A closed pipe is no error (:func:`_flush_stdout`), but a plain ``print`` that
    meets it mid-run raises ``BrokenPipeError`` there: ``check --all | head -1``
    stopped after its first model, with no further reports, no index.html, and
    exit 0 whatever the models' verdicts. Here the write goes to ``/dev/null``
    and the run finishes with its own exit code, as rich's console does.
    """

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except BrokenPipeError:
            _silence_stdout()
            return len(text)

    def flush(self) -> None:
        try:
            self._stream.flush()
        except BrokenPipeError:
            _silence_stdout()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def _silence_stdout() -> None:
    """Point file descriptor 1 at /dev/null, so the interpreter's last flush cannot fail."""
    with contextlib.suppress(OSError, ValueError, AttributeError, io.UnsupportedOperation):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def _flush_stdout(code: int) -> int:
    """Flush standard output: ``code``, or 2 with one line on stderr when it cannot be written.

    A closed pipe (``| head``) is no error: the reader has what it wanted.
    """
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        _silence_stdout()
    except OSError as exc:  # /dev/full, a full disk, an I/O error
        _silence_stdout()
        print(f"fkcheck: error: cannot write standard output: {exc.strerror or exc}",
              file=sys.stderr)  # fmt: skip
        return EXIT_BAD_INPUT
    return code


def _written(args: argparse.Namespace) -> str:
    """What an interrupted run had written: ``no report written`` or the files."""
    plan = getattr(args, "output_plan", None)
    return "no report written" if plan is None else terminal_text(plan.describe_written())


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line and return the exit code."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _on_sigterm)
    _open_closed_streams()
    _tolerant_streams()
    if argv is None and not isinstance(sys.stdout, _ClosedPipeTolerant):  # the program
        sys.stdout = _ClosedPipeTolerant(sys.stdout)
    if argv is None:  # the program's BLAS, not a Python caller's
        one_blas_thread()
    args_list = _join_negative_values(list(sys.argv[1:] if argv is None else argv))
    code = _flush_stdout(_run(args_list))
    if argv is None:  # the program, not a caller in Python
        _finish(code)
    return code


def _finish(code: int) -> None:
    """End the program: exit hooks run, the interpreter is not finalized.

    Finalizing tears down every library a check imported (Pinocchio, MuJoCo,
    iDynTree, Robotics Toolbox, numba): about 0.4 s of a 10,000-sample check, with
    nothing left to write. With a backend thread left behind at its time limit it
    is also unsafe — its library is still in C++ — and nanobind then reports every
    object it holds as leaked, dozens of lines after the one that said "timed out".
    The exit hooks (:mod:`atexit`: stopping supervised programs among them) run
    first, unless such a thread is left, which one of them could wait on.
    """
    if not _abandoned_threads():
        atexit._run_exitfuncs()
    _exit_now(code)


def _abandoned_threads() -> bool:
    """Whether a thread is still running: a backend left behind at its time limit."""
    return any(t.is_alive() for t in threading.enumerate() if t is not threading.main_thread())


def _exit_now(code: int) -> None:
    """End the process with ``code`` now, streams flushed, without finalizing the interpreter."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(code)


def _run(args_list: list[str]) -> int:
    """Parse and run; every failure becomes one line on stderr and its exit code."""
    parser = build_parser()
    main_job = not args_list
    if main_job:  # check the bundled UR5 against every default backend
        args_list = list(MAIN_JOB)
    try:
        args = parser.parse_args(args_list)
        if args.command is None:
            parser.print_help()
            return EXIT_OK
    except SystemExit as exc:  # --help, --version, or a usage error (already printed)
        return int(exc.code or 0)
    except OSError as exc:  # --help on a stdout that cannot be written
        return _os_error(exc)
    args.argv = args_list
    _current_args[:] = [args]
    try:
        code = int(args.run(args))
    except FkcheckError as exc:
        print(f"fkcheck: error: {terminal_text(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except Skip as exc:  # the one backend a command needs cannot run here: not bad input
        print(f"fkcheck: unavailable: {terminal_text(exc)}", file=sys.stderr)
        return EXIT_FAIL
    except ModuleNotFoundError as exc:  # a library of the reference extra, not installed
        missing = missing_extra(exc)
        if missing is None:
            raise
        print(f"fkcheck: error: {args.command}: {terminal_text(missing)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print(f"fkcheck: interrupted (Ctrl-C): results incomplete, {_written(args)}",
              file=sys.stderr)  # fmt: skip
        return 130
    except _Terminated:
        _terminated_said.set()
        print(f"fkcheck: terminated (SIGTERM): results incomplete, {_written(args)}",
              file=sys.stderr)  # fmt: skip
        return 143
    except OSError as exc:  # BrokenPipeError included
        return _os_error(exc)
    except SystemExit as exc:  # sys.exit() in code the run called: no verdict, never 0
        print(f"fkcheck: error: the run was ended by sys.exit({exc.code!r}) before it "
              f"finished: no verdict, {_written(args)}", file=sys.stderr)  # fmt: skip
        return EXIT_FAIL
    if main_job:
        print(_main_job_line(args))
    return code


def _main_job_line(args: argparse.Namespace) -> str:
    """Where plain ``fkcheck`` wrote its reports, and that a project's settings were not used."""
    import shlex

    from fkcheck.model.project import find_pyproject, load_project

    plan = getattr(args, "output_plan", None)
    done = [] if plan is None else [str(o.path.resolve()) for o in plan.written()]
    line = f"fkcheck: wrote {', '.join(done) or 'no report'} (plain fkcheck runs: fkcheck "
    line += f"{shlex.join(MAIN_JOB)})"
    try:
        project = load_project()
    except FkcheckError:  # a [tool.fkcheck] it could not read: still not used
        project = None
        path = find_pyproject()
    else:
        path = None if project is None else project.path
    if path is not None:
        line += (
            f"; the [tool.fkcheck] of {os.path.relpath(path)} is not used: fkcheck check "
            "checks its models with its settings"
        )
    return terminal_text(line)


def _os_error(exc: OSError) -> int:
    """Stdout failing mid-run, or a file that vanished or filled up: one line, exit 2."""
    if isinstance(exc, BrokenPipeError):
        _silence_stdout()
        return EXIT_OK
    if exc.filename is not None:
        where = f"{exc.filename}: "
    elif exc.errno in _WRITE_ERRORS:  # files fkcheck writes name themselves; stdout does not
        _silence_stdout()
        where = "cannot write standard output: "
    else:
        where = ""
    print(f"fkcheck: error: {terminal_text(where)}{terminal_text(exc.strerror or exc)}",
          file=sys.stderr)  # fmt: skip
    return EXIT_BAD_INPUT


if __name__ == "__main__":
    sys.exit(main())
