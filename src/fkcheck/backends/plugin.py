"""A Python callable as a reference backend (``--against mypkg.fk:forward``).

The callable is your own FK: it receives joint values ``q`` of shape ``(N, n)``
(radians / metres, DH joint order) and returns ``world_T_tcp`` of shape
``(N, 4, 4)`` — the same pose :meth:`fkcheck.model.Model.fk` returns, the
model's base and tool included. Being a black box, it gives only the TCP, so the
named frames it can be compared on are those rigidly attached to the world or to
the TCP (:func:`fkcheck.backends.blackbox.frame_poses_from_tcp`).

The callable runs in a process of its own (:mod:`fkcheck.process.isolation`), never in
fkcheck's: a plugin that loops forever (even holding the GIL in C), calls
``os._exit`` or ``sys.exit``, crashes, or leaves threads or processes running
cannot stop or hang the check. Its process gets this process's ``sys.path``,
current directory and environment, so the module is found as an ``import``
here would find it, and then in the current directory (:func:`search_path`:
``--against teamfk.fk:forward`` from the team's repository needs no
``PYTHONPATH=.``). Only a name given on the command line, to the API or in a
project's ``[tool.fkcheck] against`` is imported: a model file names no plugin.
At the time limit
(:attr:`~fkcheck.backends.registry.BackendOptions.timeout_s`, per call) the
process and all it started are killed. What the plugin prints goes to its
stderr, never into its answer.

**Jacobians** (``check --jacobian``): if the module also defines
``<function>_jacobian``, it receives the same ``q`` and returns the TCP's
geometric Jacobian ``(N, 6, n)``: linear rows (the TCP origin's velocity) then
angular, both in world axes — fkcheck's ``world-aligned`` (Pinocchio
``LOCAL_WORLD_ALIGNED``, Robotics Toolbox ``jacob0``). It is compared as the
plugin's own Jacobian when the check's ``to`` frame is the TCP and the reference
is ``world-aligned``; otherwise (or without it) the engine differentiates the
plugin's poses.

The module is imported (in that process) when poses are first asked for, not
when the backend is built, so a plugin that cannot be imported shows up as this
backend's *error* in the check (like every other failure of the callable: it
raises, returns the wrong shape or dtype, or returns NaN/inf; its process ends
without an answer; it times out), with a :class:`PluginError` message naming
the plugin and the problem.
"""

from __future__ import annotations

import functools
import importlib
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from fkcheck.backends.base import BackendDefaults, Evidence, Reads, validated_q
from fkcheck.backends.blackbox import frame_poses_from_tcp, require_tcp_frames
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import BackendNotFoundError
from fkcheck.model.types import Model, Offset, resolve_frame
from fkcheck.process.isolation import IsolatedDied, IsolatedTimeout, answer_limit, run_isolated

__all__ = [
    "PluginBackend",
    "PluginError",
    "import_callable",
    "module_file",
    "search_path",
    "split_spec",
]


#: Output dtypes accepted as they are (converted to float64 exactly).
_EXACT_KINDS = ("i", "u")
_EXACT_FLOATS = (np.dtype(np.float64), np.dtype(np.longdouble))
#: Longest problem (e.g. the plugin's exception message) reported, characters.
_PROBLEM_CHARS = 1000


class PluginError(RuntimeError):
    """A plugin that cannot be imported, called, or whose output is unusable.

    Not an :class:`~fkcheck.errors.FkcheckError`: the check reports it as the
    backend's *error* (exit 1), not as bad input.

    Attributes:
        spec: The plugin as named on the command line (``module:function``).
        problem: What went wrong.
    """

    def __init__(self, spec: str, problem: str) -> None:
        self.spec = spec
        self.problem = problem
        super().__init__(f"plugin {spec}: {problem}")


class PluginBackend(BackendDefaults):
    """FK from a user's Python callable ``module:function``.

    Attributes:
        name: The spec, ``module:function``.
        method: ``"python callable module:function"``.
        module: The module's dotted name.
        function: The callable's name in that module.
        evidence: ``"implementation"``: the user's code runs the model's table.
        jacobian_method: ``"python callable module:function_jacobian"``.
        timeout_s: Time limit of one call of the plugin, seconds.
    """

    evidence: Evidence = "implementation"
    reads: Reads = "program"
    #: The one reference ``<function>_jacobian`` answers in (the engine re-expresses it).
    jacobian_references: tuple[JacobianReference, ...] = ("world-aligned",)
    #: Imported by the engine before backend threads start (fixed frames use SciPy).
    imports = ("scipy.spatial.transform",)

    def __init__(self, spec: str, options: BackendOptions) -> None:
        """Remember the callable's location; nothing is imported yet.

        Args:
            spec: ``module:function``, e.g. ``mypkg.fk:forward``.
            options: Backend options; ``timeout_s`` is the time limit of each call.

        Raises:
            BackendNotFoundError: ``spec`` is not of the form ``module:function``.
        """
        self.module, self.function = split_spec(spec)
        self.name = f"{self.module}:{self.function}"
        self.method = f"python callable {self.name}"
        self.jacobian_method = f"python callable {self.name}_jacobian"
        self.timeout_s = options.timeout_s

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """The module's source file, found where it is imported from, without importing it."""
        found = module_file(self.module)
        return () if found is None else (found,)

    def unavailable_reason(self, model: Model) -> str | None:
        """Always ``None``: whether the plugin works is only known by calling it."""
        return None

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """Call the plugin on the whole batch and map its TCP poses onto named frames.

        Takes and returns what :meth:`~fkcheck.backends.base.Backend.frame_poses`
        does, with the world as the root: ``(len(frames), N, 4, 4)`` world_T_frame.

        Raises:
            FrameUnavailable: A requested frame sits mid-chain (checked before
                the plugin is imported).
            FrameError: A frame name the model does not define.
            JointInputError: ``q`` has the wrong shape or non-finite values.
            PluginError: The plugin cannot be imported or found, is not
                callable, raises, returns something other than finite
                ``(N, 4, 4)`` real numbers, its process ends without an answer
                (``os._exit``, ``sys.exit``, a crash) or answers with more than
                :func:`~fkcheck.process.isolation.answer_limit` bytes, or it has not
                answered within the time limit.
        """
        q = validated_q(model, q)
        require_tcp_frames(model, frames)
        shape = (q.shape[0], 4, 4)
        job = functools.partial(
            _call, self.name, self.module, self.function, q.copy(), shape, os.getcwd()
        )
        kind, value = self._in_child(job, q)
        if kind != "ok":
            raise PluginError(self.name, str(value))
        world_T_tcp: Float = value
        return frame_poses_from_tcp(model, world_T_tcp, frames)

    def _in_child(self, job: Callable[[], tuple[str, Any]], q: Float) -> tuple[str, Any]:
        """Run one call of the plugin in its own process, within the time limit."""
        try:
            kind, value = run_isolated(job, self.timeout_s, answer_limit(q.shape[0]))
        except IsolatedTimeout:
            raise PluginError(
                self.name, f"timed out after {self.timeout_s:g} s (its process was killed)"
            ) from None
        except IsolatedDied as exc:
            raise PluginError(self.name, str(exc)) from None
        return str(kind), value

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float | None:
        """The plugin's ``<function>_jacobian`` of the TCP, ``(N, 6, n)``, world-aligned.

        ``frame`` may be any frame whose pose is the TCP's (``tcp``, or the last
        DH frame with the tool's offset). The engine asks for ``world-aligned``
        only (:attr:`jacobian_references`) and re-expresses it itself.

        Returns:
            ``None`` when the plugin has no ``<function>_jacobian``, or ``frame``
            is not the TCP (the engine then differentiates the plugin's poses).

        Raises:
            PluginError: As for :meth:`frame_poses`, for ``(N, 6, n)``.
        """
        q = validated_q(model, q)
        spec = resolve_frame(model, frame)
        at_tcp = (spec.dh == "tcp" and spec.offset == Offset()) or (
            spec.dh == model.dof and spec.offset == model.tool
        )
        if reference != "world-aligned" or not at_tcp:
            return None
        shape = (q.shape[0], 6, model.dof)
        function = f"{self.function}_jacobian"
        job = functools.partial(
            _call, self.name, self.module, function, q.copy(), shape, os.getcwd()
        )
        kind, value = self._in_child(job, q)
        if kind == "absent":
            return None
        if kind != "ok":
            raise PluginError(self.name, str(value))
        jacobian: Float = value
        return jacobian


def split_spec(spec: str) -> tuple[str, str]:
    """``module:function`` as ``(module, function)`` (an IK solver's too).

    Raises:
        BackendNotFoundError: ``spec`` is not of the form ``module:function``.
    """
    module, sep, function = spec.strip().rpartition(":")
    if not sep or not module or not function:
        raise BackendNotFoundError(spec, ["module:function"])
    return module, function


def search_path(cwd: str | None = None) -> list[str]:
    """Where a plugin's module is looked for: ``sys.path``, then the working directory.

    The working directory comes last, as an entry of its own: a module there is
    found when nothing installed has its name (``--against teamfk.fk:forward``
    from the team's repository, without ``PYTHONPATH=.``), and it never shadows
    a module fkcheck or a library imports.
    """
    here = os.path.abspath(cwd if cwd is not None else os.getcwd())
    path = list(sys.path)
    return path if here in path else [*path, here]


def module_file(module: str) -> Path | None:
    """The source file of ``module`` (dotted) where an import in a plugin's process finds it.

    Looked for as ``module.py`` or ``module/__init__.py`` on :func:`search_path`,
    without importing anything.
    """
    parts = module.split(".")
    for entry in search_path():
        base = Path(entry or ".").joinpath(*parts)
        for candidate in (base.with_suffix(".py"), base / "__init__.py"):
            if candidate.is_file():
                return candidate
    return None


def _call(
    spec: str, module: str, function: str, q: Float, shape: tuple[int, ...], cwd: str
) -> tuple[str, Any]:
    """In the plugin's own process: import (:func:`search_path`), call, check.

    Returns:
        ``("ok", array)``, ``("absent", None)`` (an optional ``…_jacobian`` the
        module does not define) or ``("error", why)``.
    """
    try:
        optional = function.endswith("_jacobian") and shape[1:2] == (6,)
        who = f"{function} " if optional else ""  # the pose callable is the spec's own
        _, forward = import_callable(spec, module, function, cwd, optional=optional)
        if forward is None:
            return ("absent", None)
        try:
            result = forward(q)
        except Exception as exc:
            raise PluginError(spec, f"{who}raised {type(exc).__name__}: {exc}") from exc
        return ("ok", _validated(spec, result, shape, who))
    except PluginError as exc:
        problem = exc.problem
        if len(problem) > _PROBLEM_CHARS:
            problem = problem[:_PROBLEM_CHARS] + "…"
        return ("error", problem)


def import_callable(
    spec: str, module: str, function: str, cwd: str, *, optional: bool = False
) -> tuple[Any, Callable[..., Any] | None]:
    """In a plugin's (or an IK solver's) own process: its module and callable.

    The module is imported from :func:`search_path` of ``cwd`` (``sys.path`` is
    set to it: this process is the plugin's).

    Args:
        spec: The plugin as named (``module:function``), for messages.
        module: Its module's dotted name.
        function: The callable's name in it.
        cwd: The working directory fkcheck was started in.
        optional: A missing ``function`` is ``None`` (an optional ``…_jacobian``).

    Returns:
        The module, and the callable (``None``: optional and absent).

    Raises:
        PluginError: The module cannot be imported (or raises), has no such
            attribute (the message lists its public callables), or it is not callable.
    """
    sys.path[:] = search_path(cwd)
    mod = _import(spec, module)
    if optional and not hasattr(mod, function):
        return mod, None
    return mod, _callable(spec, mod, module, function)


def _import(spec: str, module: str) -> Any:
    """Import the plugin's module."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise PluginError(spec, f"cannot import module {module!r}: {exc}") from exc
    except Exception as exc:
        raise PluginError(
            spec, f"importing module {module!r} raised {type(exc).__name__}: {exc}"
        ) from exc


def _callable(spec: str, mod: Any, module: str, function: str) -> Callable[[Float], Any]:
    """The module's callable ``function``."""
    if not hasattr(mod, function):
        found = sorted(k for k, v in vars(mod).items() if callable(v) and not k.startswith("_"))
        raise PluginError(
            spec,
            f"module {module!r} has no attribute {function!r}; "
            f"its public callables are: {', '.join(found) or '(none)'}",
        )
    forward = getattr(mod, function)
    if not callable(forward):
        raise PluginError(spec, f"{module}.{function} is a {type(forward).__name__}, not callable")
    checked: Callable[[Float], Any] = forward
    return checked


def _validated(spec: str, result: Any, shape: tuple[int, ...], who: str = "") -> Float:
    """The plugin's return value as float64 of ``shape``, or PluginError.

    ``(N, 4, 4)`` is one ``world_T_tcp`` per configuration, ``(N, 6, n)`` one
    Jacobian. Only real numbers at least as precise as float64 pass (integers
    too); float32, complex, strings and objects are refused. ``who`` names the
    callable in the message (``"fk_jacobian "``; empty for the spec's own).
    """
    what = "one world_T_tcp" if shape[1:] == (4, 4) else "one Jacobian (6 rows)"
    try:
        arr = np.asarray(result)
    except Exception as exc:
        raise PluginError(
            spec,
            f"{who}returned a {type(result).__name__} that is not an array "
            f"({type(exc).__name__}: {exc}); expected shape {shape}",
        ) from exc
    if arr.shape != shape:
        raise PluginError(
            spec,
            f"{who}returned shape {arr.shape}; expected {shape} for q of "
            f"shape ({shape[0]}, n): {what} per configuration",
        )
    if arr.dtype.kind not in _EXACT_KINDS and arr.dtype not in _EXACT_FLOATS:
        hint = (
            ": too coarse for a comparison at 1e-12, return float64"
            if arr.dtype.kind == "f"
            else "; expected real numbers (float64)"
        )
        raise PluginError(spec, f"{who}returned dtype {arr.dtype}{hint}")
    # NaN or inf is an answer, and a wrong one: the engine reports it as a failure
    # (with how many configurations and where), not as "no answer".
    return arr.astype(np.float64)
