"""What a solver's answer may be: ``(k, n)`` real numbers at float64 precision, ``k`` ≥ 0."""

from __future__ import annotations

import numpy as np
import pytest

from fkcheck.ik.solver import IkSolverError, validated_solutions


@pytest.mark.parametrize(
    ("answer", "shape"),
    [([], (0, 6)), (np.zeros((0, 6)), (0, 6)), (np.ones(6), (1, 6)), ([[1] * 6] * 3, (3, 6)),
     (np.full((2, 6), np.nan), (2, 6))],
)  # fmt: skip
def test_answers_that_are_answers(answer, shape):
    out = validated_solutions("s", answer, 6)
    assert out.shape == shape
    assert out.dtype == np.float64


@pytest.mark.parametrize(
    ("answer", "message"),
    [
        (np.zeros((2, 5)), r"returned shape \(2, 5\); expected \(k, 6\)"),
        (np.zeros((2, 6, 1)), r"returned shape \(2, 6, 1\)"),
        (np.zeros((1, 6), dtype=np.float32), "dtype float32; expected real numbers at float64"),
        (np.zeros((1, 6), dtype=complex), "dtype complex128"),
        (np.array([["a"] * 6]), "dtype <U1"),
        (np.array([[object()] * 6]), "dtype object"),
    ],
)
def test_answers_that_are_not(answer, message):
    with pytest.raises(IkSolverError, match=message):
        validated_solutions("s", answer, 6)
