"""Property-based: random DH tables through the in-house core agree with the plain chain
product and are valid SE(3) (the reference backends: test_property_backends.py)."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from fkcheck.core.dh import fk_reference
from fkcheck.core.tolerances import SAME_CHAIN
from tests.helpers import assert_pose_close, assert_se3, random_q
from tests.strategies import dh_models


@given(model=dh_models(), seed=st.integers(0, 2**32 - 1))
def test_core_matches_reference_chain_on_random_tables(model, seed):
    rng = np.random.default_rng(seed)
    q = random_q(model, rng, 16)
    T = model.fk(q)
    assert_se3(T, SAME_CHAIN)
    assert_pose_close(T, fk_reference(model.chain, q), SAME_CHAIN)
    frames = model.fk(q, all_frames=True)
    assert_pose_close(frames, fk_reference(model.chain, q, all_frames=True), SAME_CHAIN)
    # The TCP is the last DH frame times the tool, whatever the table.
    assert_pose_close(T, frames[:, -1] @ model.tool.matrix, SAME_CHAIN)
