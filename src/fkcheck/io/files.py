"""What kind of file a path is, and reading input files: regular files only, bounded, UTF-8.

:func:`classify_path` is the one place that looks at what a path names without
opening it, and :func:`file_kind` the one wording for each kind of file ("a
directory", "a FIFO (named pipe)", "a character device", "a socket", …);
:meth:`PathKind.describe` adds symbolic links ("a symlink to pipe.urdf, which
is a FIFO (named pipe)"). The readers here, the URDF screen
(:mod:`fkcheck.urdf.screen`) and the output-path policy
(:mod:`fkcheck.io.output_paths`) all say what a path is in these words.

A path from the command line or a model file may name anything: a FIFO (opening
it for reading blocks until some writer comes), a directory, a device
(``/dev/zero`` never ends), or a file of many gigabytes. The readers here look
at the path first (:func:`check_regular_file`) and refuse whatever is not a
regular file without opening it; they then open it non-blocking, check the open
descriptor again (the path may have been swapped in between) and never read
more than the caller's bound:

* :data:`MAX_MODEL_FILE_BYTES` (1 MiB) for a model file (TOML or DH CSV): a
  256-joint table with every optional section takes well under 100 kB;
* :data:`MAX_TABLE_FILE_BYTES` (256 MiB) for a table of data (``--q-file``,
  measured poses): about two million six-joint configurations at full precision;
* :data:`MAX_LINE_BYTES` (64 KiB) for one line of such a table, line break
  included: 256 values of :data:`fkcheck.io.numbers.MAX_NUMBER_CHARS` characters
  take 26 kB.

Text is UTF-8. A leading UTF-8 byte-order mark (which some Windows editors and
spreadsheet exports write) is skipped. Lines end as for :meth:`str.splitlines`
(LF, CR LF, CR and the other Unicode line breaks). Problems raise
:class:`InputFileError`, whose message names the file (and the line).
"""

from __future__ import annotations

import errno
import os
import stat
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from fkcheck.errors import FkcheckError

__all__ = [
    "MAX_LINE_BYTES",
    "MAX_MODEL_FILE_BYTES",
    "MAX_TABLE_FILE_BYTES",
    "InputFileError",
    "PathKind",
    "check_regular_file",
    "classify_path",
    "file_kind",
    "read_bytes",
    "read_lines",
    "read_text",
]

#: Largest model file (TOML or DH CSV) read, bytes.
MAX_MODEL_FILE_BYTES = 1 << 20
#: Largest table of data (``--q-file``, measured poses) read, bytes.
MAX_TABLE_FILE_BYTES = 256 << 20
#: Longest line of a table, line break included, bytes.
MAX_LINE_BYTES = 64 << 10

_BOM = b"\xef\xbb\xbf"
_KINDS = (
    (stat.S_ISREG, "a regular file"),
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)
#: ``os.stat`` errors that mean "nothing there": no such name, or a file where
#: the path needs a directory on the way (``model.toml/x``).
_MISSING = (errno.ENOENT, errno.ENOTDIR)
_OPEN_FLAGS = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)


class InputFileError(FkcheckError):
    """An input file that is missing, not a regular file, too large, or not UTF-8 text.

    Attributes:
        path: The file as given.
        problem: What is wrong (with the line where there is one).
    """

    def __init__(self, path: Path | str, problem: str) -> None:
        self.path = Path(path)
        self.problem = problem
        super().__init__(f"{path}: {problem}")


def _size(n_bytes: int) -> str:
    return f"{n_bytes >> 20} MiB" if n_bytes >= 1 << 20 else f"{n_bytes >> 10} KiB"


def file_kind(mode: int) -> str:
    """What a file of this ``st_mode`` is, in words.

    One of ``"a regular file"``, ``"a directory"``, ``"a FIFO (named pipe)"``,
    ``"a character device"``, ``"a block device"``, ``"a socket"`` or
    ``"a special file"``.
    """
    return next((name for test, name in _KINDS if test(mode)), "a special file")


@dataclass(frozen=True)
class PathKind:
    """What a path names, looked at without opening anything (:func:`classify_path`).

    Attributes:
        stat: What the path names, symbolic links followed; ``None`` when
            ``os.stat`` failed (nothing there, or it cannot be looked at).
        link: Where the path points when it is itself a symbolic link, as the
            link says (``os.readlink``); ``None`` when it is none.
        errno: Why ``os.stat`` failed (``errno.ENOENT`` …); ``None`` when it
            did not, or when the path holds a NUL character.
        reason: Why ``os.stat`` failed, in words (``"Permission denied"``);
            ``None`` when it did not.
    """

    stat: os.stat_result | None
    link: str | None = None
    errno: int | None = None
    reason: str | None = None

    @property
    def missing(self) -> bool:
        """Nothing there: no such name, a symbolic link to nothing, or a file on the way."""
        return self.errno in _MISSING

    @property
    def is_regular(self) -> bool:
        """A regular file (perhaps through symbolic links)."""
        return self.stat is not None and stat.S_ISREG(self.stat.st_mode)

    @property
    def is_dir(self) -> bool:
        """A directory (perhaps through symbolic links)."""
        return self.stat is not None and stat.S_ISDIR(self.stat.st_mode)

    def describe(self) -> str:
        """What the path is, in the words every message uses.

        ``"a directory"``, ``"a FIFO (named pipe)"`` (:func:`file_kind`);
        through a symbolic link ``"a symlink to pipe.urdf, which is a FIFO
        (named pipe)"`` or ``"a symlink to gone.toml, which does not exist"``;
        ``"nothing (no such file)"``; ``"a path that cannot be looked at
        (Permission denied)"``.
        """
        if self.stat is not None:
            what = file_kind(self.stat.st_mode)
        elif self.missing:
            if self.link is not None:
                return f"a symlink to {self.link}, which does not exist"
            what = "nothing (no such file)"
        else:
            what = f"a path that cannot be looked at ({self.reason})"
        return what if self.link is None else f"a symlink to {self.link}, which is {what}"


def classify_path(path: Path | str) -> PathKind:
    """Look at what ``path`` names, with ``os.lstat`` and ``os.stat``: nothing is opened.

    Never raises: a path that cannot be looked at (missing, no permission, a
    NUL character) gives a :class:`PathKind` whose ``stat`` is ``None``.
    """
    link = None
    try:
        if stat.S_ISLNK(os.lstat(path).st_mode):
            link = os.readlink(path)
    except (OSError, ValueError):
        pass  # os.stat below fails the same way and says why
    try:
        return PathKind(os.stat(path), link)
    except ValueError:  # an embedded NUL
        return PathKind(None, link, None, "the path holds a NUL character")
    except OSError as exc:
        return PathKind(None, link, exc.errno, exc.strerror or str(exc))


def _not_regular(mode: int) -> str | None:
    if stat.S_ISREG(mode):
        return None
    return f"is {file_kind(mode)}, not a regular file"


def check_regular_file(path: Path | str, max_bytes: int) -> os.stat_result:
    """Look at ``path`` without opening it: an existing regular file of at most ``max_bytes``.

    Symbolic links are followed, and named in the message when what they point
    to is refused.

    Returns:
        Its ``os.stat`` result.

    Raises:
        InputFileError: Missing (``"no such file"``), cannot be looked at, not
            a regular file (``"is a directory, not a regular file"``), or larger
            than ``max_bytes``.
    """
    found = classify_path(path)
    if found.stat is None:
        if found.link is not None:
            raise InputFileError(path, f"is {found.describe()}")
        if found.missing:
            raise InputFileError(path, "no such file")
        raise InputFileError(path, f"cannot read: {found.reason}")
    if not found.is_regular:
        raise InputFileError(path, f"is {found.describe()}, not a regular file")
    if found.stat.st_size > max_bytes:
        raise InputFileError(
            path, f"file too large: {found.stat.st_size} bytes (at most {_size(max_bytes)})"
        )
    return found.stat


def _open_regular(path: Path, max_bytes: int) -> BinaryIO:
    """Open ``path`` for reading after making sure it is a regular file of at most ``max_bytes``."""
    check_regular_file(path, max_bytes)
    try:
        fd = os.open(path, _OPEN_FLAGS)
    except OSError as exc:
        raise InputFileError(path, f"cannot read: {exc.strerror or exc}") from None
    problem = _not_regular(os.fstat(fd).st_mode)  # swapped after the first look?
    if problem is not None:
        os.close(fd)
        raise InputFileError(path, problem)
    return os.fdopen(fd, "rb")


def read_bytes(path: Path | str, max_bytes: int) -> bytes:
    """The bytes of a regular file of at most ``max_bytes`` bytes, read without ever blocking.

    The path is looked at first (:func:`check_regular_file`), then opened
    non-blocking and checked again on the open descriptor, so a path swapped
    for a FIFO in between cannot block either. At most ``max_bytes + 1`` bytes
    are read.

    Raises:
        InputFileError: As :func:`check_regular_file`, the file cannot be read,
            or it holds more than ``max_bytes`` bytes after all (it grew, or a
            ``/proc`` file of size 0).
    """
    path = Path(path)
    try:
        with _open_regular(path, max_bytes) as f:
            data = f.read(max_bytes + 1)
    except OSError as exc:
        raise InputFileError(path, f"cannot read: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        raise InputFileError(path, f"file too large: more than {_size(max_bytes)}")
    return data


def _decode(data: bytes, path: Path, where: str) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputFileError(path, f"{where}not UTF-8 text") from None


def read_text(path: Path | str, max_bytes: int = MAX_MODEL_FILE_BYTES) -> str:
    """The whole text of a regular file of at most ``max_bytes`` bytes (a leading BOM dropped).

    Raises:
        InputFileError: Missing, unreadable, not a regular file (never opened
            then), larger than ``max_bytes``, or not UTF-8.
    """
    path = Path(path)
    data = read_bytes(path, max_bytes)
    if data.startswith(_BOM):
        data = data[len(_BOM) :]
    if b"\n" in data:
        try:
            return data.decode("utf-8")
        except UnicodeDecodeError as exc:
            line = data.count(b"\n", 0, exc.start) + 1
            raise InputFileError(path, f"line {line}: not UTF-8 text") from None
    return _decode(data, path, "")


def read_lines(
    path: Path | str,
    max_bytes: int = MAX_TABLE_FILE_BYTES,
    max_line: int = MAX_LINE_BYTES,
) -> Iterator[tuple[int, str]]:
    """Lines of a regular text file, one at a time: ``(line number, text without break)``.

    Memory stays one line long whatever the file's size. The lines and their
    numbers are those of ``text.splitlines()`` on the whole text.

    Raises:
        InputFileError: Missing, unreadable, not a regular file (never opened
            then), larger than ``max_bytes``, a line longer than ``max_line``
            bytes, or not UTF-8.
    """
    path = Path(path)
    f = _open_regular(path, max_bytes)
    with f:
        lineno = 0
        total = 0
        while True:
            try:
                raw = f.readline(max_line + 1)
            except OSError as exc:
                raise InputFileError(path, f"cannot read: {exc.strerror or exc}") from None
            if not raw:
                return
            total += len(raw)
            if total > max_bytes:
                raise InputFileError(path, f"file too large: more than {_size(max_bytes)}")
            if len(raw) > max_line:
                raise InputFileError(
                    path, f"line {lineno + 1}: longer than {_size(max_line)} (the limit per line)"
                )
            if lineno == 0 and raw.startswith(_BOM):
                raw = raw[len(_BOM) :]
            text = _decode(raw, path, f"line {lineno + 1}: ")
            for line in text.splitlines():
                lineno += 1
                yield lineno, line
