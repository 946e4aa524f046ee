"""The ``opw`` IK solver: py-opw-kinematics with the OPW parameters derived from the table.

:func:`make_opw_solver` derives the parameters (:func:`~fkcheck.ik.opw_params.derive_opw`)
and wraps py-opw-kinematics (MIT, CEAD Group; a Python binding of rs-opw-kinematics)
so that it speaks the model's language: poses are the model's ``world_T_tcp``, joint
values the model's (radians, its joint order, its zero and directions). The mapping
between the two is the parameters' offsets and sign corrections, applied by the
library itself, and the fixed base and tool transforms of
:class:`~fkcheck.ik.opw_params.OpwParameters` when OPW's frames are not the model's.

The solver returns every solution the library returns (at most eight), as it returns
them: angles wrapped by the library, no joint limits applied. Two of its calls can
answer (:data:`APIS`): ``inverse``, its IK as a user calls it (the default), and
``reach``, all eight branches in fixed slots with the ones that do not exist as NaN
rows (dropped here). They differ at the wrist singularity: at θ5 = 0 exactly,
py-opw-kinematics 1.3.0's ``inverse`` leaves out the branches with θ5 = 0, which
``reach`` keeps (with θ4 = 0 and θ6 carrying θ4 + θ6).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.errors import OptionError
from fkcheck.ik.opw_params import OPW_DOF, OpwParameters, derive_opw, opw_fk, opw_robot
from fkcheck.model.types import Model

__all__ = ["APIS", "OpwApi", "OpwSolver", "make_opw_solver"]

OpwApi = Literal["inverse", "reach"]
#: The library's calls a solver can answer with.
APIS: tuple[OpwApi, ...] = ("inverse", "reach")


@dataclass(frozen=True, eq=False)
class OpwSolver:
    """py-opw-kinematics as an IK solver of one model.

    Attributes:
        name: ``"opw"`` (``"opw-reach"`` with ``api="reach"``).
        params: The OPW parameters derived from the model's table.
        robot: The library's ``Robot`` (radians).
        api: The library's call that solves: ``"inverse"`` or ``"reach"``.
    """

    name: str
    params: OpwParameters
    robot: object
    api: OpwApi = "inverse"

    def solve(self, base_T_tool: Float) -> Float:
        """Every solution the library finds for a pose.

        Args:
            base_T_tool: The pose, ``(4, 4)``: the model's ``world_T_tcp``, as
                ``Model.fk(q)`` gives it.

        Returns:
            ``(k, 6)`` joint values, radians, the model's joint order and zero
            (``k`` may be 0: no solution).
        """
        from py_opw_kinematics import Robot
        from scipy.spatial.transform import RigidTransform

        assert isinstance(self.robot, Robot)
        p = self.params
        target = invert(p.world_T_base) @ np.asarray(base_T_tool, dtype=np.float64)
        base_T_flange = target @ invert(p.flange_T_tcp)
        if self.api == "reach":
            poses = RigidTransform.from_matrix(base_T_flange[None])
            branches = np.asarray(self.robot.reach(poses).joints, dtype=np.float64)[0]
            q: Float = branches[~np.isnan(branches).any(axis=1)]
            return q
        solutions = self.robot.inverse(RigidTransform.from_matrix(base_T_flange))
        q = np.array(solutions, dtype=np.float64).reshape(-1, OPW_DOF)
        return q

    def fk(self, q: Float) -> Float:
        """The library's own FK, ``world_T_tcp`` of the model for ``(6,)`` joint values."""
        pose: Float = opw_fk(self.params, np.asarray(q, dtype=np.float64), self.robot)[0]
        return pose


def make_opw_solver(model: Model, api: OpwApi = "inverse") -> OpwSolver:
    """The ``opw`` solver of a model.

    Args:
        model: An OPW-shaped model (six revolute joints, axes 2 and 3 parallel,
            a spherical wrist…).
        api: The library's call that solves (:data:`APIS`): ``"inverse"`` (the
            default) or ``"reach"`` (every branch, the wrist singularity's too).

    Returns:
        The solver.

    Raises:
        OptionError: An unknown ``api``.
        NotOpwShaped: The model is not an OPW arm; the message says which
            condition fails.
        ModuleNotFoundError: py-opw-kinematics is not installed (``pip install
            'fkcheck[ik]'``).
    """
    if api not in APIS:
        raise OptionError("api", f"must be one of {', '.join(APIS)}, got {api!r}")
    params = derive_opw(model)
    name = "opw" if api == "inverse" else f"opw-{api}"
    return OpwSolver(name=name, params=params, robot=opw_robot(params), api=api)
