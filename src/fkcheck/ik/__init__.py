"""Inverse kinematics checked against the verified FK: every solution right, none missing.

``fkcheck ik MODEL --solver NAME`` (:mod:`fkcheck.cli.ik`): a solver
(:class:`IkSolver`, built by :func:`make_solver`) is asked for every solution
of poses computed with the in-house FK, and :func:`check_ik` holds its answers
to the table (:mod:`fkcheck.ik.check`).
"""

from fkcheck.ik.check import IkCase, IkResult, check_ik
from fkcheck.ik.registry import ENTRY_POINT_GROUP, make_solver, valid_names
from fkcheck.ik.solver import IkSolver, IkSolverError, SolverRefused

__all__ = [
    "ENTRY_POINT_GROUP",
    "IkCase",
    "IkResult",
    "IkSolver",
    "IkSolverError",
    "SolverRefused",
    "check_ik",
    "make_solver",
    "valid_names",
]
