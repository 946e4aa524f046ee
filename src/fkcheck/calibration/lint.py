"""Lint of a calibrated model: its measured joints are exempt while its table fits.

A calibrated model (``[calibration]``) holds one robot's measured table, which the
unit and round-value rules (:data:`fkcheck.model.lint.MEASURED_RULES`) would flag.
It is exempt from them only while its table is a calibration of its nominal model
by the test ``fkcheck calibration`` applies before it writes one
(:data:`~fkcheck.calibration.apply.FIT_LIMIT_M`, :data:`~fkcheck.calibration.apply.FIT_LIMIT_RAD`);
otherwise the ``calibration`` rule says why, and every rule applies.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from fkcheck.calibration.apply import FIT_LIMIT_M, FIT_LIMIT_RAD, FIT_SAMPLES
from fkcheck.calibration.effect import dh_chain_effect, nominal_model
from fkcheck.errors import FkcheckError
from fkcheck.io.numbers import show_text
from fkcheck.model.lint import Finding, lint_model
from fkcheck.model.sampling import sample_configurations
from fkcheck.model.types import Model

__all__ = ["calibration_misfit", "lint_calibrated"]


def calibration_misfit(model: Model) -> str | None:
    """Why a calibrated model's table is no calibration of its nominal model, or ``None``.

    Over the configurations ``fkcheck calibration`` checks a fit on, the calibrated
    last DH frame may move from the nominal one, relative to DH frame 0, by at most
    ``FIT_LIMIT_M`` and ``FIT_LIMIT_RAD`` — whatever the model's ``[check]`` pair
    (:func:`~fkcheck.calibration.effect.dh_chain_effect`). ``None`` for a model
    without ``[calibration]``.
    """
    if model.calibration is None:
        return None
    spec = model.calibration
    shown = show_text(spec.nominal)  # (the model's own text, quoted bounded)
    try:
        nominal = nominal_model(model)
        if nominal.calibration is not None:  # itself, or a table calibrated already
            return (
                f"[calibration] nominal {shown} is a calibrated model itself (from "
                f"{nominal.calibration.nominal}), not a nominal one, so its joints are held "
                "to every rule"
            )
        q = sample_configurations(nominal, FIT_SAMPLES, seed=0).q
        effect = dh_chain_effect(model, nominal, q)
    except FkcheckError as exc:
        return (
            f"[calibration] nominal {shown} cannot be compared with this table "
            f"({exc}), so its joints are held to every rule"
        )
    pos, rot = effect.max_position_m, effect.max_rotation_rad
    if pos <= FIT_LIMIT_M and rot <= FIT_LIMIT_RAD:
        return None
    return (
        f"the table moves {effect.frame_to} up to {pos:.3g} m and {math.degrees(rot):.3g}° "
        f"from where nominal {shown} puts it, relative to {effect.frame_from} (a factory "
        f"calibration: at most {FIT_LIMIT_M * 1e3:g} mm and {math.degrees(FIT_LIMIT_RAD):.2g}°): "
        f"not a calibration of {shown} — a value in millimetres or degrees, or another type's "
        "table? Its joints are held to every rule"
    )


def lint_calibrated(model: Model, ignore: Iterable[str] = ()) -> tuple[list[Finding], bool]:
    """:func:`~fkcheck.model.lint.lint_model`'s findings, a calibration's joints exempt if it fits.

    Returns:
        The findings, and whether the model's joints were exempt from the
        :data:`~fkcheck.model.lint.MEASURED_RULES` (a calibrated model that fits).
    """
    if model.calibration is None:
        return lint_model(model, ignore), False
    misfit = calibration_misfit(model)
    if misfit is None:
        return lint_model(model, ignore, measured=True), True
    return lint_model(model, ignore, more=[Finding("calibration", "", misfit)]), False
