"""Every runnable example of the docs and the README runs, and prints what the page shows.

The convention is in :mod:`tests.docs.examples` (and CONTRIBUTING.md): ``console``
blocks are commands with their output, ``python`` blocks are code. A page that shows a
command which no longer works, or output it no longer prints, fails here.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

import fkcheck
from tests.docs.examples import (
    ELLIPSIS,
    Block,
    blocks,
    commands,
    output_matches,
    pages,
)
from tests.paths import REPO_ROOT

#: The repository's directories a page's commands may name (``tests/data/…``).
LINKED = ("tests", "examples", "models")


def _runnable(lang: str) -> list[Block]:
    return [b for p in pages() for b in blocks(p) if b.lang == lang and b.not_run is None]


CONSOLE = _runnable("console")


def _scratch(tmp_path: Path) -> Path:
    for name in LINKED:
        (tmp_path / name).symlink_to(REPO_ROOT / name, target_is_directory=True)
    return tmp_path


def _env() -> dict[str, str]:
    src = str(Path(fkcheck.__file__).resolve().parents[1])
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(p for p in (src, os.environ.get("PYTHONPATH")) if p),
        "COLUMNS": "200",
        "FKCHECK_PYTHON": sys.executable,
    }


def test_the_pages_have_runnable_examples():
    """The convention is in use: the tutorial and the README show commands that run."""
    where = {b.page.relative_to(REPO_ROOT).as_posix() for b in CONSOLE}
    assert {"docs/tutorial.md", "README.md"} <= where
    assert len(CONSOLE) >= 8
    assert _runnable("python")


def test_every_example_not_run_says_why():
    for page in pages():
        for block in blocks(page):
            if block.not_run is not None:
                assert len(block.not_run.split()) >= 3, block.where


def test_the_output_comparison_is_strict():
    shown = ["a  b", ELLIPSIS, "verdict: pass … answered)"]
    assert output_matches(shown, "a b\nx\ny\nverdict: pass (7 backends answered)\n") is None
    assert output_matches(shown, "a b\nverdict: pass (7 answered)") is None
    assert output_matches(shown, "a b\nverdict: fail (7 answered)") is not None
    assert output_matches(["a", "b"], "a\nx\nb") is not None  # no elision without …
    assert output_matches(["a"], "a\nb") is not None  # nor after the last line


@pytest.mark.parametrize("block", CONSOLE, ids=[b.where for b in CONSOLE])
def test_console_example(block: Block, tmp_path: Path):
    cwd = _scratch(tmp_path)
    for command in commands(block):
        # `fkcheck` is this interpreter's fkcheck, whatever is on PATH.
        script = f'fkcheck() {{ "$FKCHECK_PYTHON" -m fkcheck "$@"; }}\n{command.command}\n'
        done = subprocess.run(
            ["bash", "-c", script],
            cwd=cwd,
            env=_env(),
            capture_output=True,
            text=True,
            timeout=600,
            check=False,
        )
        shown = f"{block.where}: $ {command.command}\n{done.stdout}\n{done.stderr}"
        assert done.returncode == command.exit_code, shown
        if command.shown:
            problem = output_matches(command.shown, done.stdout)
            assert problem is None, f"{problem}\n{shown}"


PYTHON_PAGES = sorted({b.page for b in _runnable("python")})


@pytest.mark.parametrize(
    "page", PYTHON_PAGES, ids=[p.relative_to(REPO_ROOT).as_posix() for p in PYTHON_PAGES]
)
def test_python_examples(page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.chdir(_scratch(tmp_path))
    namespace: dict[str, Any] = {"__name__": "__docs__", "fkcheck": fkcheck}
    found = blocks(page)
    for i, block in enumerate(found):
        if block.lang != "python" or block.not_run is not None:
            continue
        following = found[i + 1] if i + 1 < len(found) else None
        if following is not None and following.lang == "text":
            *body, last = [line for line in block.text.splitlines() if line.strip()]
            exec(compile("\n".join(body), block.where, "exec"), namespace)
            value = eval(compile(last, block.where, "eval"), namespace)
            assert repr(value) == following.text.strip(), block.where
        else:
            exec(compile(block.text, block.where, "exec"), namespace)


def test_the_api_page_names_the_facade_automodule_cannot_see():
    """``fkcheck.check``, ``write_report`` and ``Outcome`` load on first use (a module
    ``__getattr__``), so ``automodule`` misses them: the API page names each."""
    page = (REPO_ROOT / "docs" / "reference" / "api.md").read_text(encoding="utf-8")
    assert ".. automodule:: fkcheck\n" in page
    for name in fkcheck._FACADE:
        assert name in fkcheck.__all__
        assert f":: fkcheck.{name}\n" in page, name
