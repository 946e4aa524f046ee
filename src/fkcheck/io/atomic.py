"""Atomic file writes: a temporary file in the same directory, then ``os.replace``."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

__all__ = ["write_bytes_atomic", "write_text_atomic"]

#: Permissions of written files: readable by everyone, like a plain ``open(…, "w")``.
_FILE_MODE = 0o644

#: Characters of the target's name kept in the temporary file's name (4 bytes each at most).
_PREFIX_CHARS = 48


def write_bytes_atomic(path: Path | str, data: bytes) -> Path:
    """Write ``data`` to ``path`` so that readers see the old file or the whole new one.

    Creates missing parent directories. The temporary file is removed if
    anything fails (including KeyboardInterrupt). Which paths may be written is
    decided before the run, by :mod:`fkcheck.io.output_paths`.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    # The temporary name stays within NAME_MAX whatever the target's length.
    prefix = f".{target.name[:_PREFIX_CHARS]}."
    fd, tmp = tempfile.mkstemp(prefix=prefix, suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(tmp, _FILE_MODE)  # mkstemp makes 0600; reports are meant to be shared
        os.replace(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError) and exc.filename is None:  # a write: name the file
            raise OSError(exc.errno, exc.strerror, str(target)) from exc
        raise
    return target


def write_text_atomic(path: Path | str, text: str) -> Path:
    """:func:`write_bytes_atomic` for UTF-8 text."""
    return write_bytes_atomic(path, text.encode("utf-8"))
