"""The check's plan: which configurations a slow backend compares, decided by counts alone."""

from __future__ import annotations

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends.base import BackendDefaults
from fkcheck.core.dh import fk_reference
from fkcheck.core.geometry import translation
from fkcheck.engine.plan import BUDGET_SHARE, count_text, plan_check
from fkcheck.engine.runner import run_check
from fkcheck.model.frames import frame_poses_from_dh
from fkcheck.model.options import CheckOptions, resolve_options
from fkcheck.report.json_report import TIME_FIELDS, result_to_dict
from fkcheck.report.record import check_record

STRUCTURED = 81  # ur5: zero, mid, 64 corners, 12 edges, 3 named poses


class Costed(BackendDefaults):
    """A second implementation of the table that declares a cost (µs per configuration)."""

    method = "fk_reference"
    evidence = "implementation"
    reads = "dh"

    def __init__(self, name: str, cost_us: float | None, *, isolated: bool = False) -> None:
        self.name = name
        self.pose_cost_us = cost_us
        self.isolated = isolated

    def unavailable_reason(self, model):
        return None

    def frame_poses(self, model, q, frames):
        return frame_poses_from_dh(
            model,
            fk_reference(model.chain, q, all_frames=True),
            fk_reference(model.chain, q),
            frames,
        )


class WrongAtCorners(Costed):
    """Off by 1 mm at the joint-limit corners only (every joint at a limit)."""

    def frame_poses(self, model, q, frames):
        poses = super().frame_poses(model, q, frames)
        lo, hi = model.limits[:, 0], model.limits[:, 1]
        corner = np.all(np.isclose(q, lo) | np.isclose(q, hi), axis=1)
        poses[1, corner] = poses[1, corner] @ translation(1e-3, 0.0, 0.0)
        return poses


def _origin(random: int) -> tuple[str, ...]:
    return ("zero", "mid", *("corner",) * 64, *("edge",) * 12, *("pose:p",) * 3) + (
        "random",
    ) * random


def test_cheap_backends_compare_everything() -> None:
    plan = plan_check([Costed("a", 10.0), Costed("b", 20.0)], _origin(10_000), dof=6,
                      timeout_s=120.0)  # fmt: skip
    assert [b.compared for b in plan.backends] == [10_081, 10_081]
    assert not any(b.subset for b in plan.backends)
    assert plan.notes() == ()


def test_a_slow_isolated_backend_gets_all_structured_and_a_prefix_of_the_random() -> None:
    slow = Costed("slow", 630.0, isolated=True)
    plan = plan_check([Costed("fast", 10.0), slow], _origin(1_000_000), dof=6, timeout_s=120.0)
    fast, mine = plan.backends
    assert fast.compared == 1_000_081
    # 60 s of 630 µs: 95 238 configurations, the random part rounded down to a thousand
    assert mine.compared == STRUCTURED + 95_000
    assert mine.structured == STRUCTURED
    assert mine.total == 1_000_081
    (note,) = plan.notes()
    assert note.startswith("slow compares 95 081 of 1 000 081 configurations (all 81 structured")
    assert "--full" in note
    assert "--timeout 1320" in note


def test_backends_in_the_engines_process_share_one_budget() -> None:
    pool = [Costed("a", 10.0), Costed("b", 45.0), Costed("c", 15.0)]
    plan = plan_check(pool, _origin(1_000_000), dof=6, timeout_s=120.0)
    # 60 s in all: a's 10 s and c's 15 s in full, the 35 s left for b (777 777 of them)
    assert [b.compared for b in plan.backends] == [1_000_081, STRUCTURED + 777_000, 1_000_081]
    assert "share one interpreter" in plan.notes()[0]


def test_the_plan_depends_on_its_inputs_only() -> None:
    backends = [Costed("a", 45.0), Costed("slow", 630.0, isolated=True), Costed("x", None)]
    first = plan_check(backends, _origin(300_000), dof=6, timeout_s=30.0, jacobian=False)
    again = plan_check(backends, _origin(300_000), dof=6, timeout_s=30.0, jacobian=False)
    assert first == again
    assert first.backends[2].compared == 300_081  # no declared cost: the full set
    longer = plan_check(backends, _origin(300_000), dof=6, timeout_s=1000.0)
    assert longer.backends[1].compared > first.backends[1].compared
    every = plan_check(backends, _origin(300_000), dof=6, timeout_s=30.0, full=True)
    assert all(b.compared == 300_081 for b in every.backends)


def test_a_jacobian_by_central_differences_costs_2n_plus_1_poses() -> None:
    slow = Costed("slow", 100.0, isolated=True)
    plain = plan_check([slow], _origin(100_000), dof=6, timeout_s=120.0)
    with_jacobian = plan_check([slow], _origin(100_000), dof=6, timeout_s=120.0, jacobian=True)
    assert plain.backends[0].compared == 100_081
    fits = int(BUDGET_SHARE * 120.0 * 1e6 / (100.0 * 13))  # 46 153 configurations in 60 s
    assert with_jacobian.backends[0].compared == STRUCTURED + (fits - STRUCTURED) // 1000 * 1000


def test_a_tiny_budget_still_compares_every_structured_configuration() -> None:
    plan = plan_check([Costed("slow", 630.0, isolated=True)], _origin(10_000), dof=6,
                      timeout_s=0.01)  # fmt: skip
    assert plan.backends[0].compared == STRUCTURED


def test_count_text() -> None:
    assert count_text(1_000_081) == "1 000 081"
    assert count_text(81) == "81"


def _check(backends, samples: int, timeout_s: float, **kw):
    model = load_model("ur5")
    return run_check(model, backends, samples=samples, timeout_s=timeout_s, **kw)


def test_a_subset_is_stated_in_the_record_json_headline_and_evidence() -> None:
    # 630 µs a configuration in the 0.598 s that fast leaves of 0.6 s: 949, 81 of them structured
    slow = Costed("slow", 630.0, isolated=False)
    check = _check([slow, Costed("fast", 1.0)], 2_000, 1.2)
    result = {b.name: b for b in check.backends}
    assert result["slow"].subset == (949, 2_081)
    assert result["slow"].position_error_m is not None
    assert result["slow"].position_error_m.shape == (949,)
    assert result["fast"].subset is None
    assert result["fast"].position_error_m.shape == (2_081,)
    record = check_record(check)
    slow_record = next(b for b in record.backends if b.name == "slow")
    assert slow_record.configurations == 949
    assert slow_record.subset == "949 of 2 081 configurations"
    assert "a subset: 949 of 2 081 configurations" in slow_record.summary
    assert "slow (949 of 2 081 configurations)" in record.evidence[0].sentence
    assert record.headline.endswith("on a subset: slow 949 of 2 081 configurations")
    doc = result_to_dict(check)
    backend = next(b for b in doc["backends"] if b["name"] == "slow")
    assert backend["configurations"] == 949
    assert backend["subset"] == "949 of 2 081 configurations"
    assert doc["configurations"] == 2_081


def test_the_same_check_gives_the_same_subset_and_json() -> None:
    def document() -> dict:
        check = _check([Costed("slow", 630.0)], 2_000, 1.2)
        doc = result_to_dict(check)
        for key in TIME_FIELDS:
            doc.pop(key)
        for backend in doc["backends"]:
            backend.pop("duration_s")
        return doc

    assert document() == document()


def test_a_failure_at_a_structured_configuration_is_caught_on_a_subset() -> None:
    wrong = WrongAtCorners("wrong", 630.0, isolated=False)
    check = _check([wrong], 20_000, 1.2)
    (result,) = check.backends
    assert result.subset is not None
    assert result.subset[0] < result.subset[1]
    assert result.status == "fail"
    assert check.verdict == "fail"
    assert check.origin[result.worst_index] == "corner"


def test_full_compares_every_configuration() -> None:
    check = _check([Costed("slow", 630.0)], 2_000, 1.2, full=True)
    assert check.backends[0].subset is None
    assert check.backends[0].position_error_m.shape == (2_081,)


@pytest.mark.parametrize("given", [True, False])
def test_full_is_an_option_of_the_one_options_object(given: bool) -> None:
    options = resolve_options({"full": given}, labels={"full": "--full"})  # type: ignore[dict-item]
    assert options.full is given
    assert CheckOptions().full is False
    with pytest.raises(ValueError, match="must be true or false"):
        CheckOptions(full="yes")  # type: ignore[arg-type]
