"""fkcheck.model_from_table: a model in code, validated as a model file is."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fkcheck
from fkcheck.model.read import model_from_dict

ROWS = [(0.3, 0.0, 0.1, 0.0), (0.2, math.pi / 2, 0.0, 0.0)]


def test_frames_and_check_default_as_a_toml_models_do():
    model = fkcheck.model_from_table("2r", ROWS)
    from_file = model_from_dict(
        {"name": "2r", "convention": "standard",
         "joint": [{"a": 0.3, "alpha": 0.0, "d": 0.1}, {"a": 0.2, "alpha": math.pi / 2, "d": 0.0}]}
    )  # fmt: skip
    assert model.frames == from_file.frames
    assert set(model.frames) == {"world", "tcp"}
    assert model.check == from_file.check
    assert model.joints == from_file.joints
    assert model.path is None


def test_world_to_tcp_check_runs():
    model = fkcheck.model_from_table("2r", ROWS)
    outcome = fkcheck.check(model, against=["rtb-dh"], samples=20)
    assert outcome.verdict == "pass"
    assert (outcome.check.frame_from, outcome.check.frame_to) == ("world", "tcp")


def test_dict_rows_degrees_limits_and_numpy():
    rows = np.array([[0.3, 0.0, 0.1, 0.0], [0.2, 90.0, 0.0, 0.0]])
    model = fkcheck.model_from_table(
        "2r", rows, angle_unit="deg", limits=[(-180, 180), None], check={"tol_pos_m": 1e-7}
    )
    assert model.joints[1].alpha == pytest.approx(math.pi / 2)
    assert model.joints[0].limits == pytest.approx((-math.pi, math.pi))
    assert model.check.tol_pos_m == 1e-7
    row = {"a": 0.3, "alpha": np.float32(0), "d": 0, "name": "s"}
    named = fkcheck.model_from_table("2r", [row])
    assert named.joint_names == ("s",)


@pytest.mark.parametrize(
    ("rows", "kwargs", "message"),
    [
        ([(0.3, 0.0, 0.0)], {}, "<model>: joint[0]: a tuple row is (a, alpha, d, theta), got 3"),
        ([ROWS[0], (0.2, "x", 0.0, 0.0)], {}, "<model>: joint[1].alpha: expected a number"),
        ([{"a": 0.1, "alpha": 0, "d": 0, "thta": 0}], {}, "<model>: joint[0].thta: unknown key"),
        ([{"a": 0.1, "alpha": 0, "theta": 0}], {}, "<model>: joint[0].d: missing (required)"),
        (ROWS, {"convention": "dh"}, "<model>: convention: "),
        (ROWS, {"limits": [(0, 1)]}, "<model>: limits: 1 limits for 2 joints"),
        ("ab", {}, "<model>: joint: expected a sequence of rows, got str"),
    ],
)
def test_a_bad_row_is_one_model_error_line(rows, kwargs, message):
    with pytest.raises(fkcheck.ModelError) as info:
        fkcheck.model_from_table("2r", rows, **kwargs)
    text = str(info.value)
    assert text.startswith(message)
    assert "\n" not in text


def test_a_bad_choice_names_the_alternatives():
    with pytest.raises(fkcheck.ModelError, match=r"standard.*modified"):
        fkcheck.model_from_table("2r", ROWS, convention="dh")


def test_a_model_built_directly_has_the_default_frames_too():
    joint = fkcheck.Joint("j", 0.1, 0.0, 0.0, 0.0)
    direct = fkcheck.Model(name="1r", convention="standard", joints=(joint,))
    assert direct.frames == fkcheck.model_from_table("1r", [(0.1, 0.0, 0.0, 0.0)]).frames
    assert fkcheck.check(direct, against=["rtb-dh"], samples=5).verdict == "pass"
