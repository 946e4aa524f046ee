"""The rich console the subcommands print their tables to, wide enough for a CI log."""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rich.console import Console

__all__ = ["PIPE_WIDTH", "console", "is_terminal"]

#: Columns of a table written to a pipe or file (a CI log): rich's own fallback,
#: 80, wraps backend names such as ``pinocchio-urdf`` in the middle.
PIPE_WIDTH = 120


def is_terminal(*, stderr: bool = False) -> bool:
    """Whether stdout (or stderr) is a terminal; a replaced or closed stream is not."""
    stream = sys.stderr if stderr else sys.stdout
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # replaced or closed stream
        return False


def console(*, stderr: bool = False, highlight: bool = True) -> Console:
    """A rich console on stdout (or stderr), :data:`PIPE_WIDTH` wide when that is no terminal.

    On a terminal rich follows the terminal's width; ``$COLUMNS``, when set,
    wins either way. The stream itself is asked, not rich: ``FORCE_COLOR``
    (set on many CI runners) makes rich treat a pipe as a terminal of 80 columns.
    Emoji codes (``:warning:``) print as written: text from input stays literal
    (its markup is escaped by :func:`fkcheck.io.text.terminal_markup`).
    When the stream is no terminal, lines of text are never wrapped (rich's
    ``soft_wrap``): a header or a verdict stays one line in a log, whatever its
    length, rather than breaking mid-phrase at the table's width; tables keep
    their width.
    """
    from rich.console import Console

    class _Console(Console):
        """rich's console, except that a closed pipe does not end the run.

        rich raises ``SystemExit(1)`` on a broken pipe (``fkcheck check | head``),
        which would skip the reports still to be written and turn a pass into
        exit 1. Here the console goes quiet, stdout goes to ``/dev/null``, and
        the run finishes with its own exit code.
        """

        def on_broken_pipe(self) -> None:
            self.quiet = True
            devnull = os.open(os.devnull, os.O_WRONLY)
            try:
                os.dup2(devnull, (sys.stderr if stderr else sys.stdout).fileno())
            except (OSError, ValueError):
                pass
            finally:
                os.close(devnull)

    tty = is_terminal(stderr=stderr)
    width = None if tty or os.environ.get("COLUMNS") else PIPE_WIDTH
    return _Console(stderr=stderr, highlight=highlight, width=width, emoji=False, soft_wrap=not tty)
