"""joints_spanned: the joints between two frames' anchors, and only those, move the pose."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from fkcheck.errors import FrameError
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.read import load_model
from fkcheck.model.span import joints_spanned
from fkcheck.model.types import FrameSpec, Offset


@pytest.fixture(scope="module")
def ur5():
    model = load_model("ur5")
    frames = dict(model.frames)
    frames["on1"] = FrameSpec("on1", 1, Offset((0.1, 0.0, 0.0)))
    frames["on0"] = FrameSpec("on0", 0, Offset((0.0, 0.0, 0.2), (0.0, 0.0, 1.0)))
    return replace(model, frames=frames)


@pytest.mark.parametrize(
    ("pair", "spanned"),
    [
        (("base", "tool0"), (1, 2, 3, 4, 5, 6)),
        (("tool0", "base"), (1, 2, 3, 4, 5, 6)),
        (("world", "tcp"), (1, 2, 3, 4, 5, 6)),
        (("tcp", "tcp"), ()),
        (("tool0", "flange"), ()),  # both on DH frame 6
        (("world", "base"), ()),  # DH frame 0 never moves
        (("world", "on0"), ()),
        (("world", "on1"), (1,)),
        (("on1", "tcp"), (2, 3, 4, 5, 6)),
        (("urdf:base", "urdf:tool0"), (1, 2, 3, 4, 5, 6)),
    ],
)
def test_the_joints_between_the_anchors(ur5, pair, spanned):
    assert joints_spanned(ur5, *pair) == spanned


@pytest.mark.parametrize(
    "pair",
    [("world", "tcp"), ("on1", "tool0"), ("world", "on1"), ("tcp", "tool0"), ("base", "on0")],
)
def test_a_joint_moves_the_pose_exactly_when_it_is_spanned(ur5, pair):
    rng = np.random.default_rng(7)
    q = rng.uniform(-3.0, 3.0, size=(5, ur5.dof))
    before = relative_pose(*reference_poses(ur5, q, pair))
    spanned = joints_spanned(ur5, *pair)
    for joint in range(1, ur5.dof + 1):
        moved = q.copy()
        moved[:, joint - 1] += 0.3
        after = relative_pose(*reference_poses(ur5, moved, pair))
        changed = bool(np.abs(after - before).max() > 1e-9)
        assert changed == (joint in spanned), joint


def test_an_unknown_frame_is_a_frame_error(ur5):
    with pytest.raises(FrameError, match="nowhere"):
        joints_spanned(ur5, "world", "nowhere")
