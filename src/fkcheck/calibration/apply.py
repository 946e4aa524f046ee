"""A UR calibration applied to a nominal model: the robot's own DH table, or a refusal.

``calibration.conf``'s deltas are *added* to the nominal standard-DH table
(θ, a, d, α: radians and metres — the questions of ``ros-industrial/universal_robot#357``);
KinematicsInfo already holds the sums. The result keeps the nominal model's
joints' names and limits, frames, poses and ``[check]``, and says where it
came from (``[calibration]``: the nominal model, the file, its SHA-256, UR's
checksums or hash, the calibration status).

A calibration that does not fit the nominal model is refused, by what it does
rather than by its numbers (a linearised table's d2/d3 of hundreds of metres
are normal): the calibrated last DH frame may move from the nominal one,
relative to DH frame 0, by at most :data:`FIT_LIMIT_M` and :data:`FIT_LIMIT_RAD`
over :data:`FIT_SAMPLES` configurations. UR's own test calibrations move it by
3.5–7.9 mm; deltas added to another type's table, or full values taken for
deltas, move it by metres. The fit is always measured between those two DH
frames (:func:`~fkcheck.calibration.effect.dh_chain_effect`), never between the
nominal model's ``[check]`` pair: a pair such as ``tool0 → tool0``, or one that
spans the first joint only, let a UR10 table onto a UR5 "fit" by 0 mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from fkcheck.calibration.effect import CalibrationEffect, dh_chain_effect
from fkcheck.calibration.ur_files import CalibrationError, DhValues, UrCalibration
from fkcheck.model.sampling import sample_configurations
from fkcheck.model.types import CalibrationSpec, Model

__all__ = [
    "FIT_LIMIT_M",
    "FIT_LIMIT_RAD",
    "FIT_SAMPLES",
    "CalibratedModel",
    "apply_calibration",
    "check_nominal",
    "controller_table",
]

#: The furthest a factory calibration may move the tool from the nominal one, metres.
#: UR quotes millimetres; its own test calibrations give 3.5–7.9 mm (see the module).
FIT_LIMIT_M = 0.05
#: The largest rotation it may add, radians (about 2.9°).
FIT_LIMIT_RAD = 0.05
#: Configurations compared to decide the fit (structured ones plus Sobol samples).
FIT_SAMPLES = 256
#: ``calibration_status`` as UR's controller comments it.
_STATUS = {0: "not initialised", 1: "not linearised", 2: "linearised"}
#: UR arms have six revolute joints.
_UR_JOINTS = 6


@dataclass(frozen=True)
class CalibratedModel:
    """The calibrated model and what the calibration changes over the workspace."""

    model: Model
    effect: CalibrationEffect


def check_nominal(nominal: Model, cal: UrCalibration) -> None:
    """Refuse a nominal model no UR calibration can apply to (in one line).

    Raises:
        CalibrationError: Not six revolute joints in standard DH without ``flip``,
            or a calibrated model already (its deltas would be added twice).
    """
    if nominal.calibration is not None:
        raise CalibrationError(
            cal.path,
            f"cannot apply to {nominal.name!r}: it is calibrated already (from "
            f"{nominal.calibration.nominal}, {nominal.calibration.form}); give its nominal "
            f"model, {nominal.calibration.nominal}",
        )
    problems = []
    if nominal.dof != _UR_JOINTS:
        problems.append(f"{nominal.dof} joints (a UR arm has 6)")
    if nominal.convention != "standard":
        problems.append(f"{nominal.convention} DH (UR's tables are standard DH)")
    if any(j.type != "revolute" for j in nominal.joints):
        problems.append("a prismatic joint")
    if any(j.flip for j in nominal.joints):
        problems.append("a flipped joint (UR's tables have none)")
    if problems:
        raise CalibrationError(
            cal.path, f"cannot apply to {nominal.name!r}: it has {'; '.join(problems)}"
        )


def controller_table(nominal: Model, cal: UrCalibration) -> DhValues:
    """The robot's DH table: nominal + ``calibration.conf``'s deltas, or KinematicsInfo's."""
    if cal.table is not None:
        return cal.table
    if cal.delta is None:
        raise CalibrationError(
            cal.path,
            f"a {cal.form} holds no DH table (give the controller's calibration.conf "
            "or KinematicsInfo)",
        )
    joints = nominal.joints
    return DhValues(
        theta=tuple(j.theta + v for j, v in zip(joints, cal.delta.theta, strict=True)),
        a=tuple(j.a + v for j, v in zip(joints, cal.delta.a, strict=True)),
        d=tuple(j.d + v for j, v in zip(joints, cal.delta.d, strict=True)),
        alpha=tuple(j.alpha + v for j, v in zip(joints, cal.delta.alpha, strict=True)),
    )


def apply_calibration(
    nominal: Model,
    cal: UrCalibration,
    *,
    nominal_ref: str,
    file_ref: str,
    name: str = "",
    table: DhValues | None = None,
) -> CalibratedModel:
    """The nominal model with the calibrated table, its provenance, and its effect.

    Args:
        nominal: The nominal model (a bundled UR model or the user's).
        cal: The calibration as read.
        nominal_ref: How the written model names the nominal model (``"ur5e"``,
            or a path relative to the written file).
        file_ref: How it names the calibration file.
        name: The calibrated model's name (default: ``<nominal>-calibrated``).
        table: The calibrated table, when it does not come from ``cal`` itself
            (a YAML's table, :mod:`fkcheck.calibration.description`).

    Raises:
        CalibrationError: The nominal model is no UR table, or the calibration
            does not fit it (the tool moves more than the fit limits).
    """
    check_nominal(nominal, cal)
    values = table if table is not None else controller_table(nominal, cal)
    joints = tuple(
        replace(j, theta=values.theta[i], a=values.a[i], d=values.d[i], alpha=values.alpha[i])
        for i, j in enumerate(nominal.joints)
    )
    spec = CalibrationSpec(
        nominal=nominal_ref,
        file=file_ref,
        form=cal.form,
        sha256=cal.sha256,
        identity=cal.identity,
        status=cal.status,
    )
    status = "" if cal.status is None else _STATUS[cal.status]
    source = (
        f"{nominal.name} nominal table with {cal.form} {file_ref} ({cal.identity}"
        + (f", calibration status {cal.status}: {status}" if status else "")
        + ")"
    )
    if table is not None:
        source = (
            f"derived from UR's description of {nominal.name} with {cal.form} {file_ref} "
            f"({cal.identity}) by fkcheck's URDF → DH extraction"
        )
    model = replace(
        nominal,
        name=name or f"{nominal.name}-calibrated",
        joints=joints,
        description=f"{nominal.name} with this robot's factory calibration ({cal.form})",
        source=source,
        angle_unit="rad",
        path=None,
        warnings=(),
        known_differences=(),
        calibration=spec,
    )
    samples = sample_configurations(nominal, FIT_SAMPLES, seed=0)
    effect = dh_chain_effect(model, nominal, samples.q, cal.path.name)
    bad = not (effect.max_position_m <= FIT_LIMIT_M and effect.max_rotation_rad <= FIT_LIMIT_RAD)
    if bad:
        raise CalibrationError(
            cal.path,
            f"does not fit {nominal.name}: the calibrated {effect.frame_to} is up to "
            f"{_size(effect.max_position_m)} and {math.degrees(effect.max_rotation_rad):.3g}° "
            f"from the nominal one, relative to {effect.frame_from} (a factory calibration "
            f"moves it by millimetres, at most "
            f"{FIT_LIMIT_M * 1e3:g} mm and {math.degrees(FIT_LIMIT_RAD):.2g}°); "
            "is the nominal model this robot's type"
            + (" and are these deltas, not full values?" if cal.delta is not None else "?"),
        )
    return CalibratedModel(model, effect)


def _size(metres: float) -> str:
    if not np.isfinite(metres):
        return "infinitely far"
    if metres >= 1.0:
        return f"{metres:.3g} m"
    return f"{metres * 1e3:.3g} mm"
