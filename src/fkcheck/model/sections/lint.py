"""``[lint]``: the ``fkcheck lint`` rules this model's file turns off."""

from __future__ import annotations

from typing import Any

from fkcheck.model.lint_rules import LINT_RULES, parse_lint_rules
from fkcheck.model.sections.reader import Reader, is_text_list, shown_key

__all__ = ["LINT_KEYS", "read_lint"]

LINT_KEYS = {"ignore"}


def read_lint(r: Reader, raw: Any) -> tuple[str, ...]:
    """``ignore``: names of rules of :data:`~fkcheck.model.lint_rules.LINT_RULES`."""
    raw_ignore = r.table(raw, "lint", LINT_KEYS).get("ignore", [])
    if not is_text_list(raw_ignore):
        raise r.fail(
            "lint.ignore",
            f'expected a list of rule names such as ["limits"]; rules are: {", ".join(LINT_RULES)}',
        )
    try:
        return parse_lint_rules(shown_key(x) for x in raw_ignore)
    except ValueError as exc:
        raise r.fail("lint.ignore", str(exc)) from None
