"""The runnable examples of the docs pages and the README, and how they are run.

The convention (also in CONTRIBUTING.md):

* A ```` ```console ```` block is run. Each line starting with ``$ `` is a command, run
  by bash in a scratch directory that holds ``tests/``, ``examples/`` and ``models/``
  of this repository; ``fkcheck`` is this interpreter's fkcheck. The lines up to the
  next command are what it prints on stdout. A command exits 0, or the code a trailing
  ``# exit N`` comment names.
* Shown output is compared line by line, whitespace runs counted as one space. A line
  that is only ``…`` stands for any number of lines; a ``…`` inside a line for any
  text (volatile parts: timings, absolute paths).
* A ```` ```python ```` block is run; a page's blocks share one namespace (which starts
  with ``fkcheck`` imported), in the page's order, in a scratch directory. When the
  next block is ```` ```text ````, the block's last line is an expression whose
  ``repr`` is that text (a notebook cell).
* A block preceded by a ``% not run: REASON`` line (a MyST comment; in the README
  ``<!-- not run: REASON -->``) is not run here: REASON names where it is tested or why
  it cannot run (an install, a command that needs files the page makes earlier).
* Other blocks (``sh``, ``toml``, ``yaml``, ``text``, none) are not run.
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field
from pathlib import Path

from tests.paths import REPO_ROOT

DOCS_DIR = REPO_ROOT / "docs"
ELLIPSIS = "…"
_NOT_RUN = re.compile(r"^(?:% not run: (?P<myst>.+)|<!-- not run: (?P<html>.+?) -->)$")
_EXIT = re.compile(r"\s#\s*exit (\d+)\s*$")


@dataclass(frozen=True)
class Block:
    """One fenced block of a page."""

    page: Path
    line: int  # 1-based line of the opening fence
    lang: str
    text: str
    not_run: str | None  # the reason, when marked not run

    @property
    def where(self) -> str:
        """``docs/tutorial.md:42``."""
        return f"{self.page.relative_to(REPO_ROOT)}:{self.line}"


@dataclass
class Command:
    """A console block's command and the output the page shows for it."""

    command: str
    exit_code: int
    shown: list[str] = field(default_factory=list)


def pages() -> list[Path]:
    """The docs' Markdown pages and the README."""
    return [*sorted(DOCS_DIR.rglob("*.md")), REPO_ROOT / "README.md"]


def blocks(page: Path) -> list[Block]:
    """The fenced blocks of a page, in order."""
    lines = page.read_text(encoding="utf-8").splitlines()
    out: list[Block] = []
    i = 0
    while i < len(lines):
        fence = re.match(r"^(`{3,})(\S*)\s*$", lines[i])
        if not fence:
            i += 1
            continue
        start, ticks, lang = i, fence.group(1), fence.group(2)
        j = i + 1
        while j < len(lines) and lines[j].rstrip() != ticks:
            j += 1
        previous = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
        marked = _NOT_RUN.match(previous.strip())
        reason = (marked.group("myst") or marked.group("html")) if marked else None
        out.append(Block(page, start + 1, lang, "\n".join(lines[start + 1 : j]), reason))
        i = j + 1
    return out


def commands(block: Block) -> list[Command]:
    """A console block's commands, each with its exit code and shown output."""
    out: list[Command] = []
    for line in block.text.splitlines():
        if line.startswith("$ "):
            code = _EXIT.search(line)
            out.append(Command(line[2:], int(code.group(1)) if code else 0))
        elif out:
            out[-1].shown.append(line)
        elif line.strip():
            raise ValueError(f"{block.where}: output before any '$ ' command: {line!r}")
    return out


def _norm(line: str) -> str:
    return " ".join(line.split())


def _line_pattern(shown: str) -> re.Pattern[str]:
    parts = [re.escape(p) for p in _norm(shown).split(ELLIPSIS)]
    return re.compile("^" + ".*".join(parts) + "$")


def output_matches(shown: list[str], printed: str) -> str | None:
    """``None`` when ``printed`` is what ``shown`` shows, else what does not match."""
    actual = [_norm(line) for line in printed.splitlines()]
    while actual and not actual[-1]:
        actual.pop()
    expected = list(shown)
    while expected and not expected[-1].strip():
        expected.pop()

    @functools.cache
    def match(e: int, a: int) -> bool:
        if e == len(expected):
            return a == len(actual)
        if _norm(expected[e]) == ELLIPSIS:
            return any(match(e + 1, k) for k in range(a, len(actual) + 1))
        return (
            a < len(actual)
            and bool(_line_pattern(expected[e]).match(actual[a]))
            and match(e + 1, a + 1)
        )

    if match(0, 0):
        return None
    for line in expected:  # the first shown line printed nowhere, for the message
        if _norm(line) != ELLIPSIS and not any(_line_pattern(line).match(a) for a in actual):
            return f"not printed: {line!r}"
    return "every shown line is printed, but not in this order or with other lines between"
