"""The one output-path policy: what a run may write, decided before anything runs.

Every command that writes files (``check``'s reports and ``--all``'s
directory, ``urdf -o``, ``convert -o``, ``table-from -o``, ``bench --json``,
``diagnose --json``) calls :func:`plan_outputs` with its outputs and its inputs
before the (possibly long) work starts. The rules:

* an output never replaces an input of the same run (the model file, its URDF
  and, for a xacro URDF, every file its expansion read — includes and
  ``load_yaml`` files —, a measured-poses CSV, a ``cmd:`` program or a file on
  its command line; :mod:`fkcheck.cli._outputs` names them): the same file is
  the same device and inode, so a symbolic or hard link to an input is refused
  too;
* two outputs of one run never share a path (``--json X --html X``);
* only regular files or new paths are written: an existing directory, device
  (``/dev/null``), FIFO or socket is refused — as root too, where replacing
  ``/dev/null`` by a regular file would succeed;
* the directory must be writable: the nearest existing ancestor of the file is
  a directory fkcheck can create a file in (checked by creating and removing
  one, which is the only test that is true for root, read-only file systems
  and ``/proc`` alike), and every new name fits the file system's limits.

A path that breaks a rule is an :class:`OutputPathError`: one line, exit 2,
naming the option, the path and what is wrong (what a path is, in the words of
:func:`fkcheck.io.files.classify_path`). Missing parent directories are
created when the file is written (:mod:`fkcheck.io.atomic`).

The plan also remembers what each output was before the run, so that an
interrupted run can say truly which files it wrote (:meth:`OutputPlan.written`):
every write replaces the file by a new one, so a path whose file is new was
written by this run.

``$GITHUB_STEP_SUMMARY`` is the CI page's, not the user's: a problem with it
is a warning, never a failed check (:func:`step_summary_problem`,
:func:`append_step_summary`). It is appended to only when it is a regular
file, or a new file in an existing directory, and never when it is an input or
an output of the run.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from fkcheck.errors import FkcheckError
from fkcheck.io.files import classify_path, file_kind

__all__ = [
    "Output",
    "OutputPathError",
    "OutputPlan",
    "append_step_summary",
    "check_output_dir",
    "plan_outputs",
    "step_summary_problem",
]

#: Fallbacks when the file system does not say (``pathconf``): Linux's limits.
_NAME_MAX = 255
_PATH_MAX = 4096

_Identity = tuple[int, int]  # (st_dev, st_ino)
#: ``os.stat`` errors of a path that is new (or whose directory is): the
#: checks of its directory and name lengths then say what is wrong, if anything.
_NEW = (errno.ENOENT, errno.ENOTDIR, errno.ENAMETOOLONG)


class OutputPathError(FkcheckError):
    """An output path the run must not or cannot write (bad input, exit 2).

    Attributes:
        flag: The option naming it (``--json``), or a description.
        path: The path as given.
        problem: What is wrong.
    """

    def __init__(self, flag: str, path: Path | str, problem: str) -> None:
        self.flag = flag
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{flag} {self.path}: {problem}")


@dataclass(frozen=True)
class Output:
    """One file a run will write.

    Attributes:
        flag: The option that names it (``--json``, ``-o``, ``--out-dir``).
        path: The path as given.
        before: Device and inode of the file before the run, ``None`` if new.
    """

    flag: str
    path: Path
    before: _Identity | None


@dataclass(frozen=True)
class OutputPlan:
    """The files a run will write, checked against the policy.

    Attributes:
        outputs: In the order the run writes them.
    """

    outputs: tuple[Output, ...] = ()

    def written(self) -> tuple[Output, ...]:
        """The outputs this run has written so far (their file is not the one from before)."""
        return tuple(o for o in self.outputs if _identity(o.path) not in (None, o.before))

    def describe_written(self) -> str:
        """``"no report written"``, or which files were written and which were not."""
        done = self.written()
        if not done:
            return "no report written"
        missing = [o for o in self.outputs if o not in done]
        text = "written: " + ", ".join(str(o.path) for o in done)
        if missing:
            text += "; not written: " + ", ".join(str(o.path) for o in missing)
        return text


def _identity(path: Path | str) -> _Identity | None:
    """Device and inode of the file ``path`` names (links followed), ``None`` if none."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_dev, st.st_ino)


def _limit(directory: Path, name: str, default: int) -> int:
    try:
        return int(os.pathconf(directory, name))
    except (OSError, ValueError):
        return default


def _existing_ancestor(flag: str, path: Path) -> tuple[Path, list[str]]:
    """The nearest existing ancestor directory of ``path`` and the names below it to create.

    Raises:
        OutputPathError: An ancestor exists but is not a directory, or cannot be looked at.
    """
    missing: list[str] = []
    current = Path(os.path.abspath(path)).parent
    while True:
        found = classify_path(current)
        if found.stat is None:
            if found.errno not in _NEW:
                raise OutputPathError(flag, path, f"cannot look at {current}: {found.reason}")
            missing.append(current.name)
            current = current.parent
            continue
        if not found.is_dir:
            raise OutputPathError(flag, path, f"{current} is {found.describe()}, not a directory")
        return current, missing[::-1]


def _check_writable_location(flag: str, path: Path, probed: set[Path] | None = None) -> None:
    """The directory of ``path`` exists or can be created, accepts files, and names fit.

    Args:
        flag: The option naming ``path``, for the message.
        path: The output path.
        probed: Directories already shown to accept a file in this plan (updated).

    Raises:
        OutputPathError: It does not.
    """
    directory, missing = _existing_ancestor(flag, path)
    name_max = _limit(directory, "PC_NAME_MAX", _NAME_MAX)
    for name in [*missing, path.name]:
        if len(os.fsencode(name)) > name_max:
            raise OutputPathError(
                flag, path, f"a name is longer than the file system's {name_max} bytes"
            )
    if len(os.fsencode(os.path.abspath(path))) >= _limit(directory, "PC_PATH_MAX", _PATH_MAX):
        raise OutputPathError(flag, path, "the path is longer than the file system allows")
    if probed is not None and directory in probed:
        return
    try:  # the one test that is true for root, read-only mounts and /proc alike
        fd, probe = tempfile.mkstemp(prefix=".fkcheck-probe-", dir=directory)
    except OSError as exc:
        raise OutputPathError(
            flag, path, f"cannot create a file in {directory}: {exc.strerror}"
        ) from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(probe)
    if probed is not None:
        probed.add(directory)


def _input_identities(inputs: Iterable[tuple[str, Path | str | None]]) -> dict[_Identity, str]:
    found: dict[_Identity, str] = {}
    for label, path in inputs:
        if path is None:
            continue
        identity = _identity(path)
        if identity is not None:
            found.setdefault(identity, label)
    return found


def _check_one(
    flag: str, path: Path, inputs: dict[_Identity, str], probed: set[Path]
) -> _Identity | None:
    """Apply the policy to one output; its identity before the run (``None`` when new)."""
    found = classify_path(path)
    st = found.stat
    if st is None and found.errno not in _NEW:  # new, or a problem of its directory:
        raise OutputPathError(flag, path, str(found.reason))  # the next check names that
    identity = None
    if st is not None:
        if not found.is_regular:
            raise OutputPathError(
                flag, path, f"is {found.describe()}; fkcheck writes only regular files or new paths"
            )
        identity = (st.st_dev, st.st_ino)
        if identity in inputs:
            raise OutputPathError(
                flag, path, f"is {inputs[identity]}, an input of this run: write elsewhere"
            )
    _check_writable_location(flag, path, probed)
    return identity


def plan_outputs(
    outputs: Sequence[tuple[str, Path | str | None]],
    inputs: Iterable[tuple[str, Path | str | None]] = (),
) -> OutputPlan:
    """Check a run's outputs against the policy; nothing is written or created.

    Args:
        outputs: ``(flag, path)`` in the order the run writes them; a ``None``
            path (an option not given) is left out.
        inputs: ``(what, path)`` for every file the run reads, e.g.
            ``("the model file", model.path)``; paths that do not exist are
            ignored (they cannot be overwritten).

    Returns:
        The plan, remembering each output's file before the run.

    Raises:
        OutputPathError: An output is an input, two outputs share a path, an
            output is not a regular file, or its directory cannot take it.
    """
    known = _input_identities(inputs)
    planned: list[Output] = []
    seen: dict[str, str] = {}
    seen_ids: dict[_Identity, str] = {}
    probed: set[Path] = set()
    for flag, raw in outputs:
        if raw is None:
            continue
        path = Path(raw)
        identity = _check_one(flag, path, known, probed)
        key = os.path.realpath(path)
        other = seen.get(key) or (seen_ids.get(identity) if identity is not None else None)
        if other is not None:
            raise OutputPathError(flag, path, f"is also {other}: two outputs cannot share a path")
        seen[key] = flag
        if identity is not None:
            seen_ids[identity] = flag
        planned.append(Output(flag, path, identity))
    return OutputPlan(tuple(planned))


def check_output_dir(flag: str, path: Path | str) -> None:
    """A directory a run writes its files into: existing, or creatable where it is.

    Raises:
        OutputPathError: It exists and is not a directory (``--out-dir`` naming
            a file), or it cannot be created or written.
    """
    directory = Path(path)
    found = classify_path(directory)
    if found.stat is None:
        if found.errno not in _NEW:
            raise OutputPathError(flag, directory, str(found.reason))
        _check_writable_location(flag, directory)
        return
    if not found.is_dir:
        raise OutputPathError(flag, directory, f"is {found.describe()}, not a directory")
    _check_writable_location(flag, directory / "index.html")


def step_summary_problem(
    path: str,
    inputs: Iterable[tuple[str, Path | str | None]] = (),
    plan: OutputPlan | None = None,
) -> str | None:
    """Why ``$GITHUB_STEP_SUMMARY`` cannot be appended to, or ``None`` when it can.

    It can when it names a regular file, or a new file in an existing
    directory, that is neither an input nor an output of the run.
    """
    target = Path(path)
    identity = _identity(target)
    for output in plan.outputs if plan is not None else ():
        same_file = identity is not None and output.before == identity
        if same_file or os.path.realpath(output.path) == os.path.realpath(target):
            return f"is also {output.flag}, an output of this run"
    found = classify_path(target)
    st = found.stat
    if st is None:
        if found.errno != errno.ENOENT:
            return str(found.reason)
        if not target.parent.is_dir():
            return f"its directory {target.parent} does not exist"
        return None
    if not found.is_regular:
        return f"is {found.describe()}, not a regular file"
    label = _input_identities(inputs).get((st.st_dev, st.st_ino))
    if label is not None:
        return f"is {label}, an input of this run"
    return None


def append_step_summary(path: str, text: str) -> str | None:
    """Append ``text`` to ``$GITHUB_STEP_SUMMARY``; the reason it could not, or ``None``.

    Opens without blocking (a FIFO without a reader fails at once instead of
    hanging) and writes only if what was opened is a regular file.
    """
    flags = os.O_WRONLY | os.O_APPEND | os.O_CREAT | os.O_NONBLOCK | os.O_NOCTTY
    try:
        fd = os.open(path, flags, 0o644)
    except (OSError, ValueError) as exc:
        return getattr(exc, "strerror", None) or str(exc)
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            return f"is {file_kind(mode)}, not a regular file"
        data = text.encode("utf-8", errors="backslashreplace")
        while data:
            data = data[os.write(fd, data) :]
    except OSError as exc:
        return exc.strerror or str(exc)
    finally:
        os.close(fd)
    return None
