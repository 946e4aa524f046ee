"""Whether a calibrated model is still what ``fkcheck calibration`` made of its file.

``fkcheck calibration`` records, in ``[calibration]``, the calibration file (as
the model names it) and the SHA-256 of its bytes. The model's provenance — "this
table is nominal model N with calibration F" — holds only while both are as they
were; a check compares them (:func:`calibration_provenance`) and every output
says the outcome with the calibration's line:

* the **file**: read again as when calibrating (a regular file of bounded size)
  and hashed. Another digest: the file was **edited since** the model was made;
  a file that cannot be read: the provenance is **unverified**. Nothing of the
  file is quoted, only its digest;
* the **table**: the file applied to the nominal model again
  (``calibration.conf``'s deltas added to it, KinematicsInfo's table, or the
  table derived from UR's description with the YAML) must give the model's θ,
  a, d and α to :data:`TABLE_TOL`. Otherwise the model's **table was edited
  since** it was calibrated, and the first number that differs is named.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from fkcheck.errors import FkcheckError
from fkcheck.model.types import Model

__all__ = ["TABLE_TOL", "Provenance", "ProvenanceState", "calibration_provenance"]

#: How closely the table made again must give the model's numbers (m, rad). Both
#: come from the same arithmetic on the same numbers, and a model file keeps a
#: float's every digit, so any difference is an edit; this leaves room for round-off.
TABLE_TOL = 1e-12

ProvenanceState = Literal["as recorded", "file edited since", "table edited since", "unverified"]


@dataclass(frozen=True)
class Provenance:
    """A calibrated model against its calibration file.

    Attributes:
        state: ``as recorded`` (the file's digest and the table are as made),
            ``file edited since``, ``table edited since`` or ``unverified``.
        note: One line for every output (``""`` when as recorded).
    """

    state: ProvenanceState
    note: str = ""


def _file_of(model: Model) -> Path:
    from fkcheck.urdf.locate import locate

    assert model.calibration is not None
    folder = model.path.parent if model.path is not None else None
    return locate(model.calibration.file, folder)


def calibration_provenance(model: Model, nominal: Model) -> Provenance:
    """Compare a calibrated model with its ``[calibration] file`` and its nominal model.

    Args:
        model: The calibrated model (with ``[calibration]``).
        nominal: Its nominal model (:func:`~fkcheck.calibration.effect.nominal_model`).
    """
    from fkcheck.calibration.ur_files import MAX_CALIBRATION_BYTES
    from fkcheck.io.files import read_bytes

    spec = model.calibration
    assert spec is not None
    name = Path(spec.file).name
    try:
        path = _file_of(model)
        data = read_bytes(path, MAX_CALIBRATION_BYTES)
    except FkcheckError as exc:
        problem = getattr(exc, "problem", "cannot be read")
        return Provenance("unverified", f"provenance unverified: {name}: {problem}")
    digest = hashlib.sha256(data).hexdigest()
    if digest != spec.sha256:
        return Provenance(
            "file edited since",
            f"file edited since the model was made: {name}'s sha256 is {digest[:12]}…, "
            f"[calibration] sha256 {spec.sha256[:12]}…",
        )
    try:
        table = _table_again(nominal, path)
    except FkcheckError as exc:
        return Provenance("unverified", f"provenance unverified: {_first_line(exc)}")
    differs, want = _first_difference(model, table)
    if differs:
        return Provenance(
            "table edited since",
            f"table edited since calibrating: {differs}, where {name} on {nominal.name} gives "
            f"{want:.12g}",
        )
    return Provenance("as recorded")


def _first_line(exc: Exception) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= 160 else text[:160] + "…"


def _table_again(nominal: Model, path: Path) -> tuple[tuple[float, ...], ...]:
    """The table the file gives on the nominal model: rows θ, a, d, α."""
    from fkcheck.calibration.apply import check_nominal, controller_table
    from fkcheck.calibration.description import table_from_yaml
    from fkcheck.calibration.ur_files import read_ur_calibration

    cal = read_ur_calibration(path)
    check_nominal(nominal, cal)  # six revolute joints, standard DH: what the table has
    values = (
        table_from_yaml(nominal, cal) if cal.links is not None else controller_table(nominal, cal)
    )
    return values.theta, values.a, values.d, values.alpha


def _first_difference(model: Model, table: tuple[tuple[float, ...], ...]) -> tuple[str, float]:
    """``joint[i].field (name) = value`` and the table's value, for the first that differs."""
    for i, joint in enumerate(model.joints):
        for field, row in zip(("theta", "a", "d", "alpha"), table, strict=True):
            value = getattr(joint, field)
            if not abs(value - row[i]) <= TABLE_TOL:
                return f"joint[{i}].{field} ({joint.name}) = {value:.12g}", row[i]
    return "", 0.0
