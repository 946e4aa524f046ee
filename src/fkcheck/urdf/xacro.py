"""Expanding a xacro description, only when asked: in a child process, declared packages only.

fkcheck reads plain URDF; a xacro file is refused by the screen
(:mod:`fkcheck.urdf.screen`) unless the model says ``xacro = true`` in its
``[urdf]`` table or the command line says ``--allow-xacro``. Opting in means
trusting the file: xacro evaluates ``${…}`` and ``$(eval …)`` as Python, and no
check on Python expressions is a sandbox — an opted-in file can do what Python
can, with the user's rights. What follows keeps a trusted file reproducible
and closes the ways out known here; the expansion, by xacrodoc (xacro without
ROS), is fenced in as far as fkcheck can:

* it runs in a child process (:func:`fkcheck.process.isolation.run_isolated`)
  with a time limit (:data:`XACRO_TIMEOUT_S`), a hard address-space limit
  (:data:`XACRO_MEMORY_BYTES`), an empty environment and a bounded answer: a
  ``${…}`` that loops forever or builds a huge text is stopped, and fkcheck's
  own process never runs the file's Python;
* names starting with ``__`` are refused anywhere in an expression, inside
  lambdas and comprehensions too (xacro checks only the outer expression), and
  ``python.type`` and ``python.vars`` are removed;
* ``$(find PKG)`` (and ``find()`` in ``$(eval …)``) resolves only to the
  packages the caller declares (``packages`` in ``[urdf]``, ``--package`` on the
  command line) — never ``ROS_PACKAGE_PATH``, ament, a walk up the directories
  or anything else in the environment; an undeclared package is one line that
  names the declared ones;
* ``$(env …)`` and ``$(optenv …)`` (and ``env()``/``optenv()`` in ``$(eval …)``)
  are refused: the environment is not an input of a check; pass the value as a
  xacro argument instead. ``$(arg …)``, ``$(dirname)`` and ``$(eval …)`` work as
  in xacro;
* ``<xacro:include>`` and ``xacro.load_yaml`` read files only inside the
  directory of the xacro file and the declared packages;
* the expanded text stays in memory (no file is written) and then goes through
  the very screen a plain URDF goes through (:func:`fkcheck.urdf.tree.urdf_info_from_bytes`:
  size, no DTD or entity, no xacro left, tree checks); ``package://`` mesh names
  are left as they are and meshes are never opened.
"""

from __future__ import annotations

import functools
import io
import os
import types
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from fkcheck.errors import UrdfError
from fkcheck.model.types import PACKAGE_NAME
from fkcheck.process.isolation import IsolatedDied, IsolatedTimeout, run_isolated
from fkcheck.urdf.screen import MAX_URDF_BYTES, check_urdf_path, read_urdf_bytes
from fkcheck.urdf.tree import UrdfInfo, urdf_info_from_bytes

__all__ = [
    "XACRO_MEMORY_BYTES",
    "XACRO_TIMEOUT_S",
    "XacroExpansion",
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


@dataclass(frozen=True)
class XacroExpansion:
    """A xacro file expanded: the URDF text and the files it was made of.

    Attributes:
        text: The expanded document (not screened yet: :func:`screen_expansion`).
        files: Every file the expansion read, resolved: the xacro file first, then
            its includes and ``load_yaml`` files in the order they were read.
    """

    text: str
    files: tuple[Path, ...]


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
) -> XacroExpansion:
    """Expand a xacro file to plain URDF text, in a time- and memory-limited child process.

    The text is not screened here: :func:`read_xacro` screens it as a URDF.

    Args:
        path: The xacro file (read bounded, regular files only).
        args: xacro arguments (``<xacro:arg>``), as ``name:=value`` on xacro's
            command line.
        packages: The only packages ``$(find …)`` resolves: name → directory.
        timeout_s: The time limit of the expansion, s.

    Returns:
        The expanded document and the files it was made of.

    Raises:
        UrdfError: The file cannot be read, a declared package is not a
            directory, or the expansion fails (a missing argument, an undeclared
            package, ``$(env …)``, an include outside the allowed directories, a
            xacro error, the time or memory limit, an answer beyond
            :data:`~fkcheck.urdf.screen.MAX_URDF_BYTES`): one line naming the file.
    """
    data = read_urdf_bytes(path)
    declared: dict[str, str] = {}
    for name, directory in sorted((packages or {}).items()):
        if not directory.is_dir():
            raise UrdfError(path, f"package {name!r} is declared at {directory}, not a directory")
        declared[name] = str(directory.resolve())
    roots = [str(path.resolve().parent), *declared.values()]
    job = functools.partial(
        _expand_job, data, str(path.resolve()), dict(args or {}), declared, roots
    )
    try:
        kind, value = run_isolated(job, timeout_s, _ANSWER_BYTES)
    except IsolatedTimeout:
        raise UrdfError(
            path, f"xacro expansion did not end within {timeout_s:g} s (stopped)"
        ) from None
    except IsolatedDied as exc:
        raise UrdfError(path, f"xacro expansion failed: {exc}") from None
    if kind != "ok":
        raise UrdfError(path, f"xacro expansion failed: {value}")
    text, included = value
    files = dict.fromkeys([path.resolve(), *(Path(name) for name in included)])
    return XacroExpansion(str(text), tuple(files))


def read_xacro(
    path: Path,
    args: Mapping[str, str] | None = None,
    packages: Mapping[str, Path] | None = None,
    package_dirs: tuple[Path, ...] = (),
    timeout_s: float = XACRO_TIMEOUT_S,
) -> UrdfInfo:
    """Expand a xacro file and screen, check and summarise the result as a URDF.

    The result is cached by the file, its modification time and size, the
    arguments and the packages (a check reads the URDF once per backend).

    Args:
        path: The xacro file.
        args: xacro arguments.
        packages: The packages ``$(find …)`` may resolve: name → directory.
        package_dirs: Directories holding the ``package://`` packages it names.
        timeout_s: The time limit of the expansion, s.

    Raises:
        UrdfError: As :func:`expand_xacro`, or the expanded URDF is refused by
            the screen (:mod:`fkcheck.urdf.screen`) or is not a valid tree.
    """
    st = check_urdf_path(path)
    return _read(
        path,
        tuple(sorted((args or {}).items())),
        tuple(sorted((packages or {}).items())),
        package_dirs,
        timeout_s,
        st.st_mtime_ns,
        st.st_size,
    )


@functools.lru_cache(maxsize=16)
def _read(
    path: Path,
    args: tuple[tuple[str, str], ...],
    packages: tuple[tuple[str, Path], ...],
    package_dirs: tuple[Path, ...],
    timeout_s: float,
    mtime_ns: int,
    size: int,
) -> UrdfInfo:
    expansion = expand_xacro(path, dict(args), dict(packages), timeout_s)
    return screen_expansion(path, expansion.text, package_dirs)


def screen_expansion(path: Path, text: str, package_dirs: tuple[Path, ...] = ()) -> UrdfInfo:
    """Put an expanded xacro through the screen and checks of a plain URDF.

    Args:
        path: The xacro file it came from (for messages).
        text: The expansion (:func:`expand_xacro`).
        package_dirs: Directories holding the ``package://`` packages it names.

    Raises:
        UrdfError: Larger than :data:`~fkcheck.urdf.screen.MAX_URDF_BYTES`, refused
            by the screen (a DTD or entity, xacro left over, …) or not a valid tree.
    """
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
    data: bytes, path: str, args: dict[str, str], packages: dict[str, str], roots: list[str]
) -> tuple[str, str | tuple[str, list[str]]]:
    """Expand in the child: ``("ok", (urdf, files read))`` or ``("error", one line)``."""
    import resource

    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = XACRO_MEMORY_BYTES if hard == resource.RLIM_INFINITY else min(hard, XACRO_MEMORY_BYTES)
    if soft == resource.RLIM_INFINITY or soft > limit or hard != limit:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))  # hard too: it cannot be raised
    os.environ.clear()  # nothing of the user's environment is there to be read
    read: list[str] = []
    try:
        xacro = _fenced_xacro(packages, roots, read)
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
    return "ok", (text, read)


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


def _fenced_xacro(packages: dict[str, str], roots: list[str], read: list[str]) -> Any:
    """Import xacro (through xacrodoc) and fence its file, package and environment access.

    Every file it is let read is appended to ``read``.
    """
    import xacro  # type: ignore[import-untyped]  # (no stubs; xacrodoc's dependency)
    import xacrodoc  # noqa: F401  (it patches $(find …) on import: patch after it)
    from xacro import substitution_args

    shown = ", ".join(sorted(packages)) or "none"

    def find(name: str) -> str:
        if name not in packages:
            raise _Refused(
                f"$(find {name}): package {name!r} is not declared; declared packages: {shown} "
                f'(declare it: packages = {{ {name} = "DIR" }} in [urdf], or --package {name}=DIR)'
            )
        return packages[name]

    def env(name: str, *_: str, **__: str) -> str:
        raise _Refused(
            f"$(env {name}) / $(optenv {name}): fkcheck does not read the environment for "
            "xacro; pass the value as a xacro argument (xacro_args in [urdf], or --arg)"
        )

    def inside(filename: str, what: str) -> str:
        target = Path(os.path.join(xacro.root_dir, filename)).resolve()
        if not any(target.is_relative_to(root) for root in roots):
            raise _Refused(
                f"{what} {filename!r}: outside the xacro file's directory and the declared "
                f"packages ({', '.join(roots)})"
            )
        read.append(str(target))
        return str(target)

    parse = xacro.parse

    def confined_parse(inp: Any, filename: str | None = None) -> Any:
        if inp is None and filename is not None:
            inside(filename, "include of")
        return parse(inp, filename)

    load_yaml = xacro.load_yaml

    def confined_load_yaml(filename: str) -> Any:
        return load_yaml(inside(filename, "load_yaml of"))

    substitution_args._eval_find = find
    substitution_args._eval_env = env
    substitution_args._eval_optenv = env
    substitution_args._eval_dict.update(find=find, env=env, optenv=env)
    xacro.parse = confined_parse
    xacro.load_yaml = confined_load_yaml
    symbols = xacro._global_symbols
    symbols["load_yaml"] = confined_load_yaml
    symbols["xacro"]["load_yaml"] = confined_load_yaml
    for name in ("type", "vars"):  # the class of anything, and any object's namespace
        symbols["python"].pop(name, None)
    safe_eval = xacro.safe_eval

    def stricter_eval(expr: str, globals: Any, locals: Any = None) -> Any:
        # xacro checks the expression's own names for ``__``, not those of a lambda
        # or comprehension inside it: every nested code object is checked too.
        code = compile(expr.strip(), "<expression>", "eval")
        dunder = sorted({name for name in _names(code) if name.startswith("__")})
        if dunder:
            raise _Refused(f"${{{expr.strip()[:80]}}}: use of invalid name(s) {', '.join(dunder)}")
        return safe_eval(expr, globals, locals)

    xacro.safe_eval = stricter_eval
    return xacro


def _names(code: types.CodeType) -> Iterator[str]:
    """The names a code object and every code object nested in it refer to."""
    yield from code.co_names
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            yield from _names(const)
