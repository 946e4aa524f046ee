"""Named float tolerances, each with the reason for its size. Use these, not literals.

Measured on this project's machines: two float64 implementations of the same DH
chain agree to ~1e-15 (a few ulps per joint); a URDF that writes π/2 as
1.57079632679 differs from exact π/2 by ~4.9e-12 rad per joint, which shows up
as ~1e-11 in poses; real modelling errors start around 1e-4 m (UR5's rounded d1
is 3.0e-4 m off).
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_TOL_JACOBIAN",
    "DEFAULT_TOL_POS_M",
    "DEFAULT_TOL_ROT_RAD",
    "FAST_CORE",
    "FINITE_DIFFERENCE",
    "FINITE_DIFFERENCE_STEP",
    "ROUNDED_URDF",
    "SAME_CHAIN",
    "SIX_DECIMALS",
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
