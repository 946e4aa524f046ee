"""Named float tolerances, each with the reason for its size. Use these, not literals.

Measured on this project's machines: two float64 implementations of the same DH
chain agree to ~1e-15 (a few ulps per joint); a URDF that writes π/2 as
1.57079632679 differs from exact π/2 by ~4.9e-12 rad per joint, which shows up
as ~1e-11 in poses; real modelling errors start around 1e-4 m (UR5's rounded d1
is 3.0e-4 m off).

A user's tolerances, and a ``[[known_difference]]``'s bounds, are limits a check
obeys: each is refused unless it is within ``(0, MAX_…]``, and a tolerance unless it
is at least ``MIN_…`` (:func:`limit_problem`, the one rule every way in uses: flags,
model files, ``[tool.fkcheck]``, the Python API, the pytest plugin,
:mod:`fkcheck.testing`). A check also holds its position tolerance to the round-off
of its model's reach (:func:`roundoff_floor_m`).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal

from fkcheck.errors import ToleranceError

__all__ = [
    "DEFAULT_TOL_JACOBIAN",
    "DEFAULT_TOL_POS_M",
    "DEFAULT_TOL_ROT_RAD",
    "FAST_CORE",
    "FINITE_DIFFERENCE",
    "FINITE_DIFFERENCE_STEP",
    "LIMITS",
    "MAX_KNOWN_ANGLE_RAD",
    "MAX_KNOWN_POSITION_M",
    "MAX_READER_ANGLE_RAD",
    "MAX_READER_POSITION_M",
    "MAX_TOL_JACOBIAN",
    "MAX_TOL_POS_M",
    "MAX_TOL_ROT_RAD",
    "MIN_TOL_JACOBIAN",
    "MIN_TOL_POS_M",
    "MIN_TOL_ROT_RAD",
    "ROUNDED_URDF",
    "ROUNDOFF_REACH_M",
    "SAME_CHAIN",
    "SIX_DECIMALS",
    "Limit",
    "LimitKind",
    "check_limit",
    "limit_problem",
    "pose_tolerances",
    "roundoff_floor_m",
]

#: Same chain, two float64 implementations (poses of unit-scale arms, m or rad).
#: Round-off is ~1e-15; 1e-12 leaves three orders of margin for long chains.
SAME_CHAIN = 1e-12

#: The in-house core's fast paths (numba kernels with their own polynomial sin/cos,
#: the scalar Python path, the chunked NumPy path) against its plain 4×4 reference
#: chain, entry by entry, for any finite q (m, or unitless rotation entries), for
#: arms of about a metre's reach: observed ≤ 6e-16 on the bundled arms with |q| up
#: to 1e6 rad, since the kernels' sin/cos are within one ulp; 1e-14 leaves an order
#: of magnitude. Round-off grows with the numbers: scale it by the reach (m) beyond.
FAST_CORE = 1e-14

#: A URDF whose angles are π/2 rounded to 11 decimals, against exact DH numbers:
#: observed ~1.4e-11; 1e-9 keeps two orders of margin.
ROUNDED_URDF = 1e-9

#: Values printed to six decimals (the matrices a UR5 forward-kinematics tutorial
#: computes by hand at the ur5 model's pose ``worked_example``): half a unit in the last
#: place is 5e-7, so 1e-6 is the tightest honest bound.
SIX_DECIMALS = 1e-6

#: Step of a central finite difference of poses (rad or m). Truncation error is
#: ~h²/6·|∂³p/∂q³| ≈ 2e-13 for an arm of a metre's reach, round-off ~ε·reach/h ≈
#: 2e-10: 1e-6 balances the two.
FINITE_DIFFERENCE_STEP = 1e-6

#: A Jacobian against central finite differences of poses with
#: :data:`FINITE_DIFFERENCE_STEP` (m per rad, or unitless): the error above is
#: ≤ ~1e-9 for arms of a few metres' reach; 1e-7 leaves two orders of margin and is
#: still five orders below a wrong column (a flipped sign is O(reach)).
FINITE_DIFFERENCE = 1e-7

#: User-facing default tolerances of a check: 1 µm and 1 µrad. Far above any
#: round-off, far below any real modelling error.
DEFAULT_TOL_POS_M = 1e-6
DEFAULT_TOL_ROT_RAD = 1e-6

#: User-facing default tolerance of ``check --jacobian``, on both parts: the linear
#: rows (m/rad; m/m for a prismatic column) and the angular rows (rad/rad). Same
#: scale as the pose defaults: Jacobians of one chain agree to ~1e-15, a URDF's
#: rounded π/2 moves them ~1e-11, finite differences are within
#: :data:`FINITE_DIFFERENCE`, and a wrong convention (a flipped column, the tool
#: offset left out, the wrong reference frame) is of the order of the reach.
DEFAULT_TOL_JACOBIAN = 1e-6

#: Loosest position tolerance a check accepts, metres: 1 cm. Arms are about a metre
#: across; published tables round lengths to 0.1–1 mm and measured poses of an
#: uncalibrated arm are a few mm off, all below 1 cm. A looser check cannot tell a
#: wrong link length from a right one (a UR5 table with d1 10 mm long is wrong).
MAX_TOL_POS_M = 1e-2

#: Loosest rotation tolerance, radians: 0.1 rad (5.7°). Every rotation angle is at
#: most π, so a tolerance near π accepts any rotation at all. An angle error inside
#: the chain already moves the tool by angle × reach (0.1 rad at a metre is 10 cm,
#: ten times :data:`MAX_TOL_POS_M`); what this bound alone guards is the tool's own
#: orientation, whose lever is the tool's length (~10 cm: 0.1 rad moves its tip
#: 1 cm). Angles published to 0.1° are 9e-4 rad off, far below it.
MAX_TOL_ROT_RAD = 0.1

#: Loosest Jacobian tolerance, m/rad (linear rows) and rad/rad (angular rows): 0.01.
#: A column's angular part is a unit axis (0.01 is its direction 0.6° off), its
#: linear part about the reach, ~1 m/rad (0.01 is 1 cm per radian at a metre, as
#: :data:`MAX_TOL_POS_M`). A wrong convention, a flipped column or an all-zero
#: Jacobian is off by about 1 and still fails.
MAX_TOL_JACOBIAN = 1e-2

#: Tightest position tolerance a check accepts, metres, for a model whose lengths add
#: up to at most :data:`ROUNDOFF_REACH_M` (:func:`roundoff_floor_m` scales it beyond):
#: :data:`SAME_CHAIN`, the round-off of two float64 implementations of one chain with
#: three orders of margin. A tighter check judges round-off, not the table (a right table failed at
#: 1e-300), and at 5e-324 the evidence's columns, in tolerances, overflowed to
#: infinity ("SVD did not converge").
MIN_TOL_POS_M = SAME_CHAIN

#: Reach up to which :data:`MIN_TOL_POS_M` holds, metres: round-off grows with the
#: lengths (~ε per metre and joint), and at 10 m it is still two orders below it.
ROUNDOFF_REACH_M = 10.0

#: Tightest rotation tolerance, radians: :data:`SAME_CHAIN`. Rotation entries are
#: unitless, at most 1, whatever the reach: their round-off is a few ulps per joint
#: (256 joints: ~6e-14).
MIN_TOL_ROT_RAD = SAME_CHAIN

#: Tightest Jacobian tolerance, m/rad and rad/rad: :data:`SAME_CHAIN`, as a pose's.
MIN_TOL_JACOBIAN = SAME_CHAIN

#: Largest position error a ``[[known_difference]]`` may record, metres: 0.1 m. A
#: known difference is one finding (a rounded length, a mm offset): the largest a
#: bundled model records is Baxter's 61.8 mm (rounded lengths and a last d that ends
#: at another link). A difference the size of a link (UR5's upper arm is 0.425 m)
#: is a wrong model, and a record that large would excuse one.
MAX_KNOWN_POSITION_M = 0.1

#: Largest rotation error a ``[[known_difference]]`` may record, radians: 0.1 rad
#: (5.7°). Recorded findings are rounded angles (xarm7's ±1.5708: 2.1e-5 rad) or a
#: rounded mount yaw (Baxter: 1.8e-6 rad); angles published to 0.1° are 9e-4 rad off.
#: A missing θ offset (π/2) or a reversed axis (π) is a wrong table, never a known
#: difference.
MAX_KNOWN_ANGLE_RAD = 0.1

#: Largest position error a ``[[known_difference]]`` tied to a reader's library
#: versions (``versions = "<=4.1.0"``) may record, metres: 10 m. A reader's bug is not
#: a wrong model, and it can be as large as the arm: Pinocchio 4.1.0 drops a jointless
#: root body's turn (pinocchio#2782), 1.9 m on Menagerie's UR5e, which is the arm's
#: reach (0.85 m) turned π. Twice the reach of the longest arm fkcheck bundles (UR20:
#: 1.75 m) is 3.5 m; 10 m bounds any arm turned about its base with margin, and still
#: refuses a runaway (an unnormalised axis-angle put one reader 58.6 m off).
MAX_READER_POSITION_M = 10.0

#: Largest rotation error such a record may record, radians: π, every rotation (a
#: reader that drops a half turn is off by exactly π). What keeps it honest is that
#: it applies only to the versions named, never to the table.
MAX_READER_ANGLE_RAD = math.pi

_ROUNDOFF = "a tighter check judges the round-off of float arithmetic, not the table"

LimitKind = Literal[
    "tol_pos",
    "tol_rot",
    "tol_jacobian",
    "known_position",
    "known_angle",
    "reader_position",
    "reader_angle",
]


@dataclass(frozen=True)
class Limit:
    """The range ``(0, upper]`` of one kind of limit (``[lower, upper]``), and why.

    Attributes:
        upper: The largest value allowed (inclusive).
        unit: Its unit, as printed.
        why: The reason for ``upper``, a few words for the error message.
        lower: The smallest value allowed (inclusive); ``0.0``: any above zero.
        lower_why: The reason for ``lower``.
    """

    upper: float
    unit: str
    why: str
    lower: float = 0.0
    lower_why: str = ""


#: Every limit a user sets, by kind.
LIMITS: Mapping[LimitKind, Limit] = MappingProxyType(
    {
        "tol_pos": Limit(
            MAX_TOL_POS_M,
            "m",
            "1 cm: a looser check cannot tell a wrong link length from a right one",
            MIN_TOL_POS_M,
            _ROUNDOFF,
        ),
        "tol_rot": Limit(
            MAX_TOL_ROT_RAD,
            "rad",
            "5.7°: a looser one lets a wrong joint offset through, and at π accepts every rotation",
            MIN_TOL_ROT_RAD,
            _ROUNDOFF,
        ),
        "tol_jacobian": Limit(
            MAX_TOL_JACOBIAN,
            "m/rad and rad/rad",
            "a Jacobian column is about 1 m/rad or 1 rad/rad: a looser one passes wrong columns",
            MIN_TOL_JACOBIAN,
            _ROUNDOFF,
        ),
        "known_position": Limit(
            MAX_KNOWN_POSITION_M,
            "m",
            "a larger difference is a wrong model, not a known difference",
        ),
        "known_angle": Limit(
            MAX_KNOWN_ANGLE_RAD,
            "rad",
            "5.7°: a larger one, such as a missing 90° θ offset, is a wrong model, not a known "
            "difference",
        ),
        "reader_position": Limit(
            MAX_READER_POSITION_M,
            "m",
            "a reader's recorded difference (versions = …) may be as large as the arm turned "
            "about its base, no larger",
        ),
        "reader_angle": Limit(MAX_READER_ANGLE_RAD, "rad", "a rotation is at most π"),
    }
)


def _number(value: object) -> float:
    """``value`` as a float; NaN for a boolean or a non-number, inf for a huge integer."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return math.nan
    try:
        return float(value)
    except OverflowError:  # an integer of hundreds of digits: refused whatever its sign
        return math.inf


def limit_problem(value: object, kind: LimitKind) -> str | None:
    """Why ``value`` cannot be a limit of this kind, one phrase; ``None`` when it can.

    The phrase names the range and the value: ``must be > 0 and at most 0.01 m
    (…), got 1000``; ``must be at least 1e-12 m (…), got 1e-300`` below a
    tolerance's floor. NaN, infinities, zero, negatives, booleans and non-numbers
    are all refused.
    """
    limit = LIMITS[kind]
    number = _number(value)
    if limit.lower <= number <= limit.upper and number > 0.0:
        return None
    if 0.0 < number < limit.lower:
        return f"must be at least {limit.lower:g} {limit.unit} ({limit.lower_why}), got {number:g}"
    if isinstance(value, float) or (math.isfinite(number) and not isinstance(value, bool)):
        shown = f"{number:g}"
    elif isinstance(value, int) and not isinstance(value, bool):
        shown = "an integer too large for a float"
    else:
        text = repr(value)
        shown = text if len(text) <= 40 else text[:39] + "…"
    return f"must be > 0 and at most {limit.upper:g} {limit.unit} ({limit.why}), got {shown}"


def check_limit(value: object, kind: LimitKind, where: str) -> float:
    """``value`` as a float when it is within its range (see :func:`limit_problem`).

    Raises:
        ToleranceError: It is not; the message names ``where`` (a flag, an argument).
    """
    problem = limit_problem(value, kind)
    if problem is not None:
        raise ToleranceError(where, problem)
    return _number(value)


def pose_tolerances(
    tol_pos_m: float | None,
    tol_rot_rad: float | None,
    defaults: tuple[float, float],
    reach_m: float = 0.0,
) -> tuple[float, float]:
    """The check's ``(m, rad)`` tolerances: each given one, checked, else its default.

    The position tolerance is also held to :func:`roundoff_floor_m` of the model's
    ``reach_m``: a model a kilometre long rounds off more than 1e-12 m.

    Raises:
        ToleranceError: A given tolerance is out of its range, or the position
            tolerance (given or the default) is below the model's round-off.
    """
    tol = (
        defaults[0] if tol_pos_m is None else check_limit(tol_pos_m, "tol_pos", "tol_pos_m"),
        defaults[1] if tol_rot_rad is None else check_limit(tol_rot_rad, "tol_rot", "tol_rot_rad"),
    )
    floor = roundoff_floor_m(reach_m)
    if tol[0] < floor:
        raise ToleranceError(
            "tol_pos_m" if tol_pos_m is not None else "the model's [check] tol_pos_m",
            f"must be at least {floor:g} m for a model whose lengths add up to {reach_m:g} m "
            f"({_ROUNDOFF}), got {tol[0]:g}",
        )
    return tol


def roundoff_floor_m(reach_m: float) -> float:
    """The tightest position tolerance for a model whose lengths add up to ``reach_m``, metres.

    :data:`MIN_TOL_POS_M` up to :data:`ROUNDOFF_REACH_M`; beyond, it grows with the
    reach, as round-off does (a 1 km arm's poses round off 100 times a 10 m arm's).
    """
    return MIN_TOL_POS_M * max(1.0, reach_m / ROUNDOFF_REACH_M)
