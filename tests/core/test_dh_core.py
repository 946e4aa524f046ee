"""The in-house DH core against hand computations, properties and its plain reference chain."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fkcheck import JointInputError, load_model
from fkcheck.core.dh import dh_matrix, fk_reference
from fkcheck.core.geometry import invert, matrix_from_xyz_rpy
from fkcheck.core.tolerances import SAME_CHAIN, SIX_DECIMALS
from fkcheck.model.read import model_from_dict
from tests import seed_ur5
from tests.helpers import BUNDLED, assert_pose_close, assert_se3, random_q

Q_ARTICLE = np.deg2rad(seed_ur5.Q_DEG)


@pytest.fixture(scope="module")
def ur5():
    return load_model("ur5")


@pytest.mark.parametrize("i", range(6))
def test_seed_link_matrices_A1_to_A6(ur5, i):
    j = ur5.joints[i]
    A = dh_matrix("standard", j.a, j.alpha, j.d, Q_ARTICLE[i] + j.theta)
    assert_pose_close(A, seed_ur5.A[i], SIX_DECIMALS, f"A{i + 1}")
    # The core's own frames give the same link transform: A_i = (T_0_{i-1})⁻¹ T_0_i.
    frames = ur5.fk(Q_ARTICLE, all_frames=True)
    assert_pose_close(invert(frames[i]) @ frames[i + 1], seed_ur5.A[i], SIX_DECIMALS, f"A{i + 1}")


@pytest.mark.parametrize("k", [2, 3, 4, 5, 6])
def test_seed_partial_products_T0_2_to_T0_6(ur5, k):
    frames = ur5.fk(Q_ARTICLE, all_frames=True)
    assert_pose_close(frames[k], seed_ur5.T0[k], SIX_DECIMALS, f"T0_{k}")


def test_seed_tcp_pose(ur5):
    T = ur5.fk(Q_ARTICLE)
    assert_pose_close(T, seed_ur5.T0[6], SIX_DECIMALS, "T0_6")
    np.testing.assert_allclose(T[:3, 3], [-0.505612, -0.417951, 0.178795], atol=SIX_DECIMALS)


def test_named_pose_worked_example_is_the_seed_configuration(ur5):
    np.testing.assert_allclose(ur5.poses["worked_example"], Q_ARTICLE, rtol=0, atol=1e-15)


def test_ur5_zero_pose_derived_by_hand(ur5):
    # q = 0: A1 = Tz(d1)Rx(90°), A2 = Tx(a2), A3 = Tx(a3), A4 = Tz(d4)Rx(90°),
    # A5 = Tz(d5)Rx(-90°), A6 = Tz(d6)  =>  p = (a2+a3, -(d4+d6), d1-d5).
    expected = np.array(
        [[1.0, 0, 0, -0.425 - 0.39225],
         [0, 0, -1.0, -(0.10915 + 0.0823)],
         [0, 1.0, 0, 0.089159 - 0.09465],
         [0, 0, 0, 1.0]]
    )  # fmt: skip
    assert_pose_close(ur5.fk(np.zeros(6)), expected, SAME_CHAIN, "zero pose")


@pytest.mark.parametrize(("q_deg", "xy"), [((30, 60), (0.866025, 1.3)), ((0, 0), (1.8, 0.0)),
                                           ((90, -90), (0.8, 1.0))])  # fmt: skip
def test_planar2_matches_closed_form_of_seed_002(q_deg, xy):
    model = load_model("planar2")
    T = model.fk(np.deg2rad(q_deg))
    t1, t2 = np.deg2rad(q_deg)
    closed = (
        1.0 * math.cos(t1) + 0.8 * math.cos(t1 + t2),
        1.0 * math.sin(t1) + 0.8 * math.sin(t1 + t2),
    )
    np.testing.assert_allclose(T[:2, 3], closed, atol=SAME_CHAIN)
    np.testing.assert_allclose(T[:2, 3], xy, atol=SIX_DECIMALS)
    assert T[2, 3] == 0.0
    # The end-effector heading is θ1 + θ2.
    heading = math.atan2(T[1, 0], T[0, 0])
    expected = math.atan2(math.sin(t1 + t2), math.cos(t1 + t2))
    assert math.isclose(heading, expected, abs_tol=SAME_CHAIN)


@pytest.mark.parametrize("name", BUNDLED)
def test_every_bundled_model_gives_valid_se3_and_matches_reference_chain(name, rng):
    model = load_model(name)
    q = random_q(model, rng, 500)
    T = model.fk(q)
    assert T.shape == (500, 4, 4)
    assert_se3(T, SAME_CHAIN)
    assert_pose_close(T, fk_reference(model.chain, q), SAME_CHAIN, name)
    frames = model.fk(q, all_frames=True)
    assert frames.shape == (500, model.dof + 1, 4, 4)
    assert_se3(frames, SAME_CHAIN)
    assert_pose_close(frames, fk_reference(model.chain, q, all_frames=True), SAME_CHAIN, name)


def test_shapes_single_batch_empty(ur5):
    assert ur5.fk(np.zeros(6)).shape == (4, 4)
    assert ur5.fk(np.zeros((1, 6))).shape == (1, 4, 4)
    assert ur5.fk(np.zeros((0, 6))).shape == (0, 4, 4)
    assert ur5.fk(np.zeros(6), all_frames=True).shape == (7, 4, 4)
    assert ur5.fk([0.0] * 6).shape == (4, 4)  # lists are fine


def test_batch_equals_one_by_one(ur5, rng):
    q = random_q(ur5, rng, 20)
    batch = ur5.fk(q)
    for qi, Ti in zip(q, batch, strict=True):
        np.testing.assert_array_equal(ur5.fk(qi), Ti)


def _table(convention, rows, **extra):
    return model_from_dict({"name": "t", "convention": convention,
                            "joint": [dict(zip(("a", "alpha", "d"), r, strict=True)) | {}
                                      for r in rows], **extra})  # fmt: skip


def test_standard_and_modified_on_the_same_numbers_differ(rng):
    rows = [(0.1, math.pi / 2, 0.3), (0.4, 0.0, 0.0), (0.2, -math.pi / 2, 0.1)]
    std, mod = _table("standard", rows), _table("modified", rows)
    q = rng.uniform(-math.pi, math.pi, (100, 3))
    diff = np.linalg.norm(std.fk(q)[:, :3, 3] - mod.fk(q)[:, :3, 3], axis=-1)
    assert diff.min() > 1e-3


def test_modified_single_link_is_craig_matrix():
    # Craig (3.6): Rx(α)Tx(a)Rz(θ)Tz(d), written out entry by entry.
    a, alpha, d, theta = 0.3, 0.7, 0.2, -1.1
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    craig = np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d],
                      [st * sa, ct * sa, ca, ca * d], [0, 0, 0, 1]])  # fmt: skip
    model = _table("modified", [(a, alpha, d)])
    assert_pose_close(model.fk([theta]), craig, SAME_CHAIN)


def test_prismatic_joint_moves_tcp_along_its_z_axis(rng):
    stanford = load_model("stanford")
    q = random_q(stanford, rng, 50)
    step = 0.05
    q2 = q.copy()
    q2[:, 2] += step
    z_axis = stanford.fk(q, all_frames=True)[:, 2, :3, 2]  # joint 3 slides along z of frame 2
    moved = stanford.fk(q2)[:, :3, 3] - stanford.fk(q)[:, :3, 3]
    np.testing.assert_allclose(moved, step * z_axis, atol=SAME_CHAIN)
    # Orientation does not change when a prismatic joint moves.
    np.testing.assert_allclose(
        stanford.fk(q2)[:, :3, :3], stanford.fk(q)[:, :3, :3], atol=SAME_CHAIN
    )


def test_flipped_joint_is_the_negated_variable(rng):
    rows = [(0.1, math.pi / 2, 0.3), (0.4, 0.0, 0.0), (0.0, -math.pi / 2, 0.1)]
    plain = _table("standard", rows)
    flipped = model_from_dict({"name": "f", "convention": "standard", "joint": [
        {"a": 0.1, "alpha": math.pi / 2, "d": 0.3},
        {"a": 0.4, "alpha": 0.0, "d": 0.0, "flip": True},
        {"a": 0.0, "alpha": -math.pi / 2, "d": 0.1, "type": "prismatic", "flip": True},
    ]})  # fmt: skip
    plain_prismatic = model_from_dict({"name": "p", "convention": "standard", "joint": [
        {"a": 0.1, "alpha": math.pi / 2, "d": 0.3},
        {"a": 0.4, "alpha": 0.0, "d": 0.0},
        {"a": 0.0, "alpha": -math.pi / 2, "d": 0.1, "type": "prismatic"},
    ]})  # fmt: skip
    q = rng.uniform(-1, 1, (30, 3))
    assert_pose_close(flipped.fk(q), plain_prismatic.fk(q * [1, -1, -1]), SAME_CHAIN)
    assert not np.allclose(flipped.fk(q), plain.fk(q))


def test_theta_offset_adds_to_q(rng):
    with_offset = model_from_dict({"name": "o", "convention": "standard", "joint": [
        {"a": 0.3, "alpha": 0.5, "d": 0.1, "theta": -math.pi / 2},
        {"a": 0.2, "alpha": 0.0, "d": 0.0, "theta": 0.25}]})  # fmt: skip
    without = _table("standard", [(0.3, 0.5, 0.1), (0.2, 0.0, 0.0)])
    q = rng.uniform(-2, 2, (30, 2))
    assert_pose_close(with_offset.fk(q), without.fk(q + np.array([-math.pi / 2, 0.25])), SAME_CHAIN)


def test_base_and_tool_transforms_wrap_the_chain(rng):
    rows = [(0.1, math.pi / 2, 0.3), (0.4, 0.0, 0.0), (0.2, -math.pi / 2, 0.1)]
    base = {"xyz": [0.5, -0.2, 1.0], "rpy": [0.1, -0.3, 2.0]}
    tool = {"xyz": [0.0, 0.02, 0.12], "rpy": [math.pi, 0.0, 0.4]}
    plain = _table("standard", rows)
    wrapped = _table("standard", rows, base=base, tool=tool)
    B = matrix_from_xyz_rpy(base["xyz"], base["rpy"])
    T = matrix_from_xyz_rpy(tool["xyz"], tool["rpy"])
    q = rng.uniform(-math.pi, math.pi, (50, 3))
    assert_pose_close(wrapped.fk(q), B @ plain.fk(q) @ T, SAME_CHAIN)
    frames = wrapped.fk(q, all_frames=True)
    assert_pose_close(frames[:, 0], np.broadcast_to(B, (50, 4, 4)), SAME_CHAIN)  # base included
    assert_pose_close(frames[:, -1], B @ plain.fk(q), SAME_CHAIN)  # tool not included


def test_rpy_is_urdf_fixed_axis_order():
    # URDF: R = Rz(yaw) Ry(pitch) Rx(roll). A pure yaw of 90° maps x to y.
    R = matrix_from_xyz_rpy([0, 0, 0], [0, 0, math.pi / 2])[:3, :3]
    np.testing.assert_allclose(R @ [1, 0, 0], [0, 1, 0], atol=1e-16)
    # roll then pitch (fixed axes): x-axis rotation is applied first.
    r, p = 0.3, 0.5
    Rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    Ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    np.testing.assert_allclose(
        matrix_from_xyz_rpy([0, 0, 0], [r, p, 0])[:3, :3], Ry @ Rx, atol=1e-15
    )


@pytest.mark.parametrize(
    ("q", "match"),
    [
        (np.zeros(5), r"expected 6 joint values"),
        (np.zeros((3, 7)), r"expected 6 joint values"),
        (np.zeros((2, 3, 6)), r"expected 6 joint values"),
        ([0, 0, float("nan"), 0, 0, 0], r"finite.*joint 3 is nan"),
        ([0, 0, 0, 0, float("inf"), 0], r"finite.*joint 5 is inf"),
        (["a", 0, 0, 0, 0, 0], r"not numbers"),
    ],
)
def test_bad_joint_values_raise_value_error(ur5, q, match):
    with pytest.raises(JointInputError, match=match):
        ur5.fk(q)
    with pytest.raises(ValueError, match=match):  # JointInputError is a ValueError
        ur5.fk(q)
