"""A Python callable as a reference backend (``--against mypkg.fk:forward``).

The callable is your own FK: it receives joint values ``q`` of shape ``(N, n)``
(radians / metres, DH joint order) and returns ``world_T_tcp`` of shape
``(N, 4, 4)`` — the same pose :meth:`fkcheck.model.Model.fk` returns, the
model's base and tool included. Being a black box, it gives only the TCP, so the
named frames it can be compared on are those rigidly attached to the world or to
the TCP (:func:`fkcheck.backends.blackbox.frame_poses_from_tcp`).

The module is imported when poses are first asked for, not when the backend is
built, so a plugin that cannot be imported shows up as this backend's *error*
in the check (like every other failure of the callable: it raises, returns the
wrong shape or dtype, or returns NaN/inf), with a :class:`PluginError` message
naming the plugin and the problem.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.base import Evidence
from fkcheck.backends.blackbox import frame_poses_from_tcp
from fkcheck.backends.registry import BackendOptions
from fkcheck.errors import BackendNotFoundError
from fkcheck.model import Model

__all__ = ["PluginBackend", "PluginError"]

Float = NDArray[np.float64]

#: Output dtypes accepted as they are (converted to float64 exactly).
_EXACT_KINDS = ("i", "u")
_EXACT_FLOATS = (np.dtype(np.float64), np.dtype(np.longdouble))


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


class PluginBackend:
    """FK from a user's Python callable ``module:function``.

    Attributes:
        name: The spec, ``module:function``.
        method: ``"python callable module:function"``.
        module: The module's dotted name.
        function: The callable's name in that module.
        evidence: ``"implementation"``: the user's code runs the model's table.
    """

    evidence: Evidence = "implementation"

    def __init__(self, spec: str, options: BackendOptions) -> None:
        """Remember the callable's location; nothing is imported yet.

        Args:
            spec: ``module:function``, e.g. ``mypkg.fk:forward``.
            options: Backend options (unused: a Python call cannot be timed out
                safely from the same process).

        Raises:
            BackendNotFoundError: ``spec`` is not of the form ``module:function``.
        """
        module, sep, function = spec.strip().rpartition(":")
        if not sep or not module or not function:
            raise BackendNotFoundError(spec, ["module:function"])
        self.module = module
        self.function = function
        self.name = f"{module}:{function}"
        self.method = f"python callable {self.name}"
        self._options = options

    def unavailable_reason(self, model: Model) -> str | None:
        """Always ``None``: whether the plugin works is only known by calling it."""
        return None

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """Call the plugin on the whole batch and map its TCP poses onto named frames.

        Args:
            model: The model being checked.
            q: Joint values, shape ``(N, n)``, radians / metres, DH joint order.
            frames: Names from ``model.frames``.

        Returns:
            ``(len(frames), N, 4, 4)`` world_T_frame.

        Raises:
            FrameUnavailable: A requested frame sits mid-chain (checked before
                the plugin is imported).
            FrameError: A frame name the model does not define.
            ValueError: ``q`` is not ``(N, model.dof)``.
            PluginError: The plugin cannot be imported or found, is not
                callable, raises, or returns something other than finite
                ``(N, 4, 4)`` real numbers.
        """
        q = np.asarray(q, dtype=np.float64)
        if q.ndim != 2 or q.shape[1] != model.dof:
            raise ValueError(f"q must have shape (N, {model.dof}), got {q.shape}")
        # Fail on a frame this black box cannot give before running anything.
        frame_poses_from_tcp(model, np.empty((0, 4, 4)), frames)
        forward = self._load()
        try:
            result = forward(q.copy())
        except Exception as exc:
            raise PluginError(self.name, f"raised {type(exc).__name__}: {exc}") from exc
        world_T_tcp = self._validated(result, q)
        return frame_poses_from_tcp(model, world_T_tcp, frames)

    def _load(self) -> Callable[[Float], Any]:
        """Import the module and return the callable."""
        try:
            mod = importlib.import_module(self.module)
        except ImportError as exc:
            raise PluginError(self.name, f"cannot import module {self.module!r}: {exc}") from exc
        except Exception as exc:
            raise PluginError(
                self.name,
                f"importing module {self.module!r} raised {type(exc).__name__}: {exc}",
            ) from exc
        if not hasattr(mod, self.function):
            found = sorted(k for k, v in vars(mod).items() if callable(v) and not k.startswith("_"))
            raise PluginError(
                self.name,
                f"module {self.module!r} has no attribute {self.function!r}; "
                f"its public callables are: {', '.join(found) or '(none)'}",
            )
        forward = getattr(mod, self.function)
        if not callable(forward):
            raise PluginError(
                self.name,
                f"{self.module}.{self.function} is a {type(forward).__name__}, not callable",
            )
        checked: Callable[[Float], Any] = forward
        return checked

    def _validated(self, result: Any, q: Float) -> Float:
        """The plugin's return value as finite float64 ``(N, 4, 4)``, or PluginError."""
        n_configs = q.shape[0]
        try:
            arr = np.asarray(result)
        except Exception as exc:
            raise PluginError(
                self.name,
                f"returned a {type(result).__name__} that is not an array "
                f"({type(exc).__name__}: {exc}); expected shape ({n_configs}, 4, 4)",
            ) from exc
        if arr.shape != (n_configs, 4, 4):
            raise PluginError(
                self.name,
                f"returned shape {arr.shape}; expected ({n_configs}, 4, 4) for q of "
                f"shape ({n_configs}, n): one world_T_tcp per configuration",
            )
        if arr.dtype.kind not in _EXACT_KINDS and arr.dtype not in _EXACT_FLOATS:
            hint = (
                ": too coarse for a comparison at 1e-12, return float64"
                if arr.dtype.kind == "f"
                else "; expected real numbers (float64)"
            )
            raise PluginError(self.name, f"returned dtype {arr.dtype}{hint}")
        out = arr.astype(np.float64)
        bad = ~np.isfinite(out).all(axis=(1, 2))
        if bad.any():
            first = int(np.flatnonzero(bad)[0])
            raise PluginError(
                self.name,
                f"returned NaN or inf for {int(bad.sum())} of {n_configs} configurations "
                f"(first at index {first}, q = {q[first].tolist()})",
            )
        return out
