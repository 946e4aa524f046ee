"""The IK check against seeded wrong solvers: each fails with the right count and branch named.

The solvers are :mod:`tests.ik.ur_ik`'s closed-form UR IK (its own DH maths, not
fkcheck's); the expected counts come from the solvers' own outputs and the
configurations' joint values, not from the check.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from fkcheck.ik import check_ik, make_solver
from fkcheck.ik.branches import branch_names, branch_values
from fkcheck.ik.check import SAME_CONFIGURATION_RAD
from fkcheck.ik.poses import ik_configurations
from fkcheck.model.read import load_model
from tests.ik import ur_ik

SAMPLES = 300
SEED = 7


class _Solver:
    name = "test-ur"
    method = "tests.ik.ur_ik"

    def __init__(self, params: dict[str, float] = ur_ik.UR5E, **mistakes: object) -> None:
        self.params = params
        self.mistakes = mistakes
        self.answers: list[np.ndarray] = []

    def solve(self, pose: np.ndarray) -> np.ndarray:
        answer = ur_ik.solve_with(self.params, pose, **self.mistakes)  # type: ignore[arg-type]
        self.answers.append(answer)
        return answer

    def fk(self, q: np.ndarray) -> np.ndarray:
        return ur_ik.fk_with(self.params, q)


@pytest.fixture(scope="module")
def ur5e():
    return load_model("ur5e")


def _check(model, solver):
    return check_ik(model, solver, frame_from="base", frame_to="tool0", samples=SAMPLES, seed=SEED)


def _singular(q: np.ndarray, origin: str) -> bool:
    """The UR's singular configurations, from joint values: θ3 or θ5 a multiple of π, or
    the shoulder's (built as such)."""
    return abs(math.sin(q[2])) < 1e-9 or abs(math.sin(q[4])) < 1e-9 or origin == "shoulder-singular"


def test_honest_solver_passes(ur5e):
    result = _check(ur5e, _Solver())
    assert result.verdict == "pass"
    assert (result.wrong_solutions, result.missed, result.garbage) == (0, 0, 0)
    assert result.own_fk
    assert result.own_fk_disagreements == 0
    assert result.counts[8] > SAMPLES // 2  # most poses have all eight branches


def test_eight_solutions_are_eight_branches(ur5e):
    q = np.radians([10.0, -60.0, 80.0, -20.0, 30.0, 40.0])
    sols = ur_ik.solve(ur5e.fk(q, frame_from="base", frame_to="tool0"))
    names = branch_names(branch_values(ur5e, sols))
    assert len(sols) == 8
    assert len(set(names)) == 8


def test_flipped_sign_in_one_branch_is_counted_and_named(ur5e):
    solver = _Solver(flip_wrist_theta6=True)
    result = _check(ur5e, solver)
    # Expected from the answers alone: θ6 → −θ6 turns tool0 by 2θ6 about its z.
    expected = sum(
        int(((a[:, 4] < 0) & (np.abs(np.angle(np.exp(2j * a[:, 5]))) > 1e-6)).sum())
        for a in solver.answers
    )
    assert result.verdict == "fail"
    assert result.wrong_solutions == expected > 0
    assert all(b.endswith("wrist flip") for b in result.wrong_by_branch)
    assert result.missed > 0
    assert all(b.endswith("wrist flip") for b in result.missed_by_branch)
    assert any("inversion is wrong" in line for line in result.explanation)


def test_dropped_elbow_down_branch_is_missed_and_named(ur5e):
    result = _check(ur5e, _Solver(drop_elbow_down=True))
    configs = ik_configurations(ur5e, SAMPLES, SEED)
    expected = sum(
        ur_ik.elbow_down(ur_ik.UR5E, q[1], q[2]) and not _singular(q, origin)
        for q, origin in zip(configs.q, configs.origin, strict=True)
    )
    assert result.wrong_solutions == 0
    assert result.missed == expected > 0
    assert set(result.missed_by_branch) <= {
        f"shoulder {s}, elbow down, wrist {w}"
        for s in ("left", "right")
        for w in ("flip", "no-flip")
    }


def test_solver_for_d4_off_by_a_tenth_of_a_millimetre_fails_on_its_forward_model(ur5e):
    params = {**ur_ik.UR5E, "d4": ur_ik.UR5E["d4"] + 1e-4}
    solver = _Solver(params)
    result = _check(ur5e, solver)
    assert result.wrong_solutions == sum(len(a) for a in solver.answers) > 0
    assert result.own_fk_disagreements == result.poses
    assert any("forward model disagrees with the table" in line for line in result.explanation)
    wrong = next(c for c in result.worst if c.kind == "wrong")
    assert wrong.position_error_m == pytest.approx(1e-4, rel=0.05)


def test_nothing_near_the_wrist_singularity_is_missed(ur5e):
    threshold = 1e-2
    result = _check(ur5e, _Solver(none_near_wrist=threshold))
    configs = ik_configurations(ur5e, SAMPLES, SEED)
    expected = sum(
        abs(math.sin(q[4])) < threshold and not _singular(q, origin)
        for q, origin in zip(configs.q, configs.origin, strict=True)
    )
    assert result.wrong_solutions == 0
    assert result.missed == expected > 0
    origins = {c.origin for c in result.worst if c.kind == "missed"}
    assert origins <= {"near-wrist", "random"}


def test_nan_is_garbage_even_at_a_singular_pose(ur5e):
    class Nan(_Solver):
        def solve(self, pose):
            answer = super().solve(pose)
            return np.full((1, 6), np.nan) if len(answer) == 0 else answer

    solver = Nan()
    result = _check(ur5e, solver)
    # Every pose the honest solver has no answer for (the singular home pose among them).
    assert result.garbage == sum(len(a) == 0 for a in solver.answers) > 0
    assert result.verdict == "fail"
    assert any("NaN or inf" in line for line in result.explanation)


def test_ur_analytic_ik_on_ur5e_and_its_issue_5(ur5e):
    pytest.importorskip("ur_analytic_ik")
    solver = make_solver("ur-analytic-ik", ur5e, "base", "tool0")
    issue5 = tuple(math.radians(v) for v in (0, -45, -90, -90, 90, 0))
    model = dataclasses.replace(ur5e, poses={**ur5e.poses, "issue5": issue5})
    result = check_ik(
        model, solver, frame_from="base", frame_to="tool0", samples=SAMPLES, seed=SEED
    )
    # Sound everywhere, its FK is the table's; it misses the shoulder-right branch at
    # [0, -45, -90, -90, 90, 0]° (it filters those four solutions as incorrect), and
    # nothing else but beside the elbow singularity, θ3 = 0 or π, at 1e-6 rad (it
    # rounds 1 - cos²θ3 below 1e-12 to zero there).
    assert result.wrong_solutions == 0
    assert result.own_fk_disagreements == 0
    missed = [c for c in result.worst if c.kind == "missed"]
    assert result.missed == len(missed) < 10
    issue5 = [c for c in missed if c.origin == "pose:issue5"]
    assert len(issue5) == 1
    assert issue5[0].branch == "shoulder right, elbow down, wrist no-flip"
    assert all(b.startswith("shoulder left") for b in issue5[0].returned_branches)
    for case in missed:
        if case is not issue5[0]:
            assert case.origin == "near-elbow"
            assert abs(math.sin(case.q[2])) == pytest.approx(1e-6, rel=1e-6)
    assert result.messages  # the library's "filtered incorrect IK solution" lines, counted


def test_same_configuration_tolerance_is_modulo_two_pi(ur5e):
    class Shifted(_Solver):
        def solve(self, pose):
            return super().solve(pose) + 2 * math.pi

    result = _check(ur5e, Shifted())
    assert (result.missed, result.wrong_solutions) == (0, 0)
    assert SAME_CONFIGURATION_RAD < 1e-3


def test_a_redundant_arm_is_checked_for_soundness_not_completeness():
    panda = load_model("panda")

    class Home:
        """Answers every pose with panda's zero configuration."""

        name = "home-only"

        def solve(self, pose):
            return np.zeros((1, 7))

    result = check_ik(panda, Home(), frame_from=panda.check.frame_from,
                      frame_to=panda.check.frame_to, samples=20, seed=0)  # fmt: skip
    assert not result.completeness_checked
    assert result.missed == 0
    # No configuration checked is panda's zero (joint 4's limits exclude it): all wrong.
    assert not (ik_configurations(panda, 20, 0).q == 0).all(axis=1).any()
    assert result.wrong_solutions == result.poses
    assert result.verdict == "fail"
