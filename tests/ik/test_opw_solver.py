"""The opw IK solver (fkcheck.ik.opw_solver): every solution right, none missing.

The poses come from the in-house table FK; the solver never sees q. Soundness: each
solution's table FK is the pose. Completeness: q itself (modulo 2π) is among the
solutions. On the bundled KUKA KR 6 R700 sixx, ABB IRB 2400 and PUMA 560, away from
the wrist singularity; at θ5 = 0 the library's own behaviour is pinned.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.errors import OptionError
from fkcheck.ik.opw_params import NotOpwShaped
from fkcheck.ik.opw_solver import APIS, OpwSolver, make_opw_solver
from fkcheck.model.read import load_model

pytest.importorskip("py_opw_kinematics")

ARMS = ["kr6r700sixx", "irb2400", "puma560"]
#: A solution reproduces the pose to this: the library's closed form in double
#: precision over a 1–2 m reach measured 4e-12 m and 6e-12 rad at worst in 20,000
#: random poses per arm; a wrong branch is off by centimetres or degrees.
SOUND_M = 1e-9
SOUND_RAD = 1e-9
#: At the wrist singularity (θ5 = 0) the library can return θ5 a little off 0: at the
#: KR 6's zero pose 2.1e-8 rad (the square-root error of a cosine at 1), and its
#: solutions there reproduce the pose to that.
SINGULAR_RAD = 1e-7
#: q is "among the solutions" when every joint is this close, modulo 2π.
SAME_Q_RAD = 1e-8
#: The library's FK and the table's: the same geometry in double precision.
FK_AGREEMENT = 1e-12


def _random_q(model, n, seed):
    rng = np.random.default_rng(seed)
    lo, hi = model.limits[:, 0], model.limits[:, 1]
    return lo + rng.random((n, model.dof)) * (hi - lo)


def _distance_mod_2pi(solutions, q):
    """Largest joint difference (mod 2π) of each solution from q, ``(k,)``."""
    diff = np.remainder(solutions - q + math.pi, 2 * math.pi) - math.pi
    return np.abs(diff).max(axis=1)


@pytest.mark.parametrize("api", APIS)
@pytest.mark.parametrize("name", ARMS)
def test_every_solution_is_right_and_the_configuration_is_among_them(name, api):
    model = load_model(name)
    solver = make_opw_solver(model, api)
    counts = []
    for q in _random_q(model, 300, seed=7):
        pose = model.fk(q)
        solutions = solver.solve(pose)
        assert solutions.ndim == 2
        assert solutions.shape[1] == 6
        counts.append(len(solutions))
        reached = model.fk(solutions)
        assert position_error_m(reached, pose[None]).max() < SOUND_M, q
        assert rotation_error_rad(reached, pose[None]).max() < SOUND_RAD, q
        assert _distance_mod_2pi(solutions, q).min() < SAME_Q_RAD, q
    assert max(counts) == 8  # both shoulders, elbows and wrists where the arm reaches


@pytest.mark.parametrize("name", ARMS)
def test_the_solvers_own_fk_is_the_tables(name):
    model = load_model(name)
    solver = make_opw_solver(model)
    for q in _random_q(model, 200, seed=3):
        np.testing.assert_allclose(solver.fk(q), model.fk(q), rtol=0.0, atol=FK_AGREEMENT)


def test_the_solver_speaks_the_models_frames_when_opws_are_elsewhere():
    from fkcheck.model.types import Offset

    model = replace(
        load_model("kr6r700sixx"),
        base=Offset((0.5, -0.3, 0.2), (0.2, 0.1, -0.4)),
        tool=Offset((0.02, 0.0, 0.11), (0.0, 0.5, 0.0)),
    )
    solver = make_opw_solver(model)
    assert not solver.params.base_is_world
    assert not solver.params.tool_is_tcp
    for q in _random_q(model, 50, seed=11):
        pose = model.fk(q)
        solutions = solver.solve(pose)
        assert position_error_m(model.fk(solutions), pose[None]).max() < SOUND_M
        assert _distance_mod_2pi(solutions, q).min() < SAME_Q_RAD
        np.testing.assert_allclose(solver.fk(q), pose, rtol=0.0, atol=FK_AGREEMENT)


@pytest.mark.parametrize(
    ("field", "index", "value"),
    [("sign_corrections", 3, 1), ("offsets", 1, 0.0), ("offsets", 5, 0.01)],
    ids=["sign-4", "offset-2", "offset-6"],
)
def test_a_wrong_mapping_is_caught_by_the_checks(field, index, value):
    """What would have to be wrong for the checks above to stay green: the mapping."""
    model = load_model("kr6r700sixx")
    right = make_opw_solver(model)
    values = list(getattr(right.params, field))
    values[index] = value
    params = replace(right.params, **{field: tuple(values)})
    from fkcheck.ik.opw_params import opw_robot

    wrong = OpwSolver(name="opw", params=params, robot=opw_robot(params))
    q = np.radians([20.0, -70.0, 60.0, 30.0, 40.0, 50.0])
    pose = model.fk(q)
    solutions = wrong.solve(pose)
    unsound = len(solutions) and position_error_m(model.fk(solutions), pose[None]).max() > SOUND_M
    rotated = (
        len(solutions) and rotation_error_rad(model.fk(solutions), pose[None]).max() > SOUND_RAD
    )
    assert unsound or rotated or _distance_mod_2pi(solutions, q).min() > SAME_Q_RAD


def test_an_unreachable_pose_has_no_solution():
    model = load_model("kr6r700sixx")
    pose = np.eye(4)
    pose[:3, 3] = (3.0, 0.0, 0.4)  # the arm reaches less than a metre
    assert make_opw_solver(model).solve(pose).shape == (0, 6)
    assert make_opw_solver(model, "reach").solve(pose).shape == (0, 6)


@pytest.mark.parametrize("name", ARMS)
def test_near_the_wrist_singularity_nothing_is_missed(name):
    model = load_model(name)
    solver = make_opw_solver(model)
    for q in _random_q(model, 100, seed=5):
        q[4] = 1e-3  # 0.06° from θ5 = 0
        pose = model.fk(q)
        solutions = solver.solve(pose)
        assert _distance_mod_2pi(solutions, q).min() < SAME_Q_RAD
        assert position_error_m(model.fk(solutions), pose[None]).max() < SOUND_M


def test_at_the_wrist_singularity_inverse_leaves_out_the_configurations_branch():
    """py-opw-kinematics 1.3.0's inverse() at θ5 = 0 exactly: q's arm branch is missing.

    Pinned as the library's behaviour, which ``fkcheck ik`` is there to find; every
    solution it does return is still right. reach() returns that branch (θ4 = 0,
    θ6 = θ4 + θ6) here.
    """
    model = load_model("kr6r700sixx")
    q = np.radians([36.256, -18.568, 30.04, 160.977, 0.0, -348.083])
    pose = model.fk(q)
    arm = [0, 1, 2, 4]  # the joints that choose the branch; θ4 and θ6 share one angle
    for api, has_branch in (("inverse", False), ("reach", True)):
        solutions = make_opw_solver(model, api).solve(pose)
        assert len(solutions) > 0
        assert rotation_error_rad(model.fk(solutions), pose[None]).max() < SINGULAR_RAD
        assert position_error_m(model.fk(solutions), pose[None]).max() < SOUND_M
        found = _distance_mod_2pi(solutions[:, arm], q[arm]).min() < 1e-6
        assert found == has_branch, api


def test_the_solver_is_named_and_refuses_what_it_cannot_solve():
    model = load_model("kr6r700sixx")
    assert make_opw_solver(model).name == "opw"
    assert make_opw_solver(model, "reach").name == "opw-reach"
    with pytest.raises(OptionError, match=r"api: must be one of inverse, reach, got 'fast'"):
        make_opw_solver(model, "fast")  # type: ignore[arg-type]
    with pytest.raises(NotOpwShaped, match=r"model ur5e: not OPW-shaped: axes 4, 5, 6"):
        make_opw_solver(load_model("ur5e"))
