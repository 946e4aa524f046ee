"""How numbers read in fkcheck's output: lengths in mm and m, angles in degrees and rad.

A quantity shown in two units follows one rule (:func:`format_pair`): the unit a
person reads first (mm, °), then the SI value in parentheses (m, rad) —
``251 mm (2.51e-01 m)``, ``180° (3.14e+00 rad)``. Machine outputs (JSON) keep
plain SI numbers.

Two different values shown side by side, or a difference between them, never
read the same: :func:`format_distinct` adds digits until they differ (a rounded
``-1.5708`` next to ``-π/2``), :func:`format_delta` says a difference too small
for its decimals in scientific notation rather than as ``+0.0000``.

Pure functions over floats, and the one place that decides how a number is
written for a person: the HTML, Markdown and terminal outputs all use them, so a
number reads the same everywhere it has the same role. (Model files and URDFs
write numbers for machines, exactly: :func:`fkcheck.model.write.toml_number`.)
"""

from __future__ import annotations

import math

__all__ = [
    "format_angle_console",
    "format_angle_summary",
    "format_constant",
    "format_deg",
    "format_delta",
    "format_distinct",
    "format_fixed",
    "format_length_console",
    "format_length_summary",
    "format_m",
    "format_microseconds",
    "format_mm",
    "format_pair",
    "format_rad",
    "format_scientific",
    "format_seconds",
    "format_value",
]


#: What a missing value reads as.
_MISSING = "–"


def _sig3(value: float) -> str:
    """Three significant digits, trailing zeros kept (0.300), no bare trailing point (251)."""
    text = f"{value:#.3g}"
    return text[:-1] if text.endswith(".") else text


def format_pair(human: str, si: str) -> str:
    """A quantity in two units: the human one first, the SI value in parentheses.

    The one rule of every two-unit reading: ``format_pair("251 mm", "2.51e-01 m")``
    is ``251 mm (2.51e-01 m)``, ``format_pair("180°", "3.14e+00 rad")`` is
    ``180° (3.14e+00 rad)``.
    """
    return f"{human} ({si})"


def format_scientific(value: float | None, unit: str) -> str:
    """A quantity in scientific notation, then its unit (``2.10e-11 m/rad``); ``–`` if absent."""
    return _MISSING if value is None else f"{value:.2e} {unit}"


def format_mm(value_m: float | None) -> str:
    """A length given in metres, shown in millimetres (3 significant digits)."""
    return _MISSING if value_m is None else f"{_sig3(value_m * 1e3)} mm"


def format_m(value_m: float | None) -> str:
    """A length in metres, scientific notation (3 significant digits)."""
    return format_scientific(value_m, "m")


def format_rad(value_rad: float | None) -> str:
    """An angle in radians, scientific notation (3 significant digits)."""
    return format_scientific(value_rad, "rad")


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


def format_length_summary(value_m: float | None) -> str:
    """A length error as the Markdown summary shows it: mm, then m in scientific notation."""
    return _MISSING if value_m is None else format_pair(format_mm(value_m), format_m(value_m))


def format_angle_summary(value_rad: float | None) -> str:
    """An angle error as the Markdown summary shows it: °, then rad in scientific notation."""
    if value_rad is None:
        return _MISSING
    return format_pair(format_deg(value_rad), format_rad(value_rad))


def _with_larger_unit(value: float | None, unit: str, scale: float, larger: str) -> str:
    """``value`` times ``scale`` in ``larger``, then ``value`` in ``unit``, when 1e-5 or more.

    Smaller values (round-off: ``5.7e-17 m``) read in ``unit`` alone: in mm or °
    they would be no easier to read, only longer.
    """
    if value is None:
        return "-"
    if value >= 1e-5:
        return format_pair(f"{value * scale:.3f}{larger}", f"{value:.3g} {unit}")
    return f"{value:.2g} {unit}"


def format_length_console(value_m: float | None) -> str:
    """A length error as the terminal table shows it: mm then m, when 1e-5 m or more; else m."""
    return _with_larger_unit(value_m, "m", 1e3, " mm")


def format_angle_console(value_rad: float | None) -> str:
    """An angle error as the terminal table shows it: ° then rad, when 1e-5 rad or more."""
    return _with_larger_unit(value_rad, "rad", 180.0 / math.pi, "°")  # as math.degrees


def format_constant(value: float) -> str:
    """A table constant, shortest exact-looking form (0.089159, -0.425, 90); never ``-0``."""
    text = f"{value:.10g}"
    return "0" if text == "-0" else text


def format_distinct(a: float, b: float, digits: int) -> tuple[str, str]:
    """``a`` and ``b`` with ``digits`` significant digits, or as many more as tell them apart.

    ``format_distinct(-1.5708, -math.pi / 2, 6)`` is ``("-1.5708", "-1.570796")``,
    not twice ``-1.5708``: two values that differ never read the same (up to the
    17 digits that write any float exactly). Equal values read alike; ``-0`` reads
    ``0``.
    """
    for n in range(digits, 18):
        ta, tb = (_no_minus_zero(f"{v:.{n}g}") for v in (a, b))
        if ta != tb or a == b:
            return ta, tb
    return repr(a), repr(b)


def _no_minus_zero(text: str) -> str:
    return "0" if text == "-0" else text


def format_delta(value: float, decimals: int) -> str:
    """A signed difference with ``decimals`` places (``+0.300``), never ``+0.000`` when not zero.

    A difference that rounds away at ``decimals`` reads in scientific notation
    (``+2.1e-07``): a difference that is there is shown as there.
    """
    text = f"{value:+.{decimals}f}"
    if value != 0 and not text.strip("+-0."):
        return f"{value:+.2g}"
    return text


def format_fixed(value: float, digits: int) -> str:
    """Fixed-point text without a minus sign on zero (round-off must not flip the text)."""
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and not text.strip("-0.") else text


def format_microseconds(value_us: float) -> str:
    """A time in µs (the unit is not written): three significant digits, as a plain decimal."""
    return f"{value_us:.3g}" if value_us >= 0.01 else f"{value_us:.4f}"
