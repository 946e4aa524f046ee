"""A seeded part of benchmarks/verdict_campaign.py: published tables, map → paste → check.

Three vendors' published DH tables (UR5e, Franka Panda, ABB IRB 120), each mapped
onto an independent URDF with ``fkcheck map``, the block pasted and checked with
``--require table`` against Pinocchio's URDF reader: the tables as published are
never refused, and none of the faults drawn here — half a turn added to θ1 (the
issue's base vs base_link), and a seeded draw of the rest — is a false green.
"""

from __future__ import annotations

import importlib.util
import sys

import pytest

from tests.paths import REPO_ROOT

pytestmark = pytest.mark.slow

#: Faults of each arm drawn at random, besides θ1 + 180° (the whole campaign has ~200).
DRAWN = 2
SEED = 20261128


def _campaign():
    spec = importlib.util.spec_from_file_location(
        "verdict_campaign", REPO_ROOT / "benchmarks" / "verdict_campaign.py"
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("verdict_campaign", module)
    spec.loader.exec_module(module)
    return module


def test_seeded_campaign_has_no_false_green_and_no_false_alarm(tmp_path):
    vc = _campaign()
    drawn = vc.seeded_subset(DRAWN, SEED)

    def pick(faults):
        return [f for f in faults if f.label == "θ1 +180°"] + drawn(
            [f for f in faults if f.label != "θ1 +180°"]
        )

    result = vc.campaign(["ur5e", "panda", "irb120"], tmp_path, samples=32, seed=SEED, pick=pick)
    for name, arm in result["arms"].items():
        published = arm["published"]
        assert published["outcome"] != "false-alarm", (name, published)
        # The check really ran on the table as published, through the map's pair.
        assert published["map_exit"] == 0
        assert published["verdict"] in ("pass", "unverified"), (name, published["headline"])
        assert len(arm["faults"]) == DRAWN + 1
        for case in arm["faults"]:
            assert case["outcome"] in ("caught", "not-identifiable", "not-covered"), (name, case)
        half = next(c for c in arm["faults"] if c["label"] == "θ1 +180°")
        assert half["outcome"] in ("caught", "not-identifiable"), (name, half)
    # The published UR5e table maps onto UR's base; base_link, half a turn away,
    # competes for DH frame 0, so θ1 rests on a choice the poses cannot make.
    ur5e = result["arms"]["ur5e"]["published"]
    assert ur5e["pair"] == ["base", "tool0"]
    assert "base_link" in ur5e["numbers"]["θ1"]["competing"]
    # ABB's IRB 120 against ROS-Industrial's description: every number verified.
    assert result["arms"]["irb120"]["published"]["outcome"] == "verified"
