"""The one place backends are registered, and how ``--against`` names map to them.

Backends are referenced by module path and imported only when used, so listing
them costs nothing and a missing library only affects its own backend.

Names:

* built-ins: ``rtb-dh``, ``pinocchio-dh``, ``pinocchio-urdf``, ``yourdfpy-urdf``,
  ``rtb-urdf`` (the default set);
* ``rtb-model:<Name>`` — a model Robotics Toolbox ships (``rtb-model:UR5``);
* ``poses:<file.csv>`` — measured poses (a robot's pendant log, say); the check
  runs at their configurations;
* ``cmd:<command line>`` — an external FK program (stdin/stdout protocol);
* ``<module>:<function>`` — a Python callable (plugin).
"""

from __future__ import annotations

import importlib
import re
from dataclasses import dataclass
from typing import Any

from fkcheck.backends.base import Backend
from fkcheck.errors import BackendNotFoundError
from fkcheck.model.options import DEFAULT_TIMEOUT_S
from fkcheck.process.supervise import MAX_TIMEOUT_S

__all__ = [
    "BUILTIN",
    "DEFAULT",
    "MAX_TIMEOUT_S",
    "PREFIXED",
    "BackendOptions",
    "default_backends",
    "make_backend",
    "parse_against",
]


@dataclass(frozen=True)
class BackendOptions:
    """Options every backend constructor receives.

    Attributes:
        timeout_s: Time limit for one backend's whole run (seconds): a check's
            :attr:`~fkcheck.model.options.CheckOptions.timeout_s`.
    """

    timeout_s: float = DEFAULT_TIMEOUT_S


#: Built-in backends: name -> (module, class). Order is the order results are shown.
BUILTIN: dict[str, tuple[str, str]] = {
    "rtb-dh": ("fkcheck.backends.rtb_dh", "RtbDH"),
    "pinocchio-dh": ("fkcheck.backends.pinocchio_dh", "PinocchioDH"),
    "pinocchio-urdf": ("fkcheck.backends.pinocchio_urdf", "PinocchioUrdf"),
    "yourdfpy-urdf": ("fkcheck.backends.yourdfpy_urdf", "YourdfpyUrdf"),
    "rtb-urdf": ("fkcheck.backends.rtb_urdf", "RtbUrdf"),
}

#: Backends run when ``--against`` is not given.
DEFAULT = ("rtb-dh", "pinocchio-dh", "pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf")

#: Parametrised backends: prefix -> (module, class); the rest of the name is the argument.
PREFIXED: dict[str, tuple[str, str]] = {
    "rtb-model:": ("fkcheck.backends.rtb_model", "RtbModel"),
    "cmd:": ("fkcheck.backends.command", "CommandBackend"),
    "poses:": ("fkcheck.backends.measured", "MeasuredPoses"),
}

_PLUGIN = ("fkcheck.backends.plugin", "PluginBackend")
_PLUGIN_SPEC = re.compile(r"^[A-Za-z_][\w.]*:[A-Za-z_]\w*$")


def _construct(module: str, cls: str, arg: str, options: BackendOptions) -> Backend:
    factory: Any = getattr(importlib.import_module(module), cls)
    backend: Backend = factory(arg, options)
    return backend


def _valid_names() -> list[str]:
    return [*BUILTIN, *(f"{p}…" for p in PREFIXED), "module:function"]


def make_backend(spec: str, options: BackendOptions | None = None) -> Backend:
    """Build one backend from its name.

    Raises:
        BackendNotFoundError: The name matches no backend, prefix or plugin form.
    """
    options = options or BackendOptions()
    spec = spec.strip()
    if spec in BUILTIN:
        return _construct(*BUILTIN[spec], "", options)
    for prefix, target in PREFIXED.items():
        if spec.startswith(prefix) and spec[len(prefix) :].strip():
            return _construct(*target, spec[len(prefix) :].strip(), options)
    if _PLUGIN_SPEC.match(spec):
        return _construct(*_PLUGIN, spec, options)
    raise BackendNotFoundError(spec, _valid_names())


def default_backends(options: BackendOptions | None = None) -> list[Backend]:
    """The backends a plain check runs."""
    return [make_backend(name, options) for name in DEFAULT]


def parse_against(values: list[str], options: BackendOptions | None = None) -> list[Backend]:
    """Backends from ``--against`` values (repeatable and comma-separated).

    A ``cmd:`` item takes the rest of its value, commas included, so a command
    line with commas must come last or in its own ``--against``.

    Raises:
        BackendNotFoundError: An unknown name.
    """
    names: list[str] = []
    for value in values:
        rest = value
        while rest:
            head, sep, tail = rest.partition(",")
            if head.strip().startswith("cmd:"):
                names.append(rest.strip())
                break
            if head.strip():
                names.append(head.strip())
            rest = tail if sep else ""
    if not names:
        raise BackendNotFoundError("", _valid_names())
    return [make_backend(name, options) for name in names]
