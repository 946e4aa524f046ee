"""Expanding a xacro description, only when asked: in a child process, declared packages only.

fkcheck reads plain URDF; a xacro file is refused by the screen
(:mod:`fkcheck.urdf.screen`) unless the model says ``xacro = true`` in its
``[urdf]`` table or the command line says ``--allow-xacro``. The expansion is
xacrodoc's (xacro without ROS), with what a description can do cut down to
xacro's macros and properties over plain data:

* ``${…}`` and ``$(eval …)`` are never Python: fkcheck's own evaluator
  (:mod:`fkcheck.urdf.expression`) takes the place of xacro's ``eval``. It
  evaluates numbers, strings, properties and arguments, arithmetic,
  comparisons, conditionals, lists and mappings, the math functions and the
  builtins xacro documents, and refuses everything else in one line naming the
  file and the expression — attribute access on values, lambdas,
  comprehensions, format strings — so no expression reaches a class, a frame
  or a builtin, whatever it is named. xacro's own global names are emptied;
* ``$(find PKG)`` (and ``find()`` in ``$(eval …)``) resolves only to the
  packages the caller declares (``packages`` in ``[urdf]``, ``--package`` on the
  command line) — never ``ROS_PACKAGE_PATH``, ament, a walk up the directories
  or anything else in the environment; an undeclared package is one line that
  names the declared ones;
* ``$(env …)`` and ``$(optenv …)`` (and ``env()``/``optenv()`` in ``$(eval …)``)
  are refused: the environment is not an input of a check; pass the value as a
  xacro argument instead. ``$(arg …)``, ``$(dirname)`` (the directory of the
  file being read) and ``$(eval …)`` work as in xacro;
* ``<xacro:include>`` (wildcards too) and ``xacro.load_yaml`` read files only
  inside the directory of the xacro file and the declared packages, regular
  files of at most :data:`~fkcheck.urdf.screen.MAX_URDF_BYTES`, named relative to
  the file that names them, as xacro does — and the files the caller passes as
  arguments (``xacro_files`` in ``[urdf]``, ``--arg-file`` on the command
  line), each of them alone; yaml is read with yaml's safe loader
  (and xacro's unit tags, ``!degrees 90``) and becomes plain data;
* it runs in a child process (:func:`fkcheck.process.isolation.run_isolated`)
  executed with an empty environment, with a time limit
  (:data:`XACRO_TIMEOUT_S`), a hard address-space limit
  (:data:`XACRO_MEMORY_BYTES`) and a bounded answer: macros that recurse or
  multiply without end are stopped;
* the expanded text stays in memory (no file is written) and then goes through
  the very screen a plain URDF goes through (:func:`fkcheck.urdf.tree.urdf_info_from_bytes`:
  size, no DTD or entity, no xacro left, tree checks); ``package://`` mesh names
  are left as they are and meshes are never opened.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import threading
import types
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

from fkcheck.errors import INSTALL_REFERENCE, UrdfError
from fkcheck.model.types import PACKAGE_NAME
from fkcheck.process.isolation import IsolatedDied, IsolatedTimeout, run_isolated
from fkcheck.urdf.screen import MAX_URDF_BYTES, check_urdf_path, read_urdf_bytes
from fkcheck.urdf.tree import UrdfInfo, urdf_info_from_bytes
from fkcheck.urdf.xacro_child import XACRO_MEMORY_BYTES
from fkcheck.urdf.xacro_child import expand_job as _expand_job  # the child's side

__all__ = [
    "XACRO_MEMORY_BYTES",
    "XACRO_TIMEOUT_S",
    "XacroExpansion",
    "check_argument_files",
    "check_package_name",
    "expand_xacro",
    "read_xacro",
    "screen_expansion",
]

#: How long one expansion may take, s (a real description takes well under a second).
XACRO_TIMEOUT_S = 60.0
#: The answer's limit: the largest URDF, UTF-8 (up to 4 bytes a character), plus framing.
_ANSWER_BYTES = 4 * MAX_URDF_BYTES + 64 * 1024
#: The environment the expansion's process is executed with: none.
_CHILD_ENV: Mapping[str, str] = types.MappingProxyType({})


@dataclass(frozen=True)
class XacroExpansion:
    """A xacro file expanded: the URDF text and the files it was made of.

    Attributes:
        text: The expanded document (not screened yet: :func:`screen_expansion`).
        files: Every file the expansion read, resolved: the xacro file first, then
            its includes and ``load_yaml`` files in the order they were read.
        probed: Whether the expansion looked for files it did not read (a
            wildcard include, an optional include of a missing file): then the
            files alone do not say whether it would expand the same again.
    """

    text: str
    files: tuple[Path, ...]
    probed: bool = False


def check_argument_files(
    path: Path | str, args: Mapping[str, str], files: Mapping[str, Path]
) -> dict[str, Path]:
    """The files of xacro arguments that name one, resolved and checked.

    Each must be a regular file of at most
    :data:`~fkcheck.urdf.screen.MAX_URDF_BYTES`; a symbolic link is followed, as
    an include's is, and the file it leads to is the one passed and readable.

    Args:
        path: The xacro file (for messages).
        args: The other xacro arguments: a name may not be in both.
        files: Argument name → file.

    Returns:
        Argument name → the file's resolved absolute path.

    Raises:
        UrdfError: A name is in both, or a file is missing, not a regular file
            (a directory, a FIFO, a device) or too large: one line naming it.
    """
    from fkcheck.io.files import InputFileError, check_regular_file

    checked: dict[str, Path] = {}
    for name, file in files.items():
        if name in args:
            raise UrdfError(
                path,
                f"xacro argument {name!r} is given both as a value and as a file: give it once "
                "(xacro_args or xacro_files in [urdf]; --arg or --arg-file)",
            )
        try:
            check_regular_file(file, MAX_URDF_BYTES)
        except InputFileError as exc:
            raise UrdfError(path, f"xacro argument file {name}={file}: {exc.problem}") from None
        checked[name] = file.resolve()
    return checked


def check_package_name(name: str) -> str:
    """``name`` if it can be a package name (letters, digits, ``_ . -``), else ``ValueError``."""
    if not PACKAGE_NAME.fullmatch(name):
        raise ValueError(
            f"{name!r} is not a package name (letters, digits, '_', '.', '-'; as in $(find NAME))"
        )
    return name


def expand_xacro(
    path: Path,
    args: Mapping[str, str] | None = None,
    packages: Mapping[str, Path] | None = None,
    timeout_s: float = XACRO_TIMEOUT_S,
    files: Mapping[str, Path] | None = None,
) -> XacroExpansion:
    """Expand a xacro file to plain URDF text, in a time- and memory-limited child process.

    The text is not screened here: :func:`read_xacro` screens it as a URDF.

    Args:
        path: The xacro file (read bounded, regular files only).
        args: xacro arguments (``<xacro:arg>``), as ``name:=value`` on xacro's
            command line.
        packages: The only packages ``$(find …)`` resolves: name → directory.
        timeout_s: The time limit of the expansion, s.
        files: xacro arguments that name a file: name → file. Each is passed as
            its absolute path and becomes readable by ``load_yaml`` and includes
            (that file only; :func:`check_argument_files`).

    Returns:
        The expanded document and the files it was made of.

    Raises:
        UrdfError: The file cannot be read, a declared package is not a
            directory, an argument file is refused (:func:`check_argument_files`),
            or the expansion fails (a missing argument, an undeclared
            package, ``$(env …)``, an include outside the allowed directories, a
            xacro error, the time or memory limit, an answer beyond
            :data:`~fkcheck.urdf.screen.MAX_URDF_BYTES`), or xacrodoc (of the
            ``reference`` extra) is not installed: one line naming the file.
    """
    data = read_urdf_bytes(path)
    if importlib.util.find_spec("xacrodoc") is None:
        raise UrdfError(
            path, f"expanding xacro needs xacrodoc, which is not installed ({INSTALL_REFERENCE})"
        )
    declared: dict[str, str] = {}
    for name, directory in sorted((packages or {}).items()):
        if not directory.is_dir():
            raise UrdfError(path, f"package {name!r} is declared at {directory}, not a directory")
        declared[name] = str(directory.resolve())
    roots = [str(path.resolve().parent), *declared.values()]
    arg_files = check_argument_files(path, args or {}, files or {})
    values = {**(args or {}), **{name: str(file) for name, file in arg_files.items()}}
    allowed = sorted({str(file) for file in arg_files.values()})
    job = functools.partial(
        _expand_job, data, str(path.resolve()), values, declared, roots, allowed
    )
    try:
        kind, value = run_isolated(job, timeout_s, _ANSWER_BYTES, env=_CHILD_ENV)
    except IsolatedTimeout:
        raise UrdfError(
            path, f"xacro expansion did not end within {timeout_s:g} s (stopped)"
        ) from None
    except IsolatedDied as exc:
        raise UrdfError(path, f"xacro expansion failed: {exc}") from None
    if kind != "ok":
        raise UrdfError(path, f"xacro expansion failed: {value}")
    text, included, probed = value
    read = dict.fromkeys([path.resolve(), *(Path(name) for name in included)])
    return XacroExpansion(str(text), tuple(read), bool(probed))


def read_xacro(
    path: Path,
    args: Mapping[str, str] | None = None,
    packages: Mapping[str, Path] | None = None,
    package_dirs: tuple[Path, ...] = (),
    timeout_s: float = XACRO_TIMEOUT_S,
    files: Mapping[str, Path] | None = None,
) -> UrdfInfo:
    """Expand a xacro file and screen, check and summarise the result as a URDF.

    The result is kept for the rest of the process (a test suite checks the same
    description many times), keyed by the file, the arguments, the argument
    files, the packages, ``package_dirs`` and the working directory, and used
    again only while every file the expansion read has the same bytes; an
    expansion that looked for files it did not read (a wildcard include, an
    optional include of a missing file) is not kept.

    Args:
        path: The xacro file.
        args: xacro arguments.
        packages: The packages ``$(find …)`` may resolve: name → directory.
        package_dirs: Directories holding the ``package://`` packages it names.
        timeout_s: The time limit of the expansion, s.
        files: xacro arguments that name a file (:func:`expand_xacro`).

    Raises:
        UrdfError: As :func:`expand_xacro`, or the expanded URDF is refused by
            the screen (:mod:`fkcheck.urdf.screen`) or is not a valid tree.
    """
    check_urdf_path(path)
    key = (
        str(path.resolve()),
        tuple(sorted((args or {}).items())),
        tuple(sorted((name, str(d.resolve())) for name, d in (packages or {}).items())),
        tuple(sorted((name, str(f.resolve())) for name, f in (files or {}).items())),
        tuple(str(d) for d in package_dirs),
        os.getcwd(),
    )
    with _CACHE_LOCK:
        kept = _CACHE.get(key)
    if kept is not None and kept[1] == _digests(kept[0].files):
        return kept[0]
    expansion = expand_xacro(path, args, packages, timeout_s, files)
    info = screen_expansion(path, expansion.text, package_dirs)
    info = replace(info, files=expansion.files)  # no output of the run may replace one
    digests = _digests(expansion.files)
    if not expansion.probed and digests is not None:
        with _CACHE_LOCK:
            _CACHE.pop(key, None)
            _CACHE[key] = (info, digests)
            while len(_CACHE) > _CACHE_SIZE:
                del _CACHE[next(iter(_CACHE))]
    return info


#: How many expansions :func:`read_xacro` keeps.
_CACHE_SIZE = 16
_CACHE: dict[tuple[object, ...], tuple[UrdfInfo, tuple[str, ...]]] = {}
_CACHE_LOCK = threading.Lock()


def _digests(files: tuple[Path, ...]) -> tuple[str, ...] | None:
    """The SHA-256 of each file's bytes (``None`` when one cannot be read)."""
    from fkcheck.io.files import InputFileError, read_bytes

    try:
        return tuple(hashlib.sha256(read_bytes(f, MAX_URDF_BYTES)).hexdigest() for f in files)
    except (InputFileError, OSError):
        return None


def screen_expansion(path: Path, text: str, package_dirs: tuple[Path, ...] = ()) -> UrdfInfo:
    """Put an expanded xacro through the screen and checks of a plain URDF.

    Args:
        path: The xacro file it came from (for messages).
        text: The expansion (:func:`expand_xacro`).
        package_dirs: Directories holding the ``package://`` packages it names.

    Raises:
        UrdfError: Not UTF-8 (a directory name through ``$(find …)``), larger than
            :data:`~fkcheck.urdf.screen.MAX_URDF_BYTES`, refused by the screen (a
            DTD or entity, xacro left over, …) or not a valid tree.
    """
    stray = next((c for c in text if "\udc80" <= c <= "\udcff"), None)
    if stray is not None:  # a directory or argument name that is not UTF-8, via $(find …)
        raise UrdfError(
            path,
            f"its expansion holds a byte that is not UTF-8 (0x{ord(stray) - 0xDC00:02x}, "
            "from a directory or argument name): a URDF cannot; rename it",
        )
    data = text.encode("utf-8")
    if len(data) > MAX_URDF_BYTES:
        raise UrdfError(
            path, f"its expansion is larger than {MAX_URDF_BYTES} bytes (the limit for a URDF)"
        )
    return urdf_info_from_bytes(path, data, package_dirs)
