"""The bounds of a user's limits: one rule (``limit_problem``) for every way a limit comes in."""

from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np
import pytest

from fkcheck.core.tolerances import (
    DEFAULT_TOL_JACOBIAN,
    DEFAULT_TOL_POS_M,
    DEFAULT_TOL_ROT_RAD,
    FINITE_DIFFERENCE,
    LIMITS,
    MAX_KNOWN_ANGLE_RAD,
    MAX_KNOWN_POSITION_M,
    MAX_READER_ANGLE_RAD,
    MAX_READER_POSITION_M,
    MAX_TOL_JACOBIAN,
    MAX_TOL_POS_M,
    MAX_TOL_ROT_RAD,
    check_limit,
    limit_problem,
)
from fkcheck.errors import FkcheckError, ToleranceError
from fkcheck.model.read import bundled_model_paths, load_model


@pytest.mark.parametrize("kind", sorted(LIMITS))
def test_the_range_is_from_its_floor_up_to_the_bound_inclusive(kind):
    upper, lower = LIMITS[kind].upper, LIMITS[kind].lower
    tiny = (1e-300, 5e-324) if lower == 0.0 else (lower, np.float64(lower))
    for value in (upper, upper / 2, *tiny, np.float64(upper), np.float32(upper / 2)):
        assert limit_problem(value, kind) is None, value
    assert limit_problem(Fraction(1, 1000), "tol_pos") is None  # any real number, as a float


@pytest.mark.parametrize("kind", ["tol_pos", "tol_rot", "tol_jacobian"])
@pytest.mark.parametrize("value", [1e-300, 5e-324, 9.99e-13])
def test_a_tolerance_below_the_round_off_is_refused(kind, value):
    # 5e-324 made the evidence's columns infinite (SVD did not converge); 1e-300 failed a
    # right table on round-off (issue 31).
    problem = limit_problem(value, kind)
    assert problem is not None
    assert problem.startswith(f"must be at least 1e-12 {LIMITS[kind].unit} (a tighter check ")
    assert problem.endswith(f"got {value:g}")


def test_known_differences_have_no_floor():
    # A tiny recorded difference excuses nothing: it is harmless, and stays allowed.
    assert limit_problem(1e-300, "known_position") is None
    assert limit_problem(5e-324, "known_angle") is None


@pytest.mark.parametrize("kind", sorted(LIMITS))
@pytest.mark.parametrize(
    "value",
    [0, 0.0, -0.0, -1e-9, math.nan, math.inf, -math.inf, 1e300, 10**400, -(10**400), 1000],
)
def test_zero_negative_nan_infinite_and_huge_are_refused(kind, value):
    problem = limit_problem(value, kind)
    assert problem is not None
    assert problem.startswith(
        f"must be > 0 and at most {LIMITS[kind].upper:g} {LIMITS[kind].unit} ("
    )


@pytest.mark.parametrize("kind", sorted(LIMITS))
def test_just_above_the_bound_is_refused(kind):
    upper = LIMITS[kind].upper
    assert limit_problem(math.nextafter(upper, math.inf), kind) is not None


@pytest.mark.parametrize(
    ("value", "shown"),
    [
        (True, "True"),
        ("0.001", "'0.001'"),
        (None, "None"),
        ([0.001], r"\[0\.001\]"),
        (10**400, "an integer too large for a float"),
        (1e300, r"1e\+300"),
        (math.nan, "nan"),
        (-2, "-2"),
        ("x" * 100, "'x{38}…"),
    ],
)
def test_the_problem_names_the_value(value, shown):
    problem = limit_problem(value, "tol_pos")
    assert problem is not None
    assert "\n" not in problem
    assert re.search(f", got {shown}$", problem), problem


def test_a_rotation_tolerance_of_pi_or_more_is_always_refused():
    # Every rotation angle is within [0, π]: such a tolerance accepts any rotation.
    # π/2 too: a missing 90° θ offset is a wrong table, never a known difference.
    for value in (math.pi, math.pi / 2, 3.2, 10.0):
        assert limit_problem(value, "tol_rot") is not None
        assert limit_problem(value, "known_angle") is not None


def test_check_limit_raises_one_line_naming_where():
    assert check_limit(1e-3, "tol_pos", "--tol-pos") == 1e-3
    assert type(check_limit(np.float32(1e-3), "tol_pos", "--tol-pos")) is float
    with pytest.raises(
        ToleranceError,
        match=r"^--tol-pos: must be > 0 and at most 0\.01 m \(1 cm: a looser check cannot tell a "
        r"wrong link length from a right one\), got 1000$",
    ) as info:
        check_limit(1000, "tol_pos", "--tol-pos")
    assert isinstance(info.value, FkcheckError)  # the CLI's exit 2
    assert isinstance(info.value, ValueError)  # numeric code's usual catch
    assert (info.value.where, info.value.problem) == ("--tol-pos", limit_problem(1000, "tol_pos"))
    with pytest.raises(ToleranceError, match=r"^tol_rot_rad: must be > 0 and at most 0\.1 rad"):
        check_limit(10, "tol_rot", "tol_rot_rad")
    with pytest.raises(ToleranceError, match=r"^tol_jacobian: must be > 0 and at most 0\.01 m/rad"):
        check_limit(1e300, "tol_jacobian", "tol_jacobian")


def test_the_defaults_and_the_engine_s_own_tolerances_are_inside_the_bounds():
    assert 0 < DEFAULT_TOL_POS_M < MAX_TOL_POS_M
    assert 0 < DEFAULT_TOL_ROT_RAD < MAX_TOL_ROT_RAD
    assert 0 < DEFAULT_TOL_JACOBIAN < MAX_TOL_JACOBIAN
    assert FINITE_DIFFERENCE < MAX_TOL_JACOBIAN  # the floor a finite-difference Jacobian gets
    # A known difference may record more than a tolerance may accept, never less.
    assert MAX_KNOWN_POSITION_M >= MAX_TOL_POS_M
    assert MAX_KNOWN_ANGLE_RAD >= MAX_TOL_ROT_RAD
    # A reader's recorded difference may be larger than a table's, and a rotation is at most π.
    assert MAX_READER_POSITION_M > MAX_KNOWN_POSITION_M
    assert math.pi == MAX_READER_ANGLE_RAD


@pytest.mark.parametrize("name", sorted(bundled_model_paths()))
def test_every_bundled_model_is_inside_the_bounds(name):
    model = load_model(name)
    assert limit_problem(model.check.tol_pos_m, "tol_pos") is None
    assert limit_problem(model.check.tol_rot_rad, "tol_rot") is None
    assert limit_problem(model.check.tol_jacobian, "tol_jacobian") is None
    for known in model.known_differences:
        # A reader's own difference, for its library's versions, may be as large as the arm.
        position, angle = (
            ("reader_position", "reader_angle")
            if known.versions
            else ("known_position", "known_angle")
        )
        assert limit_problem(known.max_position_m, position) is None
        assert limit_problem(known.max_angle_rad, angle) is None
    # Only a record tied to a reader's versions goes beyond the table's 0.1 m and 0.1 rad.
    assert all(
        limit_problem(k.max_position_m, "known_position") is None
        and limit_problem(k.max_angle_rad, "known_angle") is None
        for k in model.known_differences
        if not k.versions
    )
