"""Edits of a table's rows: applied to a model, said in the file's unit, half turns as signs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fkcheck.model.edits import TableEdits, format_turn, half_turns_as_signs
from fkcheck.model.types import Joint, Model
from tests.vendor_arms import dh_row


def _model(unit: str = "deg") -> Model:
    joints = (
        Joint("A1", a=0.26, alpha=-math.pi / 2, d=0.675),
        Joint("A2", a=0.68, alpha=0.0, d=0.0),
        Joint("A3", a=0.035, alpha=-math.pi / 2, d=0.0, flip=True),
    )
    return Model(name="m", convention="standard", joints=joints, angle_unit=unit)  # type: ignore[arg-type]


def test_edits_apply_to_a_new_model_and_leave_the_old_one():
    model = _model()
    edits = TableEdits(
        flips=("A1", "A3"),
        thetas=(("A2", -math.pi / 2),),
        negated=(("A3", "alpha"),),
        values=(("A2", "a", 0.681),),
    )
    edited = edits.apply(model)
    assert [j.flip for j in edited.joints] == [True, False, False]
    assert edited.joints[1].theta == -math.pi / 2
    assert edited.joints[1].a == 0.681
    assert edited.joints[2].alpha == math.pi / 2
    assert model.joints[1].theta == 0.0  # unchanged
    assert edits.count == 5
    assert not TableEdits()


def test_lines_say_each_edit_in_the_files_unit_in_joint_order():
    edits = TableEdits(
        flips=("A3", "A1"), thetas=(("A2", -math.pi / 2),), negated=(("A3", "alpha"),),
        values=(("A2", "a", 0.681),),
    )  # fmt: skip
    assert edits.lines(_model("deg")) == [
        "[[joint]] A1: flip = true",
        "[[joint]] A2: a = 0.681 (was 0.68: a2 differs)",
        "[[joint]] A2: theta = -90 (was 0: θ2's zero -90° away)",
        "[[joint]] A3: flip = false",
        "[[joint]] A3: alpha = 90 (was -90: α3's sign)",
    ]
    rad = edits.lines(_model("rad"))
    assert "[[joint]] A2: theta = -1.5707963267948966 (was 0: θ2's zero -90° away)" in rad
    assert "[[joint]] A3: alpha = 1.5707963267948966 (was -1.5707963267948966: α3's sign)" in rad


def test_only_alpha_and_a_may_be_negated():
    with pytest.raises(ValueError, match="cannot negate 'd': only alpha, a"):
        TableEdits(negated=(("A1", "d"),))


@pytest.mark.parametrize(("rad", "text"), [(math.pi / 2, "+90°"), (-math.pi / 2, "-90°"),
                                           (math.pi, "180°"), (-math.pi, "180°")])  # fmt: skip
def test_turns_read_as_people_say_them(rad, text):
    assert format_turn(rad) == text


@pytest.mark.parametrize("a", [0.0, 0.3])
def test_two_half_turns_are_the_sign_of_the_row_between_them(a, rng):
    """θ2 + 180° and θ3 + 180° move the chain as α2 (and a2) with the other sign: checked here."""
    rows = [(0.1, -math.pi / 2, 0.4, 0.0), (a, math.pi / 2, 0.2, 0.3), (0.2, 0.0, 0.1, 0.0)]
    joints = tuple(
        Joint(f"J{k}", a=r[0], alpha=r[1], d=r[2], theta=r[3]) for k, r in enumerate(rows)
    )
    thetas = [0.0, math.pi, -math.pi]
    negated = half_turns_as_signs(joints, "standard", thetas)
    assert negated == ([(1, "alpha"), (1, "a")] if a else [(1, "alpha")])
    assert thetas == [0.0, 0.0, 0.0]
    for q in rng.uniform(-3, 3, size=(10, 3)):
        turned = np.eye(4)
        signed = np.eye(4)
        for k, ((ak, alpha, d, theta), qk) in enumerate(zip(rows, q, strict=True)):
            turn = (0.0, math.pi, -math.pi)[k]
            turned = turned @ dh_row(ak, alpha, d, theta + turn + qk)
            sign = -1.0 if k == 1 else 1.0
            signed = signed @ dh_row(sign * ak, sign * alpha, d, theta + qk)
        np.testing.assert_allclose(turned, signed, atol=1e-12)
