"""The names of ``fkcheck lint``'s rules, and reading a list of rules to ignore.

Shared by the model file's ``[lint] ignore``, ``[tool.fkcheck] lint_ignore``
and ``fkcheck lint --ignore``; what each rule looks for is in
:mod:`fkcheck.model.lint`.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Literal, get_args

__all__ = ["LINT_RULES", "Rule", "parse_lint_rules"]

Rule = Literal[
    "degrees",
    "rounded-angle",
    "twist",
    "length",
    "limits",
    "convention",
    "published",
    "calibration",
    "known-difference",
]

#: Every rule, in the order :func:`fkcheck.model.lint.lint_model` applies them.
LINT_RULES: tuple[Rule, ...] = get_args(Rule)


def parse_lint_rules(values: Iterable[str]) -> tuple[str, ...]:
    """Rule names, validated, each once, in the order given.

    Raises:
        ValueError: A name that is no rule; the message lists the rules.
    """
    out: list[str] = []
    for value in values:
        if value not in LINT_RULES:
            raise ValueError(f"unknown lint rule {value!r}; rules are: {', '.join(LINT_RULES)}")
        if value not in out:
            out.append(value)
    return tuple(out)
