"""Reading input files: regular files only, bounded in size and line length, UTF-8.

A path from the command line or a model file may name anything: a FIFO (opening
it for reading blocks until some writer comes), a directory, a device
(``/dev/zero`` never ends), or a file of many gigabytes. The readers here look
at the path with ``os.stat`` first and refuse whatever is not a regular file
without opening it; they then open it non-blocking, check the open descriptor
again (the path may have been swapped in between) and never read more than the
caller's bound:

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

import os
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import BinaryIO

from fkcheck.errors import FkcheckError

__all__ = [
    "MAX_LINE_BYTES",
    "MAX_MODEL_FILE_BYTES",
    "MAX_TABLE_FILE_BYTES",
    "InputFileError",
    "file_kind",
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
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)
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
    """What a file that is not a regular file is, in words: ``"a FIFO (named pipe)"``."""
    return next((name for test, name in _KINDS if test(mode)), "a special file")


def _not_regular(mode: int) -> str | None:
    if stat.S_ISREG(mode):
        return None
    return f"is {file_kind(mode)}, not a regular file"


def _open_regular(path: Path, max_bytes: int) -> BinaryIO:
    """Open ``path`` for reading after making sure it is a regular file of at most ``max_bytes``."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise InputFileError(path, "no such file") from None
    except (OSError, ValueError) as exc:  # ValueError: a NUL character in the path
        reason = getattr(exc, "strerror", None) or str(exc)
        raise InputFileError(path, f"cannot read: {reason}") from None
    problem = _not_regular(info.st_mode)
    if problem is None and info.st_size > max_bytes:
        problem = f"file too large: {info.st_size} bytes (at most {_size(max_bytes)})"
    if problem is not None:
        raise InputFileError(path, problem)
    try:
        fd = os.open(path, _OPEN_FLAGS)
    except OSError as exc:
        raise InputFileError(path, f"cannot read: {exc.strerror or exc}") from None
    problem = _not_regular(os.fstat(fd).st_mode)  # swapped after the first look?
    if problem is not None:
        os.close(fd)
        raise InputFileError(path, problem)
    return os.fdopen(fd, "rb")


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
    try:
        with _open_regular(path, max_bytes) as f:
            data = f.read(max_bytes + 1)
    except OSError as exc:
        raise InputFileError(path, f"cannot read: {exc.strerror or exc}") from None
    if len(data) > max_bytes:  # grew after the stat, or a /proc file of size 0
        raise InputFileError(path, f"file too large: more than {_size(max_bytes)}")
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
