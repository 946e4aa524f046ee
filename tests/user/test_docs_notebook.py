"""The notebook example (docs/howto/notebook.md), run as written.

The code and the output it shows are read from the page, so the two cannot
drift apart: the last line is evaluated as a notebook cell's would be, and its
``repr`` must be the text the page prints.
"""

from __future__ import annotations

from typing import Any

import fkcheck
from tests.paths import REPO_ROOT

PAGE = REPO_ROOT / "docs" / "howto" / "notebook.md"


def _example() -> tuple[list[str], str]:
    """The page's ``python`` block (its lines) and the ``text`` block after it."""
    section = PAGE.read_text(encoding="utf-8")
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    shown = section.split("```text\n", 1)[1].split("```", 1)[0]
    return [line for line in code.splitlines() if line.strip()], shown.strip()


def test_the_example_is_three_lines_ending_in_the_result():
    lines, shown = _example()
    assert len(lines) == 3
    assert lines[0].startswith("model = fkcheck.model_from_table(")
    assert lines[-1] == "result"
    assert shown.startswith("<fkcheck.Outcome ")


def test_the_page_example_runs_and_shows_its_output():
    lines, shown = _example()
    namespace: dict[str, Any] = {"fkcheck": fkcheck}
    exec("\n".join(lines[:-1]), namespace)  # the page's own code
    result = eval(lines[-1], namespace)  # as a notebook cell shows its last line
    assert isinstance(result, fkcheck.Outcome)
    assert result.verdict == "pass"
    assert repr(result) == shown
    assert 'data-verdict="pass"' in result._repr_html_()
    assert result.check.frame_from == "world"
    assert result.check.frame_to == "tcp"
