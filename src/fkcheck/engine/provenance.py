"""A URDF written from the model's own table is no evidence for it: it proves the arithmetic.

URDF backends count as *table* evidence because a robot's URDF does not come
from the DH table. One that ``fkcheck urdf`` wrote from this very table does
(:func:`fkcheck.urdf.provenance.derived_from_table` finds it by its mark or by
its numbers): a wrong table is wrong in it too. So after the run, the results of
the backends that read the model's URDF are counted as *implementation*
evidence, as a backend built from the table is, with the reason added to their
message; ``--require table`` then finds the table unverified.

Measured poses (``poses:``) likewise: a file whose every pose is the table's
own forward kinematics to round-off (:data:`ROUND_OFF`) holds more digits than
any measurement, so it was computed from this table (``fkcheck fk``, or a
program given it), marks or no marks, and is implementation evidence. A UR RTDE
recording is exempt: its poses are the controller's own computation, from the
controller's table, which a calibrated model is meant to be.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from fkcheck.backends.base import Backend, reads_format
from fkcheck.backends.measured import MeasuredPoses
from fkcheck.description.registry import load_description, model_format
from fkcheck.description.urdf import urdf_info
from fkcheck.engine.results import BackendResult
from fkcheck.errors import FkcheckError, Skip
from fkcheck.model.types import Model
from fkcheck.urdf.provenance import Derivation, derived_from_table

__all__ = ["ROUND_OFF", "apply_provenance", "urdf_derivation"]

#: Poses that agree with the table's forward kinematics within this (m and rad) at every
#: configuration were computed from it: a file of doubles written in full agrees to
#: ~1e-15, while a pendant shows 0.1 mm and a laser tracker resolves about 10 µm.
ROUND_OFF = 1e-9


def urdf_derivation(model: Model, tol: tuple[float, float]) -> Derivation | None:
    """How the model's description was written from its own table, or ``None``.

    ``None`` too when the model has no description, or it cannot be read here
    (its readers then say so themselves, and answer nothing), or it is not in
    the URDF language (``fkcheck urdf`` writes URDF only: another format's
    derivation is not recognised).
    """
    if model_format(model, "urdf") is None:
        return None
    try:
        described = load_description(model, language="urdf")
    except (FkcheckError, Skip):
        return None
    if described.language != "urdf":
        return None
    return derived_from_table(model, urdf_info(described), tol)


def _computed_poses(
    backends: Sequence[Backend], results: Sequence[BackendResult]
) -> tuple[BackendResult, ...]:
    """The results, those of ``poses:`` files that are the table's own poses demoted."""
    out = list(results)
    for i, (b, r) in enumerate(zip(backends, results, strict=True)):
        if not (isinstance(b, MeasuredPoses) and r.evidence == "table" and r.status == "pass"):
            continue
        pos, rot = r.max_position_error_m, r.max_rotation_error_rad
        if b.recording or pos is None or rot is None or pos > ROUND_OFF or rot > ROUND_OFF:
            continue
        why = (
            f"the poses are this table's own forward kinematics to round-off (at most "
            f"{pos:.2g} m and {rot:.2g} rad): no measurement carries that many digits, so they "
            "were computed from this table (fkcheck fk, or a program given it) and cannot "
            "verify it; their agreement counts as implementation evidence"
        )
        out[i] = replace(
            r, evidence="implementation", message=f"{r.message}; {why}" if r.message else why
        )
    return tuple(out)


def apply_provenance(
    model: Model,
    backends: Sequence[Backend],
    tol: tuple[float, float],
    results: Sequence[BackendResult],
) -> tuple[BackendResult, ...]:
    """The results, URDF backends reading a URDF written from this table demoted, poses too.

    Args:
        model: The model checked.
        backends: The backends, in the order of ``results``.
        tol: The check's ``(position m, rotation rad)`` tolerances.
        results: One result per backend.

    Returns:
        The results, where a table-evidence backend that reads the model's
        description (:func:`~fkcheck.backends.base.reads_format`) now counts as
        implementation evidence, its message saying why, when that URDF was
        written from the model's own table; and so does a measured-poses file
        computed from it (see the module docstring).
    """
    results = _computed_poses(backends, results)
    fmt = model_format(model, "urdf")  # fkcheck writes URDF only: its readers
    readers = [
        i
        for i, (b, r) in enumerate(zip(backends, results, strict=True))
        if r.evidence == "table" and fmt is not None and reads_format(b, fmt.name)
    ]
    # Only when one of them answered: a URDF none could read proves nothing either way.
    answered = any(results[i].ran for i in readers)
    derivation = urdf_derivation(model, tol) if answered else None
    if derivation is None:
        return tuple(results)
    out = list(results)
    for i in readers:
        r = out[i]
        message = f"{r.message}; {derivation.message}" if r.message else derivation.message
        out[i] = replace(r, evidence="implementation", message=message)
    return tuple(out)
