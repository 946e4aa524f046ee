"""The contract every IK solver keeps, and how its answers are held to it.

A solver (:class:`IkSolver`) is given ``from_T_to``, the pose of the IK check's
``to`` frame in its ``from`` frame (the model's ``[check] from`` and ``to`` unless
``fkcheck ik --from/--to`` says otherwise), and returns every joint configuration
it finds for that pose as a ``(k, n)`` array: radians (metres for a prismatic
joint), in the model's joint order and zero — the values :meth:`Model.fk
<fkcheck.model.types.Model.fk>` takes. ``k`` may be 0: "no solution" (or, at a
singular pose, "singular") is an answer; NaN or inf is not
(:func:`validated_solutions`).

A solver may also have its own forward kinematics, ``fk(q) -> (4, 4)`` of the
same frame pair: the IK check compares it with the table's, because an inverse
consistent with a wrong forward model (ur_ikfast#11) reproduces its own poses
perfectly.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.errors import FkcheckError

__all__ = [
    "IkSolver",
    "IkSolverError",
    "SolverRefused",
    "validated_solutions",
]


@runtime_checkable
class IkSolver(Protocol):
    """An inverse-kinematics solver for one model.

    Attributes:
        name: How the solver is named on the command line (``ur-analytic-ik``,
            ``mypkg.ik:solve``).
        method: One line saying what computes the answers (library, version,
            robot); a third party's solver may leave it out.

    Optional members the check uses when present: ``fk(q) -> (4, 4)``, its own
    forward kinematics; ``frame_from``/``frame_to``, the pair it answers for
    (:func:`fkcheck.ik.frames.for_frames`); ``messages``, lines it printed during
    the last solve; ``batch()``, a context in which to solve many poses.
    """

    name: str
    method: str

    def solve(self, from_T_to: Float) -> Float:
        """Every solution for one pose.

        Args:
            from_T_to: ``(4, 4)``, the pose of the check's ``to`` frame in its
                ``from`` frame.

        Returns:
            ``(k, n)`` joint values, radians / metres, the model's joint order and
            zero; ``k = 0`` for none.
        """
        ...


class IkSolverError(RuntimeError):
    """A solver that failed while solving: it raised, or answered what is not an answer.

    Not an :class:`~fkcheck.errors.FkcheckError`: the IK check reports it as the
    solver's failure (exit 1), not as bad input.

    Attributes:
        solver: The solver's name.
        problem: What went wrong.
    """

    def __init__(self, solver: str, problem: str) -> None:
        self.solver = solver
        self.problem = problem
        super().__init__(f"IK solver {solver}: {problem}")


class SolverRefused(FkcheckError):
    """A solver that does not fit the model, or cannot be built here (exit 2, one line)."""


def validated_solutions(name: str, answer: Any, dof: int) -> Float:
    """A solver's answer as float64 ``(k, dof)``; NaN and inf rows are kept (they count as garbage).

    Args:
        name: The solver's name, for the message.
        answer: What it returned: an array-like of shape ``(k, dof)`` (``k`` may
            be 0; an empty list is ``(0, dof)``).
        dof: The model's number of joints.

    Raises:
        IkSolverError: Not real numbers of shape ``(k, dof)``.
    """
    try:
        arr = np.asarray(answer)
    except Exception as exc:  # a solver's odd object: one line
        raise IkSolverError(
            name, f"returned a {type(answer).__name__} that is not an array ({exc})"
        ) from None
    if arr.size == 0:
        return np.zeros((0, dof))
    if arr.ndim == 1 and arr.shape[0] == dof:
        arr = arr[None, :]  # one solution given as a plain vector
    if arr.ndim != 2 or arr.shape[1] != dof:
        raise IkSolverError(
            name, f"returned shape {arr.shape}; expected (k, {dof}): one row per solution"
        )
    if arr.dtype.kind not in "iuf" or (arr.dtype.kind == "f" and arr.dtype.itemsize < 8):
        raise IkSolverError(
            name, f"returned dtype {arr.dtype}; expected real numbers at float64 precision"
        )
    return arr.astype(np.float64)
