"""Registered backends, and building one from its name.

The built-ins (:data:`BUILTIN`), the third-party backends installed
distributions register (:data:`ENTRY_POINT_GROUP`), ``module:function``
plugins (:data:`PLUGIN`), and :func:`make_backend`, which builds the one backend
a name answers to. :mod:`fkcheck.backends.registry` is the public face (see its
docstring for the names); the lists of backends by kind are
:mod:`fkcheck.backends.listing`.
"""

from __future__ import annotations

import functools
import re
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from fkcheck.backends.base import Backend, contract_problems
from fkcheck.backends.entry_points import TargetUnloadable, load_target, scan_entry_points
from fkcheck.errors import BackendNotFoundError, FkcheckError
from fkcheck.model.options import DEFAULT_TIMEOUT_S
from fkcheck.process.supervise import MAX_TIMEOUT_S

__all__ = [
    "BUILTIN",
    "ENTRY_POINT_GROUP",
    "MAX_TIMEOUT_S",
    "PLUGIN",
    "AmbiguousBackendError",
    "BackendContractError",
    "BackendOptions",
    "Registration",
    "build_in_process",
    "find_registration",
    "make_backend",
    "name_problems",
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
PLUGIN = Registration("module:function", "fkcheck.backends.plugin:PluginBackend")
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
    return [*(r.shown for r in registrations()), PLUGIN.name]


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
    if not isinstance(name, str) or registration is PLUGIN:
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
    registration, arg = find_registration(spec, (*BUILTIN, *found))
    if registration is None:
        raise BackendNotFoundError(spec, valid_names())
    if registration is not PLUGIN:
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


def find_registration(spec: str, found: Sequence[Registration]) -> tuple[Registration | None, str]:
    """The registration ``spec`` names and its argument (``None``: none)."""
    for registration in found:
        if not registration.prefixed and spec == registration.name:
            return registration, ""
    for registration in found:
        prefix = registration.name
        if registration.prefixed and spec.startswith(prefix) and spec[len(prefix) :].strip():
            return registration, spec[len(prefix) :].strip()
    if _PLUGIN_SPEC.match(spec):
        return PLUGIN, spec
    return None, ""


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
