"""Library versions a ``[[known_difference]]`` applies to: ``versions = ">=4.0, <=4.1.0"``.

A reader's bug belongs to the versions it was measured on: a record of it must
stop applying once the library is fixed (its agreement is then the check's
news, not a stale record). The form is a small, documented subset of PEP 440
specifiers, so that no dependency is needed: clauses separated by commas, each
an operator (``==``, ``!=``, ``<``, ``<=``, ``>``, ``>=``) and a release number
of dot-separated integers (``4.1.0``). Releases compare number by number, the
shorter padded with zeros (``4.1`` is ``4.1.0``). An installed version is read
by its release part only: ``4.1.1rc1`` and ``4.1.1.post2`` are ``4.1.1``.
"""

from __future__ import annotations

import operator
import re
from collections.abc import Callable

__all__ = ["OPERATORS", "parse_versions", "release", "release_text", "versions_match"]

#: The operators a clause may use, and what each compares.
OPERATORS: dict[str, Callable[[tuple[int, ...], tuple[int, ...]], bool]] = {
    "==": operator.eq,
    "!=": operator.ne,
    "<=": operator.le,
    ">=": operator.ge,
    "<": operator.lt,
    ">": operator.gt,
}
_CLAUSE = re.compile(r"\s*(==|!=|<=|>=|<|>)\s*(\d{1,9}(?:\.\d{1,9}){0,4})\s*")
_RELEASE = re.compile(r"\s*v?(\d{1,9}(?:\.\d{1,9}){0,4})")
_PARTS = 5  # releases are compared on this many numbers (``4.1`` is ``4.1.0.0.0``)


def _padded(numbers: str) -> tuple[int, ...]:
    parts = tuple(int(x) for x in numbers.split("."))
    return parts + (0,) * (_PARTS - len(parts))


def parse_versions(text: str) -> tuple[tuple[str, tuple[int, ...]], ...]:
    """The clauses of ``text``, as ``(operator, release)``.

    Raises:
        ValueError: ``text`` is empty or a clause is not ``OPERATOR RELEASE``;
            the message names the clause and the operators allowed.
    """
    if len(text) > 200:
        raise ValueError("longer than 200 characters")
    clauses = text.split(",")
    out = []
    for clause in clauses:
        found = _CLAUSE.fullmatch(clause)
        if found is None:
            raise ValueError(
                f"{clause.strip()!r} is not an operator and a release (e.g. '<=4.1.0'); "
                f"operators: {', '.join(OPERATORS)}, clauses separated by commas"
            )
        out.append((found.group(1), _padded(found.group(2))))
    return tuple(out)


def release(version: str) -> tuple[int, ...] | None:
    """The release part of an installed version (``4.1.1rc1`` → ``(4, 1, 1, 0, 0)``); ``None``."""
    found = _RELEASE.match(version)
    return _padded(found.group(1)) if found else None


def release_text(version: str) -> str | None:
    """The release part of an installed version as a clause writes it (``4.1.1rc1`` → ``4.1.1``).

    What :func:`release` reads of ``version``, so that ``<=`` it matches that version;
    ``None`` when it has none.
    """
    found = _RELEASE.match(version)
    return found.group(1) if found else None


def versions_match(spec: str, version: str) -> bool:
    """Whether ``version`` (as installed) is within ``spec``; never for an unreadable one.

    Raises:
        ValueError: ``spec`` is not valid (:func:`parse_versions`).
    """
    have = release(version)
    if have is None:
        return False
    return all(OPERATORS[op](have, want) for op, want in parse_versions(spec))
