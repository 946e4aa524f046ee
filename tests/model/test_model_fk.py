"""``Model.fk(q, frame_from=, frame_to=)``: one named frame's pose in another.

Held against values fkcheck did not compute: seed 000's hand-computed UR5 matrices
(each ``A_i`` and ``T0_i`` as printed, six decimals), and the ROS 2 description's
``base_link`` as ``base`` turned π about z, written out as a matrix here.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.core.tolerances import SAME_CHAIN, SIX_DECIMALS
from fkcheck.errors import FrameError, OptionError
from fkcheck.model.types import FrameSpec, Offset
from tests import seed_ur5
from tests.helpers import assert_pose_close

#: Rz(π), by hand: base_link is base turned half a turn about z (ur_macro.xacro).
RZ_PI = np.diag([-1.0, -1.0, 1.0, 1.0])


def ur5_with_dh_frames():
    """The bundled UR5 with a named frame on every DH frame: ``dh0`` … ``dh6``."""
    model = load_model("ur5")
    frames = dict(model.frames)
    frames.update({f"dh{k}": FrameSpec(f"dh{k}", k) for k in range(model.dof + 1)})
    return replace(model, frames=frames)


@pytest.mark.parametrize("k", range(1, 7))
def test_each_link_transform_is_the_seeds_A_i(k):
    model = ur5_with_dh_frames()
    q = np.deg2rad(seed_ur5.Q_DEG)
    got = model.fk(q, frame_from=f"dh{k - 1}", frame_to=f"dh{k}")
    assert_pose_close(got, seed_ur5.A[k - 1], SIX_DECIMALS, f"A{k}")


@pytest.mark.parametrize("k", sorted(seed_ur5.T0))
def test_dh0_to_each_dh_frame_is_the_seeds_T0_i(k):
    model = ur5_with_dh_frames()
    got = model.fk(np.deg2rad(seed_ur5.Q_DEG), frame_from="dh0", frame_to=f"dh{k}")
    assert_pose_close(got, seed_ur5.T0[k], SIX_DECIMALS, f"T0_{k}")


def test_base_link_to_tool0_is_rz_pi_times_base_to_tool0(rng):
    model = load_model("ur5e")
    q = rng.uniform(-np.pi, np.pi, (50, model.dof))
    base = model.fk(q, frame_from="base", frame_to="tool0")
    base_link = model.fk(q, frame_from="base_link", frame_to="tool0")
    assert_pose_close(base_link, RZ_PI @ base, SAME_CHAIN)
    # urdf:LINK names the same frames by their URDF twins.
    by_twin = model.fk(q, frame_from="urdf:base_link", frame_to="urdf:tool0")
    np.testing.assert_array_equal(by_twin, base_link)
    # ...and a pose one frame away from differing: base → tool0 is not base_link → tool0.
    assert np.abs(base - base_link).max() > 0.1


def test_tool0_to_flange_is_the_descriptions_fixed_rotation_at_every_q(rng):
    # flange → tool0 is rpy(π/2, 0, π/2) in ur_macro.xacro: Rz(90°)·Rx(90°), by hand, and
    # tool0 → flange its transpose. An offset applied on the wrong side varies with q.
    flange_R_tool0 = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    model = load_model("ur5e")
    q = rng.uniform(-np.pi, np.pi, (50, model.dof))
    expected = np.broadcast_to(np.eye(4), (50, 4, 4)).copy()
    expected[:, :3, :3] = flange_R_tool0.T
    assert_pose_close(model.fk(q, frame_from="tool0", frame_to="flange"), expected, SAME_CHAIN)
    expected[:, :3, :3] = flange_R_tool0
    assert_pose_close(model.fk(q, frame_from="flange", frame_to="tool0"), expected, SAME_CHAIN)


def test_one_frame_given_the_other_is_the_world_or_the_tcp(rng):
    model = load_model("ur5e")
    q = rng.uniform(-np.pi, np.pi, (20, model.dof))
    world_T_tcp = model.fk(q)
    np.testing.assert_allclose(model.fk(q, frame_to="tcp"), world_T_tcp, atol=SAME_CHAIN)
    np.testing.assert_allclose(model.fk(q, frame_from="world"), world_T_tcp, atol=SAME_CHAIN)
    tool0_T_tcp = model.fk(q, frame_from="tool0")
    assert_pose_close(world_T_tcp, model.fk(q, frame_to="tool0") @ tool0_T_tcp, SAME_CHAIN)


def test_shapes_one_configuration_and_a_batch():
    model = load_model("ur5e")
    assert model.fk(np.zeros(6), frame_from="base_link", frame_to="flange").shape == (4, 4)
    assert model.fk(np.zeros((3, 6)), frame_from="base_link", frame_to="flange").shape == (3, 4, 4)


def test_a_tcp_frame_declared_in_the_file_is_the_one_named(rng):
    # [frames.tcp] with an offset: frame_to="tcp" is that frame; fk(q) stays world_T_tcp.
    model = load_model("ur5e")
    frames = dict(model.frames)
    frames["tcp"] = FrameSpec("tcp", "tcp", Offset((0.0, 0.0, 0.1)))
    model = replace(model, frames=frames)
    q = rng.uniform(-np.pi, np.pi, (5, model.dof))
    named = model.fk(q, frame_to="tcp")
    chain = model.fk(q)
    np.testing.assert_allclose(named[:, :3, 3], (chain @ [0.0, 0.0, 0.1, 1.0])[:, :3], atol=1e-12)


def test_an_unknown_frame_lists_the_models_frames():
    model = load_model("ur5e")
    with pytest.raises(
        FrameError,
        match=r"frame 'tool1' not in model ur5e; frames are: world, tcp, base, base_link, "
        r"tool0, flange$",
    ):
        model.fk(np.zeros(6), frame_from="base", frame_to="tool1")


def test_all_frames_with_a_frame_is_refused():
    with pytest.raises(OptionError, match=r"^all_frames: gives every DH frame in the world"):
        load_model("ur5e").fk(np.zeros(6), all_frames=True, frame_from="base_link")
