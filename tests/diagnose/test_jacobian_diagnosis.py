"""Jacobian diagnosis: seeded convention mistakes, built from the real references, are named."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, event, given, settings
from hypothesis import strategies as st

import fkcheck.backends.registry as registry
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.diagnose.jacobian import (
    REFERENCE_NAMES,
    JacobianMistake,
    column_errors,
    diagnose_jacobian,
)
from fkcheck.model.frames import reference_poses
from fkcheck.model.read import load_model
from fkcheck.model.types import Offset
from tests.helpers import random_q
from tests.strategies import dh_models

#: Standard revolute, modified with a real tool, standard with a prismatic joint, classic.
MODELS = ("ur5", "panda", "stanford", "puma560")
#: Every ordered pair (expected, observed) of different reference frames.
PAIRS = [(a, b) for a in JACOBIAN_REFERENCES for b in JACOBIAN_REFERENCES if a != b]
#: Two float64 implementations of the same chain: the references agree with the core to this.
TOL = SAME_CHAIN


@pytest.fixture(scope="module")
def pin():
    return registry.make_backend("pinocchio-dh")


def case(name, reference="world-aligned", seed=3, n=6, frame="tcp"):
    """``(model, q, expected, from_T_to)``: the core's Jacobian and the frame's pose."""
    model = load_model(name)
    q = random_q(model, np.random.default_rng(seed), n)
    pose = reference_poses(model, q, [frame])[0]
    return model, q, model.jacobian(q, frame, reference), pose


def run(model, expected, observed, pose, reference="world-aligned", tol=TOL):
    return diagnose_jacobian(
        expected,
        observed,
        from_T_to=pose,
        reference=reference,
        prismatic=model.chain.prismatic,
        tolerance=tol,
        joint_names=[j.name for j in model.joints],
    )


def angular_first(jac):
    return np.concatenate([jac[:, 3:], jac[:, :3]], axis=1)


# (a) the reference frame swapped -------------------------------------------------------


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize(("expected_ref", "observed_ref"), PAIRS)
def test_a_real_reference_in_another_frame_is_named(pin, name, expected_ref, observed_ref):
    model, q, expected, pose = case(name, expected_ref)
    observed = pin.frame_jacobian(model, q, "tcp", observed_ref)
    d = run(model, expected, observed, pose, expected_ref)
    assert not d.agrees
    assert d.best is not None
    assert d.best.kinds == ("reference",)
    assert d.best.mistake.reference == observed_ref
    assert d.best.residual.within(TOL, TOL)
    assert d.headline == (
        f"the backend's Jacobian is {REFERENCE_NAMES[observed_ref]} where "
        f"{REFERENCE_NAMES[expected_ref]} was expected"
    )


@pytest.mark.parametrize("backend_name", ["pinocchio-dh", "rtb-dh"])
@pytest.mark.parametrize("name", MODELS)
def test_an_end_effector_frame_jacobian_where_the_world_one_is_expected(backend_name, name):
    """Pinocchio's LOCAL and Robotics Toolbox's jacobe, handed over for a jacob0."""
    model, q, expected, pose = case(name)
    observed = registry.make_backend(backend_name).frame_jacobian(model, q, "tcp", "local")
    d = run(model, expected, observed, pose)
    assert d.best is not None
    assert d.best.mistake == JacobianMistake(reference="local")
    assert d.headline.startswith("the backend's Jacobian is in the frame's own axes (local: ")
    assert "LOCAL, Robotics Toolbox jacobe) where world-aligned" in d.headline


# (b) angular rows first ------------------------------------------------------------------


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
def test_b_angular_rows_first_is_named(pin, name, reference):
    model, q, expected, pose = case(name, reference)
    observed = angular_first(pin.frame_jacobian(model, q, "tcp", reference))
    d = run(model, expected, observed, pose, reference)
    assert d.best is not None
    assert d.best.kinds == ("blocks",)
    assert d.headline.startswith("the backend's rows are angular first, then linear")


def test_angular_first_and_local_together_are_named_together(pin):
    model, q, expected, pose = case("ur5")
    observed = angular_first(pin.frame_jacobian(model, q, "tcp", "local"))
    d = run(model, expected, observed, pose)
    assert d.best is not None
    assert d.best.kinds == ("reference", "blocks")
    assert d.best.mistake == JacobianMistake(reference="local", angular_first=True)
    assert "; and the backend's rows are angular first" in d.headline


# (c) one column's sign -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "joint"), [("ur5", 0), ("ur5", 2), ("ur5", 5), ("panda", 3), ("stanford", 2)]
)
@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
def test_c_one_flipped_column_is_named_with_its_joint(pin, name, joint, reference):
    model, q, expected, pose = case(name, reference)
    observed = pin.frame_jacobian(model, q, "tcp", reference).copy()
    observed[:, :, joint] *= -1
    d = run(model, expected, observed, pose, reference)
    assert d.best is not None
    assert d.best.kinds == ("sign",)
    assert d.best.mistake.flipped == (joint,)
    assert d.first_disagreeing is not None
    assert d.first_disagreeing.joint == joint
    label = f"joint {joint + 1} ({model.joints[joint].name})"
    assert d.headline == (
        f"the column of {label} has the opposite sign "
        "(the joint turns the other way in the backend)"
    )


def test_two_flipped_columns_are_both_named(pin):
    model, q, expected, pose = case("puma560")
    observed = pin.frame_jacobian(model, q, "tcp", "world-aligned") * [1, -1, 1, -1, 1, 1]
    d = run(model, expected, observed, pose)
    assert d.best is not None
    assert d.best.mistake.flipped == (1, 3)
    assert "joint 2 (shoulder) and joint 4 (wrist_roll) have the opposite sign" in d.headline


# columns in another order, or a joint left out --------------------------------------------


def test_swapped_columns_are_named(pin):
    model, q, expected, pose = case("ur5")
    observed = pin.frame_jacobian(model, q, "tcp", "world-aligned")[:, :, [0, 2, 1, 3, 4, 5]]
    d = run(model, expected, observed, pose)
    assert d.best is not None
    assert d.best.kinds == ("columns",)
    assert d.best.mistake.columns == (0, 2, 1, 3, 4, 5)
    assert "column 2 holds joint 3 (elbow)'s, column 3 holds joint 2 (shoulder_lift)'s" in (
        d.headline
    )


@pytest.mark.parametrize("name", MODELS)
def test_a_zero_column_is_named_as_the_joint_left_out(pin, name):
    model, q, expected, pose = case(name)
    observed = pin.frame_jacobian(model, q, "tcp", "world-aligned").copy()
    observed[:, :, 1] = 0.0
    d = run(model, expected, observed, pose)
    assert d.best is not None
    assert d.best.kinds == ("missing",)
    assert d.best.mistake.missing == (1,)
    assert f"the column of joint 2 ({model.joints[1].name}) is zero in the backend" in d.headline


# (d) the tool offset left out of the linear part ------------------------------------------

#: The models' TCPs as fkcheck knows them: panda's own tool; a translated tool added elsewhere.
TOOLS = {
    "panda": None,  # its model file's tool: 107 mm along z of the flange
    "ur5": Offset((0.01, -0.02, 0.15)),
    "stanford": Offset((0.0, 0.03, 0.2)),
    "puma560": Offset((0.05, 0.0, 0.0)),
}


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("reference", ["world-aligned", "local"])
def test_d_the_flange_jacobian_where_the_tcp_is_expected_names_the_tool_offset(
    pin, name, reference
):
    model = load_model(name)
    if TOOLS[name] is not None:
        model = replace(model, tool=TOOLS[name])
    tool = np.array(model.tool.xyz)
    assert np.linalg.norm(tool) > 0.01
    flange = replace(model, tool=Offset())
    q = random_q(model, np.random.default_rng(4), 6)
    pose = reference_poses(model, q, ["tcp"])[0]
    expected = model.jacobian(q, "tcp", reference)
    observed = pin.frame_jacobian(flange, q, "tcp", reference)  # Pinocchio, no tool
    d = run(model, expected, observed, pose, reference)
    assert d.best is not None
    assert d.best.kinds == ("offset",)
    offset = d.best.mistake.point_offset_m
    assert offset is not None
    np.testing.assert_allclose(offset, -tool, atol=1e-9)  # the flange, seen from the TCP
    shown = ", ".join(f"{v * 1e3:.3f}" for v in tool).replace("-0.000", "0.000")
    assert f"a tool offset of ({shown}) mm left out" in d.headline


def test_panda_tool_offset_reads_107_mm(pin):
    model, q, expected, pose = case("panda")
    observed = pin.frame_jacobian(replace(model, tool=Offset()), q, "tcp", "world-aligned")
    d = run(model, expected, observed, pose)
    assert "a tool offset of (0.000, 0.000, 107.000) mm left out" in d.headline


def test_the_tool_offset_cannot_show_in_the_spatial_twist(pin):
    """In "world" every point of the last link has the same twist: the flange's agrees."""
    model, q, expected, pose = case("panda", "world")
    observed = pin.frame_jacobian(replace(model, tool=Offset()), q, "tcp", "world")
    d = run(model, expected, observed, pose, "world")
    assert d.agrees
    assert not d.explanations


def test_the_flange_in_local_axes_where_the_spatial_twist_is_expected(pin):
    """Two mistakes at once: the reference frame, and the tool offset (visible in "local")."""
    model, q, expected, pose = case("panda", "world")
    observed = pin.frame_jacobian(replace(model, tool=Offset()), q, "tcp", "local")
    d = run(model, expected, observed, pose, "world")
    assert d.best is not None
    assert d.best.kinds == ("reference", "offset")
    assert d.best.mistake.reference == "local"
    np.testing.assert_allclose(d.best.mistake.point_offset_m, (0.0, 0.0, -0.107), atol=1e-9)


# (e) correct input -------------------------------------------------------------------------


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
def test_e_agreeing_jacobians_have_nothing_to_explain(pin, name, reference):
    model, q, expected, pose = case(name, reference)
    d = run(model, expected, pin.frame_jacobian(model, q, "tcp", reference), pose, reference)
    assert d.agrees
    assert not d.explained
    assert d.best is None
    assert d.first_disagreeing is None
    assert d.headline.startswith("the Jacobians agree (linear ")
    assert all(c.agrees for c in d.columns)


def test_a_mid_chain_frame_agrees_with_its_zero_columns(pin):
    model, q, expected, pose = case("ur5", frame="tool0")
    observed = pin.frame_jacobian(model, q, "tool0", "world-aligned")
    assert run(model, expected, observed, pose).agrees


# (f) nothing explains it -------------------------------------------------------------------


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("seed", [0, 1])
def test_f_random_garbage_is_not_explained(name, seed):
    model, _, expected, pose = case(name)
    observed = np.random.default_rng(seed).normal(size=expected.shape)
    d = run(model, expected, observed, pose)
    assert not d.agrees
    assert not d.explained
    assert d.first_disagreeing is not None
    assert d.first_disagreeing.joint == 0
    assert d.headline.startswith("no convention explains it: the Jacobians differ by linear ")
    assert d.headline.endswith(
        f"joint 1 ({model.joints[0].name}) is the first column that disagrees"
    )


@pytest.mark.parametrize(("name", "joint"), [("ur5", 3), ("panda", 6), ("stanford", 2)])
def test_f_one_garbage_column_is_the_first_that_disagrees(pin, name, joint):
    model, q, expected, pose = case(name)
    observed = pin.frame_jacobian(model, q, "tcp", "world-aligned").copy()
    observed[:, :, joint] += np.random.default_rng(joint).normal(size=observed[:, :, joint].shape)
    d = run(model, expected, observed, pose)
    assert not d.explained
    assert d.first_disagreeing is not None
    assert d.first_disagreeing.joint == joint
    assert [c.agrees for c in d.columns] == [j != joint for j in range(model.dof)]
    assert f"joint {joint + 1} ({model.joints[joint].name}) is the first column" in d.headline


# the column breakdown on its own ---------------------------------------------------------


def test_column_errors_and_the_first_disagreeing_joint():
    expected = np.zeros((2, 6, 4))
    observed = expected.copy()
    observed[1, 0, 2] = 0.5  # linear row of joint 3
    observed[0, 5, 3] = -0.25  # angular row of joint 4
    linear, angular = column_errors(expected, observed)
    np.testing.assert_array_equal(linear, [0.0, 0.0, 0.5, 0.0])
    np.testing.assert_array_equal(angular, [0.0, 0.0, 0.0, 0.25])


def test_a_column_is_measured_as_the_check_measures_it_by_the_length_of_its_3_vectors():
    """Every linear entry of joint 3 off by 0.8e-6: each entry is within 1e-6, the column is not."""
    model, _, expected, pose = case("ur5")
    observed = expected.copy()
    observed[:, :3, 2] += 0.8e-6
    linear, _ = column_errors(expected, observed)
    assert linear[2] == pytest.approx(0.8e-6 * np.sqrt(3))
    d = run(model, expected, observed, pose)
    assert not d.agrees
    assert d.first_disagreeing is not None
    assert d.first_disagreeing.joint == 2


def test_a_non_finite_observed_column_disagrees_and_is_not_explained():
    model, _, expected, pose = case("ur5")
    observed = expected.copy()
    observed[2, 4, 1] = np.nan
    linear, angular = column_errors(expected, observed)
    assert angular[1] == np.inf
    assert linear[1] == 0.0
    d = run(model, expected, observed, pose)
    assert not d.explained
    assert d.first_disagreeing is not None
    assert d.first_disagreeing.joint == 1


def test_the_diagnosis_as_data_and_as_text(pin):
    model, q, expected, pose = case("stanford")
    observed = pin.frame_jacobian(model, q, "tcp", "world-aligned") * [1, 1, -1, 1, 1, 1]
    d = run(model, expected, observed, pose)
    assert d.explained
    assert d.best is not None
    assert d.best.kinds == ("sign",)
    assert d.best.mistake.flipped == (2,)
    assert d.first_disagreeing is not None
    assert d.first_disagreeing.joint == 2
    assert [c.prismatic for c in d.columns] == [False, False, True, False, False, False]
    text = d.text()
    assert text.splitlines()[0] == d.headline
    assert "joint 3 (j3): linear " in text
    assert " m/m, angular " in text
    assert "DIFFERS" in text


def test_the_mistake_applied_to_the_core_is_the_reference(pin):
    """JacobianMistake.apply, checked against Pinocchio itself (not against fkcheck's maths)."""
    model, q, expected, pose = case("panda")
    for target in JACOBIAN_REFERENCES:
        np.testing.assert_allclose(
            JacobianMistake(reference=target).apply(expected, pose, "world-aligned"),
            pin.frame_jacobian(model, q, "tcp", target),
            atol=TOL,
        )
    flange = pin.frame_jacobian(replace(model, tool=Offset()), q, "tcp", "local")
    moved = JacobianMistake(point_offset_m=(0.0, 0.0, -0.107)).apply(
        model.jacobian(q, "tcp", "local"), pose, "local"
    )
    np.testing.assert_allclose(moved, flange, atol=TOL)


# bad input ---------------------------------------------------------------------------------


def test_bad_shapes_and_values_are_refused_with_the_reason():
    model, _, expected, pose = case("ur5", n=3)
    good = {
        "from_T_to": pose,
        "reference": "world-aligned",
        "prismatic": model.chain.prismatic,
        "tolerance": 1e-9,
    }
    with pytest.raises(ValueError, match=r"observed Jacobian has shape \(3, 6, 5\).*must match"):
        diagnose_jacobian(expected, expected[:, :, :5], **good)
    with pytest.raises(ValueError, match=r"expected Jacobian has shape \(3, 5, 6\); a Jacobian is"):
        diagnose_jacobian(expected[:, :5], expected[:, :5], **good)
    with pytest.raises(ValueError, match=r"from_T_to has shape \(2, 4, 4\); expected \(3, 4, 4\)"):
        diagnose_jacobian(expected, expected, **{**good, "from_T_to": pose[:2]})
    with pytest.raises(ValueError, match=r"unknown reference 'base'; references are: world"):
        diagnose_jacobian(expected, expected, **{**good, "reference": "base"})
    with pytest.raises(ValueError, match="prismatic has 5 entries; the Jacobians have 6 columns"):
        diagnose_jacobian(expected, expected, **{**good, "prismatic": [False] * 5})
    with pytest.raises(ValueError, match="joint_names has 1 names; the Jacobians have 6"):
        diagnose_jacobian(expected, expected, joint_names=["a"], **good)
    with pytest.raises(ValueError, match=r"tolerances must be positive, got 0\.0"):
        diagnose_jacobian(expected, expected, **{**good, "tolerance": 0.0})
    bad = expected.copy()
    bad[0, 0, 0] = np.inf
    with pytest.raises(ValueError, match="the expected Jacobian and the poses must be finite"):
        diagnose_jacobian(bad, expected, **good)
    with pytest.raises(ValueError, match=r"observed Jacobian has shape \(6,\)"):
        column_errors(expected, np.zeros(6))


# a random mistake on a random table is recovered ----------------------------------------

MISTAKES = ("reference", "blocks", "reference+blocks", "sign", "columns", "missing", "offset")


def seeded(kind, rng, expected_ref, jac_aligned, pose):
    """The observed Jacobian with one mistake, built by hand from the world-aligned one.

    Returns ``(observed, kinds a correct diagnosis lists)``.
    """
    n = jac_aligned.shape[2]
    R, p = pose[:, :3, :3], pose[:, :3, 3]

    def express(jac, ref):
        v, w = jac[:, :3], jac[:, 3:]
        if ref == "local":
            return np.concatenate([R.transpose(0, 2, 1) @ v, R.transpose(0, 2, 1) @ w], axis=1)
        if ref == "world":
            return np.concatenate([v + np.cross(p[:, :, None], w, axis=1), w], axis=1)
        return jac

    expected = express(jac_aligned, expected_ref)
    if kind in ("reference", "reference+blocks"):
        other = rng.choice([r for r in JACOBIAN_REFERENCES if r != expected_ref])
        observed = express(jac_aligned, other)
        if kind == "reference+blocks":
            return angular_first(observed), {("reference", "blocks")}
        return observed, {("reference",)}
    if kind == "blocks":
        return angular_first(expected), {("blocks",)}
    if kind == "sign":
        signs = np.ones(n)
        signs[rng.integers(n)] = -1
        return expected * signs, {("sign",)}
    if kind == "columns":
        order = rng.permutation(n)
        # Two columns that are each other's negatives read as flipped signs just as well.
        return expected[:, :, order], {("columns",), ("sign",), ("sign", "columns")}
    if kind == "missing":
        observed = expected.copy()
        observed[:, :, rng.integers(n)] = 0.0
        return observed, {("missing",)}
    r = rng.uniform(-0.5, 0.5, 3)
    lever = R @ r
    v = jac_aligned[:, :3] + np.cross(jac_aligned[:, 3:], lever[:, :, None], axis=1)
    return express(np.concatenate([v, jac_aligned[:, 3:]], axis=1), expected_ref), {("offset",)}


@settings(deadline=None)
@given(
    model=dh_models(max_joints=7),
    seed=st.integers(0, 2**32 - 1),
    kind=st.sampled_from(MISTAKES),
    expected_ref=st.sampled_from(JACOBIAN_REFERENCES),
)
def test_a_random_mistake_on_a_random_table_is_recovered(model, seed, kind, expected_ref):
    assume(not (kind == "offset" and expected_ref == "world"))  # invisible there, tested above
    rng = np.random.default_rng(seed)
    q = random_q(model, rng, 4)
    pose = reference_poses(model, q, ["tcp"])[0]
    scale = 1.0 + float(np.abs(model.jacobian(q, "tcp", "world")).max())
    tol = SAME_CHAIN * scale * 10
    aligned = model.jacobian(q, "tcp", "world-aligned")
    expected = model.jacobian(q, "tcp", expected_ref)
    observed, kinds = seeded(kind, rng, expected_ref, aligned, pose)
    d = run(model, expected, observed, pose, expected_ref, tol)
    linear, angular = column_errors(expected, observed)
    if max(linear.max(), angular.max()) <= tol:  # the mistake does not show on this table
        event(f"{kind}: does not show")
        assert d.agrees
        return
    assume(max(linear.max(), angular.max()) > 1e3 * tol)  # clearly seen, not round-off
    event(f"{kind}: shows")
    assert d.explained, d.text()
    assert kinds & {e.kinds for e in d.explanations}, d.text()
    assert d.best is not None
    assert len(d.best.kinds) <= max(len(k) for k in kinds)
    # The best explanation, applied, reproduces the observed Jacobian.
    again = d.best.mistake.apply(expected, pose, expected_ref)
    np.testing.assert_allclose(again, observed, rtol=0, atol=tol)
