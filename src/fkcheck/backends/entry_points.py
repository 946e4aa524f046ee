"""Third-party registrations read from an entry-point group, and the names refused.

One reading for both of fkcheck's groups: backends (``fkcheck.backends``,
:mod:`fkcheck.backends.registry`) and IK solvers (``fkcheck.ik_solvers``,
:mod:`fkcheck.ik.registry`). A registration is a name, a ``module:attribute``
target and the distribution that registered it; the target is imported only when
its registry asks for it (:func:`load_target`).
"""

from __future__ import annotations

import importlib
import re
from collections.abc import Callable, Collection
from dataclasses import dataclass
from importlib import metadata
from typing import Any

__all__ = ["EntryPoint", "TargetUnloadable", "load_target", "scan_entry_points"]

#: What a target must look like: ``module:attribute`` (dotted names on both sides).
_TARGET = re.compile(r"^[\w.]+:[\w.]+$")


@dataclass(frozen=True)
class EntryPoint:
    """One usable registration of an entry-point group.

    Attributes:
        name: The name it registers (``"my-backend"``).
        target: ``"module:attribute"``, not imported.
        origin: The distribution and version that registered it, or ``"an entry point"``.
    """

    name: str
    target: str
    origin: str


def scan_entry_points(
    group: str,
    *,
    kind: str,
    taken: Collection[str],
    name: re.Pattern[str],
    bad_name: str,
    target: str,
) -> tuple[list[EntryPoint], dict[str, str]]:
    """The usable registrations of ``group``, and each refused name with why.

    A name is refused when it does not match ``name``, when a built-in has it
    (``taken``), when two distributions register it (neither is used: asking
    for it names both), or when its value is not ``module:attribute``. Asking
    for a refused name is one line (the caller's); any other name is not affected.

    Args:
        group: The entry-point group (``"fkcheck.backends"``).
        kind: What its entries are, in messages (``"backend"``, ``"IK solver"``).
        taken: The built-ins' names.
        name: What a name must match.
        bad_name: Why a name that does not match is refused (``"not a backend
            name (…)"``).
        target: What a value must be, in messages (``"module:Class"``).

    Returns:
        The usable registrations, by name; and per refused name, the reason.
    """
    found: dict[str, EntryPoint] = {}
    problems: dict[str, str] = {}
    owners: dict[str, list[str]] = {}
    for ep in metadata.entry_points(group=group):
        dist = getattr(ep, "dist", None)
        origin = f"{dist.name} {dist.version}" if dist is not None else "an entry point"
        where = f"entry point {ep.name!r} of {origin} (group {group})"
        owners.setdefault(ep.name, []).append(origin)
        if not name.match(ep.name):
            problems[ep.name] = f"{where}: {bad_name}"
        elif ep.name in taken:
            problems[ep.name] = f"{where}: the name is taken by fkcheck"
        elif len(owners[ep.name]) > 1:
            found.pop(ep.name, None)
            problems[ep.name] = (
                f"{kind} name {ep.name!r} is registered by {' and by '.join(owners[ep.name])} "
                f"(group {group}): uninstall one of them"
            )
        elif not _TARGET.match(ep.value):
            problems[ep.name] = f"{where}: {ep.value!r} is not {target}"
        else:
            found[ep.name] = EntryPoint(ep.name, ep.value, origin)
    return sorted(found.values(), key=lambda e: e.name), problems


class TargetUnloadable(Exception):
    """A ``module:attribute`` target that cannot be imported, or is not callable.

    Attributes:
        problem: ``"cannot load m:a: ImportError: …"`` or ``"m:a is not callable"``;
            the registry puts who registered it in front.
        missing: Whether the module itself is not installed (not a module it imports).
    """

    def __init__(self, problem: str, *, missing: bool = False) -> None:
        self.problem = problem
        self.missing = missing
        super().__init__(problem)


def load_target(target: str) -> Callable[..., Any]:
    """The callable ``module:attribute`` names, imported now.

    Raises:
        TargetUnloadable: Importing it fails (however a third party's module
            fails: one line), or it is not callable.
    """
    module, _, attribute = target.partition(":")
    try:
        found = getattr(importlib.import_module(module), attribute)
    except Exception as exc:  # a third party's broken module: one line
        missing = isinstance(exc, ModuleNotFoundError) and exc.name == module
        raise TargetUnloadable(
            f"cannot load {target}: {type(exc).__name__}: {exc}", missing=missing
        ) from None
    if not callable(found):
        raise TargetUnloadable(f"{target} is not callable")
    loaded: Callable[..., Any] = found
    return loaded
