"""How numbers read in reports: lengths in mm and m, angles in rad and degrees.

Pure functions over floats; the HTML and Markdown writers share them so a
number reads the same everywhere.
"""

from __future__ import annotations

import math

__all__ = [
    "format_deg",
    "format_m",
    "format_mm",
    "format_rad",
    "format_seconds",
    "format_value",
]


#: What a missing value reads as.
_MISSING = "–"


def _sig3(value: float) -> str:
    """Three significant digits, trailing zeros kept (0.300), no bare trailing point (251)."""
    text = f"{value:#.3g}"
    return text[:-1] if text.endswith(".") else text


def _scientific(value: float | None, unit: str) -> str:
    """Scientific notation, 3 significant digits, then the unit; ``–`` when absent."""
    return _MISSING if value is None else f"{value:.2e} {unit}"


def format_mm(value_m: float | None) -> str:
    """A length given in metres, shown in millimetres (3 significant digits)."""
    return _MISSING if value_m is None else f"{_sig3(value_m * 1e3)} mm"


def format_m(value_m: float | None) -> str:
    """A length in metres, scientific notation (3 significant digits)."""
    return _scientific(value_m, "m")


def format_rad(value_rad: float | None) -> str:
    """An angle in radians, scientific notation (3 significant digits)."""
    return _scientific(value_rad, "rad")


def format_deg(value_rad: float | None) -> str:
    """An angle given in radians, shown in degrees (3 significant digits)."""
    return _MISSING if value_rad is None else f"{_sig3(math.degrees(value_rad))}°"


def format_seconds(value_s: float) -> str:
    """A duration in seconds."""
    if value_s < 1.0:
        return f"{value_s * 1e3:.0f} ms"
    return f"{value_s:.2f} s"


def format_value(value: float, prismatic: bool) -> str:
    """A joint value: degrees for a revolute joint (given in rad), metres for a prismatic one."""
    if prismatic:
        return f"{value:.4f} m"
    return f"{math.degrees(value):.2f}°"
