"""Diagnose a finished check: each distinct disagreement, once, for the reports.

:func:`diagnose_failures` runs :func:`fkcheck.diagnose.diagnose` against the
check's disagreeing backends, with the check's model, frame pair, tolerances
and seed, once per distinct disagreement: a backend whose errors equal those of
one already diagnosed (within tolerance, at every configuration of the check —
the URDF backends reading one URDF, typically) shares its diagnosis. It never
raises for a diagnosis that fails: the exception is kept as text, so the
reports that show it are always written. It runs after the check and before
any report is written (``fkcheck check``, :func:`fkcheck.check`); the reports
only format its outcomes.
"""

from __future__ import annotations

import shlex
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fkcheck.backends.base import Backend
from fkcheck.diagnose.findings import Diagnosis
from fkcheck.diagnose.run import diagnose
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.io.text import operand
from fkcheck.model.options import DEFAULT_TIMEOUT_S

__all__ = [
    "BackendDiagnosis",
    "bag_arguments",
    "diagnose_command",
    "diagnose_failures",
    "same_disagreement",
]


@dataclass(frozen=True, eq=False)
class BackendDiagnosis:
    """The diagnosis of one disagreeing backend, or why there is none.

    Attributes:
        backend: The backend diagnosed.
        diagnosis: What :func:`fkcheck.diagnose.diagnose` returned, or ``None`` when it raised.
        error: The exception it raised, ``"Type: message"`` in full (empty when it ran).
        also: Other disagreeing backends this diagnosis stands for (see
            :func:`same_disagreement`).
        command: The ``fkcheck diagnose`` command line that reproduces it (``""`` for a
            table fkcheck derived: no model file to name).
    """

    backend: str
    diagnosis: Diagnosis | None
    error: str = ""
    also: tuple[str, ...] = ()
    command: str = ""


def same_disagreement(check: CheckResult, a: BackendResult, b: BackendResult) -> bool:
    """Whether two backends' errors agree within tolerance at every configuration of the check.

    Then they almost surely compute the same poses (two libraries reading the
    same URDF, say), and one diagnosis stands for both.
    """
    arrays = (a.position_error_m, b.position_error_m, a.rotation_error_rad, b.rotation_error_rad)
    if any(x is None for x in arrays):
        return False
    pa, pb, ra, rb = (np.asarray(x) for x in arrays)
    return bool(
        pa.shape == pb.shape
        and np.all(np.abs(pa - pb) <= check.tol_pos_m)
        and np.all(np.abs(ra - rb) <= check.tol_rot_rad)
    )


def bag_arguments(backend: Backend | None) -> list[str]:
    """The ``--bag-*`` flags that read ``backend``'s ROS 2 bag as the check read it.

    Only the settings that differ from the defaults, and only for a bag read as
    measured poses (``poses:BAG``); ``[]`` for any other backend.
    """
    from fkcheck.backends.bag_screen import is_bag
    from fkcheck.backends.registration import BackendOptions
    from fkcheck.model.options import BAG_FLAGS

    options, path = getattr(backend, "options", None), getattr(backend, "path", None)
    if not (isinstance(options, BackendOptions) and isinstance(path, Path) and is_bag(path)):
        return []
    default = BackendOptions()
    argv: list[str] = []
    for name, flag in BAG_FLAGS.items():
        value = getattr(options, name)
        if value != getattr(default, name):
            argv += [flag, repr(value) if isinstance(value, float) else str(value)]
    return argv


def diagnose_command(
    check: CheckResult, backend: str, bag: Sequence[str] = (), model_arg: str | None = None
) -> str:
    """The ``fkcheck diagnose`` command line that reproduces a diagnosis of the report.

    ``""`` for a table fkcheck derived (``check --source A --against-description
    B``): there is no model file to name, the check's own run is the reproduction.
    ``bag`` is the backend's :func:`bag_arguments`: a ROS 2 bag whose topics are not
    the default ones is read by the same settings. ``model_arg``: the model as the
    check was given it (default: its file, or its bundled name).
    """
    model = check.model
    if model.derived is not None:
        return ""
    named = model_arg or (str(model.path) if model.path is not None else model.name)
    argv = ["diagnose", operand(named)]
    argv += ["--against", backend, "--from", check.frame_from, "--to", check.frame_to]
    if check.options.seed != 0:
        argv += ["--seed", str(check.options.seed)]
    if check.tol_pos_m != model.check.tol_pos_m:
        argv += ["--tol-pos", repr(check.tol_pos_m)]
    if check.tol_rot_rad != model.check.tol_rot_rad:
        argv += ["--tol-rot", repr(check.tol_rot_rad)]
    if check.options.timeout_s != DEFAULT_TIMEOUT_S:  # a recording's read is within it
        argv += ["--timeout", repr(check.options.timeout_s)]
    return "fkcheck " + shlex.join([*argv, *bag])


def _run_one(check: CheckResult, backend: Backend) -> tuple[Diagnosis | None, str]:
    """Diagnose one backend with the check's settings; an exception becomes its text."""
    try:
        result = diagnose(
            check.model,
            backend,
            frame_from=check.frame_from,
            frame_to=check.frame_to,
            seed=check.options.seed,
            tol_pos_m=check.tol_pos_m,
            tol_rot_rad=check.tol_rot_rad,
            timeout_s=check.options.timeout_s,
        )
    except Exception as exc:  # a report is written whatever the diagnosis does
        return None, f"{type(exc).__name__}: {exc}"
    return result, ""


def diagnose_failures(
    check: CheckResult, backends: Sequence[Backend]
) -> tuple[BackendDiagnosis, ...]:
    """Diagnose each distinct disagreement of a check, in the order of the backends.

    Args:
        check: The check result.
        backends: The backend objects the check ran, aligned with ``check.backends``.

    Returns:
        One outcome per diagnosed backend (none unless the verdict is ``fail``). A
        diagnosis that raises is an outcome with its error text, never an exception.

    Raises:
        ValueError: ``backends`` does not match ``check.backends``.
    """
    if len(backends) != len(check.backends):
        raise ValueError(
            f"{len(backends)} backend objects for {len(check.backends)} results: "
            "pass the backends the check ran, in order"
        )
    if check.verdict != "fail":
        return ()
    diagnosed: list[tuple[BackendResult, BackendDiagnosis, list[str]]] = []
    for result, backend in zip(check.backends, backends, strict=True):
        if result.status != "fail" or result.reader_finding:  # a reader's, not the table's
            continue
        twin = next((t for t in diagnosed if same_disagreement(check, t[0], result)), None)
        if twin is not None:
            twin[2].append(result.name)
            continue
        diagnosis, error = _run_one(check, backend)
        command = diagnose_command(check, result.name, bag_arguments(backend))
        diagnosed.append((result, BackendDiagnosis(result.name, diagnosis, error, (), command), []))
    return tuple(
        BackendDiagnosis(d.backend, d.diagnosis, d.error, tuple(also), d.command)
        for _, d, also in diagnosed
    )
