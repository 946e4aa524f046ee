"""The analysis' numeric settings: samples, steps and thresholds, each justified.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

__all__ = [
    "BLAME_MARGIN",
    "CARRY_EPS",
    "CHECK_SAMPLES",
    "FLAT",
    "FREED_PRISMATIC_M",
    "MOVING_EPS",
    "RESOLUTION_LIMIT",
    "SAMPLES",
    "SPAN_RTOL",
    "STEP",
    "TRADE_SHARE",
]

#: Configurations the sensitivities are taken at (seeded, uniform within limits).
#: Generic configurations: 64 × 6 rows for at most 4·256 + 24 numbers.
SAMPLES = 64
#: Of the check's own configurations, at most this many (a seeded subset) are
#: analysed: a thousand-sample check's first 256 already tell more than it needs.
CHECK_SAMPLES = 256
#: Central-difference step of every number (m or rad). Columns are O(1) per unit;
#: truncation ~h² ≈ 1e-12, round-off ~ε·reach/h ≈ 1e-10 relative.
STEP = 1e-6
#: A column lies in a span when what is left of it is below this fraction of its
#: length: far above the differences' ~1e-10, far below what an independent
#: direction leaves over 64 random configurations (≥ 1e-3 on every bundled arm).
SPAN_RTOL = 1e-6
#: An offset carries a direction when its distance from the identity changes
#: along it faster than this (rad, or m at ``L``): above the round-off of a
#: URDF's rounded π/2 (~5e-12) and of ``fkcheck map``'s snapped numbers (1e-9).
CARRY_EPS = 1e-9
#: A number moves the compared pose when some configuration's twist per unit of it
#: exceeds this (m/m, rad/rad…): an unobstructed number moves it 1:1, central
#: differences leave ~1e-10.
MOVING_EPS = 1e-6
#: How much better than a check's configurations generic ones must show a
#: combination before the check's are blamed for hiding it (root mean square).
BLAME_MARGIN = 3.0
#: A number takes part in a combination when its share of it is above this
#: fraction of the largest share (rows of an orthonormal basis: noise ~1e-10).
TRADE_SHARE = 1e-3
#: An offset's angle is flat along a turn when its curvature there is below this
#: fraction of the identity's: a half turn about an axis across it (exactly flat),
#: or within a few tenths of a degree of one.
FLAT = 1e-3
#: A number is verified only if an error of this many tolerances (in its own
#: unit: tol_pos for lengths, tol_rot for angles), alone, would fail the check.
#: An unobstructed length or angle shows 1:1 (resolution = one tolerance); 10
#: leaves room for a partial overlap with a carried offset.
RESOLUTION_LIMIT = 10.0
#: A held (or limit-confined) sliding joint is freed this far either side of its
#: range's middle (m) to see what the kinematics could tell. A prismatic joint
#: has no natural range (a revolute one has its turn), and a change of the table
#: hidden at one displacement shows, to first order, in proportion to the
#: displacement: an angle error of one tolerance (1 µrad) moves the pose by one
#: more µm per metre of slide. Whatever changes with the displacement at all is
#: what the kinematics could tell, not what shows within an arbitrary metre (the
#: sampling default for a slide without limits): 10 m shows such a change ten
#: times as much, a tenth of a tolerance per tolerance at a hundredth of the
#: rate, while the largest column stays ~10 per unit, so the differences'
#: round-off (~ε·10/STEP ≈ 2e-9 relative) stays far below ``SPAN_RTOL``. A slide
#: held farther from zero than this is freed its held displacement either side: held
#: at s, a tilt of what follows it is mostly a translation s times as large, which
#: lengths make up, so a fixed 10 m shows such a change only about 10/s as much
#: (Stanford's slide held at 100 m read verified). The round-off grows with s:
#: ~ε·2s/STEP, 4e-7 relative at 1 km, still under ``SPAN_RTOL``.
FREED_PRISMATIC_M = 10.0

_AXES = ("x", "y", "z")
_COMPONENTS = ("x", "y", "z", "rx", "ry", "rz")  # translations along, rotations about
