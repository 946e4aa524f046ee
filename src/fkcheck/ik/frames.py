"""Where the IK check's frames sit on the DH chain, for a solver that works between DH frames.

A library solver such as ur-analytic-ik answers for one frame pair of its own
(UR's DH frame 0, the controller's ``base``, to DH frame 6, ``tool0``). The check
hands every solver the pose between its own named frames; :func:`dh_anchor` says
on which DH frame a named frame sits and by which fixed transform, from the
model's ``[frames.NAME]`` (``world`` sits on DH frame 0 through the inverse base,
``tcp`` on the last through the tool), so a wrapper turns ``from_T_to`` into its
library's pose and refuses, in one line, a pair it cannot express. A solver built
by a factory (``opw``, a third party's) that declares the pair it answers for
(``frame_from``, ``frame_to``) is converted to the check's pair the same way
(:func:`for_frames`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.ik.solver import IkSolver, SolverRefused
from fkcheck.model.types import Model, resolve_frame

__all__ = ["Reframed", "dh_anchor", "dh_pose", "for_frames"]


def dh_anchor(model: Model, name: str) -> tuple[int, Float]:
    """The DH frame a named frame is fixed to and ``dh_T_frame``, ``(4, 4)``.

    Raises:
        FrameError: ``name`` is not one of the model's frames.
    """
    spec = resolve_frame(model, name)
    if spec.dh == "world":
        return 0, invert(model.base.matrix) @ spec.offset.matrix
    if spec.dh == "tcp":
        return model.dof, model.tool.matrix @ spec.offset.matrix
    return int(spec.dh), spec.offset.matrix


def dh_pose(model: Model, frame_from: str, frame_to: str, from_T_to: Float) -> Float:
    """``dh0_T_dhn`` (first DH frame to last) from ``from_T_to``.

    Only for a pair whose ``from`` is fixed to DH frame 0 and ``to`` to the last
    (:func:`dh_anchor`); the caller checks that.
    """
    _, dh0_T_from = dh_anchor(model, frame_from)
    _, dhn_T_to = dh_anchor(model, frame_to)
    dh0_T_dhn: Float = dh0_T_from @ from_T_to @ invert(dhn_T_to)
    return dh0_T_dhn


class Reframed:
    """A solver that answers for its own frame pair, asked for the check's.

    ``solve(from_T_to)`` hands the solver ``A_T_B = A_T_from · from_T_to · to_T_B``
    (its pair ``A → B``, fixed to the same DH frames as the check's), and its
    ``fk`` is turned back into the check's pair.

    Attributes:
        name: The solver's name.
        method: Its method, with the frames it answers for.
    """

    def __init__(self, solver: Any, A_T_from: Float, to_T_B: Float, pair: str) -> None:
        self._solver = solver
        self._A_T_from = A_T_from
        self._to_T_B = to_T_B
        self._from_T_A = invert(A_T_from)
        self._B_T_to = invert(to_T_B)
        self.name: str = solver.name
        self.method = f"{getattr(solver, 'method', '')} (it solves {pair})".strip()
        if callable(getattr(solver, "fk", None)):
            self.fk = self._fk

    def solve(self, from_T_to: Float) -> Any:
        """The solver's answers for the same pose in its own pair."""
        return self._solver.solve(self._A_T_from @ from_T_to @ self._to_T_B)

    def _fk(self, q: Float) -> Float:
        A_T_B = np.asarray(self._solver.fk(q), dtype=np.float64)
        from_T_to: Float = self._from_T_A @ A_T_B @ self._B_T_to
        return from_T_to

    def __getattr__(self, member: str) -> Any:
        return getattr(self._solver, member)


def for_frames(model: Model, solver: IkSolver, frame_from: str, frame_to: str) -> IkSolver:
    """``solver`` for the check's pair: itself, or :class:`Reframed` when it declares another.

    A solver may declare the pair it answers for as ``frame_from`` and ``frame_to``
    (names of the model's frames). A pair fixed to the same DH frames as the
    check's is converted; any other is refused.

    Raises:
        SolverRefused: Its pair is not fixed to the check's DH frames, or names no frame.
        FrameError: It names a frame the model does not have.
    """
    own_from = getattr(solver, "frame_from", None)
    own_to = getattr(solver, "frame_to", None)
    if not isinstance(own_from, str) or not isinstance(own_to, str):
        return solver
    if (own_from, own_to) == (frame_from, frame_to):
        return solver
    ours = dh_anchor(model, frame_from), dh_anchor(model, frame_to)
    theirs = dh_anchor(model, own_from), dh_anchor(model, own_to)
    if ours[0][0] != theirs[0][0] or ours[1][0] != theirs[1][0]:
        raise SolverRefused(
            f"IK solver {solver.name} solves {own_from} -> {own_to} (DH frames "
            f"{theirs[0][0]} -> {theirs[1][0]}); the check's {frame_from} -> {frame_to} is on "
            f"DH frames {ours[0][0]} -> {ours[1][0]}: use --from {own_from} --to {own_to}"
        )
    A_T_from = invert(theirs[0][1]) @ ours[0][1]
    to_T_B = invert(ours[1][1]) @ theirs[1][1]
    return Reframed(solver, A_T_from, to_T_B, f"{own_from} -> {own_to}")
