"""What a ROS 2 bag may be and hold: its files screened, its size limits, its errors.

A bag is untrusted input (:mod:`fkcheck.backends.bag`): before :mod:`rosbags`
opens it, :func:`_screen` checks that its files are regular files in it and that
its ``metadata.yaml`` is plain data of an uncompressed bag; the limits here bound
what a message may hold. :class:`BagError` is the one line a bad bag ends in;
:class:`_Bad` is what a message's reader raises, and becomes one.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from fkcheck.backends.measured import PosesFileError

__all__ = [
    "MAX_DEPTH",
    "MAX_FRAMES",
    "MAX_FRAME_ID_CHARS",
    "MAX_JOINT_NAMES",
    "MAX_MESSAGE_BYTES",
    "MAX_METADATA_BYTES",
    "MAX_TRANSFORMS",
    "QUATERNION_NORM_TOL",
    "BagError",
    "bag_files",
    "is_bag",
]

#: Largest message read (bytes, serialised): a joint state of a few arms or a tf
#: message of a few hundred frames is a few kilobytes.
MAX_MESSAGE_BYTES = 1 << 20
#: Largest ``metadata.yaml`` (bytes).
MAX_METADATA_BYTES = 1 << 20
#: Joints one joint state may name, transforms one tf message may hold, frames the
#: tree may hold, characters a frame id may have.
MAX_JOINT_NAMES = 1_000
MAX_TRANSFORMS = 10_000
MAX_FRAMES = 10_000
MAX_FRAME_ID_CHARS = 256
#: Frames between a frame and the root of its tf tree at most.
MAX_DEPTH = 256
#: Largest distance of a quaternion's norm from 1 on the compared path (tf2 refuses
#: quaternions further than about 1e-3 from unit length, too).
QUATERNION_NORM_TOL = 1e-3


class BagError(PosesFileError):
    """A bag that cannot be read as measured poses (one line, exit 2)."""


class _Bad(Exception):
    """What a message of the bag holds cannot be used (becomes a :class:`BagError`)."""


def is_bag(path: Path) -> bool:
    """Whether ``poses:PATH`` names a ROS 2 bag: a directory, or a ``.mcap`` / ``.db3`` file."""
    return path.is_dir() or path.suffix.lower() in (".mcap", ".db3")


def bag_files(path: Path) -> tuple[Path, ...]:
    """The bag and the files in its directory: what no output of the run may replace.

    At most :data:`MAX_FRAMES` entries of the directory are listed (a bag has a few).
    """
    if not path.is_dir():
        return (path,)
    try:
        with os.scandir(path) as entries:
            found = [Path(e.path) for _, e in zip(range(MAX_FRAMES), entries, strict=False)]
    except OSError:
        found = []
    return (path, *sorted(found))


def _regular(path: Path, what: str, bag: Path, *, follow: bool) -> None:
    """Refuse anything but a regular file (a FIFO would hang the read; a link may lead out)."""
    try:
        info = os.stat(path) if follow else os.lstat(path)
    except OSError as exc:
        raise BagError(bag, f"{what}: {exc.strerror or exc}") from None
    if stat.S_ISLNK(info.st_mode):
        raise BagError(bag, f"{what} is a symbolic link; a bag's files must be in it")
    if not stat.S_ISREG(info.st_mode):
        raise BagError(bag, f"{what} is not a regular file")


def _screen(path: Path) -> str:
    """The bag's storage, ``mcap`` or ``sqlite3``, once its files are known to be safe to read.

    Raises:
        BagError: Not a bag, a file of it not a regular file in it, compressed, or
            metadata that is not a bag's.
    """
    import yaml

    if not path.is_dir():
        _regular(path, "the bag", path, follow=True)
        return "mcap" if path.suffix.lower() == ".mcap" else "sqlite3"
    meta = path / "metadata.yaml"
    if not os.path.lexists(meta):
        raise BagError(
            path,
            "is a directory, not a regular file, and not a ROS 2 bag either (no "
            "metadata.yaml): give a poses CSV, the bag directory ros2 bag record wrote, or "
            "its .mcap or .db3 file",
        )
    _regular(meta, "metadata.yaml", path, follow=False)
    if os.path.getsize(meta) > MAX_METADATA_BYTES:
        raise BagError(path, f"metadata.yaml is larger than {MAX_METADATA_BYTES >> 20} MiB")
    try:
        text = meta.read_bytes()
        # Plain data, as ROS writes it: an alias bomb of a few hundred bytes expands to
        # billions of values in whoever walks it (rosbags reads this file too).
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None):
                raise BagError(
                    path, "metadata.yaml has an anchor or alias (&name, *name); ROS writes none"
                )
        doc = yaml.safe_load(text)
        info = doc["rosbag2_bagfile_information"]
        storage = info["storage_identifier"]
        files = info["relative_file_paths"]
        mode = str(info.get("compression_mode", "") or "").lower()
    except (yaml.YAMLError, KeyError, TypeError, AttributeError, OSError, UnicodeError) as exc:
        reason = type(exc).__name__ if isinstance(exc, KeyError) else exc
        raise BagError(path, f"metadata.yaml is not a ROS 2 bag's ({reason})") from None
    if storage not in ("mcap", "sqlite3"):
        raise BagError(path, f"storage {str(storage)[:40]!r} is not mcap or sqlite3")
    if mode not in ("", "none"):
        raise BagError(
            path,
            f"the bag is compressed (compression_mode {mode[:20]!r}); write it uncompressed "
            "(ros2 bag convert) or record it with the mcap storage, whose chunk compression "
            "is read",
        )
    if not isinstance(files, list) or not files or len(files) > 10_000:
        raise BagError(path, "metadata.yaml's relative_file_paths is not a list of files")
    for name in files:
        _regular(path / Path(str(name)).name, f"its file {Path(str(name)).name}", path,
                 follow=False)  # fmt: skip
    return str(storage)
