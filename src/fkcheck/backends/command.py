"""An external FK program as a reference backend (``--against "cmd:./build/fk_tool"``).

Any language works: the program talks to fkcheck over stdin and stdout.

Protocol:

* The command line after ``cmd:`` is split with :func:`shlex.split` (POSIX
  quoting) and run **without a shell**, in the current directory. A program
  name without a ``/`` is looked up on ``PATH``; ``./fk`` or ``build/fk`` is
  relative to the current directory.
* fkcheck writes one configuration per line to the program's stdin: ``n``
  comma-separated joint values in radians / metres, DH joint order, each as
  Python's ``repr`` of the float (the shortest decimal that reads back as the
  same double: at most 17 significant digits, e.g. ``0.5235987755982988``),
  then closes stdin.
* For each input line, in order, the program writes one line to stdout: 16
  numbers separated by whitespace and/or commas, the 4×4 ``world_T_tcp``
  row-major (the pose :meth:`fkcheck.model.Model.fk` returns: base and tool
  included). Blank output lines are ignored; anything else must parse as a
  finite float (``%.17g`` in C, ``repr`` in Python keep every bit).
* The program exits with status 0. On bad input it should print a message on
  stderr and exit non-zero; fkcheck reports the last line of stderr (of which
  it keeps only the last :data:`~fkcheck.process.supervise.STDERR_TAIL_BYTES`).
* Output is bounded: a line may be at most :data:`MAX_LINE_BYTES` bytes, and a
  run may print at most one line per configuration plus :data:`EXTRA_LINES`
  (blank lines count). Past either limit fkcheck stops reading, kills the
  program and the backend fails with "printed a line longer than …" or
  "printed more than … lines".
* Configurations are sent in batches of :data:`BATCH_SIZE`, one process run
  per batch: a stateless program that reads to end of input is all that is
  needed, and no run holds more than one batch in its pipes.
* The whole backend run (all batches) has a time limit,
  :attr:`~fkcheck.backends.registry.BackendOptions.timeout_s`. The program
  runs under fkcheck's supervisor (:mod:`fkcheck.process.supervise`), in a session of
  its own: when the time limit is reached, the program and every process it
  started — on Linux even those that left its session with ``setsid`` — are
  killed and the backend fails with "timed out after X s"; the run ends within
  the time limit plus :data:`~fkcheck.process.supervise.TERMINATE_GRACE_S`. When the
  program exits, whatever it left running is killed. Programs still running
  when fkcheck exits (it gave up on this backend, or was stopped by SIGTERM or
  Ctrl-C) are killed too, and so are they if fkcheck itself is killed.
  A crashing program writes no ``core`` file into the current directory (its
  core size limit is 0).

The program gives only the TCP, so named frames come from
:func:`fkcheck.backends.blackbox.frame_poses_from_tcp`. Every failure (program not found,
non-zero exit, wrong number of lines or numbers, non-numeric or non-finite
output, too much output, time-out) raises :class:`CommandError`, which the check reports as this
backend's *error*.
"""

from __future__ import annotations

import errno
import os
import re
import shlex
import shutil
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from fkcheck.backends.base import BackendDefaults, Evidence, Reads, validated_q
from fkcheck.backends.blackbox import frame_poses_from_tcp, require_tcp_frames
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float
from fkcheck.errors import FkcheckError
from fkcheck.io.numbers import NumberError, parse_number
from fkcheck.model.types import Model
from fkcheck.process.supervise import (
    IsolatedOutputLimit,
    IsolatedTimeout,
    SpawnError,
    ended,
    last_stderr_line,
    run_supervised,
)

__all__ = [
    "BATCH_SIZE",
    "EXTRA_LINES",
    "MAX_LINE_BYTES",
    "CommandBackend",
    "CommandError",
    "CommandSpecError",
]


#: Configurations sent to one run of the program.
BATCH_SIZE = 4096
#: Longest line the program may print, bytes (16 numbers at full precision take ~400).
MAX_LINE_BYTES = 8192
#: Lines the program may print beyond one per configuration (blank lines count).
EXTRA_LINES = 1024

#: Longest piece of the program's output quoted in an error message.
_QUOTE_CHARS = 120


class CommandError(RuntimeError):
    """The external program failed or printed something that is not poses.

    Not an :class:`~fkcheck.errors.FkcheckError`: the check reports it as the
    backend's *error* (exit 1), not as bad input.

    Attributes:
        command: The command line as given after ``cmd:``.
        problem: What went wrong.
    """

    def __init__(self, command: str, problem: str) -> None:
        self.command = command
        self.problem = problem
        super().__init__(f"cmd:{command}: {problem}")


class CommandSpecError(FkcheckError, ValueError):
    """A ``cmd:`` command line that cannot be split into arguments (bad input, exit 2)."""


class CommandBackend(BackendDefaults):
    """FK from an external program over stdin/stdout: one line in, one pose out.

    Attributes:
        name: ``cmd:<command line>``.
        method: ``"external program <command line> (CSV on stdin, 16 numbers per line out)"``.
        command: The command line as given.
        argv: The command line split into arguments.
        timeout_s: Time limit for all runs of one :meth:`frame_poses` call, seconds.
        evidence: ``"implementation"``: the user's program runs the model's table.
    """

    evidence: Evidence = "implementation"
    reads: Reads = "program"
    #: Imported by the engine before backend threads start (fixed frames use SciPy).
    imports = ("scipy.spatial.transform",)

    def __init__(self, spec: str, options: BackendOptions) -> None:
        """Split the command line; nothing is run yet.

        Args:
            spec: The command line after ``cmd:``, e.g. ``./build/fk_tool --ur5``.
            options: Backend options; ``timeout_s`` is the time limit.

        Raises:
            CommandSpecError: Unbalanced quotes, or an empty command line.
        """
        self.command = spec.strip()
        try:
            self.argv = shlex.split(self.command)
        except ValueError as exc:
            raise CommandSpecError(
                f"cmd:{self.command}: cannot split command line: {exc}"
            ) from None
        if not self.argv:
            raise CommandSpecError("cmd:: empty command line; expected e.g. cmd:./build/fk_tool")
        self.name = f"cmd:{self.command}"
        self.method = f"external program {self.command} (CSV on stdin, 16 numbers per line out)"
        self.timeout_s = options.timeout_s

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """The program and every word of its command line that names an existing file."""
        found: list[Path] = []
        for word in self.argv:
            program = word if os.sep in word or os.path.isfile(word) else shutil.which(word)
            if program is not None:
                found.append(Path(program))
        return tuple(found)

    def unavailable_reason(self, model: Model) -> str | None:
        """Always ``None``: a program asked for explicitly that does not run is an error."""
        return None

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """Run the program over the batch and map its TCP poses onto named frames.

        Takes and returns what :meth:`~fkcheck.backends.base.Backend.frame_poses`
        does, with the world as the root: ``(len(frames), N, 4, 4)`` world_T_frame.

        Raises:
            FrameUnavailable: A requested frame sits mid-chain (checked before
                the program is run).
            FrameError: A frame name the model does not define.
            JointInputError: ``q`` has the wrong shape or non-finite values.
            CommandError: The program is missing, fails, times out, or prints
                something other than one finite 4×4 per configuration.
        """
        q = validated_q(model, q)
        require_tcp_frames(model, frames)
        deadline = time.monotonic() + self.timeout_s
        world_T_tcp = np.empty((q.shape[0], 4, 4))
        for start in range(0, q.shape[0], BATCH_SIZE):
            batch = q[start : start + BATCH_SIZE]
            stdout = self._run(_format_input(batch), deadline, len(batch))
            world_T_tcp[start : start + len(batch)] = self._parse(stdout, batch, start)
        return frame_poses_from_tcp(model, world_T_tcp, frames)

    # ------------------------------------------------------------------ running

    def _fail(self, problem: str) -> CommandError:
        return CommandError(self.command, problem)

    def _run(self, stdin: bytes, deadline: float, n_configs: int) -> bytes:
        """One run of the program: feed ``stdin``, return its stdout (bounded)."""
        max_lines = n_configs + EXTRA_LINES
        try:
            done = run_supervised(
                self.argv,
                stdin,
                max(deadline - time.monotonic(), 0.0),
                max_stdout_bytes=max_lines * (MAX_LINE_BYTES + 1),
                max_line_bytes=MAX_LINE_BYTES,
                max_lines=max_lines,
            )
        except SpawnError as exc:
            if exc.errno == errno.ENOENT:
                where = "on PATH" if os.sep not in self.argv[0] else f"(from {os.getcwd()})"
                raise self._fail(f"program {self.argv[0]!r} not found {where}") from None
            if exc.errno == errno.EACCES:
                raise self._fail(f"program {self.argv[0]!r} is not executable") from None
            raise self._fail(f"cannot run {self.argv[0]!r}: {exc.strerror}") from None
        except IsolatedTimeout:
            raise self._fail(
                f"timed out after {self.timeout_s:g} s (the program was killed)"
            ) from None
        except IsolatedOutputLimit as exc:
            raise self._fail(
                f"{exc.problem} for {n_configs} configurations (the program was killed)"
            ) from None
        if done.returncode != 0:
            last = last_stderr_line(done.stderr_tail)
            what = ended(done.returncode, "status")
            raise self._fail(f"{what}: {last}" if last else f"{what} (nothing on stderr)")
        return done.stdout

    # ------------------------------------------------------------------ parsing

    def _parse(self, stdout: bytes, batch: Float, start: int) -> Float:
        """Poses ``(len(batch), 4, 4)`` from one run's stdout."""
        try:
            text = stdout.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise self._fail(
                f"output is not UTF-8 text ({exc.reason} at byte {exc.start})"
            ) from None
        # Lines end in \n (or \r\n); fields are split at ASCII spaces, tabs and
        # commas only: Unicode separators are not number separators.
        lines = [line for line in text.split("\n") if line.strip(" \t\r")]
        if len(lines) != len(batch):
            raise self._fail(
                f"printed {len(lines)} pose lines for {len(batch)} configurations "
                f"(configurations {start}…{start + len(batch) - 1}); expected one line "
                "of 16 numbers per input line"
            )
        tokens: list[str] = []
        for k, line in enumerate(lines):
            fields = [f for f in re.split(r"[ \t\r,]+", line) if f]
            if len(fields) != 16:
                raise self._fail(
                    f"configuration {start + k}: expected 16 numbers (row-major 4×4), "
                    f"got {len(fields)}: {_quote(line)}"
                )
            tokens.extend(fields)
        values = np.empty(len(tokens))
        for i, token in enumerate(tokens):
            value = _number(token)
            if value is None:
                k = i // 16
                raise self._fail(
                    f"configuration {start + k}: {_quote(token)} is not a number "
                    f"in line {_quote(lines[k])}"
                )
            values[i] = value
        # NaN or inf is an answer, and a wrong one: the engine reports it as a
        # failure (how many configurations, and where), not as "no answer".
        return values.reshape(len(batch), 4, 4)


def _format_input(batch: Float) -> bytes:
    """CSV lines, one configuration each, every value as its exact ``repr``."""
    return "".join(",".join(map(repr, row)) + "\n" for row in batch.tolist()).encode("ascii")


#: What a C or Python program prints for a non-finite value; read so the engine
#: can report the answer as wrong.
_NON_FINITE = {"nan", "+nan", "-nan", "inf", "+inf", "-inf", "infinity", "+infinity", "-infinity"}


def _number(token: str) -> float | None:
    """A printed number (fkcheck's strict ASCII decimal, or nan/inf), or ``None``."""
    if token.lower() in _NON_FINITE:
        return float(token.lower().replace("+", ""))
    try:
        return parse_number(token)
    except NumberError:
        return None


def _quote(text: str) -> str:
    """``repr`` of ``text``, shortened to a readable length."""
    if len(text) > _QUOTE_CHARS:
        text = text[:_QUOTE_CHARS] + "…"
    return repr(text)
