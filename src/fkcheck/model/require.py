"""The kinds of evidence a check can require: the vocabulary of ``[check] require``.

``implementation`` — the in-house core agrees with libraries running the same
table; ``table`` — the table agrees with something that does not come from it
(a URDF, measured poses, a table published elsewhere). The verdict built on them
is :mod:`fkcheck.engine.verdict`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal, get_args

__all__ = ["KINDS", "Kind", "parse_require"]

Kind = Literal["implementation", "table"]

#: The kinds of evidence, in the order they are shown.
KINDS: tuple[Kind, ...] = get_args(Kind)


def parse_require(values: Sequence[str], where: str) -> tuple[Kind, ...]:
    """Validate ``require`` values (``"table"``, ``"implementation"``), in ``KINDS`` order.

    Raises:
        ValueError: An unknown kind (the message names ``where`` and the valid kinds).
    """
    unknown = [v for v in values if v not in KINDS]
    if unknown:
        raise ValueError(
            f"{where}: {unknown[0]!r} is not a kind of evidence; kinds are: {', '.join(KINDS)}"
        )
    return tuple(k for k in KINDS if k in values)
