"""A subset compared, all numbers claimed (issue 30, item 2).

A table backend over its budget compares the structured configurations first
(:mod:`fkcheck.engine.plan`). On an arm whose limits are ±2π those are all
``q ≡ 0 (mod 2π)``: one pose, which cannot tell a joint's direction nor a
split of a2/a3. The numbers' evidence must come from what the table's evidence
answered, not from every configuration of the check.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from fkcheck.backends.registry import make_backend
from fkcheck.engine.runner import run_check
from fkcheck.engine.verdict import headline
from fkcheck.model.read import load_model
from tests.dh_urdf import UR5E, dh_model, dh_urdf

#: A cost no budget fits: the plan gives the backend its structured configurations only.
PRICELESS_US = 1e9


def _wrong(kind: str) -> str:
    rows = list(UR5E)
    axes = [1] * 6
    if kind == "joint 2 reversed":
        axes[1] = -1
    else:  # a2/a3 split 50 mm differently, the same sum
        rows[1], rows[2] = (-0.375, 0.0, 0.0), (-0.4422, 0.0, 0.0)
    return dh_urdf(rows, axes)


def _check(model: Path, *, subset: bool, names: tuple[str, ...] = ("pinocchio-urdf",)):
    backends = [make_backend(n) for n in names]
    if subset:
        backends[0].pose_cost_us = PRICELESS_US  # type: ignore[misc]
    return run_check(load_model(model), backends, samples=200, seed=0, require=("table",))


WRONG = ["joint 2 reversed", "a2/a3 split"]


@pytest.mark.parametrize("kind", WRONG)
def test_the_wrong_urdf_fails_on_every_configuration(tmp_path, kind):
    """The URDFs below are wrong: compared on all the check's configurations, they fail."""
    result = _check(dh_model(tmp_path, _wrong(kind)), subset=False)
    assert result.verdict == "fail"


@pytest.mark.parametrize("kind", WRONG)
def test_a_subset_at_one_pose_verifies_no_number(tmp_path, kind):
    result = _check(dh_model(tmp_path, _wrong(kind)), subset=True)
    (only,) = result.backends
    assert only.status == "pass"
    assert only.subset == (78, 278)  # zero, mid, 64 corners, 12 edges: all q ≡ 0 mod 2π
    assert result.numbers is not None
    by_name = {n.name: n for n in result.numbers.table_numbers}
    # What the wrong URDF hides is not verified, and says why.
    for name in ("flip2", "a2", "a3"):
        assert by_name[name].status == "not-identifiable", name
    assert by_name["flip2"].reason == "direction"
    assert by_name["a2"].reason == "configurations"
    assert "78 configurations" in by_name["a2"].absorbed_by
    line = headline(result.verdict, result.evidence, len(result.ran))
    assert "table verified" not in line
    assert result.verdict == "unverified"  # --require table: not a pass
    assert result.evidence.table.status == "partly-verified"


def test_the_numbers_come_from_the_backend_that_compared_most(tmp_path):
    """Two table backends, one on a subset: the full one's configurations verify the table."""
    right = dh_urdf(UR5E)
    result = _check(dh_model(tmp_path, right), subset=True,
                    names=("pinocchio-urdf", "rtb-urdf"))  # fmt: skip
    assert [b.subset for b in result.backends] == [(78, 278), None]
    assert result.verdict == "pass"
    assert result.numbers is not None
    assert result.numbers.complete
    assert headline(result.verdict, result.evidence, 2).startswith(
        "pass — table verified independently"
    )


def test_the_right_urdf_on_a_subset_with_random_samples_is_verified(tmp_path):
    """A subset whose random prefix moves every joint verifies every number."""
    model = dh_model(tmp_path, dh_urdf(UR5E))
    backend = make_backend("pinocchio-urdf")
    # 60 s of budget at 0.5 s a configuration: the 78 structured ones and 42 random samples.
    backend.pose_cost_us = 5e5  # type: ignore[misc]
    result = run_check(load_model(model), [backend], samples=200, seed=0, require=("table",))
    assert result.backends[0].subset == (120, 278)
    assert result.verdict == "pass"
    assert result.numbers is not None
    assert result.numbers.complete
