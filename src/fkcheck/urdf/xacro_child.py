"""The child's side of a xacro expansion: xacro, fenced, in a process of its own.

:func:`expand_job` runs only in the child process :func:`fkcheck.urdf.xacro.expand_xacro`
starts (under its memory limit, :data:`XACRO_MEMORY_BYTES`, with no
environment): it imports xacro (through xacrodoc), replaces its evaluator with
fkcheck's (:mod:`fkcheck.urdf.expression`) and fences what it may read and
resolve, as :mod:`fkcheck.urdf.xacro`'s docstring says. Nothing here runs in
fkcheck's own process.
"""

from __future__ import annotations

import functools
import io
import os
import re
import types
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from fkcheck.urdf.screen import MAX_URDF_BYTES

__all__ = ["XACRO_MEMORY_BYTES", "expand_job"]

#: The child's address-space limit, bytes: a ``${…}`` building a huge value fails there.
XACRO_MEMORY_BYTES = 2 * 1024**3


class _Refused(Exception):
    """Something the expansion may not do (raised inside xacro, reported as is)."""


def expand_job(
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
    # Executed with no environment (fkcheck.urdf.xacro's _CHILD_ENV); what Python itself set
    # at start-up goes too.
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
