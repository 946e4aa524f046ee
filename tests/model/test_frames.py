"""reference_poses: the named frames' poses, from only the core calls they need."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.errors import JointInputError
from fkcheck.model.frames import frame_poses_from_dh, reference_poses
from fkcheck.model.types import Offset
from tests.helpers import random_q

PAIRS = [
    ("base", "tool0"),  # both on DH frames: the TCP call is skipped
    ("world", "tcp"),  # only the TCP: the every-frame call is skipped
    ("tcp", "base_link"),  # both calls
    ("world", "world"),  # neither is read: the every-frame call still validates q
]


@pytest.mark.parametrize("pair", PAIRS)
def test_reference_poses_are_the_poses_of_both_core_calls(pair, rng):
    # A tool and a base make the TCP differ from the last DH frame and frame 0 from
    # the world, so a frame read from the wrong (or a skipped, NaN) call shows.
    ur5 = load_model("ur5")
    model = replace(
        ur5, base=Offset((0.1, -0.2, 0.3), (0.1, 0.2, 0.3)), tool=Offset((0, 0, 0.05), (0, 0.4, 0))
    )
    q = random_q(model, rng, 50)
    expected = frame_poses_from_dh(model, model.fk(q, all_frames=True), model.fk(q), pair)
    got = reference_poses(model, q, pair)
    assert np.array_equal(got, expected)  # the same calls, bit for bit
    assert np.isfinite(got).all()


def test_reference_poses_validate_q_when_no_frame_is_on_the_chain():
    model = load_model("ur5")
    q = np.zeros((3, model.dof))
    q[1, 2] = np.nan
    with pytest.raises(JointInputError, match="configuration 1 joint 3 is nan"):
        reference_poses(model, q, ("world", "world"))


def test_a_given_chain_is_computed_with_the_models_frames(rng):
    # The diagnosis's one-number fits hand a changed chain instead of a changed model:
    # the poses must be the changed model's, bit for bit, and not the given model's.
    model = load_model("ur5")
    changed = replace(
        model, joints=(replace(model.joints[0], d=0.1), *model.joints[1:])
    )  # d1 + 10.8 mm
    q = random_q(model, rng, 20)
    for pair in PAIRS:
        got = reference_poses(model, q, pair, chain=changed.chain)
        assert np.array_equal(got, reference_poses(changed, q, pair))
    # d1 moves every pose along base z by the change; 1e-12 m: round-off of a 1 m chain.
    moved = reference_poses(model, q, ("base", "tool0"), chain=changed.chain)
    assert np.allclose(
        moved[1, :, 2, 3] - reference_poses(model, q, ("base", "tool0"))[1, :, 2, 3],
        0.1 - model.joints[0].d,
        rtol=0,
        atol=1e-12,
    )
