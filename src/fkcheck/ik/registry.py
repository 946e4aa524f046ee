"""Where ``--solver`` names map to IK solvers: built-ins, entry points, the user's function.

Names, as ``fkcheck ik --solver`` takes them:

* ``ur-analytic-ik`` — the UR family's analytic IK (:mod:`fkcheck.ik.ur_analytic`),
  for the library's robot of the model's name; ``ur-analytic-ik:ROBOT`` names it;
* ``opw`` — py-opw-kinematics with the OPW parameters derived from the table
  (``fkcheck.ik.opw_solver:make_opw_solver``, imported when asked for);
* third-party solvers: an installed distribution's entry point in the
  ``fkcheck.ik_solvers`` group (:data:`ENTRY_POINT_GROUP`), whose value
  ``module:factory`` is called as ``factory(model)`` and returns an
  :class:`~fkcheck.ik.solver.IkSolver`. It is asked for the check's frame pair,
  or declares the pair it answers for as ``frame_from``/``frame_to`` (then
  converted, :func:`fkcheck.ik.frames.for_frames`)::

      [project.entry-points."fkcheck.ik_solvers"]
      my-ik = "my_ik.fkcheck:make_solver"

* ``module:function`` — the user's own function, importable from the working
  directory (:mod:`fkcheck.ik.python_solver`).

A solver that cannot be built — its library is missing, it does not fit the
model, a third party's factory raises or returns something that is not a
solver — is one line and exit 2 (:class:`~fkcheck.ik.solver.SolverRefused`),
never a traceback. Built-in names win: an entry point taking one is refused
when asked for, naming both.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from fkcheck.backends.entry_points import TargetUnloadable, load_target, scan_entry_points
from fkcheck.errors import FkcheckError
from fkcheck.ik.frames import for_frames
from fkcheck.ik.solver import IkSolver, SolverRefused
from fkcheck.model.options import DEFAULT_TIMEOUT_S
from fkcheck.model.types import Model

__all__ = [
    "BUILTIN",
    "ENTRY_POINT_GROUP",
    "SolverRegistration",
    "make_solver",
    "registrations",
    "valid_names",
]

#: The entry-point group third-party IK solvers register in.
ENTRY_POINT_GROUP = "fkcheck.ik_solvers"
#: A solver's name: lower case, digits, ``-`` ``_`` ``.``.
_NAME = re.compile(r"^[a-z0-9][a-z0-9._-]*$")
_FUNCTION_SPEC = re.compile(r"^[A-Za-z_][\w.]*:[A-Za-z_]\w*$")


@dataclass(frozen=True)
class SolverRegistration:
    """One registered IK solver.

    Attributes:
        name: ``"ur-analytic-ik"``.
        target: ``"module:factory"``, called as ``factory(model)`` (built-ins also
            get the frame pair and the argument after a colon).
        origin: ``"fkcheck"``, or the distribution (and version) that registered it.
        summary: One line for ``--help``.
    """

    name: str
    target: str
    origin: str = "fkcheck"
    summary: str = ""

    def factory(self) -> Any:
        """The factory the target names, imported now.

        Raises:
            SolverRefused: It cannot be imported (a built-in's module absent from
                this installation is "not available"), or is not callable.
        """
        try:
            return load_target(self.target)
        except TargetUnloadable as exc:
            if self.origin == "fkcheck" and exc.missing:
                module = self.target.partition(":")[0]
                raise SolverRefused(
                    f"IK solver {self.name} is not available in this fkcheck ({module} "
                    "is not part of it)"
                ) from None
            raise SolverRefused(f"IK solver {self.name} ({self.origin}): {exc.problem}") from None


#: Built-in solvers (their libraries are imported only when one is asked for).
BUILTIN: tuple[SolverRegistration, ...] = (
    SolverRegistration(
        "ur-analytic-ik",
        "fkcheck.ik.ur_analytic:UrAnalyticIk",
        summary="UR family, analytic (pip install ur-analytic-ik; MIT)",
    ),
    SolverRegistration(
        "opw",
        "fkcheck.ik.opw_solver:make_opw_solver",
        summary="OPW arms, py-opw-kinematics (MIT) with parameters from the table",
    ),
)


def _scan() -> tuple[list[SolverRegistration], dict[str, str]]:
    """Third-party registrations, and the names refused (with why).

    As the backends' (:func:`fkcheck.backends.entry_points.scan_entry_points`).
    """
    found, problems = scan_entry_points(
        ENTRY_POINT_GROUP,
        kind="IK solver",
        taken={r.name for r in BUILTIN},
        name=_NAME,
        bad_name="not a solver name (lower-case letters, digits, '-_.')",
        target="module:factory",
    )
    return [SolverRegistration(e.name, e.target, origin=e.origin) for e in found], problems


def registrations() -> tuple[SolverRegistration, ...]:
    """Every usable registered solver: the built-ins, then third-party ones (by name)."""
    return (*BUILTIN, *_scan()[0])


def valid_names() -> list[str]:
    """Every name ``--solver`` accepts, as listed to users."""
    return [*(r.name for r in registrations()), "ur-analytic-ik:ROBOT", "module:function"]


def make_solver(
    spec: str,
    model: Model,
    frame_from: str,
    frame_to: str,
    *,
    timeout_s: float = DEFAULT_TIMEOUT_S,
) -> IkSolver:
    """Build the solver ``spec`` names for ``model`` and the check's frame pair.

    Raises:
        SolverRefused: No solver has this name (the message lists them), or it
            cannot be built or does not fit (one line).
    """
    from fkcheck.ik.python_solver import PythonIkSolver

    spec = spec.strip()
    found, problems = _scan()
    if spec in problems:
        raise SolverRefused(problems[spec])
    name, _, argument = spec.partition(":")
    for registration in BUILTIN:
        if name == registration.name and (not argument or name == "ur-analytic-ik"):
            factory = registration.factory()
            if registration.name == "ur-analytic-ik":
                built = factory(model, frame_from, frame_to, argument or None)
            else:
                built = _built(registration, factory, model)
            return for_frames(model, _checked(registration, built), frame_from, frame_to)
    for registration in found:
        if spec == registration.name:
            built = _built(registration, registration.factory(), model)
            return for_frames(model, _checked(registration, built), frame_from, frame_to)
    if _FUNCTION_SPEC.match(spec):
        return PythonIkSolver(spec, model.dof, timeout_s)
    raise SolverRefused(f"unknown IK solver {spec!r}; solvers are: {', '.join(valid_names())}")


def _built(registration: SolverRegistration, factory: Any, model: Model) -> Any:
    """``factory(model)``; its failure is one line."""
    try:
        return factory(model)
    except FkcheckError as exc:  # the factory's own refusal, as it says it
        raise SolverRefused(str(exc)) from None
    except Exception as exc:
        raise SolverRefused(
            f"IK solver {registration.name} ({registration.origin}): building it for model "
            f"{model.name} failed: {type(exc).__name__}: {exc}"
        ) from None


def _checked(registration: SolverRegistration, solver: Any) -> IkSolver:
    """``solver`` if it keeps the contract (a name and ``solve``); else one line."""
    missing = [m for m in ("name", "solve") if not hasattr(solver, m)]
    if missing or not callable(getattr(solver, "solve", None)):
        raise SolverRefused(
            f"IK solver {registration.name} ({registration.origin}, {registration.target}) "
            "breaks fkcheck's solver contract: it has no "
            f"{' or '.join(missing) or 'callable solve'}"
        )
    checked: IkSolver = solver
    return checked
