"""How numbers read: two values that differ never read the same, nor a difference as zero."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fkcheck.io.format import format_delta, format_distinct


@pytest.mark.parametrize(
    ("a", "b", "digits", "expected"),
    [
        (-1.5708, -math.pi / 2, 6, ("-1.5708", "-1.570796")),
        (math.degrees(-1.5708), -90.0, 4, ("-90.0002", "-90")),
        (0.089459, 0.089159, 6, ("0.089459", "0.089159")),  # enough already: unchanged
        (90.0, 90.0, 4, ("90", "90")),  # the same value reads the same
        (-0.0, 0.0, 4, ("0", "0")),
        (1.0, math.nextafter(1.0, 2.0), 6, ("1", "1.0000000000000002")),
    ],
)
def test_two_values_get_the_digits_that_tell_them_apart(a, b, digits, expected):
    assert format_distinct(a, b, digits) == expected


def test_no_two_different_values_read_the_same(rng):
    """Random pairs, near and far: the texts differ exactly when the values do."""
    for _ in range(2000):
        a = float(rng.normal()) * 10.0 ** float(rng.integers(-6, 6))
        b = a + float(rng.normal()) * 10.0 ** float(rng.integers(-15, 0)) * abs(a)
        ta, tb = format_distinct(a, b, 4)
        assert (ta != tb) == (a != b), (a, b, ta, tb)
        assert float(ta) == pytest.approx(a, rel=1e-3)


@pytest.mark.parametrize(
    ("value", "decimals", "expected"),
    [(0.3, 3, "+0.300"), (-0.3, 3, "-0.300"), (0.0, 4, "+0.0000"), (2.1e-7, 4, "+2.1e-07"),
     (-4.4e-5, 4, "-4.4e-05"), (np.float64(0.00021), 4, "+0.0002")],
)  # fmt: skip
def test_a_difference_never_reads_as_zero_when_it_is_not(value, decimals, expected):
    assert format_delta(value, decimals) == expected
