"""The ``fkcheck`` command line: argparse subcommands, ``main(argv) -> int``.

Each subcommand lives in its own module under :mod:`fkcheck.commands` with
``add_parser(subparsers)`` and ``run(args) -> int``; those modules import heavy
libraries only inside ``run``, so ``fkcheck --help`` stays fast.

Exit codes: 0 ok, 1 a check disagreed or errored, 2 bad input (one line on stderr).
"""

from __future__ import annotations

import argparse
import importlib
import signal
import sys
import threading
from collections.abc import Sequence
from typing import NoReturn

from fkcheck import __version__
from fkcheck.errors import FkcheckError

__all__ = ["COMMANDS", "MAIN_JOB", "main"]

#: Subcommand modules under fkcheck.commands, in the order ``--help`` lists them.
COMMANDS = ("check", "fk", "models", "convert", "dh_from_urdf", "urdf", "lint", "diagnose", "bench")

#: What plain ``fkcheck`` runs.
MAIN_JOB = ("check", "ur5", "--json", "reports/ur5.json", "--html", "reports/ur5.html")

EXIT_OK = 0
EXIT_FAIL = 1
EXIT_BAD_INPUT = 2


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line and exit 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The full ``fkcheck`` parser with every subcommand."""
    parser = _Parser(
        prog="fkcheck",
        description="Cross-validate robot-arm forward kinematics: an in-house DH core "
        "checked pose by pose against reference libraries.",
    )
    parser.add_argument("--version", action="version", version=f"fkcheck {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in COMMANDS:
        importlib.import_module(f"fkcheck.commands.{name}").add_parser(sub)
    return parser


def _join_negative_values(argv: list[str]) -> list[str]:
    """Let ``--q -30,60`` through: argparse would take ``-30,60`` for an option."""
    out: list[str] = []
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in ("--q",) and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            out.append(f"{arg}={argv[i + 1]}")
            i += 2
            continue
        out.append(arg)
        i += 1
    return out


class _Terminated(Exception):
    """SIGTERM, turned into an exception so the run unwinds and says so."""


def _on_sigterm(signum: int, frame: object) -> None:
    raise _Terminated


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line and return the exit code."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _on_sigterm)
    args_list = _join_negative_values(list(sys.argv[1:] if argv is None else argv))
    parser = build_parser()
    if not args_list:  # the main job: check the bundled UR5 against every default backend
        args_list = list(MAIN_JOB)
    try:
        args = parser.parse_args(args_list)
    except SystemExit as exc:  # --help, --version, or a usage error (already printed)
        return int(exc.code or 0)
    if args.command is None:
        parser.print_help()
        return EXIT_OK
    args.argv = args_list
    try:
        return int(args.run(args))
    except FkcheckError as exc:
        print(f"fkcheck: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print(
            "fkcheck: interrupted (Ctrl-C): results incomplete, no report written", file=sys.stderr
        )
        return 130
    except _Terminated:
        print(
            "fkcheck: terminated (SIGTERM): results incomplete, no report written", file=sys.stderr
        )
        return 143
    except BrokenPipeError:
        return EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
