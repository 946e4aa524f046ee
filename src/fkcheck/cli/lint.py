"""``fkcheck lint``: flag what looks wrong in a DH table on its own."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "lint",
        help="flag what looks wrong in a DH table before anything runs",
        description="Look at a model file on its own: degrees in a radian file, twists that "
        "are not multiples of 90°, lengths beyond a few metres, revolute limits beyond ±360°, "
        "a table whose shape fits the other DH convention, numbers that match a published "
        "table except for rounding. Exit 0: clean; 1: warnings; 2: unreadable.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5) or a .toml/.csv file")
    p.add_argument("--json", action="store_true", help="print the findings as JSON")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Lint and print."""
    from fkcheck.io.strict_json import strict_json
    from fkcheck.io.text import terminal_text
    from fkcheck.model.lint import lint_model
    from fkcheck.model.read import load_model

    model = load_model(args.model)
    findings = lint_model(model)
    where = str(model.path) if model.path is not None else model.name
    if args.json:
        print(
            strict_json(
                {
                    "model": model.name,
                    "path": where,
                    "findings": [
                        {"rule": f.rule, "field": f.field, "message": f.message} for f in findings
                    ],
                }
            )
        )
    else:
        for f in findings:
            field = f"{f.field}: " if f.field else ""
            print(terminal_text(f"{where}: {field}warning [{f.rule}]: {f.message}"))
        if not findings:
            print(f"{terminal_text(where)}: clean ({model.dof} joints, {model.convention} DH)")
    return 1 if findings else 0
