"""The one place backends are registered, and how ``--against`` names map to them.

Backends are referenced by ``module:attribute`` and imported only when used, so
listing them costs nothing and a missing library only affects its own backend.
Every list of backends by kind — the default set, the URDF readers, the names a
``[[known_difference]]`` may give, the ``--against`` help — is derived here from
what each backend declares (:class:`~fkcheck.backends.base.Backend`).

Names:

* built-ins: ``rtb-dh``, ``pinocchio-dh``, ``pinocchio-urdf``, ``yourdfpy-urdf``,
  ``rtb-urdf``… (:data:`BUILTIN`; those marked default run without ``--against``,
  and ``mujoco-mjcf``, ``pinocchio-mjcf`` too for a model with ``[mjcf]``);
* ``rtb-model:<Name>`` — a model Robotics Toolbox ships (``rtb-model:UR5``);
* ``poses:<file.csv>`` — measured poses (a robot's pendant log, say), or
  ``poses:<bag>`` — a ROS 2 bag's joint states and tf (:mod:`fkcheck.backends.bag`);
  the check runs at their configurations;
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
  when its evidence is ``table``, may be named in ``[[known_difference]]``. Its
  code runs only in processes of its own (:mod:`fkcheck.backends.thirdparty`).

A name answers to one source only: a name a built-in has or two distributions
register, and a prefix whose ``prefix:function`` also names an importable
module, are refused when asked for, naming both (:func:`make_backend`).
"""

from __future__ import annotations

import functools
import platform
import re
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from importlib import metadata
from typing import Any

from fkcheck.backends.base import Backend, Evidence, Reads, contract_problems
from fkcheck.backends.entry_points import TargetUnloadable, load_target, scan_entry_points
from fkcheck.errors import BackendNotFoundError, FkcheckError, ModelError
from fkcheck.io.numbers import show_text
from fkcheck.model.options import DEFAULT_TIMEOUT_S
from fkcheck.model.types import Model
from fkcheck.process.supervise import MAX_TIMEOUT_S

__all__ = [
    "BUILTIN",
    "ENTRY_POINT_GROUP",
    "MAX_TIMEOUT_S",
    "AmbiguousBackendError",
    "BackendContractError",
    "BackendOptions",
    "Registration",
    "against_help",
    "build_in_process",
    "check_known_differences",
    "default_backends",
    "default_names",
    "known_difference_names",
    "library_versions",
    "make_backend",
    "name_problems",
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
        frame_from: The check's ``--from`` (``None``: the model's ``[check]``); a ROS 2
            bag (``poses:BAG``) composes its transform for the check's pair.
        frame_to: The check's ``--to`` (``None``: the model's ``[check]``).
        bag_joint_states: A bag's topic of joint states (``--bag-joint-states``).
        bag_tf: A bag's topic of changing transforms (``--bag-tf``).
        bag_tf_static: A bag's topic of static transforms (``--bag-tf-static``).
        bag_stamp_tolerance_s: Largest lag of a joint state before the pose it is
            paired with, seconds (``--bag-stamp-tolerance``; :mod:`fkcheck.backends.bag`).
    """

    timeout_s: float = DEFAULT_TIMEOUT_S
    frame_from: str | None = None
    frame_to: str | None = None
    bag_joint_states: str = "/joint_states"
    bag_tf: str = "/tf"
    bag_tf_static: str = "/tf_static"
    bag_stamp_tolerance_s: float = 1e-3


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
        default_for: A description format (``"mjcf"``): a check without
            ``--against`` runs it for a model that declares that format, and
            only for such a model (its readers have nothing to read otherwise).
        origin: ``"fkcheck"``, or the distribution (and version) that registered it.
    """

    name: str
    target: str
    default: bool = False
    origin: str = "fkcheck"
    default_for: str = ""

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
        try:
            return load_target(self.target)
        except TargetUnloadable as exc:
            raise BackendContractError(
                f"backend {self.name} ({self.origin}): {exc.problem}"
            ) from None

    def declared(self, member: str) -> Any:
        """A member every backend of this registration declares (``reads``, ``evidence``).

        A prefix's class declares it as a class attribute; a plain name's backend
        is built (cheap: libraries are imported when poses are asked for). A
        third party's code runs only in a process of its own.

        Raises:
            BackendContractError: It cannot be imported or built.
        """
        if self.prefixed and self.origin != "fkcheck":  # its class, read in its own process
            from fkcheck.backends.thirdparty import class_members

            return class_members(self).get(member)
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
    Registration("mujoco-mjcf", "fkcheck.backends.mjcf_readers:MujocoMjcf", default_for="mjcf"),
    Registration(
        "pinocchio-mjcf", "fkcheck.backends.mjcf_readers:PinocchioMjcf", default_for="mjcf"
    ),
    Registration("rtb-model:", "fkcheck.backends.rtb_model:RtbModel"),
    Registration("cmd:", "fkcheck.backends.command:CommandBackend"),
    Registration("poses:", "fkcheck.backends.measured:MeasuredPoses"),
)

#: A Python callable ``module:function`` (after every registered name and prefix).
_PLUGIN = Registration("module:function", "fkcheck.backends.plugin:PluginBackend")
_PLUGIN_SPEC = re.compile(r"^[A-Za-z_][\w.]*:[A-Za-z_]\w*$")
#: A third-party backend's name: lower case, digits, ``-`` ``_`` ``.``; a prefix ends in ``:``.
_NAME = re.compile(r"^[a-z0-9][a-z0-9._-]*:?$")


def _scan() -> tuple[list[Registration], dict[str, str]]:
    """Third-party registrations, and the names no backend may answer to (with why).

    A name that is not a backend name, that a built-in has, or that two
    distributions register is not registered: asking for it is one line naming
    every source (:func:`make_backend`); asking for any other backend is not
    affected (:func:`fkcheck.backends.entry_points.scan_entry_points`).
    """
    found, problems = scan_entry_points(
        ENTRY_POINT_GROUP,
        kind="backend",
        taken={r.name for r in BUILTIN},
        name=_NAME,
        bad_name="not a backend name (lower-case letters, digits, '-', '_', '.'; "
        "a prefix ends in ':')",
        target="module:Class",
    )
    return [Registration(e.name, e.target, default=False, origin=e.origin) for e in found], problems


def registrations() -> tuple[Registration, ...]:
    """Every usable registered backend: the built-ins, then third-party ones (by name).

    A malformed or clashing third-party registration is left out (asking for its
    name says why: :func:`make_backend`).
    """
    return (*BUILTIN, *_scan()[0])


def valid_names() -> list[str]:
    """Every name ``--against`` accepts, as listed to users."""
    return [*(r.shown for r in registrations()), _PLUGIN.name]


def build_in_process(registration: Registration, arg: str, options: BackendOptions) -> Backend:
    """Build one backend in this process and hold it to the contract.

    fkcheck's own backends are built so; a third-party one only inside its own
    process (:mod:`fkcheck.backends.thirdparty`).

    Raises:
        BackendContractError: It cannot be built, or it breaks the contract: a
            member missing or of the wrong type, evidence its reads cannot give, a
            plain backend not called by its registered name, a prefixed one whose
            name does not start with its prefix (``rtb-model:UR5``).
    """
    try:
        backend = registration.factory()(arg, options)
    except FkcheckError:
        raise
    except Exception as exc:  # a third party's constructor: one line, not a traceback
        raise BackendContractError(
            f"backend {registration.name} ({registration.origin}): building it failed: "
            f"{type(exc).__name__}: {exc}"
        ) from None
    problems = contract_problems(backend) or name_problems(registration, backend)
    if problems:
        raise BackendContractError(
            f"backend {registration.name} ({registration.origin}, {registration.target}) "
            f"breaks fkcheck's backend contract: {'; '.join(problems)}"
        )
    built: Backend = backend
    return built


def name_problems(registration: Registration, backend: Any) -> list[str]:
    """How a built backend's name breaks its registration's (empty: it keeps it).

    A plain backend is called by its registered name; a prefixed one's name
    starts with its prefix, so no backend can answer to another's name.
    """
    name = getattr(backend, "name", None)
    if not isinstance(name, str) or registration is _PLUGIN:
        return []
    if registration.prefixed and not (
        name.startswith(registration.name) and name[len(registration.name) :]
    ):
        return [
            f"calls itself {name!r}, which does not start with its prefix {registration.name!r}"
        ]
    if not registration.prefixed and name != registration.name:
        return [f"calls itself {name!r}"]
    return []


@functools.cache
def _built(name: str) -> Backend:
    """A plain-named backend with default options, to read what it declares."""
    return make_backend(name)


class AmbiguousBackendError(FkcheckError):
    """An ``--against`` name two sources answer to (exit 2: say which one is meant).

    Attributes:
        spec: The name asked for.
        sources: What answers to it, in words.
    """

    def __init__(self, spec: str, sources: Sequence[str]) -> None:
        self.spec = spec
        self.sources = tuple(sources)
        super().__init__(
            f"backend {spec!r} is ambiguous: {' and '.join(self.sources)} both answer to it; "
            "rename the module or uninstall the distribution"
        )


def _plugin_module(spec: str, owner: Registration) -> str | None:
    """Where the Python module a ``module:function`` spec names is, if it could be imported.

    Found without importing anything, on ``sys.path`` and then the working directory
    (where a plugin's module is looked for: :mod:`fkcheck.backends.plugin`). The
    standard library's modules and the registering distribution's own package are
    not counted: nobody names them as a plugin.
    """
    if not _PLUGIN_SPEC.match(spec):
        return None
    top = spec.partition(":")[0].split(".")[0]
    if top in sys.stdlib_module_names or top in sys.builtin_module_names:
        return None
    if owner.origin != "fkcheck" and owner.target.split(".")[0].split(":")[0] == top:
        return None
    from fkcheck.backends.plugin import module_file

    found = module_file(top)
    return None if found is None else str(found)


def make_backend(spec: str, options: BackendOptions | None = None) -> Backend:
    """Build one backend from its name.

    A name answers to exactly one source: a built-in, an installed distribution's
    entry point, or a Python module (``module:function``). A prefix (``rt4mod:``)
    whose ``--against rt4mod:fk`` also names an importable module ``rt4mod`` is
    refused, naming both, and so is a name registered twice or taken from a
    built-in. A third-party backend is built, and runs, in processes of its own
    (:class:`~fkcheck.backends.thirdparty.IsolatedBackend`).

    Raises:
        BackendNotFoundError: The name matches no backend, prefix or plugin form.
        AmbiguousBackendError: Two sources answer to it.
        BackendContractError: Its registration or the backend breaks the contract.
    """
    options = options or BackendOptions()
    spec = spec.strip()
    found, problems = _scan()
    for name, problem in problems.items():
        if spec == name or (name.endswith(":") and spec.startswith(name)):
            raise BackendContractError(problem)
    registration, arg = _find(spec, (*BUILTIN, *found))
    if registration is None:
        raise BackendNotFoundError(spec, valid_names())
    if registration is not _PLUGIN:
        module = _plugin_module(spec, registration) if registration.prefixed else None
        if module is not None:
            raise AmbiguousBackendError(
                spec,
                [
                    f"the prefix {registration.name} of {registration.origin}",
                    f"the Python module {spec.partition(':')[0]} ({module})",
                ],
            )
    if registration.origin == "fkcheck":
        return build_in_process(registration, arg, options)
    from fkcheck.backends.thirdparty import IsolatedBackend

    return IsolatedBackend.build(registration, arg, options)


def _find(spec: str, found: Sequence[Registration]) -> tuple[Registration | None, str]:
    """The registration ``spec`` names and its argument (``None``: none)."""
    for registration in found:
        if not registration.prefixed and spec == registration.name:
            return registration, ""
    for registration in found:
        prefix = registration.name
        if registration.prefixed and spec.startswith(prefix) and spec[len(prefix) :].strip():
            return registration, spec[len(prefix) :].strip()
    if _PLUGIN_SPEC.match(spec):
        return _PLUGIN, spec
    return None, ""


def names(
    *,
    reads: Reads | str | None = None,
    evidence: Evidence | None = None,
    default: bool | None = None,
    format: str | None = None,
) -> tuple[str, ...]:
    """Registered names (prefixes as ``"cmd:"``) with the given declarations, in order.

    ``format``: only the readers of that description format (``formats`` holds it).

    Asking for declarations builds each third-party backend in its own process; one
    that cannot be built is left out (asking for it by name says why).
    """
    out = []
    for r in registrations():
        if default is not None and r.default != default:
            continue
        try:
            if reads is not None and r.declared("reads") != reads:
                continue
            if evidence is not None and r.declared("evidence") != evidence:
                continue
            if format is not None and format not in (r.declared("formats") or ()):
                continue
        except FkcheckError:
            if r.origin == "fkcheck":
                raise
            continue
        out.append(r.name)
    return tuple(out)


def default_names(model: Model | None = None) -> tuple[str, ...]:
    """The backends a check of ``model`` runs when ``--against`` is not given.

    The default set, then the readers of each description format ``model``
    declares (``default_for``: ``mujoco-mjcf`` and ``pinocchio-mjcf`` for a
    model with ``[mjcf]``); without a model, the default set alone.
    """
    plain = names(default=True)
    if model is None:
        return plain
    from fkcheck.description.registry import model_formats

    declared = {fmt.name for fmt in model_formats(model)}
    return plain + tuple(r.name for r in registrations() if r.default_for in declared)


def default_backends(
    options: BackendOptions | None = None, model: Model | None = None
) -> list[Backend]:
    """The backends a plain check of ``model`` runs (:func:`default_names`)."""
    return [make_backend(name, options) for name in default_names(model)]


def known_difference_names() -> tuple[str, ...]:
    """What a ``[[known_difference]]`` may name: backends whose evidence is the table's.

    Backends computing from the model's own table (``rtb-dh``, plugins, ``cmd:``)
    disagree only through a bug, never through a known difference.
    """
    return names(evidence="table")


def _known_difference_ok(name: str, used: Sequence[Backend]) -> bool:
    """Whether a ``[[known_difference]]`` may name ``name``.

    A backend this check uses says its own evidence. Otherwise the name must be
    registered: a built-in's evidence is read from it; a third party's is held
    to it only by a check that uses it (building it would run its code, and a
    broken distribution the check does not use must not end it).
    """
    for backend in used:
        if backend.name == name:
            return backend.evidence == "table"
    registration, _ = _find(name, registrations())
    if registration is None or registration is _PLUGIN:
        return False
    if registration.origin != "fkcheck":
        return True
    return bool(registration.declared("evidence") == "table")


def check_known_differences(model: Model, used: Sequence[Backend] = ()) -> None:
    """Refuse a ``[[known_difference]]`` naming a backend whose evidence is not the table's.

    Builds no backend but the built-ins it names (``used``: those a check has
    built already).

    Raises:
        ModelError: The first such name, with its field and the names allowed.
    """
    if not model.known_differences:
        return
    for i, known in enumerate(model.known_differences):
        for k, name in enumerate(known.backends):
            if not _known_difference_ok(name, used):
                builtin = [r.name for r in BUILTIN if r.declared("evidence") == "table"]
                others = [r.name for r in registrations() if r.origin != "fkcheck"]
                shown = ", ".join(a + "…" if a.endswith(":") else a for a in builtin + others)
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

    A built-in backend names its distributions (``distributions``); a third-party
    one's own distribution is listed. Nothing is imported; a distribution that is
    absent reads ``"not installed"``.
    """
    wanted: list[str] = list(CORE_DISTRIBUTIONS)
    for r in registrations():
        if r.origin != "fkcheck":  # its own distribution: its code runs only when it is used
            names = [r.origin.rpartition(" ")[0]]
        else:
            names = list(r.declared("distributions") or ())
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
    found = registrations()  # a broken registration is reported when it is asked for
    plain = [r.name for r in found if r.default]
    formats = sorted({r.default_for for r in found if r.default_for})
    per_format = [
        f"{', '.join(r.name for r in found if r.default_for == fmt)} (the default for a model "
        f"with [{fmt}]), "
        for fmt in formats
    ]
    extra = [r.name for r in found if not r.default and not r.default_for and not r.prefixed]
    return (
        f"backends, comma-separated or repeated: {', '.join(plain)} (the default set), "
        + "".join(per_format)
        + "".join(f"{name}, " for name in extra)
        + "rtb-model:NAME, poses:FILE.csv or poses:BAG (measured poses, or a ROS 2 bag: "
        "the check runs at their configurations), cmd:PROGRAM, module:function"
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
