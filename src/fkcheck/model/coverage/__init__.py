"""Which numbers of a model one check can vouch for: per-number evidence.

A check compares one relative pose, ``from_T_to(q)``, with evidence that does not
come from the table (a URDF, measured poses, a published table). Agreement proves
what that pose depends on — and only where nothing else in the model could have
absorbed an error. This module decides, for every number of the model, what a
check of one frame pair can say about it:

* the table: each row's ``a``, ``α``, ``d``, ``θ`` (by their textbook names,
  :mod:`fkcheck.model.names`) and its joint's direction (``flip``: not a small
  number, so judged by turning the joint the other way on the check's own
  configurations);
* a declared ``[base]`` and ``[tool]`` (six components each: translations along
  and rotations about their own axes);
* the offsets of the two compared frames (``[frames.NAME]``).

Statuses (:data:`Status`):

``verified``
    The compared pose depends on it, no offset of a compared frame carries
    what it produces, and the check's own configurations tell it apart: alone,
    an error in it larger than its *resolution* (shown; at most
    :data:`RESOLUTION_LIMIT` tolerances) would have failed the check.
    Numbers that trade only against each other inside the compared chain (UR's
    d2, d3, d4 along parallel axes) describe the same kinematics however they
    are split: each is verified, and :attr:`NumberEvidence.trades_with` says that
    only their combination is.
``not-identifiable``
    An offset of a compared frame carries a component this number produces over
    every configuration (``d1 ≡ translation along z of DH frame 0, carried by
    [frames.base]``): a wrong number and an offset fitted around it (``fkcheck
    map``, ``--to urdf:LINK``) agree with any reference. Also a number the
    check's configurations cannot tell from others that the kinematics do
    separate (two measured poses against 24 numbers), and one whose effect
    survives the offsets only so faintly that an error of more than
    :data:`RESOLUTION_LIMIT` tolerances would pass.
``not-covered``
    The compared pose does not depend on it: it is outside the frame pair.
``vouched``
    A compared frame's offset that the model vouches for with its ``source``
    (``[frames.NAME] source = "…"``): taken as given, it hides nothing, and every
    output shows the source.

*Decided from the kinematics, not from names.* The sensitivity of ``from_T_to``
to each number is taken by central differences of the in-house core on seeded
configurations within limits (first order), as body twists in units of the
check's tolerances. A compared frame's offset can absorb a number when the
number's column lies in the span of the offset's six columns; it *carries* that
direction when the offset is not indifferent to it: the distance of the offset
from the identity (``angle² + (|t|/L)²``, ``L = tol_pos / tol_rot``) has a
non-zero slope along it. A frame that sits exactly on a DH frame (no offset)
carries nothing, so the numbers next to it stay verified; so does a
translation across the first joint's axis, which no table number produces. A
90° turn about the first joint's axis is carried: it is exactly what a wrong θ1
looks like.

The modules: :mod:`~fkcheck.model.coverage.analysis` (:func:`coverage`),
:mod:`~fkcheck.model.coverage.results` (the result types and their wording),
:mod:`~fkcheck.model.coverage.tuning` (the thresholds),
:mod:`~fkcheck.model.coverage.sensitivity` (the numbers as columns, the
configurations), :mod:`~fkcheck.model.coverage.spectrum` (spans, weak directions,
trades), :mod:`~fkcheck.model.coverage.held` (joints held still, the limits),
:mod:`~fkcheck.model.coverage.carrying` (what an offset carries, absorbs, takes),
:mod:`~fkcheck.model.coverage.links` (the choice among links),
:mod:`~fkcheck.model.coverage.evidence` (each number's status) and
:mod:`~fkcheck.model.coverage.clock` (the time limit).
"""

from __future__ import annotations

from fkcheck.model.coverage.analysis import coverage
from fkcheck.model.coverage.links import FEWEST, MAX_COMPETITORS, PRODUCE_ITERATIONS, TURNS_RAD
from fkcheck.model.coverage.results import (
    SOURCE_SHOWN,
    Competitor,
    Coverage,
    NumberEvidence,
    Reason,
    Status,
)

# Used by the tests, from this path.
from fkcheck.model.coverage.sensitivity import _numbers as _numbers
from fkcheck.model.coverage.sensitivity import _Pose as _Pose
from fkcheck.model.coverage.sensitivity import _twist_matrix as _twist_matrix
from fkcheck.model.coverage.tuning import (
    BLAME_MARGIN,
    CARRY_EPS,
    CHECK_SAMPLES,
    FLAT,
    FREED_PRISMATIC_M,
    MOVING_EPS,
    RESOLUTION_LIMIT,
    SAMPLES,
    SPAN_RTOL,
    STEP,
    TRADE_SHARE,
)

__all__ = [
    "BLAME_MARGIN",
    "CARRY_EPS",
    "CHECK_SAMPLES",
    "FEWEST",
    "FLAT",
    "FREED_PRISMATIC_M",
    "MAX_COMPETITORS",
    "MOVING_EPS",
    "PRODUCE_ITERATIONS",
    "RESOLUTION_LIMIT",
    "SAMPLES",
    "SOURCE_SHOWN",
    "SPAN_RTOL",
    "STEP",
    "TRADE_SHARE",
    "TURNS_RAD",
    "Competitor",
    "Coverage",
    "NumberEvidence",
    "Reason",
    "Status",
    "coverage",
]
