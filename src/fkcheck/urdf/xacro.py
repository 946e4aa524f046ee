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
import io
import os
import re
import threading
import types
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from fkcheck.errors import INSTALL_REFERENCE, UrdfError
from fkcheck.model.types import PACKAGE_NAME
from fkcheck.process.isolation import IsolatedDied, IsolatedTimeout, run_isolated
from fkcheck.urdf.screen import MAX_URDF_BYTES, check_urdf_path, read_urdf_bytes
from fkcheck.urdf.tree import UrdfInfo, urdf_info_from_bytes

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
#: The child's address-space limit, bytes: a ``${…}`` building a huge value fails there.
XACRO_MEMORY_BYTES = 2 * 1024**3
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


# --- the child's side: everything below runs in the child process only --------------


class _Refused(Exception):
    """Something the expansion may not do (raised inside xacro, reported as is)."""


def _expand_job(
    data: bytes,
    path: str,
    args: dict[str, str],
    packages: dict[str, str],
    roots: list[str],
    files: list[str],
) -> tuple[str, str | tuple[str, list[str], list[str]]]:
    """Expand in the child: ``("ok", (urdf, files read, looked for))`` or ``("error", one line)``.

    ``files`` are the only files outside ``roots`` it may read (argument files).
    """
    import resource

    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = XACRO_MEMORY_BYTES if hard == resource.RLIM_INFINITY else min(hard, XACRO_MEMORY_BYTES)
    if soft == resource.RLIM_INFINITY or soft > limit or hard != limit:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))  # hard too: it cannot be raised
    # Executed with no environment (_CHILD_ENV); what Python itself set at start-up goes too.
    os.environ.clear()
    read: list[str] = []
    probed: list[str] = []
    try:
        xacro = _fenced_xacro(path, packages, roots, files, read, probed)
        from xacrodoc import XacroDoc

        xacro.init_stacks(path)  # relative includes are relative to the file, not to the cwd
        doc = XacroDoc.from_string(io.BytesIO(data), subargs=args, resolve_packages=False)
        text: str = doc.dom.toxml()
    except Exception as exc:  # xacro's errors, whatever their type: one line, no traceback
        return "error", _one_line(exc)
    if len(text) > MAX_URDF_BYTES:
        return (
            "error",
            f"its expansion is larger than {MAX_URDF_BYTES} bytes (the limit for a URDF)",
        )
    return "ok", (text, read, probed)


def _one_line(exc: BaseException) -> str:
    """The xacro message for ``exc``, unwrapped to ours when it wraps a refusal, on one line."""
    chain = [exc]  # xacro wraps the error it met in XacroException(…, exc=error)
    while isinstance(getattr(chain[-1], "exc", None), BaseException) and len(chain) < 100:
        chain.append(chain[-1].exc)  # type: ignore[attr-defined]
    for error in chain:
        if isinstance(error, _Refused):
            return str(error)
        if isinstance(error, MemoryError):
            return f"it needs more than {XACRO_MEMORY_BYTES // 1024**3} GiB of memory"
        if isinstance(error, RecursionError):
            return "it recurses without end (a macro calling itself?)"
    text = str(exc).strip() or type(exc).__name__
    if type(exc).__name__ == "XacroException" and "Undefined substitution argument" in text:
        name = text.rsplit(" ", 1)[-1]
        return (
            f"xacro argument {name!r} is not given and has no default: give it "
            f'(xacro_args = {{ {name} = "…" }} in [urdf], or --arg {name}=VALUE)'
        )
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return "; ".join(lines)[:500]


def _shown(text: str) -> str:
    """An expression as a message quotes it: on one line, at most 100 characters."""
    flat = " ".join(text.split())
    return flat if len(flat) <= 100 else flat[:100] + "…"


def _fenced_xacro(
    top: str,
    packages: dict[str, str],
    roots: list[str],
    files: list[str],
    read: list[str],
    probed: list[str],
) -> Any:
    """Import xacro (through xacrodoc) and put fkcheck's evaluator and fences in it.

    ``${…}`` and ``$(eval …)`` are evaluated by :func:`fkcheck.urdf.expression.evaluate`
    (xacro's ``safe_eval`` and ``substitution_args._eval`` are replaced; nothing
    calls Python's ``eval``); files are read only inside ``roots`` or among
    ``files``, each appended to ``read`` (wildcards and missing optional
    includes to ``probed``); ``$(find …)`` resolves only ``packages``; the environment is refused.
    """
    import xacro  # type: ignore[import-untyped]  # (no stubs; xacrodoc's dependency)
    import xacrodoc  # noqa: F401  (it patches $(find …) on import: patch after it)
    from xacro import substitution_args

    fence = _Fence(
        xacro, top, packages, roots, frozenset(files), read, probed, xacro.parse,
        xacro.eval_extension,
    )  # fmt: skip
    names: dict[str, object] = {}
    load_yaml = functools.partial(_load_yaml, fence, names)
    names.update(_expression_names(fence, load_yaml))
    evaluator = _Evaluator(fence, names)
    substitution_args._eval_find = fence.find
    substitution_args._eval_env = fence.env
    substitution_args._eval_optenv = fence.env
    substitution_args._eval = evaluator.eval_substitution  # $(eval …): never Python's eval
    substitution_args._eval_dict.clear()
    xacro.safe_eval = evaluator.xacro_eval  # ${…}: never Python's eval
    xacro._global_symbols.clear()  # xacro's own names (builtins, modules) are unreachable
    xacro.parse = fence.confined_parse
    xacro.glob = types.SimpleNamespace(glob=fence.confined_glob)
    xacro.load_yaml = load_yaml
    xacro.eval_extension = fence.located_extension
    return xacro


@dataclass(frozen=True)
class _Fence:
    """What an expansion may reach: files inside ``roots`` and the declared ``packages``.

    Attributes:
        xacro: The xacro module.
        top: The xacro file being expanded.
        packages: The only packages ``$(find …)`` resolves: name → directory.
        roots: The directories files may be read from.
        files: The files outside them that may be read (argument files), resolved.
        read: The files read, appended to as they are.
        probed: Wildcard includes and missing optional includes, appended to as met.
        parse: xacro's own ``parse`` (before it is replaced).
        eval_extension: xacro's own ``eval_extension`` (before it is replaced).
    """

    xacro: Any
    top: str
    packages: dict[str, str]
    roots: list[str]
    files: frozenset[str]
    read: list[str]
    probed: list[str]
    parse: Callable[..., Any]
    eval_extension: Callable[[str], Any]

    def where(self) -> str:
        """``in FILE: `` when xacro is in another file than the top one (for messages)."""
        xacro = self.xacro
        current = xacro.filestack[-1] if xacro.filestack else None
        if not current or current == self.top:
            return ""
        return f"in {os.path.relpath(current, os.path.dirname(self.top))}: "

    # --- files: the xacro file's directory and the declared packages only

    def confined(self, filename: str, what: str, name: str) -> Path:
        """``filename`` resolved, when inside the roots or one of the argument files."""
        target = Path(filename).resolve()
        if str(target) in self.files:
            return target
        if not any(target.is_relative_to(root) for root in self.roots):
            raise _Refused(
                f"{what} {name!r}: outside the xacro file's directory and the declared "
                f"packages ({', '.join(self.roots)})"
            )
        return target

    def read_file(self, target: Path, what: str, name: str) -> bytes:
        """A regular file of at most :data:`MAX_URDF_BYTES`, recorded as read."""
        from fkcheck.io.files import InputFileError, read_bytes

        try:
            data = read_bytes(target, MAX_URDF_BYTES)
        except InputFileError as exc:
            raise _Refused(f"{what} {name!r}: {exc.problem}") from None
        self.read.append(str(target))
        return data

    def confined_parse(self, inp: Any, filename: str | None = None) -> Any:
        """The ``parse`` of xacro, reading an included file only inside the roots."""
        if inp is None and filename is not None:
            target = self.confined(
                os.path.join(self.xacro.root_dir, filename), "include of", filename
            )
            if not target.exists():  # xacro's own error (an optional include is skipped)
                self.probed.append(str(target))
                return self.parse(None, filename)
            return self.parse(io.BytesIO(self.read_file(target, "include of", filename)))
        return self.parse(inp, filename)

    def confined_glob(self, pattern: str) -> list[str]:
        """The files an include's wildcard matches, all inside the roots."""
        import glob

        magic = next((i for i, c in enumerate(pattern) if c in "*?["), len(pattern))
        if ".." in Path(pattern[magic:]).parts:
            raise _Refused(f"include of {pattern!r}: '..' after a wildcard is not allowed")
        self.confined(os.path.dirname(pattern[:magic]) or ".", "include of", pattern)
        found = sorted(glob.glob(pattern))
        self.probed.append(pattern)
        for name in found:
            if not any(Path(name).resolve().is_relative_to(root) for root in self.roots):
                raise _Refused(
                    f"include of {pattern!r}: it matches files outside the xacro file's "
                    "directory and the declared packages"
                )
        return found

    # --- $(find …), $(env …), $(optenv …), $(dirname)

    def find(self, name: str) -> str:
        """``$(find NAME)``: a declared package's directory."""
        if name not in self.packages:
            shown = ", ".join(sorted(self.packages)) or "none"
            raise _Refused(
                f"$(find {name}): package {name!r} is not declared; declared packages: {shown} "
                f'(declare it: packages = {{ {name} = "DIR" }} in [urdf], or --package {name}=DIR)'
            )
        return self.packages[name]

    def env(self, name: str, *_: str, **__: str) -> str:
        """``$(env …)`` and ``$(optenv …)``: refused."""
        raise _Refused(
            f"$(env {name}) / $(optenv {name}): fkcheck does not read the environment for "
            "xacro; pass the value as a xacro argument (xacro_args in [urdf], or --arg)"
        )

    def located_extension(self, text: str) -> Any:
        """The ``$(…)`` of xacro, ``$(dirname)`` being the directory of the file being read."""
        # (as xacro documents it: this xacro never sets the file it reads, so its own
        # $(dirname) always fails)
        xacro = self.xacro
        context = xacro.substitution_args_context
        context["filename"] = xacro.filestack[-1] if xacro.filestack else None
        return self.eval_extension(text)


# --- the names of an expression


def _expression_names(fence: _Fence, load_yaml: Callable[[object], object]) -> dict[str, object]:
    """The names an expression may use: the standard ones and xacro's helpers."""
    from fkcheck.urdf.expression import Function, namespace, standard_names

    names = standard_names()

    def abs_filename(filename: object) -> object:
        from fkcheck.urdf.expression import ExpressionError

        if type(filename) is not str:
            raise ExpressionError("abs_filename takes a file name (a string)")
        return str(fence.xacro.abs_filename_spec(filename))

    def arg(name: object) -> object:
        return str(fence.xacro.substitution_args_context["arg"][name])

    helpers: dict[str, Callable[..., object]] = {
        "load_yaml": load_yaml, "abs_filename": abs_filename, "dotify": _dotify, "arg": arg,
        "tokenize": _tokenize, "fatal": _fatal, "message": _quiet, "warning": _quiet,
        "error": _quiet, "print_location": _quiet,
    }  # fmt: skip
    members = {name: Function(f"xacro.{name}", fn) for name, fn in helpers.items()}
    names["xacro"] = namespace("xacro", members)
    for name in ("load_yaml", "abs_filename", "dotify"):  # xacro has them directly too
        names[name] = members[name]
    return names


def _load_yaml(fence: _Fence, names: dict[str, object], filename: object) -> object:
    """``xacro.load_yaml``: a yaml file inside the roots, as plain data."""
    import yaml

    from fkcheck.urdf.expression import ExpressionError, plain

    if type(filename) is not str:
        raise ExpressionError("load_yaml takes a file name (a string)")
    target = fence.confined(fence.xacro.abs_filename_spec(filename), "load_yaml of", filename)
    data = fence.read_file(target, "load_yaml of", filename)
    try:
        return plain(yaml.load(data, Loader=_yaml_loader(fence.xacro, names)))  # a SafeLoader
    except yaml.YAMLError as exc:
        raise ExpressionError(f"load_yaml of {filename!r}: {_shown(str(exc))}") from None
    except RecursionError:
        raise ExpressionError(f"load_yaml of {filename!r}: nested too deeply") from None
    except ExpressionError as exc:
        raise ExpressionError(f"load_yaml of {filename!r}: {exc}") from None


def _dotify(value: object) -> object:
    """``xacro.dotify``: a mapping as it is (its keys are reached with ``a.b`` already)."""
    from fkcheck.urdf.expression import ExpressionError

    if type(value) is not dict:
        raise ExpressionError("dotify takes a mapping")
    return value


def _tokenize(text: object, sep: object = ",; ", skip_empty: object = True) -> object:
    """``xacro.tokenize``: ``text`` split at any of the ``sep`` characters."""
    from fkcheck.urdf.expression import MAX_ITEMS, ExpressionError

    if type(text) is not str or type(sep) is not str or not 0 < len(sep) <= 100:
        raise ExpressionError("tokenize takes a string and up to 100 separator characters")
    if sum(text.count(c) for c in sep) >= MAX_ITEMS:
        raise ExpressionError(f"tokenize would give more than {MAX_ITEMS} items")
    parts = re.split(f"[{re.escape(sep)}]", text)
    return [part for part in parts if part] if skip_empty else parts


def _fatal(*args: object) -> object:
    """``xacro.fatal``: the expansion stops with the message."""
    from fkcheck.urdf.expression import ExpressionError

    raise ExpressionError("xacro.fatal: " + _shown(" ".join(map(str, args))))


def _quiet(*args: object, **kwargs: object) -> object:
    """``xacro.message``, ``warning``…: nothing (xacro prints them on stderr, not shown)."""
    return ""


_MISSING = object()


@dataclass(frozen=True)
class _Evaluator:
    """``${…}`` and ``$(eval …)`` by :func:`fkcheck.urdf.expression.evaluate`, never Python's.

    Attributes:
        fence: What the expansion may reach (``find``, ``env``, messages' file).
        names: The names an expression may use besides the properties.
    """

    fence: _Fence
    names: dict[str, object]

    def lookup(self, table: Any, name: str) -> object:
        """A property: in ``table`` or the tables around it, never xacro's own globals."""
        from fkcheck.urdf.expression import Namespace

        xacro = self.fence.xacro
        while isinstance(table, xacro.Table):
            if dict.__contains__(table, name):
                value = table[name]  # a lazy property is evaluated here (by evaluate, again)
                if isinstance(value, xacro.NameSpace):  # <xacro:include ns="NAME"/>
                    return Namespace(name, functools.partial(self.member, value))
                return value
            table = table.parent
        return _MISSING

    def member(self, table: Any, name: str) -> object:
        """A property, else a name of :attr:`names`."""
        found = self.lookup(table, name)
        return self.names[name] if found is _MISSING else found

    def xacro_eval(self, expr: str, symbols: Any, locals: Any = None) -> object:
        """The ``safe_eval`` of xacro, for ``${…}``."""
        from fkcheck.urdf.expression import ExpressionError, evaluate

        try:
            return evaluate(expr, functools.partial(self.member, symbols))
        except ExpressionError as exc:
            raise _Refused(f"{self.fence.where()}${{{_shown(expr)}}}: {exc}") from None

    def eval_substitution(self, text: str, context: dict[str, Any]) -> str:
        """``$(eval …)``, with ``find``, ``env``, ``arg`` and ``dirname`` as functions."""
        from xacro import substitution_args

        from fkcheck.urdf.expression import ExpressionError, Function, evaluate

        args = context.setdefault("arg", {})

        def value_of(name: str) -> object:
            return substitution_args.convert_value(args[name], "auto")

        def dirname() -> object:
            return substitution_args._eval_dirname(context.get("filename"))

        fence = self.fence
        local: dict[str, object] = {
            "true": True, "false": False, "find": Function("find", fence.find),
            "env": Function("env", fence.env), "optenv": Function("optenv", fence.env),
            "arg": Function("arg", value_of), "dirname": Function("dirname", dirname),
        }  # fmt: skip

        def resolve(name: str) -> object:
            if name in local:
                return local[name]
            if name in self.names:
                return self.names[name]
            return value_of(name)

        try:
            return str(evaluate(text, resolve))
        except ExpressionError as exc:
            raise _Refused(f"{fence.where()}$(eval {_shown(text)}): {exc}") from None


def _yaml_loader(xacro: Any, names: dict[str, object]) -> type[Any]:
    """A yaml SafeLoader with xacro's unit tags (``!degrees 90``), evaluated by fkcheck."""
    import yaml

    from fkcheck.urdf.expression import ExpressionError, evaluate

    class Loader(yaml.SafeLoader):  # type: ignore[misc]  # (no stubs)
        """yaml's safe loader, and xacro's units."""

    def unit(tag: str, factor: float) -> Any:
        def construct(loader: Any, node: Any) -> float:
            text = str(loader.construct_scalar(node))
            try:
                value = evaluate(text, names.__getitem__)
            except ExpressionError as exc:
                raise ExpressionError(f"{tag} {_shown(text)}: {exc}") from None
            if type(value) not in (bool, int, float):
                raise ExpressionError(f"{tag} {_shown(text)}: not a number")
            return float(value) * factor  # type: ignore[arg-type]

        return construct

    for item in xacro.ConstructUnits:
        Loader.add_constructor(item.value.tag, unit(item.value.tag, item.value.conversion_constant))
    return Loader
