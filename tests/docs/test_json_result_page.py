"""docs/reference/json-result.md's example is a real result's shape: the same keys.

The JSON is a contract other tools read; a key added to or dropped from the result
without the page following fails here.
"""

from __future__ import annotations

import json
from typing import Any

import fkcheck
from tests.paths import REPO_ROOT

PAGE = REPO_ROOT / "docs" / "reference" / "json-result.md"


def _example() -> dict[str, Any]:
    text = PAGE.read_text(encoding="utf-8")
    example: dict[str, Any] = json.loads(text.split("```json\n", 1)[1].split("```", 1)[0])
    return example


def _shape(value: Any) -> Any:
    """Keys all the way down (a list by its first item): what a reader relies on."""
    if isinstance(value, dict):
        return {k: _shape(v) for k, v in value.items()}
    if isinstance(value, list) and value and isinstance(value[0], dict):
        return [_shape(value[0])]
    return None


def test_the_page_shows_the_keys_a_check_writes(tmp_path):
    outcome = fkcheck.check("ur5", against=["rtb-dh", "pinocchio-urdf"], samples=1000)
    fkcheck.write_report(outcome, json=tmp_path / "r.json")
    real = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    example = _example()
    assert _shape(example) == _shape(real)
    same = ("model", "samples", "seed", "sampler", "timeout_s", "configurations", "from", "to",
            "tolerance", "reference", "verdict", "headline", "cross_checked")  # fmt: skip
    assert {k: example[k] for k in same} == {k: real[k] for k in same}
    assert example["evidence"] == real["evidence"]
    assert example["numbers"]["line"] == real["numbers"]["line"]
