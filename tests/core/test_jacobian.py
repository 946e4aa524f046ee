"""The in-house geometric Jacobian: finite differences, the references, random tables."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import fkcheck.backends.registry as registry
from fkcheck.core.tolerances import (
    FINITE_DIFFERENCE,
    FINITE_DIFFERENCE_STEP,
    ROUNDED_URDF,
    SAME_CHAIN,
)
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.model.frames import reference_poses
from fkcheck.model.read import bundled_model_paths, load_model
from tests.helpers import random_q
from tests.strategies import dh_models

MODELS = sorted(bundled_model_paths())
URDF_MODELS = ("panda", "ur10", "ur3", "ur5")


def _fd_world_aligned(model, q, frame):
    """Central differences of the frame's pose: ``(N, 6, n)`` world-aligned (v; ω)."""
    h = FINITE_DIFFERENCE_STEP
    N = q.shape[0]
    out = np.empty((N, 6, model.dof))
    for j in range(model.dof):
        step = np.zeros(model.dof)
        step[j] = h
        plus = reference_poses(model, q + step, [frame])[0]
        minus = reference_poses(model, q - step, [frame])[0]
        out[:, :3, j] = (plus[:, :3, 3] - minus[:, :3, 3]) / (2 * h)
        turn = plus[:, :3, :3] @ minus[:, :3, :3].transpose(0, 2, 1)  # world axes
        out[:, 3:, j] = Rotation.from_matrix(turn).as_rotvec() / (2 * h)
    return out


def _adjoint(world_T_frame, jac_world_aligned, reference):
    """World-aligned (v; ω) moved by hand to ``local`` or ``world`` (the definitions)."""
    R = world_T_frame[:, :3, :3]
    p = world_T_frame[:, :3, 3]
    v, w = jac_world_aligned[:, :3], jac_world_aligned[:, 3:]
    if reference == "local":
        Rt = R.transpose(0, 2, 1)
        return np.concatenate([Rt @ v, Rt @ w], axis=1)
    if reference == "world":
        return np.concatenate([v + np.cross(p[:, :, None], w, axis=1), w], axis=1)
    return jac_world_aligned


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
def test_core_jacobian_is_the_derivative_of_the_core_fk(name, reference):
    model = load_model(name)
    q = random_q(model, np.random.default_rng(11), 6)
    for frame in model.frames:
        fd = _fd_world_aligned(model, q, frame)
        pose = reference_poses(model, q, [frame])[0]
        expected = _adjoint(pose, fd, reference)
        jac = model.jacobian(q, frame, reference)
        assert jac.shape == (q.shape[0], 6, model.dof)
        np.testing.assert_allclose(jac, expected, rtol=0, atol=FINITE_DIFFERENCE, err_msg=frame)


def test_one_configuration_gives_one_matrix_and_unknown_reference_is_refused():
    model = load_model("ur5")
    assert model.jacobian(np.zeros(6)).shape == (6, 6)
    assert model.jacobian(np.zeros((3, 6)), "tool0").shape == (3, 6, 6)
    with pytest.raises(ValueError, match=r"unknown reference 'base'; references are: world, local"):
        model.jacobian(np.zeros(6), reference="base")  # type: ignore[arg-type]


def test_frames_before_a_joint_do_not_move_with_it():
    model = load_model("ur5")
    q = random_q(model, np.random.default_rng(2), 4)
    assert not model.jacobian(q, "world").any()
    assert not model.jacobian(q, "base").any()  # DH frame 0: fixed to the base
    np.testing.assert_array_equal(model.jacobian(q, "base_link"), 0.0)


@pytest.mark.parametrize("backend_name", ["rtb-dh", "pinocchio-dh"])
@pytest.mark.parametrize("name", MODELS)
def test_dh_references_agree_in_every_frame_and_reference(backend_name, name):
    backend = registry.make_backend(backend_name)
    model = load_model(name)
    q = random_q(model, np.random.default_rng(5), 5)
    for frame in model.frames:
        for reference in JACOBIAN_REFERENCES:
            theirs = backend.frame_jacobian(model, q, frame, reference)
            ours = model.jacobian(q, frame, reference)
            np.testing.assert_allclose(
                theirs, ours, rtol=0, atol=SAME_CHAIN, err_msg=f"{frame} {reference}"
            )


@pytest.mark.parametrize("name", URDF_MODELS)
def test_pinocchio_urdf_agrees_once_its_root_is_placed(name):
    """URDF Jacobians live in the URDF's root frame: moved into the DH world, they agree."""
    backend = registry.make_backend("pinocchio-urdf")
    model = load_model(name)
    q = random_q(model, np.random.default_rng(8), 5)
    twins = [f for f, spec in model.frames.items() if spec.urdf is not None]
    anchor = twins[0]
    # world_T_root from the anchor frame: ours (world_T_anchor) times theirs⁻¹ (root_T_anchor).
    root_T_anchor = backend.frame_poses(model, q[:1], [anchor])[0, 0]
    world_T_anchor = reference_poses(model, q[:1], [anchor])[0, 0]
    world_T_root = world_T_anchor @ np.linalg.inv(root_T_anchor)
    R, t = world_T_root[:3, :3], world_T_root[:3, 3]
    for frame in twins:
        local = backend.frame_jacobian(model, q, frame, "local")
        np.testing.assert_allclose(local, model.jacobian(q, frame, "local"), atol=ROUNDED_URDF)
        aligned = backend.frame_jacobian(model, q, frame, "world-aligned")
        aligned = np.concatenate([R @ aligned[:, :3], R @ aligned[:, 3:]], axis=1)
        np.testing.assert_allclose(
            aligned, model.jacobian(q, frame, "world-aligned"), atol=ROUNDED_URDF
        )
        spatial = backend.frame_jacobian(model, q, frame, "world")
        v, w = R @ spatial[:, :3], R @ spatial[:, 3:]
        spatial = np.concatenate([v + np.cross(t[None, :, None], w, axis=1), w], axis=1)
        np.testing.assert_allclose(spatial, model.jacobian(q, frame, "world"), atol=ROUNDED_URDF)


@settings(max_examples=max(1, settings().max_examples // 2))
@given(model=dh_models(max_joints=7), seed=st.integers(0, 2**32 - 1))
def test_random_tables_agree_with_both_dh_references(model, seed):
    q = random_q(model, np.random.default_rng(seed), 3)
    scale = 1.0 + float(np.abs(reference_poses(model, q, ["tcp"])[0][:, :3, 3]).max())
    for backend_name in ("rtb-dh", "pinocchio-dh"):
        backend = registry.make_backend(backend_name)
        for reference in JACOBIAN_REFERENCES:
            theirs = backend.frame_jacobian(model, q, "tcp", reference)
            np.testing.assert_allclose(
                theirs,
                model.jacobian(q, "tcp", reference),
                rtol=0,
                atol=SAME_CHAIN * scale,
                err_msg=f"{backend_name} {reference}",
            )
