"""Joint axes of a DH table against its URDF: they agree for every shipped mapping,
and a wrong table is caught at the first joint whose axis moved."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import BUNDLED, random_q
from fkcheck import load_model
from fkcheck.backends.base import BackendUnavailable
from fkcheck.report.urdf_axes import compare_joint_axes
from fkcheck.tolerances import ROUNDED_URDF
from fkcheck.urdf_source import example_robot_data_dir

WITH_URDF = [name for name in BUNDLED if load_model(name).urdf is not None]
UR5 = Path(load_model("ur5").path or "")


@pytest.fixture(autouse=True)
def _needs_example_robot_data():
    try:
        example_robot_data_dir()
    except BackendUnavailable as exc:
        pytest.skip(f"the bundled URDFs come from example-robot-data: {exc}")


def _variant(tmp_path: Path, old: str, new: str, after: str = "") -> Path:
    """The bundled UR5 file with one line changed (the first match after ``after``)."""
    text = UR5.read_text(encoding="utf-8")
    start = text.index(after) if after else 0
    at = text.index(old, start)
    path = tmp_path / "ur5_variant.toml"
    path.write_text(text[:at] + new + text[at + len(old) :], encoding="utf-8")
    return path


def test_shipped_models_with_a_urdf_are_found():
    assert {"ur3", "ur5", "ur10", "panda"} <= set(WITH_URDF)


@pytest.mark.parametrize("name", WITH_URDF)
def test_every_joint_axis_lies_on_the_urdfs(name, rng):
    model = load_model(name)
    for q in random_q(model, rng, 20):
        axes = compare_joint_axes(model, q, model.check.frame_from, ROUNDED_URDF, ROUNDED_URDF)
        assert axes is not None
        assert axes.first is None
        assert axes.angle_rad.max() <= ROUNDED_URDF
        assert axes.offset_m.max() <= ROUNDED_URDF


def test_older_d1_moves_the_axis_of_joint_2_by_the_difference(tmp_path, rng):
    model = load_model(_variant(tmp_path, "d = 0.089159", "d = 0.08946"))
    for q in random_q(model, rng, 5):
        axes = compare_joint_axes(model, q, "base", 1e-6, 1e-6)
        assert axes is not None
        assert axes.first == 1  # joint 2, on DH frame 1: row 1 (d1) is wrong
        # Joint 2's axis is horizontal; d1 moves it along z0 by exactly Δd1.
        assert axes.offset_m[1] == pytest.approx(0.08946 - 0.089159, abs=1e-12)
        assert axes.angle_rad.max() <= ROUNDED_URDF  # a length: no axis turns


def test_flipped_alpha_turns_the_next_axis_by_pi(tmp_path, rng):
    model = load_model(_variant(tmp_path, "alpha = 90", "alpha = -90", after='name = "wrist_1"'))
    for q in random_q(model, rng, 5):
        axes = compare_joint_axes(model, q, "base", 1e-6, 1e-6)
        assert axes is not None
        assert axes.first == 4  # joint 5 turns about z of DH frame 4: row 4 (α4) is wrong
        assert axes.angle_rad[4] == pytest.approx(math.pi, abs=1e-9)
        assert axes.angle_rad[:4].max() <= ROUNDED_URDF


def test_reversed_joint_shows_as_an_axis_turned_by_pi(tmp_path, rng):
    model = load_model(_variant(tmp_path, 'name = "elbow"', 'name = "elbow"\nflip = true'))
    q = random_q(model, rng, 1)[0]
    axes = compare_joint_axes(model, q, "base", 1e-6, 1e-6)
    assert axes is not None
    assert axes.first == 2
    assert axes.angle_rad[2] == pytest.approx(math.pi, abs=1e-9)
    assert axes.offset_m[2] <= ROUNDED_URDF  # same line, other way round


def test_no_urdf_or_no_urdf_twin_means_no_comparison():
    puma = load_model("puma560")
    assert compare_joint_axes(puma, np.zeros(puma.dof), "world", 1e-6, 1e-6) is None
    ur5 = load_model("ur5")
    assert compare_joint_axes(ur5, np.zeros(6), "world", 1e-6, 1e-6) is None  # world: no twin
