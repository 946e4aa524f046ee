"""Hypothesis strategies: random DH tables as the model files would hold them."""

from __future__ import annotations

import math
from typing import Any

from hypothesis import strategies as st

from fkcheck.model.read import model_from_dict
from fkcheck.model.types import Model

#: Special angles where implementations take different branches or lose digits.
SPECIAL_ANGLES = (0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi, 1e-9, -1e-9)
#: Lengths: zero, tiny, and up to a few metres (large arms). Agreement to 1e-12 m
#: needs |lengths| × n × ulp ≲ 1e-13, which 5 m × 10 joints × 2.2e-16 meets.
SPECIAL_LENGTHS = (0.0, 1e-9, -1e-9, 5.0, -5.0)

angles = st.one_of(
    st.sampled_from(SPECIAL_ANGLES),
    st.floats(-2 * math.pi, 2 * math.pi, allow_nan=False, allow_infinity=False),
)
lengths = st.one_of(
    st.sampled_from(SPECIAL_LENGTHS),
    st.floats(-5.0, 5.0, allow_nan=False, allow_infinity=False),
)


@st.composite
def joints(draw: st.DrawFn, index: int) -> dict[str, Any]:
    kind = draw(st.sampled_from(("revolute", "revolute", "prismatic")))
    lo = draw(st.floats(-math.pi, 0.0) if kind == "revolute" else st.floats(-1.0, 0.0))
    hi = draw(st.floats(0.0, math.pi) if kind == "revolute" else st.floats(0.0, 1.0))
    return {
        "name": f"j{index}",
        "type": kind,
        "a": draw(lengths),
        "alpha": draw(angles),
        "d": draw(lengths),
        "theta": draw(angles),
        "flip": draw(st.booleans()),
        "limits": [lo, hi],
    }


offsets = st.fixed_dictionaries(
    {
        "xyz": st.lists(lengths, min_size=3, max_size=3),
        "rpy": st.lists(angles, min_size=3, max_size=3),
    }
)


@st.composite
def dh_models(draw: st.DrawFn, max_joints: int = 10) -> Model:
    n = draw(st.integers(1, max_joints))
    data: dict[str, Any] = {
        "name": "random",
        "convention": draw(st.sampled_from(("standard", "modified"))),
        "joint": [draw(joints(i)) for i in range(n)],
    }
    if draw(st.booleans()):
        data["base"] = draw(offsets)
    if draw(st.booleans()):
        data["tool"] = draw(offsets)
    return model_from_dict(data)
