"""A command that writes a model file: ``-o MODEL.toml`` or the model printed, then a summary."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any

__all__ = ["add_model_output", "emit_model"]


def add_model_output(p: Any) -> None:
    """Add ``-o/--output MODEL.toml`` (default: print the model)."""
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="MODEL.toml",
        help="write the model file here (default: print it)",
    )


def emit_model(args: argparse.Namespace, text: str, summary: str) -> str:
    """Write the model to ``args.output`` (atomically) or print it; say so and how to check it.

    Printed, the model goes to stdout and ``summary`` to stderr; written, both
    lines go to stdout. Returns the written file as a shell operand (``""`` when
    printed), for a command's further advice.
    """
    from fkcheck.io.atomic import write_text_atomic
    from fkcheck.io.text import operand, terminal_text

    if args.output is None:
        sys.stdout.write(text)
        print(summary, file=sys.stderr)
        return ""
    write_text_atomic(args.output, text)
    print(summary)
    again = terminal_text(shlex.quote(operand(str(args.output))))
    print(f"wrote {terminal_text(args.output)}; check it: fkcheck check {again}")
    return again
