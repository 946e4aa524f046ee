"""``fkcheck models``: list the bundled models, one line each; details on request.

The default listing fits a screen and 80 columns: one line per model (name,
joints, convention, what its evidence can be), then a footer that says how to
see more. ``fkcheck models NAME…`` shows the named models in full (their
source, their URDF), ``--long`` every bundled model.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from fkcheck.model.types import Model

__all__ = ["add_parser", "evidence_text", "run"]

#: The footer of the compact listing: how to see more.
FOOTER = "details: fkcheck models NAME (e.g. ur5), or --long for all"


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "models",
        help="list the bundled models (one line each; NAME or --long for details)",
        description="List the bundled models, one line each. Name models to see them in full "
        "(their source and URDF); --long shows every bundled model in full.",
    )
    p.add_argument(
        "names",
        nargs="*",
        metavar="NAME",
        help="a bundled model (or a model file) to show in full",
    )
    p.add_argument("--long", action="store_true", help="show every bundled model in full")
    p.set_defaults(run=run)


def evidence_text(model: Model) -> str:
    """What a check of ``model`` can verify, in a few words.

    With a description (URDF, xacro, MJCF), backends that read it check the table
    itself (``table + code (ur.urdf.xacro)``, the description's file name); without
    one, only other implementations of the same table can answer (``code only (no
    description)``). A recorded difference is counted.
    """
    from fkcheck.description.registry import model_format

    fmt = model_format(model)
    if fmt is None:
        return "code only (no description)"
    file = fmt.written(model).split(":")[-1].rsplit("/", 1)[-1]
    known = len(model.known_differences)
    recorded = f", {known} known difference{'s' if known != 1 else ''}" if known else ""
    return f"table + code ({file}{recorded})"


def _compact(models: dict[str, Model]) -> list[str]:
    """One line per model, under a header line, then the footer."""
    width = max(len("model"), *(len(n) for n in models))
    rows = [("model", "DOF", "DH", "evidence (description)")]
    rows += [(n, str(m.dof), m.convention, evidence_text(m)) for n, m in models.items()]
    lines = [f"{n:<{width}}  {j:>3}  {c:<8}  {e}".rstrip() for n, j, c, e in rows]
    return [*lines, f"{len(models)} bundled models; {FOOTER}"]


def _long(models: dict[str, Model]) -> None:
    """Every model in full: DOF, convention, URDF and source (a table that wraps)."""
    from rich.table import Table

    from fkcheck.cli._console import console
    from fkcheck.description.registry import model_format
    from fkcheck.io.text import terminal_markup

    table = Table(title="bundled models", title_justify="left")
    for column in ("model", "DOF", "convention", "URDF", "source"):
        table.add_column(column, overflow="fold", no_wrap=column == "model")
    for name, model in models.items():
        fmt = model_format(model)
        urdf = fmt.written(model) if fmt is not None else "-"
        cells = (name, str(model.dof), model.convention, urdf, model.source)
        table.add_row(*map(terminal_markup, cells))
    console().print(table)


def run(args: argparse.Namespace) -> int:
    """The compact listing, or the named (``--long``: every) models in full."""
    from fkcheck.io.text import terminal_text
    from fkcheck.model.read import bundled_model_paths, load_model

    if args.names:
        _long({name: load_model(name) for name in args.names})
        return 0
    models = {name: load_model(path) for name, path in bundled_model_paths().items()}
    if args.long:
        _long(models)
        return 0
    for line in _compact(models):
        print(terminal_text(line))
    return 0
