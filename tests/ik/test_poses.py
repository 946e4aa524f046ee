"""The IK check's singular configurations are singular, and the near ones are not."""

from __future__ import annotations

import numpy as np
import pytest

from fkcheck.ik.check import SINGULAR_SIGMA
from fkcheck.ik.poses import NEAR, SEEDS_PER_KIND, ik_configurations
from fkcheck.model.read import load_model
from fkcheck.model.sampling import sampling_box


@pytest.mark.parametrize("name", ["ur5e", "ur10", "puma560"])
def test_singular_kinds_are_singular_and_near_ones_regular(name):
    model = load_model(name)
    configs = ik_configurations(model, 0, seed=3)
    sigma = np.linalg.svd(model.jacobian(configs.q, frame=model.check.frame_to), compute_uv=False)[
        :, -1
    ]
    origin = np.array(configs.origin)
    lo, hi = sampling_box(model)
    assert ((configs.q >= lo) & (configs.q <= hi)).all()
    for kind in ("wrist", "elbow", "shoulder"):
        exact = origin == f"{kind}-singular"
        near = origin == f"near-{kind}"
        assert 0 < exact.sum() <= SEEDS_PER_KIND, kind
        assert near.sum() == len(NEAR) * 2 * exact.sum(), kind
        assert (sigma[exact] < SINGULAR_SIGMA).all(), kind
        assert (sigma[near] > SINGULAR_SIGMA).all(), kind


def test_a_model_branches_are_not_named_for_gets_the_checks_set_only():
    model = load_model("panda")
    configs = ik_configurations(model, 10, seed=0)
    assert not any("singular" in o or o.startswith("near-") for o in configs.origin)
