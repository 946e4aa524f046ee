"""The user's own IK as a Python function: ``--solver mypkg.ik:solve``.

The function takes one pose, ``from_T_to`` as a ``(4, 4)`` ndarray (the check's
frame pair, :mod:`fkcheck.ik.solver`), and returns ``(k, n)``: every solution,
radians / metres, the model's joint order and zero (``k`` may be 0). Its module
is found as a ``--against module:function`` plugin's is: on ``sys.path``, then
in the working directory (:func:`fkcheck.backends.plugin.search_path`), so
``fkcheck ik ur5e --solver myik:solve`` works from the directory holding
``myik.py`` without ``PYTHONPATH=.``.

It runs in a process of its own (:func:`fkcheck.process.isolation.run_isolated`),
once for every pose of the check: a function that loops, crashes, calls
``sys.exit`` or prints cannot stop or hang fkcheck; at the time limit its
process is killed and the check fails naming it. A module may also define
``fk(q) -> (4, 4)``, its own forward kinematics, which the check compares with
the table's.
"""

from __future__ import annotations

import functools
import os
from typing import Any

import numpy as np

from fkcheck.backends.plugin import PluginError, import_callable, split_spec
from fkcheck.core.typing import Float
from fkcheck.ik.solver import IkSolverError, validated_solutions
from fkcheck.model.options import DEFAULT_TIMEOUT_S
from fkcheck.process.isolation import IsolatedDied, IsolatedTimeout, answer_limit, run_isolated

__all__ = ["PythonIkSolver"]

#: Longest problem (the function's exception message) reported, characters.
_PROBLEM_CHARS = 1000
#: Name of the optional forward kinematics a solver's module may define.
FK_FUNCTION = "fk"


class PythonIkSolver:
    """IK from the user's ``module:function``, run in a process of its own.

    Attributes:
        name: ``module:function``.
        method: ``"python function module:function"``.
        timeout_s: Time limit of one batch (every pose of the check), seconds.
        has_fk: Whether the module's own ``fk`` was found (known after the first batch).
    """

    def __init__(self, spec: str, dof: int, timeout_s: float = DEFAULT_TIMEOUT_S) -> None:
        """Remember the function's location; nothing is imported here.

        Raises:
            BackendNotFoundError: ``spec`` is not ``module:function``.
        """
        self.module, self.function = split_spec(spec)
        self.name = f"{self.module}:{self.function}"
        self.method = f"python function {self.name}"
        self.timeout_s = timeout_s
        self._dof = dof
        self.has_fk = False
        #: The module's own FK at the last batch's configurations, ``(N, 4, 4)``.
        self.fk_poses: Float | None = None
        #: And at each of its solutions, one ``(k, 4, 4)`` per pose.
        self.fk_at_solutions: list[Float] | None = None

    def solve(self, from_T_to: Float) -> Float:
        """Every solution for one pose (its own process, as :meth:`solve_batch`)."""
        return self.solve_batch(np.asarray(from_T_to)[None])[0]

    def solve_batch(self, poses: Float, q_for_fk: Float | None = None) -> list[Float]:
        """Every solution for each of ``poses`` ``(N, 4, 4)``, in one process of its own.

        Args:
            poses: The poses.
            q_for_fk: Configurations ``(N, n)`` at which to also call the module's
                ``fk`` (kept on ``fk_poses``; its FK at every solution on
                ``fk_at_solutions``), or ``None``.

        Raises:
            IkSolverError: The module cannot be imported, the function is missing
                or raises, an answer is not ``(k, n)`` real numbers, the process
                ends without an answer or times out.
        """
        job = functools.partial(
            _solve_all,
            self.name,
            self.module,
            self.function,
            np.ascontiguousarray(poses, dtype=np.float64),
            None if q_for_fk is None else np.ascontiguousarray(q_for_fk, dtype=np.float64),
            self._dof,
            os.getcwd(),
        )
        count = len(poses)
        try:
            kind, value = run_isolated(job, self.timeout_s, answer_limit(count) * 8)
        except IsolatedTimeout:
            raise IkSolverError(
                self.name, f"timed out after {self.timeout_s:g} s (its process was killed)"
            ) from None
        except IsolatedDied as exc:
            raise IkSolverError(self.name, str(exc)) from None
        if kind != "ok":
            raise IkSolverError(self.name, str(value))
        solutions, fk_poses, fk_at = value
        self.fk_poses = fk_poses
        self.fk_at_solutions = fk_at
        self.has_fk = fk_poses is not None
        return list(solutions)


def _solve_all(
    spec: str,
    module: str,
    function: str,
    poses: Float,
    q_for_fk: Float | None,
    dof: int,
    cwd: str,
) -> tuple[str, Any]:
    """In the solver's own process: import, call on every pose, check each answer."""
    try:
        try:  # as a --against module:function plugin's module is found, in its process
            mod, solve = import_callable(spec, module, function, cwd)
        except PluginError as exc:
            raise IkSolverError(spec, exc.problem) from None
        solutions = [validated_solutions(spec, _call(spec, solve, T), dof) for T in poses]
        fk_poses = _own_fk(spec, mod, q_for_fk)
        fk_at = None
        if fk_poses is not None:  # also at every solution: tells its FK from its inversion
            fk_at = [_own_fk(spec, mod, np.nan_to_num(s)) for s in solutions]
        return ("ok", (solutions, fk_poses, fk_at))
    except IkSolverError as exc:
        problem = exc.problem
        return ("error", problem[:_PROBLEM_CHARS] + ("…" if len(problem) > _PROBLEM_CHARS else ""))


def _call(spec: str, solve: Any, pose: Float) -> Any:
    try:
        return solve(pose.copy())
    except Exception as exc:
        raise IkSolverError(spec, f"raised {type(exc).__name__}: {exc}") from None


def _own_fk(spec: str, mod: Any, q: Float | None) -> Float | None:
    """The module's own ``fk`` at each configuration, ``(N, 4, 4)``, or ``None`` without one.

    (Also at each returned solution: :attr:`PythonIkSolver.fk_at_solutions`.)
    """
    fk = getattr(mod, FK_FUNCTION, None)
    if q is None or not callable(fk):
        return None
    out = np.empty((len(q), 4, 4))
    for i, row in enumerate(q):
        try:
            pose = np.asarray(fk(row.copy()), dtype=np.float64)
        except Exception as exc:
            raise IkSolverError(spec, f"its fk raised {type(exc).__name__}: {exc}") from None
        if pose.shape != (4, 4):
            raise IkSolverError(spec, f"its fk returned shape {pose.shape}; expected (4, 4)")
        out[i] = pose
    return out
