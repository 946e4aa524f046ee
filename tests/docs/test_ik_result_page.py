"""docs/reference/ik-result.md's example is a real ``fkcheck ik --json`` result's shape."""

from __future__ import annotations

import dataclasses
import json
import math
from typing import Any

import pytest

from fkcheck.ik import check_ik, make_solver
from fkcheck.ik.output import to_dict
from fkcheck.model.read import load_model
from tests.paths import REPO_ROOT

PAGE = REPO_ROOT / "docs" / "reference" / "ik-result.md"


def _example() -> dict[str, Any]:
    text = PAGE.read_text(encoding="utf-8")
    example: dict[str, Any] = json.loads(text.split("```json\n", 1)[1].split("```", 1)[0])
    return example


def _shape(value: Any) -> Any:
    """Keys all the way down (a list by its first item), without the counts' keys."""
    if isinstance(value, dict):
        return {k: _shape(v) for k, v in value.items()}
    if isinstance(value, list) and value and isinstance(value[0], dict):
        return [_shape(value[0])]
    return None


def test_the_page_shows_the_keys_fkcheck_ik_writes():
    pytest.importorskip("ur_analytic_ik")
    ur5e = load_model("ur5e")
    issue5 = tuple(math.radians(v) for v in (0, -45, -90, -90, 90, 0))
    model = dataclasses.replace(ur5e, poses={**ur5e.poses, "issue5": issue5})
    solver = make_solver("ur-analytic-ik", model, "base", "tool0")
    result = check_ik(model, solver, frame_from="base", frame_to="tool0", samples=200, seed=0)
    real = json.loads(json.dumps(to_dict(result)))
    example = _example()
    for volatile in ("counts", "missed_by_branch", "wrong_by_branch", "messages"):
        assert isinstance(example[volatile], dict)
        example[volatile] = real[volatile] = None
    assert _shape(example) == _shape(real)
    same = ("schema", "verdict", "model", "solver", "frame_from", "frame_to", "samples", "seed",
            "tolerances", "poses", "singular_poses", "wrong_solutions", "missed", "garbage",
            "raised", "own_fk", "own_fk_disagreements", "explanation")  # fmt: skip
    assert {k: example[k] for k in same} == {k: real[k] for k in same}
    assert example["worst"][0]["q_deg"] == real["worst"][0]["q_deg"]
