"""Joint axes of a DH table against its URDF, at one configuration (what the report shows).

They agree for every shipped mapping, and a wrong table is caught at the first
joint whose axis moved, by exactly how much it moved. (Ported from the report's
own axis comparison, which now uses :mod:`fkcheck.diagnose.axes`.)
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends.base import BackendUnavailable
from fkcheck.core.tolerances import ROUNDED_URDF
from fkcheck.engine.axes import axis_lines, axis_rows, first_difference
from fkcheck.urdf.locate import example_robot_data_dir
from tests.helpers import BUNDLED, random_q

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


def _rows(model, q, frame_from="base", tol=1e-6):
    lines = axis_lines(model, q, frame_from)
    assert lines is not None
    return axis_rows(model, [lines], tol, tol)


def test_shipped_models_with_a_urdf_are_found():
    assert {"ur3", "ur5", "ur10", "panda"} <= set(WITH_URDF)


#: Models whose URDF agrees with the table (a recorded known difference moves axes).
AGREEING = [n for n in WITH_URDF if not load_model(n).known_differences]


@pytest.mark.parametrize("name", AGREEING)
def test_every_joint_axis_lies_on_the_urdfs(name, rng):
    model = load_model(name)
    for q in random_q(model, rng, 20):
        rows = _rows(model, q, model.check.frame_from, ROUNDED_URDF)
        assert first_difference(rows) is None
        assert max(r.angle_rad for r in rows) <= ROUNDED_URDF
        assert max(r.distance_m or 0.0 for r in rows) <= ROUNDED_URDF
        assert all(r.distance_m is not None for r in rows)  # all revolute: lines with a place


def test_older_d1_moves_the_axis_of_joint_2_by_the_difference(tmp_path, rng):
    model = load_model(_variant(tmp_path, "d = 0.089159", "d = 0.08946"))
    for q in random_q(model, rng, 5):
        rows = _rows(model, q)
        first = first_difference(rows)
        assert first is not None
        assert first.joint == 1  # joint 2, on DH frame 1: row 1 (d1) is wrong
        # Joint 2's axis is horizontal; d1 moves it along z0 by exactly Δd1.
        assert rows[1].distance_m == pytest.approx(0.08946 - 0.089159, abs=1e-12)
        assert max(r.angle_rad for r in rows) <= ROUNDED_URDF  # a length: no axis turns


def test_flipped_alpha_turns_the_next_axis_by_pi(tmp_path, rng):
    model = load_model(_variant(tmp_path, "alpha = 90", "alpha = -90", after='name = "wrist_1"'))
    for q in random_q(model, rng, 5):
        rows = _rows(model, q)
        first = first_difference(rows)
        assert first is not None
        assert first.joint == 4  # joint 5 turns about z of DH frame 4: row 4 (α4) is wrong
        assert rows[4].angle_rad == pytest.approx(math.pi, abs=1e-9)
        assert max(r.angle_rad for r in rows[:4]) <= ROUNDED_URDF


def test_reversed_joint_shows_as_an_axis_turned_by_pi(tmp_path, rng):
    model = load_model(_variant(tmp_path, 'name = "elbow"', 'name = "elbow"\nflip = true'))
    q = random_q(model, rng, 1)[0]
    rows = _rows(model, q)
    first = first_difference(rows)
    assert first is not None
    assert first.joint == 2
    assert first.reversed
    assert rows[2].angle_rad == pytest.approx(math.pi, abs=1e-9)
    assert rows[2].distance_m is not None
    assert rows[2].distance_m <= ROUNDED_URDF  # same line, other way round


def test_lines_are_unit_and_joint_1_is_the_same_line(rng):
    model = load_model("ur5")
    lines = axis_lines(model, random_q(model, rng, 1)[0], "base")
    assert lines is not None
    for directions in (lines.dh_directions, lines.urdf_directions):
        np.testing.assert_allclose(np.linalg.norm(directions, axis=1), 1.0, atol=1e-15)
    # Joint 1 turns about z of base (= DH frame 0) in both descriptions.
    np.testing.assert_allclose(lines.urdf_directions[0], [0.0, 0.0, 1.0], atol=ROUNDED_URDF)
    np.testing.assert_allclose(lines.dh_directions[0], [0.0, 0.0, 1.0], atol=ROUNDED_URDF)


def test_no_urdf_or_no_urdf_twin_means_no_comparison():
    puma = load_model("puma560")
    assert axis_lines(puma, np.zeros(puma.dof), "world") is None
    ur5 = load_model("ur5")
    assert axis_lines(ur5, np.zeros(6), "world") is None  # world: no twin
