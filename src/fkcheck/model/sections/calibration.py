"""``[calibration]``: where a calibrated table came from, and its nominal model."""

from __future__ import annotations

import re
from typing import Any

from fkcheck.model.sections.reader import Reader
from fkcheck.model.types import CalibrationSpec

__all__ = ["CALIBRATION_FORMS", "CALIBRATION_KEYS", "read_calibration"]

CALIBRATION_KEYS = {"nominal", "file", "form", "sha256", "identity", "status"}
#: The forms a calibration is read from (:mod:`fkcheck.calibration.ur_files`).
CALIBRATION_FORMS = ("calibration.conf", "KinematicsInfo", "ur_calibration YAML")
_SHA256 = re.compile(r"[0-9a-f]{64}")


def read_calibration(r: Reader, raw: Any) -> CalibrationSpec:
    """``nominal``, ``file``, ``form`` and ``sha256`` (required), ``identity``, ``status``."""
    table = r.table(raw, "calibration", CALIBRATION_KEYS)
    for key in ("nominal", "file", "form", "sha256"):
        if key not in table:
            raise r.fail(f"calibration.{key}", "missing (required)")
    nominal = r.string(table["nominal"], "calibration.nominal")
    if not nominal.strip():
        raise r.fail("calibration.nominal", 'empty: name the nominal model (e.g. "ur5e")')
    sha256 = r.string(table["sha256"], "calibration.sha256")
    if _SHA256.fullmatch(sha256) is None:
        raise r.fail("calibration.sha256", "expected 64 lowercase hexadecimal digits")
    status = table.get("status")
    if status is not None and (isinstance(status, bool) or status not in (0, 1, 2)):
        raise r.fail(
            "calibration.status",
            "expected 0 (not initialised), 1 (not linearised) or 2 (linearised)",
        )
    return CalibrationSpec(
        nominal=nominal,
        file=r.string(table["file"], "calibration.file"),
        form=r.choice(table["form"], "calibration.form", CALIBRATION_FORMS),
        sha256=sha256,
        identity=r.string(table.get("identity", ""), "calibration.identity"),
        status=status,
    )
