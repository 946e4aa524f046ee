"""Typed accessors for the section readers, and how a file's values go into messages.

Every accessor raises :class:`~fkcheck.errors.ModelError` naming the file, the
field and what is wrong; values from the file are quoted short and on one line
(:func:`shown_key`, :func:`shown_value`), so that a hostile file cannot flood a
message.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from fkcheck.core.tolerances import LimitKind, limit_problem
from fkcheck.errors import ModelError
from fkcheck.io.numbers import show_text
from fkcheck.model.types import MAX_LENGTH_M

__all__ = ["Reader", "digits", "is_text_list", "kind", "shown_key", "shown_value"]


class Reader:
    """Typed accessors that raise ModelError naming the file and field."""

    def __init__(self, path: Path | None) -> None:
        self.path = path

    def fail(self, field_: str, problem: str) -> ModelError:
        """The error to raise for ``field_`` (``""`` for the whole file)."""
        return ModelError(self.path, field_, problem)

    def table(self, value: Any, field_: str, allowed: set[str]) -> dict[str, Any]:
        """A table with no key outside ``allowed``."""
        if not isinstance(value, dict):
            raise self.fail(field_, f"expected a table, got {kind(value)}")
        unknown = sorted(set(value) - allowed)
        if unknown:
            raise self.fail(
                f"{field_}.{shown_key(unknown[0])}" if field_ else shown_key(unknown[0]),
                f"unknown key; allowed keys are: {', '.join(sorted(allowed))}",
            )
        return value

    def number(self, value: Any, field_: str) -> float:
        """A finite number (an integer or a float, not a boolean)."""
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(field_, f"expected a number, got {kind(value)}")
        try:
            result = float(value)
        except OverflowError:  # a TOML integer of hundreds of digits
            raise self.fail(
                field_, f"number too large: an integer of {digits(int(value))} digits"
            ) from None
        if not math.isfinite(result):
            raise self.fail(field_, f"must be a finite number, got {value}")
        return result

    def bounded(self, value: float, field_: str, bound: float, unit: str) -> float:
        """``value`` when within ``±bound``."""
        if abs(value) > bound:
            raise self.fail(
                field_, f"{value:g} {unit} is beyond ±{bound:g} {unit}, more than any arm needs"
            )
        return value

    def limit(self, value: Any, field_: str, limit_kind: LimitKind) -> float:
        """A tolerance or bound within its range (:mod:`fkcheck.core.tolerances`)."""
        number = self.number(value, field_)
        problem = limit_problem(number, limit_kind)
        if problem is not None:
            raise self.fail(field_, problem)
        return number

    def length(self, value: Any, field_: str) -> float:
        """A length in metres, within ±:data:`~fkcheck.model.types.MAX_LENGTH_M`."""
        return self.bounded(self.number(value, field_), field_, MAX_LENGTH_M, "m")

    def string(self, value: Any, field_: str) -> str:
        """A string."""
        if not isinstance(value, str):
            raise self.fail(field_, f"expected a string, got {kind(value)}")
        return value

    def choice(self, value: Any, field_: str, choices: tuple[str, ...]) -> str:
        """One of ``choices``."""
        text = self.string(value, field_)
        if text not in choices:
            raise self.fail(field_, f"{show_text(text)} is not one of: {', '.join(choices)}")
        return text

    def flag(self, value: Any, field_: str) -> bool:
        """``true`` or ``false``."""
        if not isinstance(value, bool):
            raise self.fail(field_, f"expected true or false, got {kind(value)}")
        return value

    def numbers(self, value: Any, field_: str, length: int | None) -> list[float]:
        """A list of finite numbers, of ``length`` items when given."""
        if not isinstance(value, list):
            raise self.fail(field_, f"expected a list of numbers, got {kind(value)}")
        if length is not None and len(value) != length:
            raise self.fail(field_, f"expected {length} numbers, got {len(value)}")
        return [self.number(v, f"{field_}[{i}]") for i, v in enumerate(value)]

    def text_table(self, value: Any, field_: str, what: str) -> dict[str, str]:
        """An inline table of strings (``{ ur_type = "ur5e" }``), each naming ``what``."""
        if not isinstance(value, dict):
            raise self.fail(field_, f'expected a table such as {{ name = "…" }}, got {kind(value)}')
        for key, item in value.items():
            if not isinstance(item, str):
                raise self.fail(
                    f"{field_}.{shown_key(key)}",
                    f"expected a string ({what}, as text), got {kind(item)}",
                )
        return dict(value)


def is_text_list(value: Any) -> bool:
    """Whether ``value`` is a list of strings (empty included)."""
    return isinstance(value, list) and all(isinstance(x, str) for x in value)


def shown_key(name: str) -> str:
    """A key or name from the file as it goes into a message: as is when short and printable."""
    return name if name.isprintable() and len(name) <= 64 else show_text(name)


def shown_value(value: Any) -> str:
    """A scalar from the file as it goes into a message (short, one line); else its kind."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 64:
        return f"an integer of {digits(value)} digits"
    if isinstance(value, str):
        return show_text(value)
    return repr(value) if isinstance(value, int | float) else kind(value)


def digits(value: int) -> str:
    """How many decimal digits ``value`` has, without converting it to text."""
    return f"about {int(abs(value).bit_length() * math.log10(2)) + 1}"


def kind(value: Any) -> str:
    """What a value from the file is, for messages: ``"a string"``, ``"a table"``."""
    names = {bool: "a boolean", str: "a string", int: "an integer", float: "a number",
             list: "a list", dict: "a table"}  # fmt: skip
    return names.get(type(value), type(value).__name__)
