"""The description formats, and the one place a model's description is loaded and kept.

:func:`load_description` is how every part of fkcheck reads a model's
description: the engine, the backends, provenance, coverage, ``map``,
``diagnose``. What it read is kept for the rest of the process (a test suite
checks one description many times) in one cache, keyed by the format and the
model's description keys (:meth:`DescriptionFormat.key`) and used again only
while every file it was made of has the same bytes (SHA-256; a file edited in
place within one clock tick, its size unchanged, is read again). A format
whose reading runs code keeps its own results (:func:`fkcheck.urdf.xacro.read_xacro`
knows when an expansion looked for files it did not read, which must run again).
"""

from __future__ import annotations

import hashlib
import os
import threading
from collections.abc import Mapping
from pathlib import Path

from fkcheck.description.mjcf import MJCF
from fkcheck.description.types import Description, DescriptionFormat
from fkcheck.description.urdf import URDF, XACRO
from fkcheck.errors import FkcheckError, UrdfError
from fkcheck.model.types import Model
from fkcheck.urdf.screen import MAX_URDF_BYTES
from fkcheck.urdf.xacro import XACRO_TIMEOUT_S

__all__ = [
    "DESCRIPTION_TIMEOUT_S",
    "FORMATS",
    "LANGUAGES",
    "clear_descriptions",
    "format_named",
    "format_of_file",
    "load_description",
    "model_format",
    "model_formats",
    "read_description_file",
]

#: Every description format, in the order a model's sections are asked.
FORMATS: tuple[DescriptionFormat, ...] = (XACRO, URDF, MJCF)

#: The languages descriptions are read in (a backend's ``reads`` when it reads one).
LANGUAGES: tuple[str, ...] = tuple(dict.fromkeys(f.language for f in FORMATS))

#: The time limit of any code reading a description runs (xacro's macros), s.
DESCRIPTION_TIMEOUT_S = XACRO_TIMEOUT_S


def format_named(name: str) -> DescriptionFormat:
    """The format called ``name``.

    Raises:
        FkcheckError: No such format (the message lists them).
    """
    for fmt in FORMATS:
        if fmt.name == name:
            return fmt
    raise FkcheckError(
        f"unknown description format {name!r}; formats are: {', '.join(f.name for f in FORMATS)}"
    )


def model_formats(model: Model) -> tuple[DescriptionFormat, ...]:
    """Every description format ``model`` declares (one per section), in :data:`FORMATS` order."""
    return tuple(fmt for fmt in FORMATS if fmt.declared_by(model))


def model_format(model: Model, language: str | None = None) -> DescriptionFormat | None:
    """The format of ``model``'s description (the first it declares), or ``None``.

    ``language``: the format of its description in that language (``"urdf"``
    for ``[urdf]``, whether URDF or xacro).
    """
    for fmt in model_formats(model):
        if language is None or fmt.language == language:
            return fmt
    return None


def format_of_file(path: str | Path) -> DescriptionFormat:
    """The format a file named on the command line is read as, by its suffix.

    A file no format claims is read as a URDF (whose screen refuses xacro and
    says how to allow it), as ``map`` and ``table-from`` always did.
    """
    name = str(path).lower()
    for fmt in sorted(FORMATS, key=lambda f: -max((len(s) for s in f.suffixes), default=0)):
        if any(name.endswith(s) for s in fmt.suffixes) and not fmt.executes:
            return fmt
    return URDF


def load_description(
    model: Model,
    timeout_s: float = DESCRIPTION_TIMEOUT_S,
    *,
    mapping: bool = True,
    language: str | None = None,
) -> Description:
    """``model``'s description: found, screened, read once per process, its mapping checked.

    ``timeout_s`` bounds any code the reading runs (a xacro expansion);
    ``mapping=False`` leaves the joint mapping unchecked (``map``, which proposes it,
    and the files a run reads); ``language``: its description in that language
    (:func:`model_format`), for a model that declares more than one.

    Raises:
        UrdfError: The model has no description; or it is missing, unsafe, not
            valid, or a mapped joint is missing or of the wrong type.
        BackendUnavailable: It names a package that is not installed.
    """
    fmt = model_format(model, language)
    if fmt is None:
        section = "urdf" if language is None else language
        raise UrdfError(f"model {model.name}", f"has no [{section}] table")
    key = (fmt.name, fmt.key(model), os.getcwd())
    with _LOCK:
        kept = _KEPT.get(key)
    if kept is not None and kept[1] == _digests(kept[0].files):
        description = kept[0]
    else:
        description = fmt.read_model(model, timeout_s)
        # An expansion is kept by its format (which knows whether it looked for files
        # it did not read, :func:`fkcheck.urdf.xacro.read_xacro`), not here.
        kept_here = not format_named(description.format).executes
        digests = _digests(description.files) if kept_here else None
        if digests is not None:
            with _LOCK:
                _KEPT.pop(key, None)
                _KEPT[key] = (description, digests)
                while len(_KEPT) > _KEPT_SIZE:
                    del _KEPT[next(iter(_KEPT))]
    if mapping:
        fmt.check_mapping(model, description)
    return description


def read_description_file(
    spec: str | Path,
    *,
    args: Mapping[str, str] | None = None,
    packages: Mapping[str, Path] | None = None,
) -> Description:
    """A description named on the command line, read as its suffix's format (not kept).

    Args: as :meth:`DescriptionFormat.read_file`.

    Raises:
        UrdfError: Missing, unsafe or not valid.
        BackendUnavailable: It names a package that is not installed.
    """
    return format_of_file(spec).read_file(spec, args=args, packages=packages)


def clear_descriptions() -> None:
    """Forget every kept description (tests that count readings)."""
    with _LOCK:
        _KEPT.clear()


#: How many descriptions :func:`load_description` keeps.
_KEPT_SIZE = 32
_KEPT: dict[tuple[object, ...], tuple[Description, tuple[str, ...]]] = {}
_LOCK = threading.Lock()


def _digests(files: tuple[Path, ...]) -> tuple[str, ...] | None:
    """The SHA-256 of each file's bytes (``None`` when one cannot be read)."""
    from fkcheck.io.files import InputFileError, read_bytes

    try:
        return tuple(hashlib.sha256(read_bytes(f, MAX_URDF_BYTES)).hexdigest() for f in files)
    except (InputFileError, OSError):
        return None
