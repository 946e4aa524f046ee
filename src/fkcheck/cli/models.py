"""``fkcheck models``: list the bundled models."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser("models", help="list the bundled models")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print name, DOF, convention, URDF and source of every bundled model."""
    from rich.table import Table

    from fkcheck.cli._console import console
    from fkcheck.io.text import terminal_markup
    from fkcheck.model.read import bundled_model_paths, load_model

    table = Table(title="bundled models", title_justify="left")
    for column in ("model", "DOF", "convention", "URDF", "source"):
        table.add_column(column, overflow="fold", no_wrap=column == "model")
    for name, path in bundled_model_paths().items():
        model = load_model(path)
        urdf = model.urdf.path.split(":")[-1].rsplit("/", 1)[-1] if model.urdf else "-"
        cells = (name, str(model.dof), model.convention, urdf, model.source)
        table.add_row(*map(terminal_markup, cells))
    console().print(table)
    return 0
