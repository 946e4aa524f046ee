"""Zero-range or near-zero limits hide a split (issue 30, item 3).

A joint the model's limits freeze (``[0, 0]``, ±1e-7°) never turns in a check:
a URDF that splits a2/a3 50 mm otherwise (the same sum) agrees with the table
on every configuration within limits. Those numbers are the limits' to hide,
not "verified as a combination"; lint flags the joint.
"""

from __future__ import annotations

import pytest

from fkcheck.backends.registry import make_backend
from fkcheck.engine.runner import run_check
from fkcheck.engine.verdict import evidence_sentences
from fkcheck.model.lint import lint_model
from fkcheck.model.read import load_model
from tests.dh_urdf import UR5E, WHOLE_TURNS, dh_model, dh_urdf

SPLIT = (UR5E[0], (-0.375, 0.0, 0.0), (-0.4422, 0.0, 0.0), *UR5E[3:])  # a2 + 50 mm, a3 − 50 mm
FROZEN = {"[0, 0]": (0.0, 0.0), "±1e-7°": (-1e-7, 1e-7)}


def _limits(elbow: tuple[float, float]) -> tuple[tuple[float, float], ...]:
    return (WHOLE_TURNS, WHOLE_TURNS, elbow, WHOLE_TURNS, WHOLE_TURNS, WHOLE_TURNS)


@pytest.mark.parametrize("elbow", FROZEN.values(), ids=FROZEN.keys())
def test_a_split_behind_a_frozen_joint_is_not_identifiable(tmp_path, elbow):
    model = load_model(dh_model(tmp_path, dh_urdf(SPLIT), limits=_limits(elbow)))
    result = run_check(model, [make_backend("pinocchio-urdf")], samples=64, seed=0,
                       require=("table",))  # fmt: skip
    assert result.backends[0].status == "pass"  # within the limits the split agrees
    assert result.numbers is not None
    by_name = {n.name: n for n in result.numbers.table_numbers}
    for name in ("a2", "a3", "flip3"):
        assert by_name[name].status == "not-identifiable", name
        assert by_name[name].reason == "limits", name
    assert "the limits of joint 3" in by_name["a2"].absorbed_by
    assert "a3" in by_name["a2"].absorbed_by
    assert by_name["d2"].status == "verified"  # UR's parallel d2, d3, d4: whatever the limits
    table = evidence_sentences(result.evidence)[1]
    assert table.startswith("table PARTLY verified")
    assert "not identifiable (the joint limits keep any configuration" in table
    assert result.verdict == "unverified"  # --require table
    (finding,) = lint_model(model)
    assert (finding.rule, finding.field) == ("limits", "joint[2].limits")


def test_the_same_split_with_the_joint_free_fails(tmp_path):
    model = load_model(dh_model(tmp_path, dh_urdf(SPLIT)))
    result = run_check(model, [make_backend("pinocchio-urdf")], samples=64, seed=0)
    assert result.verdict == "fail"


def test_the_right_urdf_with_free_joints_stays_verified(tmp_path):
    model = load_model(dh_model(tmp_path, dh_urdf(UR5E)))
    result = run_check(model, [make_backend("pinocchio-urdf")], samples=64, seed=0,
                       require=("table",))  # fmt: skip
    assert result.verdict == "pass"
    assert result.numbers is not None
    assert result.numbers.complete
    assert lint_model(model) == []
