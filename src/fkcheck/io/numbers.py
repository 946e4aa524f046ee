"""The one parser for numbers written as text: model CSV, ``--q``, ``--q-file``, poses CSV.

Python's ``float()`` is lenient in ways that change numbers silently: it reads
``1_0`` as 10, Arabic-Indic or fullwidth digits as ASCII ones, surrounding
Unicode whitespace, ``nan``/``inf`` and (through ``float.fromhex``'s cousins in
other tools) hex floats. A number from a file or the command line is accepted
here only when it is a plain ASCII decimal, optionally in scientific notation:

.. code-block:: text

    [+|-] digits [. digits] [(e|E) [+|-] digits]     e.g. 0.5  -.5  3.  1e-3  +2.5E+02

at most :data:`MAX_NUMBER_CHARS` characters long, and finite once read (a
value beyond the largest float, ~1.8e308, is "too large"). Anything else is a
:class:`NumberError` whose ``problem`` says what is wrong in a few words; the
reader that called :func:`parse_number` puts the file, line, column and field
in front of it. Fields are split by :func:`split_fields`, which keeps empty
fields (``0.1,,0.2`` is three fields, the middle one empty) and each field's
column, so that no value is ever dropped or shifted; :func:`parse_numbers`
reads a whole line of numbers that way (fast when the line is clean, and the
first bad field is named by its position and column).
"""

from __future__ import annotations

import math
import re

from fkcheck.errors import FkcheckError

__all__ = [
    "MAX_NUMBER_CHARS",
    "NumberError",
    "parse_number",
    "parse_numbers",
    "show_text",
    "split_fields",
]

#: Longest accepted number, in characters. ``repr`` of any float needs at most
#: 24; the rest is room for hand-written digits. A longer token (a 400-digit
#: integer, a pasted blob) is refused without being converted.
MAX_NUMBER_CHARS = 100

_PLAIN = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)
_NON_FINITE = {"nan", "inf", "infinity"}
#: Longest input text quoted back in a message.
_SHOW_CHARS = 40
#: A character no plain number (nor the spaces and separators around it) holds.
#: Within the rest, ``float()`` accepts exactly what :data:`_PLAIN` does.
_FOREIGN = re.compile(r"[^0-9+\-.eE \t,;]")


class NumberError(FkcheckError, ValueError):
    """Text that is not a plain, finite number.

    Readers catch it and raise their own error with the location; its ``str()``
    alone is the problem without a location.

    Attributes:
        problem: What is wrong, e.g. ``"not a number: '1_0' (no '_' in numbers)"``.
        index: From :func:`parse_numbers`: which field (1-based), else ``None``.
        column: From :func:`parse_numbers`: where that field starts (1-based), else ``None``.
    """

    def __init__(self, problem: str, index: int | None = None, column: int | None = None) -> None:
        self.problem = problem
        self.index = index
        self.column = column
        super().__init__(problem)


def show_text(text: str) -> str:
    """``text`` quoted for a one-line message: escaped (``repr``), at most ~40 characters."""
    if len(text) > _SHOW_CHARS:
        return repr(text[:_SHOW_CHARS]) + f"… ({len(text)} characters)"
    return repr(text)


def _why_not(text: str) -> str:
    """The reason a token that failed the pattern is not a number."""
    if not text.isascii():
        return "non-ASCII characters; write numbers with the digits 0-9"
    if "_" in text:
        return "no '_' in numbers"
    lowered = text.lower()
    if "0x" in lowered:
        return "no hex numbers"
    if any(char.isspace() for char in text):
        return "a space inside a number, or a missing separator"
    return "plain decimal numbers only, e.g. -0.5 or 1e-3"


def parse_number(text: str) -> float:
    """Read one plain ASCII decimal number; surrounding ASCII spaces and tabs are ignored.

    Args:
        text: One field, e.g. ``" -1.5e-3"``.

    Returns:
        The finite float.

    Raises:
        NumberError: Empty, too long, not a plain decimal number, not finite
            (``nan``, ``inf``), or too large for a float.
    """
    token = text.strip(" \t")
    if not token:
        raise NumberError("empty field (no number between the separators)")
    if len(token) > MAX_NUMBER_CHARS:
        raise NumberError(f"number too long: {len(token)} characters (at most {MAX_NUMBER_CHARS})")
    if _PLAIN.fullmatch(token) is None:
        if token.lower().lstrip("+-") in _NON_FINITE:
            raise NumberError(f"must be finite, got {show_text(token)}")
        raise NumberError(f"not a number: {show_text(token)} ({_why_not(token)})")
    value = float(token)
    if not math.isfinite(value):
        raise NumberError(f"number too large: {show_text(token)} (beyond ±1.8e308)")
    return value


def split_fields(line: str, separators: str = ",") -> list[tuple[int, str]]:
    """Split a line at each separator character, keeping empty fields and their columns.

    Args:
        line: One line of text, without its line break.
        separators: Each of these characters separates two fields.

    Returns:
        ``(column, text)`` per field, ``column`` 1-based (where the field starts
        in ``line``), ``text`` as written (not stripped). A line of ``k``
        separators gives ``k + 1`` fields.
    """
    parts = _split(line, separators)
    fields: list[tuple[int, str]] = []
    column = 1
    for part in parts:
        fields.append((column, part))
        column += len(part) + 1
    return fields


def parse_numbers(line: str, separators: str = ",") -> list[float]:
    """Every field of ``line`` as a number, as :func:`parse_number` reads each.

    Args:
        line: One line, e.g. ``"0.1, -2, 3e-4"``.
        separators: Each of these characters separates two fields.

    Returns:
        One float per field (``k`` separators: ``k + 1`` values).

    Raises:
        NumberError: For the first field that is not a number, with its
            ``index`` and ``column`` set.
    """
    if _FOREIGN.search(line) is None:  # the common case: one pass in C per step
        parts = _split(line, separators)
        if max(map(len, parts)) <= MAX_NUMBER_CHARS:
            try:
                values = list(map(float, parts))
            except ValueError:
                pass
            else:
                if all(map(math.isfinite, values)):
                    return values
    values = []
    for index, (column, text) in enumerate(split_fields(line, separators), start=1):
        try:
            values.append(parse_number(text))
        except NumberError as exc:
            raise NumberError(exc.problem, index, column) from None
    return values


def _split(line: str, separators: str) -> list[str]:
    for other in separators[1:]:  # same length: the columns stay where they were
        line = line.replace(other, separators[0])
    return line.split(separators[0])
