"""The one place backends are registered, and how ``--against`` names map to them.

Backends are referenced by ``module:attribute`` and imported only when used, so
listing them costs nothing and a missing library only affects its own backend.
Every list of backends by kind — the default set, the URDF readers, the names a
``[[known_difference]]`` may give, the ``--against`` help — is derived here from
what each backend declares (:class:`~fkcheck.backends.base.Backend`).

Names:

* built-ins: ``rtb-dh``, ``pinocchio-dh``, ``pinocchio-urdf``, ``yourdfpy-urdf``,
  ``rtb-urdf``… (:data:`BUILTIN`; those marked default run without ``--against``);
* ``rtb-model:<Name>`` — a model Robotics Toolbox ships (``rtb-model:UR5``);
* ``poses:<file.csv>`` — measured poses (a robot's pendant log, say); the check
  runs at their configurations;
* ``cmd:<command line>`` — an external FK program (stdin/stdout protocol);
* ``<module>:<function>`` — a Python callable (plugin);
* third-party backends: an installed distribution's entry point in the
  ``fkcheck.backends`` group (:data:`ENTRY_POINT_GROUP`), as pytest plugins
  register. The entry point's name is the backend's name (ending in ``:`` for a
  prefix taking an argument) and its value a ``module:Class`` called as
  ``Class(argument, options)``::

      [project.entry-points."fkcheck.backends"]
      my-urdf = "my_fk.backend:MyUrdf"

  Such a backend is named with ``--against my-urdf``, appears in reports and,
  when its evidence is ``table``, may be named in ``[[known_difference]]``.
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import platform
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from importlib import metadata
from typing import Any

from fkcheck.backends.base import Backend, Evidence, Reads, contract_problems
from fkcheck.errors import BackendNotFoundError, FkcheckError, ModelError
from fkcheck.io.numbers import show_text
from fkcheck.model.options import DEFAULT_TIMEOUT_S
from fkcheck.model.types import Model
from fkcheck.process.supervise import MAX_TIMEOUT_S

__all__ = [
    "BUILTIN",
    "ENTRY_POINT_GROUP",
    "MAX_TIMEOUT_S",
    "BackendContractError",
    "BackendOptions",
    "Registration",
    "against_help",
    "check_known_differences",
    "default_backends",
    "default_names",
    "known_difference_names",
    "library_versions",
    "make_backend",
    "names",
    "parse_against",
    "registrations",
    "valid_names",
]


#: The entry-point group third-party backends register in.
ENTRY_POINT_GROUP = "fkcheck.backends"


@dataclass(frozen=True)
class BackendOptions:
    """Options every backend constructor receives.

    Attributes:
        timeout_s: Time limit for one backend's whole run (seconds): a check's
            :attr:`~fkcheck.model.options.CheckOptions.timeout_s`.
    """

    timeout_s: float = DEFAULT_TIMEOUT_S


class BackendContractError(FkcheckError):
    """A registered backend that cannot be used: a bad registration or a broken contract."""


@dataclass(frozen=True)
class Registration:
    """One registered backend (or prefix of parametrised backends).

    Attributes:
        name: ``"rtb-dh"``, or a prefix ending in ``:`` (``"cmd:"``) whose backends
            take the rest of their name as argument.
        target: ``"module:attribute"`` of the class (or factory) called as
            ``target(argument, options)``.
        default: Whether a check without ``--against`` runs it.
        origin: ``"fkcheck"``, or the distribution (and version) that registered it.
    """

    name: str
    target: str
    default: bool = False
    origin: str = "fkcheck"

    @property
    def prefixed(self) -> bool:
        """Whether the name is a prefix taking an argument."""
        return self.name.endswith(":")

    @property
    def shown(self) -> str:
        """The name as listed to users (``"cmd:…"`` for a prefix)."""
        return f"{self.name}…" if self.prefixed else self.name

    def factory(self) -> Callable[[str, BackendOptions], Any]:
        """The class (or factory) the target names, imported now.

        Raises:
            BackendContractError: The target cannot be imported or is not callable.
        """
        module, _, attribute = self.target.partition(":")
        try:
            found = getattr(importlib.import_module(module), attribute)
        except Exception as exc:  # a third party's broken module: one line
            raise BackendContractError(
                f"backend {self.name} ({self.origin}): cannot load {self.target}: "
                f"{type(exc).__name__}: {exc}"
            ) from None
        if not callable(found):
            raise BackendContractError(
                f"backend {self.name} ({self.origin}): {self.target} is not callable"
            )
        return found  # type: ignore[no-any-return]

    def declared(self, member: str) -> Any:
        """A member every backend of this registration declares (``reads``, ``evidence``).

        A prefix's class declares it as a class attribute; a plain name's backend
        is built (cheap: libraries are imported when poses are asked for).
        """
        if self.prefixed:
            return getattr(self.factory(), member, None)
        return getattr(_built(self.name), member, None)


#: Built-in backends, in the order results are shown.
BUILTIN: tuple[Registration, ...] = (
    Registration("rtb-dh", "fkcheck.backends.rtb_dh:RtbDH", default=True),
    Registration("pinocchio-dh", "fkcheck.backends.pinocchio_dh:PinocchioDH", default=True),
    Registration("pinocchio-urdf", "fkcheck.backends.pinocchio_urdf:PinocchioUrdf", default=True),
    Registration("yourdfpy-urdf", "fkcheck.backends.yourdfpy_urdf:YourdfpyUrdf", default=True),
    Registration("rtb-urdf", "fkcheck.backends.rtb_urdf:RtbUrdf", default=True),
    Registration("mujoco-urdf", "fkcheck.backends.mujoco_urdf:MujocoUrdf", default=True),
    Registration("idyntree-urdf", "fkcheck.backends.idyntree_urdf:IdyntreeUrdf", default=True),
    Registration("rtb-model:", "fkcheck.backends.rtb_model:RtbModel"),
    Registration("cmd:", "fkcheck.backends.command:CommandBackend"),
    Registration("poses:", "fkcheck.backends.measured:MeasuredPoses"),
)

#: A Python callable ``module:function`` (after every registered name and prefix).
_PLUGIN = Registration("module:function", "fkcheck.backends.plugin:PluginBackend")
_PLUGIN_SPEC = re.compile(r"^[A-Za-z_][\w.]*:[A-Za-z_]\w*$")
#: A third-party backend's name: lower case, digits, ``-`` ``_`` ``.``; a prefix ends in ``:``.
_NAME = re.compile(r"^[a-z0-9][a-z0-9._-]*:?$")


def _entry_point_registrations() -> list[Registration]:
    """Registrations from installed distributions' ``fkcheck.backends`` entry points.

    Raises:
        BackendContractError: A name that is not a backend name, or one taken already.
    """
    found: list[Registration] = []
    taken = {r.name: r.origin for r in BUILTIN}
    for ep in metadata.entry_points(group=ENTRY_POINT_GROUP):
        dist = getattr(ep, "dist", None)
        origin = f"{dist.name} {dist.version}" if dist is not None else "an entry point"
        where = f"entry point {ep.name!r} of {origin} (group {ENTRY_POINT_GROUP})"
        if not _NAME.match(ep.name):
            raise BackendContractError(
                f"{where}: not a backend name (lower-case letters, digits, '-', '_', '.'; "
                "a prefix ends in ':')"
            )
        if ep.name in taken:
            raise BackendContractError(f"{where}: the name is taken by {taken[ep.name]}")
        if not re.match(r"^[\w.]+:[\w.]+$", ep.value):
            raise BackendContractError(f"{where}: {ep.value!r} is not module:Class")
        taken[ep.name] = origin
        found.append(Registration(ep.name, ep.value, default=False, origin=origin))
    return found


def registrations() -> tuple[Registration, ...]:
    """Every registered backend: the built-ins, then third-party ones (by name).

    Raises:
        BackendContractError: A third-party registration is malformed.
    """
    return (*BUILTIN, *sorted(_entry_point_registrations(), key=lambda r: r.name))


def valid_names() -> list[str]:
    """Every name ``--against`` accepts, as listed to users."""
    return [*(r.shown for r in registrations()), _PLUGIN.name]


def _build(registration: Registration, arg: str, options: BackendOptions) -> Backend:
    """Build one backend and hold it to the contract."""
    try:
        backend = registration.factory()(arg, options)
    except FkcheckError:
        raise
    except Exception as exc:  # a third party's constructor: one line, not a traceback
        raise BackendContractError(
            f"backend {registration.name} ({registration.origin}): building it failed: "
            f"{type(exc).__name__}: {exc}"
        ) from None
    problems = contract_problems(backend)
    plain = not registration.prefixed and registration is not _PLUGIN
    if not problems and plain and backend.name != registration.name:
        problems.append(f"calls itself {backend.name!r}")
    if problems:
        raise BackendContractError(
            f"backend {registration.name} ({registration.origin}, {registration.target}) "
            f"breaks fkcheck's backend contract: {'; '.join(problems)}"
        )
    built: Backend = backend
    return built


@functools.cache
def _built(name: str) -> Backend:
    """A plain-named backend with default options, to read what it declares."""
    return make_backend(name)


def make_backend(spec: str, options: BackendOptions | None = None) -> Backend:
    """Build one backend from its name.

    Raises:
        BackendNotFoundError: The name matches no backend, prefix or plugin form.
        BackendContractError: Its registration or the backend breaks the contract.
    """
    options = options or BackendOptions()
    spec = spec.strip()
    found = registrations()
    for registration in found:
        if not registration.prefixed and spec == registration.name:
            return _build(registration, "", options)
    for registration in found:
        prefix = registration.name
        if registration.prefixed and spec.startswith(prefix) and spec[len(prefix) :].strip():
            return _build(registration, spec[len(prefix) :].strip(), options)
    if _PLUGIN_SPEC.match(spec):
        return _build(_PLUGIN, spec, options)
    raise BackendNotFoundError(spec, valid_names())


def names(
    *, reads: Reads | None = None, evidence: Evidence | None = None, default: bool | None = None
) -> tuple[str, ...]:
    """Registered names (prefixes as ``"cmd:"``) with the given declarations, in order."""
    out = []
    for r in registrations():
        if default is not None and r.default != default:
            continue
        if reads is not None and r.declared("reads") != reads:
            continue
        if evidence is not None and r.declared("evidence") != evidence:
            continue
        out.append(r.name)
    return tuple(out)


def default_names() -> tuple[str, ...]:
    """The backends a check runs when ``--against`` is not given."""
    return names(default=True)


def default_backends(options: BackendOptions | None = None) -> list[Backend]:
    """The backends a plain check runs."""
    return [make_backend(name, options) for name in default_names()]


def known_difference_names() -> tuple[str, ...]:
    """What a ``[[known_difference]]`` may name: backends whose evidence is the table's.

    Backends computing from the model's own table (``rtb-dh``, plugins, ``cmd:``)
    disagree only through a bug, never through a known difference.
    """
    return names(evidence="table")


def _known_difference_ok(name: str, allowed: Sequence[str]) -> bool:
    return any(
        name.startswith(a) and len(name) > len(a) if a.endswith(":") else name == a for a in allowed
    )


def check_known_differences(model: Model) -> None:
    """Refuse a ``[[known_difference]]`` naming a backend whose evidence is not the table's.

    Raises:
        ModelError: The first such name, with its field and the names allowed.
    """
    if not model.known_differences:
        return
    allowed = known_difference_names()
    shown = ", ".join(a + "…" if a.endswith(":") else a for a in allowed)
    for i, known in enumerate(model.known_differences):
        for k, name in enumerate(known.backends):
            if not _known_difference_ok(name, allowed):
                raise ModelError(
                    model.path,
                    f"known_difference[{i}].backends[{k}]",
                    f"{show_text(name)} is not a backend whose evidence is independent of the "
                    f"table; known differences may name: {shown}",
                )


#: Distributions every check relies on, whatever its backends: fkcheck, its core, its plots.
CORE_DISTRIBUTIONS = ("fkcheck", "numpy", "numba", "scipy", "matplotlib")


def library_versions() -> dict[str, str]:
    """Python's version, then each distribution's: the core's and every registered backend's.

    A backend names its distributions (``distributions``); a third-party one's own
    distribution is listed too. Nothing is imported; a distribution that is
    absent reads ``"not installed"``.
    """
    wanted: list[str] = list(CORE_DISTRIBUTIONS)
    try:
        found = registrations()
    except BackendContractError:
        found = BUILTIN
    for r in found:
        names = [r.origin.rpartition(" ")[0]] if r.origin != "fkcheck" else []
        with contextlib.suppress(FkcheckError):  # a broken third party: reported when used
            names += list(r.declared("distributions") or ())
        wanted += [name for name in names if name and name not in wanted]
    out = {"Python": platform.python_version()}
    for dist in wanted:
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out


def against_help() -> str:
    """What ``--against`` accepts, for the command line's help (from the registry)."""
    try:
        found = registrations()
    except BackendContractError:  # reported when a backend is made; help still works
        found = BUILTIN
    plain = [r.name for r in found if r.default]
    extra = [r.name for r in found if not r.default and not r.prefixed]
    return (
        f"backends, comma-separated or repeated: {', '.join(plain)} (the default set), "
        + "".join(f"{name}, " for name in extra)
        + "rtb-model:NAME, poses:FILE.csv (measured poses: the check runs at their "
        "configurations), cmd:PROGRAM, module:function"
        + "".join(f", {r.name}ARG" for r in found if r.prefixed and r.origin != "fkcheck")
    )


def parse_against(values: list[str], options: BackendOptions | None = None) -> list[Backend]:
    """Backends from ``--against`` values (repeatable and comma-separated).

    A ``cmd:`` item takes the rest of its value, commas included, so a command
    line with commas must come last or in its own ``--against``.

    Raises:
        BackendNotFoundError: An unknown name.
    """
    parsed: list[str] = []
    for value in values:
        rest = value
        while rest:
            head, sep, tail = rest.partition(",")
            if head.strip().startswith("cmd:"):
                parsed.append(rest.strip())
                break
            if head.strip():
                parsed.append(head.strip())
            rest = tail if sep else ""
    if not parsed:
        raise BackendNotFoundError("", valid_names())
    return [make_backend(name, options) for name in parsed]
