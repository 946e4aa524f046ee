"""A robot's factory calibration: read, applied to its nominal model, and what it changes.

* :mod:`fkcheck.calibration.ur_files` reads a Universal Robots calibration in
  its three forms (``calibration.conf``, KinematicsInfo, ``ur_calibration``'s YAML);
* :mod:`fkcheck.calibration.apply` makes the calibrated model, or refuses a
  calibration that does not fit the nominal model;
* :mod:`fkcheck.calibration.effect` measures what the calibration changes.
"""

from fkcheck.calibration.apply import CalibratedModel, apply_calibration
from fkcheck.calibration.effect import CalibrationEffect, calibration_effect, nominal_model
from fkcheck.calibration.ur_files import CalibrationError, UrCalibration, read_ur_calibration

__all__ = [
    "CalibratedModel",
    "CalibrationEffect",
    "CalibrationError",
    "UrCalibration",
    "apply_calibration",
    "calibration_effect",
    "nominal_model",
    "read_ur_calibration",
]
