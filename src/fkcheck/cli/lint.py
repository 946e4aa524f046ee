"""``fkcheck lint``: flag what looks wrong in DH tables on their own.

Takes any number of bundled names, model files and directories (with none, the
``[tool.fkcheck] models`` of the nearest ``pyproject.toml``); every file is read
before any is linted, so an unreadable one is exit 2 before anything prints.
Rules are turned off by ``--ignore RULE``, the project's ``lint_ignore`` and a
model file's ``[lint] ignore``. Imports no reference library: it is fast enough
for a pre-commit hook.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeAlias

from fkcheck.cli._targets import ONLY_MODELS_HELP
from fkcheck.model.lint_rules import LINT_RULES

if TYPE_CHECKING:
    from fkcheck.cli._targets import Target
    from fkcheck.model.lint import Finding
    from fkcheck.model.types import Model

    # A model, where it was named, its findings, whether measured values were exempt.
    _Report: TypeAlias = tuple[Model, str, list[Finding], bool]

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "lint",
        help="flag what looks wrong in DH tables before anything runs",
        description="Look at model files on their own: degrees in a radian file, twists that "
        "are not multiples of 90°, lengths beyond a few metres, revolute limits beyond ±360°, "
        "a table whose shape fits the other DH convention, numbers that match a published "
        "table except for rounding. With no MODEL, lints [tool.fkcheck] models of the nearest "
        "pyproject.toml. Exit 0: clean; 1: warnings; 2: unreadable.",
    )
    p.add_argument(
        "models",
        metavar="MODEL",
        nargs="*",
        help="bundled model names (ur5), .toml/.csv files or directories of them",
    )
    p.add_argument(
        "--ignore",
        action="append",
        default=[],
        metavar="RULE",
        help=f"leave out a rule (repeatable): {', '.join(LINT_RULES)}; adds to "
        "[tool.fkcheck] lint_ignore and the model file's [lint] ignore",
    )
    p.add_argument("--json", action="store_true", help="print the findings as JSON")
    p.add_argument("--only-models", action="store_true", help=ONLY_MODELS_HELP)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Lint every model and print one block per file; exit 1 if any has a warning."""
    from fkcheck.cli._targets import load_targets, named_model_files, project_config
    from fkcheck.errors import FkcheckError
    from fkcheck.model.lint_rules import parse_lint_rules

    try:
        ignore = parse_lint_rules(args.ignore)
    except ValueError as exc:
        raise FkcheckError(f"--ignore: {exc}") from None
    models = named_model_files(args.models, "lint") if args.only_models else args.models
    if models is None:  # files were named, none a model: nothing to lint
        if args.json:
            print("[]")
        return 0
    project = project_config()
    targets = load_targets(models, project)
    ignore += project.lint_ignore if project is not None else ()
    reports = _lint_targets(targets, ignore)
    if args.json:
        _print_json(reports)
    else:
        _print_text(reports)
    return 1 if any(findings for _, _, findings, _ in reports) else 0


def _lint_targets(targets: Sequence[Target], ignore: tuple[str, ...]) -> list[_Report]:
    """Each target's model, where it was named, its findings, and whether its joints were exempt.

    (Exempt: a calibrated model's measured joints are not held to the measured rules.)
    """
    from fkcheck.calibration.lint import lint_calibrated
    from fkcheck.engine.expected import known_difference_findings

    reports = []
    for target in targets:
        model = target.model
        # A file as it was named (relative when it can be); a bundled model by its file.
        where = target.arg if model.path is None or Path(target.arg).exists() else str(model.path)
        findings, measured = lint_calibrated(model, ignore)
        findings += known_difference_findings(model, ignore)
        reports.append((model, where, findings, measured))
    return reports


def _print_json(reports: Sequence[_Report]) -> None:
    """The findings as JSON: one object for one model, else a list."""
    from fkcheck.io.strict_json import strict_json

    blocks = [
        {
            "model": model.name,
            "path": where,
            "findings": [
                {"rule": f.rule, "field": f.field, "message": f.message} for f in findings
            ],
        }
        for model, where, findings, _ in reports
    ]
    print(strict_json(blocks[0] if len(blocks) == 1 else blocks))


def _print_text(reports: Sequence[_Report]) -> None:
    """One block per model, and a count line when there are several."""
    from fkcheck.io.text import terminal_text
    from fkcheck.model.lint import MEASURED_RULES
    from fkcheck.model.names import field_text
    from fkcheck.urdf.locate import display_path

    for model, path, findings, measured in reports:
        where = display_path(path)  # a bundled model as fkcheck:NAME.toml (JSON: its file)
        for f in findings:
            field = f"{field_text(model, f.field)}: " if f.field else ""
            print(terminal_text(f"{where}: {field}warning [{f.rule}]: {f.message}"))
        if not findings:
            print(f"{terminal_text(where)}: clean ({model.dof} joints, {model.convention} DH)")
        if measured and model.calibration is not None:
            print(
                terminal_text(
                    f"{where}: calibrated from {model.calibration.nominal}: its joints' "
                    f"measured values are not held to the {', '.join(sorted(MEASURED_RULES))} "
                    f"rules (lint {model.calibration.nominal} for those)"
                )
            )
    if len(reports) > 1:
        warned = sum(1 for _, _, findings, _ in reports if findings)
        print(
            f"fkcheck lint: {len(reports)} models, {len(reports) - warned} clean, "
            f"{warned} with warnings"
        )
