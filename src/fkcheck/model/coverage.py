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
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from fkcheck.core import dh
from fkcheck.core.geometry import invert
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.errors import TimeLimitError
from fkcheck.model.names import PARAMS, param_symbol
from fkcheck.model.sampling import UNLIMITED_PRISMATIC_M, sampling_box
from fkcheck.model.types import FrameSpec, Model, Offset, resolve_frame

__all__ = [
    "BLAME_MARGIN",
    "CARRY_EPS",
    "CHECK_SAMPLES",
    "FEWEST",
    "FLAT",
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

Status = Literal["verified", "not-identifiable", "not-covered", "vouched"]
#: Why a number is not identifiable: an offset carries it; another link of the
#: description could be the DH frame instead of the compared one (``link``: the
#: choice among them is a fit); an offset fitted over the check's configurations
#: takes it; they cannot tell a joint's direction, or the number from others; the
#: joint limits keep it from others that free joints tell apart; or its effect is
#: too faint for the tolerance.
Reason = Literal["", "offset", "link", "taken", "direction", "configurations", "limits", "faint"]
Unit = Literal["m", "rad"]

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

_AXES = ("x", "y", "z")
_COMPONENTS = ("x", "y", "z", "rx", "ry", "rz")  # translations along, rotations about


@dataclass(frozen=True)
class NumberEvidence:
    """What one check can say about one number of the model.

    Attributes:
        name: ``d1``, ``α4`` (a row's number), ``[base] z``, ``[frames.base_link] rz``
            (a component of an offset: a translation along or rotation about its own axis).
        group: ``joint 1 (shoulder_pan)``, ``[base]``, ``[tool]``, ``[frames.NAME]``.
        unit: ``m`` or ``rad``.
        status: ``verified``, ``not-identifiable``, ``not-covered`` or ``vouched``.
        table: Part of the table the headline speaks of (rows, ``[base]``,
            ``[tool]``); ``False`` for a compared frame's offset.
        resolution: The smallest error of it alone that the check would catch, in
            ``unit`` (first order); ``None`` when nothing catches it.
        absorbed_by: For ``not-identifiable``: which offset carries it, and how
            (``[frames.base]: translation along z of DH frame 0``), or why else
            (the check's configurations cannot tell it from others; too faint).
        trades_with: Other verified numbers that only its combination with is
            checked (parallel axes).
        source: For ``vouched``: the model's source for the offset.
        reason: For ``not-identifiable``, which kind of reason (:data:`Reason`).
        by: The compared frames' offsets (``[frames.NAME]``) that carry or take it.
        competing: For reason ``link``: the description's links that could be the
            DH frame instead of the compared one.
        on_word_of: For ``verified``: the vouched frames (``[frames.NAME]``) without
            whose ``source`` it would not be identifiable: verified on their word.
    """

    name: str
    group: str
    unit: Unit
    status: Status
    table: bool
    resolution: float | None = None
    absorbed_by: str = ""
    trades_with: tuple[str, ...] = ()
    source: str = ""
    reason: Reason = ""
    by: tuple[str, ...] = ()
    competing: tuple[str, ...] = ()
    on_word_of: tuple[str, ...] = ()


@dataclass(frozen=True, eq=False)
class Competitor:
    """Another link of the description, rigidly attached to a compared frame's link.

    Which link of a description is DH frame 0, or the last DH frame, is a choice.
    When another link sits where a change of the table's numbers at that end would
    put the DH frame exactly, choosing the compared link over it is a fit: those
    numbers are not identifiable unless a frame of the group is vouched for.

    Attributes:
        link: Its name in the description.
        anchor_T_link: Where it sits relative to the compared frame's DH frame (or
            ``world``/``tcp``), 4×4, metres: the compared frame's offset composed
            with the description's fixed joints between the two links.
    """

    link: str
    anchor_T_link: Float


@dataclass(frozen=True)
class Coverage:
    """Every number of a model against one compared frame pair.

    Attributes:
        frame_from: The frame the compared pose is expressed in.
        frame_to: The frame whose pose is compared.
        numbers: One entry per number, rows first, then base, tool, frames.
        joints_spanned: 1-based joints whose motion moves ``from_T_to``.
        tol_pos_m: Position tolerance the resolutions are measured in, metres.
        tol_rot_rad: Rotation tolerance, radians.
        vouches: The vouched frames some verified number rests on, with their
            ``source``: ``(("[frames.base_link]", "UR's ur_macro.xacro …"), …)``.
    """

    frame_from: str
    frame_to: str
    numbers: tuple[NumberEvidence, ...]
    joints_spanned: tuple[int, ...]
    tol_pos_m: float
    tol_rot_rad: float
    vouches: tuple[tuple[str, str], ...] = ()

    @property
    def table_numbers(self) -> tuple[NumberEvidence, ...]:
        """The numbers of the table (rows, declared base and tool)."""
        return tuple(n for n in self.numbers if n.table)

    def count(self, status: Status) -> int:
        """How many table numbers have ``status``."""
        return sum(n.status == status for n in self.table_numbers)

    @property
    def complete(self) -> bool:
        """Whether every table number is verified (what "table verified" needs)."""
        return all(n.status == "verified" for n in self.table_numbers)

    @property
    def spans_no_joint(self) -> bool:
        """The pair moves with no joint: it cannot verify any row of the table."""
        return not self.joints_spanned

    def by_status(self, status: Status) -> tuple[NumberEvidence, ...]:
        """Table numbers with ``status``, in table order."""
        return tuple(n for n in self.table_numbers if n.status == status)

    @property
    def vouched(self) -> tuple[NumberEvidence, ...]:
        """Compared frames' offsets taken from their ``source``."""
        return tuple(n for n in self.numbers if n.status == "vouched")

    def on_word(self) -> str:
        """Which verified table numbers rest on a vouch, and whose; ``""`` when none.

        E.g. ``θ1, α6 on the word of [frames.base_link] ("UR's ur_macro.xacro …")``.
        """
        resting = [n for n in self.table_numbers if n.status == "verified" and n.on_word_of]
        if not resting:
            return ""
        sources = dict(self.vouches)
        whose = _unique(f for n in resting for f in n.on_word_of)
        by_source: dict[str, list[str]] = {}  # frames whose shown sources read the same, once
        for frame in whose:
            by_source.setdefault(_cut(sources.get(frame, "")), []).append(frame)
        said = ", ".join(f'{", ".join(frames)} ("{cut}")' for cut, frames in by_source.items())
        return f"{_short(resting)} on the word of {said}"

    def gaps(self) -> str:
        """What keeps the table from being verified, one clause; ``""`` when nothing does.

        E.g. ``d1, θ6 not identifiable (the offsets of [frames.base], [frames.tool0]
        could absorb them); [base] not covered (outside base → tool0)``.
        """
        if self.spans_no_joint:
            return f"the pair {self.frame_from} → {self.frame_to} spans no joint"
        parts = []
        hidden = self.by_status("not-identifiable")
        clauses: dict[Reason, str] = {
            "offset": "the offset{s} of {by} could absorb {them}",
            "link": "link{ls} {links} of the description could be the DH frame instead of "
            "{by}: the choice is a fit; vouch for the frame with source",
            "taken": "over the check's configurations the offset{s} of {by} could take {them}",
            "direction": "the check's configurations cannot tell which way the joint turns",
            "configurations": "the check's configurations cannot tell them apart: compare more",
            "limits": "the joint limits keep any configuration from telling them apart: "
            "are the limits right?",
            "faint": "too faint for the tolerance",
        }
        for reason, clause in clauses.items():
            these = [n for n in hidden if n.reason == reason]
            if not these:
                continue
            by = _unique(f for n in these for f in n.by)
            links = _unique(link for n in these for link in n.competing)
            text = clause.format(
                s="s" if len(by) > 1 else "", by=", ".join(by),
                them="it" if len(these) == 1 else "them",
                ls="s" if len(links) > 1 else "", links=", ".join(links),
            )  # fmt: skip
            parts.append(f"{_short(these)} not identifiable ({text})")
        uncovered = self.by_status("not-covered")
        if uncovered:
            parts.append(
                f"{_short(uncovered)} not covered (outside {self.frame_from} → {self.frame_to})"
            )
        return "; ".join(parts)

    @property
    def verifies_any(self) -> bool:
        """Whether the pair verifies at least one number of the rows (a direction aside)."""
        return not self.spans_no_joint and any(
            n.status == "verified" and not n.name.startswith("flip") for n in self.table_numbers
        )

    def scope(self) -> str:
        """What the pair can verify, before any check: ``every number of the table except …``."""
        if self.spans_no_joint:
            return f"no number of the table ({self.gaps()})"
        if self.complete:
            return "every number of the table"
        if len(self.joints_spanned) == len(_row_groups(self)):
            return f"every number of the table except {self.gaps()}"
        return f"joints {_ranges(self.joints_spanned)} of {len(_row_groups(self))}; {self.gaps()}"

    def summary(self) -> str:
        """``table verified``, ``table verified except …`` or ``table partly verified: …``."""
        if self.spans_no_joint:
            return f"table not verified: {self.gaps()}"
        if self.complete:
            word = self.on_word()
            return f"table verified, {word}" if word else "table verified"
        if not self.verifies_any:
            return f"table not verified: {self.gaps()}"
        dof = len(_row_groups(self))
        if len(self.joints_spanned) == dof:
            return f"table verified except {self.gaps()}"
        return (
            f"table partly verified: joints {_ranges(self.joints_spanned)} of {dof}; {self.gaps()}"
        )


def _ranges(joints: Sequence[int]) -> str:
    """``1–3, 5`` for ``(1, 2, 3, 5)``."""
    parts: list[str] = []
    start = prev = joints[0]
    for j in (*joints[1:], None):
        if j is not None and j == prev + 1:
            prev = j
            continue
        parts.append(str(start) if start == prev else f"{start}–{prev}")
        if j is not None:
            start = prev = j
    return ", ".join(parts)


def _row_groups(c: Coverage) -> list[str]:
    return _unique(n.group for n in c.table_numbers if n.group.startswith("joint "))


def _unique(items: Iterable[str]) -> list[str]:
    out: list[str] = []
    for item in items:
        if item not in out:
            out.append(item)
    return out


#: A vouch's source in a headline is cut to this many characters (the JSON and
#: the numbers' table carry it whole).
SOURCE_SHOWN = 60


def _cut(text: str) -> str:
    return text if len(text) <= SOURCE_SHOWN else text[: SOURCE_SHOWN - 1] + "…"


def _short(numbers: Sequence[NumberEvidence]) -> str:
    """Names, with a whole offset group shown once: ``d1, θ6, [base]``."""
    rows = [n for n in numbers if n.group.startswith("joint ")]
    if len(rows) > 8:  # a whole table's worth: count, don't list
        rest = _short([n for n in numbers if not n.group.startswith("joint ")])
        return f"{len(rows)} numbers of the rows" + (f", {rest}" if rest else "")
    out: list[str] = []
    for n in numbers:
        label = n.group if n.group.startswith("[") else n.name
        if label not in out:
            out.append(label)
    return ", ".join(out)


# ----------------------------------------------------------------------------- sensitivities


class _Clock:
    """The analysis' time limit, looked at between its steps.

    A step is at most one decomposition of the model's columns (about a second at
    :data:`~fkcheck.model.types.MAX_JOINTS` joints), or one number's nudge.
    """

    def __init__(self, limit_s: float | None, what: str) -> None:
        self.limit_s, self.what = limit_s, what
        self.deadline = math.inf if limit_s is None else time.monotonic() + limit_s

    def check(self) -> None:
        """Raise :class:`TimeLimitError` once the limit has passed."""
        if time.monotonic() > self.deadline:
            raise TimeLimitError(
                f"per-number evidence of {self.what} did not finish within the check's "
                f"time limit of {self.limit_s:g} s; give it more with --timeout"
            )


_NO_LIMIT = _Clock(None, "")


@dataclass(frozen=True)
class _Number:
    """A number to nudge: where it lives and how."""

    name: str
    group: str
    unit: Unit
    kind: Literal["row", "flip", "base", "tool", "from", "to", "joint"]
    index: int  # row (0-based) for row and joint, component 0…5 for offsets
    param: str = ""

    @property
    def table(self) -> bool:
        return self.kind in ("row", "flip", "base", "tool")


def _twist_matrix(component: int, h: float) -> Float:
    """``exp(h·e_component)`` as a 4×4: a translation along or a rotation about an axis."""
    from scipy.spatial.transform import Rotation

    E = np.eye(4)
    if component < 3:
        E[component, 3] = h
    else:
        rotvec = np.zeros(3)
        rotvec[component - 3] = h
        E[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    return E


class _Pose:
    """``from_T_to`` of one model and frame pair, with any one number nudged.

    The chain's frames are computed once by the core (``dh.fk``, every DH frame).
    A nudged number changes one link (a row's number, a joint value), the base,
    the tool or one compared frame's offset; only the compared ends at or after it
    move, each by the same left factor: ``F'_k = F_i · A'_{i+1} · F_{i+1}⁻¹ · F_k``
    for a link. A nudge costs a few 4×4 products per configuration, not a
    chain (``n`` numbers × ``n`` links × configurations was minutes at the model
    limit); the round-off is the chain's own, ε·reach, against a step of ``2h``.
    """

    def __init__(self, model: Model, q: Float, spec_from: FrameSpec, spec_to: FrameSpec) -> None:
        self.chain, self.q = model.chain, np.asarray(q, dtype=np.float64)
        self.spec = {"from": spec_from, "to": spec_to}
        self.frames = np.asarray(dh.fk(self.chain, self.q, all_frames=True))
        self.offsets = {side: spec.offset.matrix for side, spec in self.spec.items()}
        tool = self.chain.flange_T_tool
        n = self.chain.dof
        # Each end's anchor and the index of the DH frame it sits on (the TCP on the
        # last one, after the tool; the world, before the base, on none: -1).
        self.index: dict[str, int] = {}
        self.anchor: dict[str, Float] = {}
        for side, spec in self.spec.items():
            self.index[side] = -1 if spec.dh == "world" else n if spec.dh == "tcp" else int(spec.dh)
            self.anchor[side] = _anchor(spec, self.frames, tool)
        self.ends = {side: self.anchor[side] @ self.offsets[side] for side in self.spec}
        self.inverse = invert(self.frames)

    def _link(
        self, i: int, q: Float, sign: Float | None = None, param: str = "", h: float = 0.0
    ) -> Float:
        """``A_{i+1}`` at joint values ``q[:, i]`` (``param`` nudged by ``h``), ``(N, 4, 4)``."""
        chain = self.chain
        values = {p: float(getattr(chain, p)[i]) for p in ("a", "alpha", "d", "theta")}
        if param:
            values[param] += h
        s = float(chain.sign[i] if sign is None else sign[i])
        qs = q[:, i] * s
        if chain.prismatic[i]:
            d, theta = qs + values["d"], np.full_like(qs, values["theta"])
        else:
            d, theta = np.full_like(qs, values["d"]), qs + values["theta"]
        A: Float = dh.dh_matrix(chain.convention, values["a"], values["alpha"], d, theta)
        return A

    def _relinked(self, i: int, A_new: Float) -> Float:
        """``from_T_to`` with link ``i + 1`` replaced by ``A_new``."""
        head = self.frames[:, i] @ A_new
        ends = {
            side: head @ (self.inverse[:, i + 1] @ end) if self.index[side] > i else end
            for side, end in self.ends.items()
        }
        return invert(ends["from"]) @ ends["to"]

    def _moved(self, first: int, L: Float) -> Float:
        """``from_T_to`` with every end on DH frame ``first`` or later moved by ``L``."""
        ends = {
            side: L @ end if self.index[side] >= first else end for side, end in self.ends.items()
        }
        return invert(ends["from"]) @ ends["to"]

    def pose(self, number: _Number | None = None, h: float = 0.0) -> Float:
        if number is None:
            return invert(self.ends["from"]) @ self.ends["to"]
        kind, i = number.kind, number.index
        if kind == "row":
            return self._relinked(i, self._link(i, self.q, param=number.param, h=h))
        if kind in ("joint", "flip"):
            q = self.q.copy()
            q[:, i] += h
            return self._relinked(i, self._link(i, q))
        E = _twist_matrix(i, h)
        if kind == "base":
            B = self.chain.world_T_base
            return self._moved(0, B @ E @ invert(B))
        ends = dict(self.ends)
        if kind == "tool":
            tool = self.chain.flange_T_tool
            ends = {
                side: self.frames[:, -1] @ tool @ E @ self.offsets[side]
                if self.spec[side].dh == "tcp"
                else end
                for side, end in ends.items()
            }
        else:  # a compared frame's offset
            ends[kind] = self.anchor[kind] @ self.offsets[kind] @ E
        return invert(ends["from"]) @ ends["to"]

    def flipped(self, i: int) -> Float:
        """``from_T_to`` with joint ``i + 1`` turning the other way."""
        sign = self.chain.sign.copy()
        sign[i] = -sign[i]
        return self._relinked(i, self._link(i, self.q, sign))

    def changed(self, changes: Sequence[tuple[_Number, float]]) -> Float:
        """``from_T_to`` with each ``(number, h)`` of ``changes`` changed by ``h``, at once.

        The whole chain again, for finite changes of several numbers (the search
        for the numbers that put a DH frame on a competing link, on a few
        configurations); :meth:`pose` nudges one number, incrementally.
        """
        chain, q = self.chain, self.q
        base, tool = chain.world_T_base, chain.flange_T_tool
        offsets = {side: spec.offset.matrix for side, spec in self.spec.items()}
        for number, h in changes:
            kind = number.kind
            if kind == "row":
                values = getattr(chain, number.param).copy()
                values[number.index] += h
                chain = replace(chain, **{number.param: values})
            elif kind in ("joint", "flip"):
                q = q.copy()
                q[:, number.index] += h
            elif kind == "base":
                base = base @ _twist_matrix(number.index, h)
            elif kind == "tool":
                tool = tool @ _twist_matrix(number.index, h)
            else:  # "from", "to"
                offsets[kind] = offsets[kind] @ _twist_matrix(number.index, h)
        chain = replace(chain, world_T_base=base, flange_T_tool=tool)
        frames = np.asarray(dh.fk(chain, q, all_frames=True))
        ends = {
            side: _anchor(spec, frames, tool) @ offsets[side] for side, spec in self.spec.items()
        }
        out: Float = invert(ends["from"]) @ ends["to"]
        return out


def _anchor(spec: FrameSpec, frames: Float, tool: Float) -> Float:
    """World → the DH frame (or world, TCP) a frame sits on, ``(N, 4, 4)``."""
    if spec.dh == "world":
        return np.broadcast_to(np.eye(4), frames[:, 0].shape)
    if spec.dh == "tcp":
        out: Float = frames[:, -1] @ tool
        return out
    return frames[:, int(spec.dh)]


def _twists(pose: _Pose, F_inv: Float, number: _Number, clock: _Clock = _NO_LIMIT) -> Float:
    """The body twist of ``from_T_to`` per unit of ``number``, ``(N, 6)`` (m and rad)."""
    clock.check()
    G = (F_inv @ pose.pose(number, STEP) - F_inv @ pose.pose(number, -STEP)) / (2.0 * STEP)
    W = G[:, :3, :3]
    w = np.stack([W[:, 2, 1] - W[:, 1, 2], W[:, 0, 2] - W[:, 2, 0], W[:, 1, 0] - W[:, 0, 1]], 1)
    twists: Float = np.concatenate([G[:, :3, 3], w / 2.0], axis=1)
    return twists


def _numbers(model: Model, pair: tuple[FrameSpec, FrameSpec]) -> list[_Number]:
    """The table's numbers, a declared base and tool, and the compared frames' offsets."""
    out: list[_Number] = []
    for i, joint in enumerate(model.joints):
        group = f"joint {i + 1} ({joint.name})"
        for param in PARAMS:
            unit: Unit = "m" if param in ("a", "d") else "rad"
            out.append(_Number(param_symbol(model, i, param), group, unit, "row", i, param))
        out.append(_Number(f"flip{i + 1}", group, "rad", "flip", i))
    for kind, offset in (("base", model.base), ("tool", model.tool)):
        if not offset.is_identity:
            out.extend(
                _Number(f"[{kind}] {comp}", f"[{kind}]", _unit(c), kind, c)  # type: ignore[arg-type]
                for c, comp in enumerate(_COMPONENTS)
            )
    sides = (("from", pair[0]), ("to", pair[1])) if pair[0].name != pair[1].name else ()
    for side, spec in sides:
        if not spec.offset.is_identity:
            group = f"[frames.{spec.name}]"
            out.extend(
                _Number(f"{group} {comp}", group, _unit(c), side, c)  # type: ignore[arg-type]
                for c, comp in enumerate(_COMPONENTS)
            )
    return out


def _flip_errors(
    model: Model,
    specs: dict[str, FrameSpec],
    q: Float,
    tols: tuple[float, float],
    clock: _Clock = _NO_LIMIT,
) -> Float:
    """Per joint, how far (in tolerances) ``from_T_to`` moves at worst if it turned the other way.

    A joint's direction is not a small number: its error is the whole mirror of
    its motion, measured on the check's own configurations (joint values of
    only 0 and π cannot tell it).
    """
    pose = _Pose(model, q, specs["from"], specs["to"])
    F = pose.pose()
    out = np.zeros(model.dof)
    for i in range(model.dof):
        clock.check()
        G = pose.flipped(i)
        out[i] = max(
            float((position_error_m(F, G) / tols[0]).max()),
            float((rotation_error_rad(F, G) / tols[1]).max()),
        )
    return out


def _unit(component: int) -> Unit:
    return "m" if component < 3 else "rad"


def _subset(q: Float, samples: int, seed: int) -> Float:
    """At most ``samples`` rows of ``q``, a seeded choice (all of them when fewer)."""
    q = np.asarray(q, dtype=np.float64)
    if q.shape[0] <= samples:
        return q
    rows = np.sort(np.random.default_rng(seed).choice(q.shape[0], samples, replace=False))
    subset: Float = q[rows]
    return subset


def _configurations(
    model: Model, samples: int, seed: int, free: Sequence[int] | None = ()
) -> Float:
    """Seeded configurations within limits; the joints in ``free`` (all: ``None``) freed.

    A freed joint ranges over at least a whole turn (revolute) or
    :data:`~fkcheck.model.sampling.UNLIMITED_PRISMATIC_M` either side of its
    range's middle (prismatic): what the kinematics could tell, whatever the limits.
    """
    lo, hi = sampling_box(model)
    for j in range(model.dof) if free is None else free:
        if model.joints[j].type == "prismatic":
            mid = (lo[j] + hi[j]) / 2.0
            lo[j], hi[j] = (
                min(lo[j], mid - UNLIMITED_PRISMATIC_M),
                max(hi[j], mid + UNLIMITED_PRISMATIC_M),
            )
        else:
            lo[j], hi[j] = min(lo[j], -math.pi), max(hi[j], math.pi)
    rng = np.random.default_rng(seed)
    q: Float = lo + (hi - lo) * rng.random((samples, model.dof))
    return q


def _held_still(
    model: Model,
    specs: dict[str, FrameSpec],
    q: Float,
    spanned: Sequence[int],
    tols: tuple[float, float],
) -> list[int]:
    """Joints (0-based) whose whole range moves the pose by at most ``RESOLUTION_LIMIT`` tolerances.

    Over configurations ``q`` within limits: the joint's twist per unit, at its
    worst, times its range (``[0, 0]``, ``[v, v]``, ±1e-7°: held still).
    """
    lo, hi = sampling_box(model)
    pose = _Pose(model, q, specs["from"], specs["to"])
    F_inv = invert(pose.pose())
    out = []
    for j in range(model.dof):
        if j + 1 not in spanned:
            continue
        twist = _twists(pose, F_inv, _Number("", "", "rad", "joint", j))
        per_unit = max(
            float(np.linalg.norm(twist[:, :3], axis=1).max()) / tols[0],
            float(np.linalg.norm(twist[:, 3:], axis=1).max()) / tols[1],
        )
        if per_unit * float(hi[j] - lo[j]) <= RESOLUTION_LIMIT:
            out.append(j)
    return out


def _limited(
    model: Model,
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    removed: Sequence[tuple[list[int], Float]],
    within: Float,
    candidates: Sequence[bool],
    frozen: Sequence[int],
    samples: int,
    seed: int,
    tols: tuple[float, float],
) -> dict[int, tuple[tuple[int, ...], tuple[int, ...]]]:
    """Numbers the joint limits tie: ``{i: (the numbers, the joints whose limits do)}``.

    ``within`` is the residual over configurations within limits, in tolerances
    per tolerance of each number; ``frozen`` the joints whose whole range moves
    the pose by at most :data:`RESOLUTION_LIMIT` tolerances (``[0, 0]``,
    ±1e-7°). The same numbers with those joints free (a whole turn each) show
    what the kinematics could tell: a combination only their limits hide is the
    limits'. A joint is named when freeing it alone shows that number's combination.
    """
    if not frozen:  # every joint moves the pose within its limits: they hide nothing
        return {}
    unit_tol = np.array([tols[0] if n.unit == "m" else tols[1] for n in numbers])

    def residual(free: Sequence[int] | None) -> Float:
        J = _sensitivities(
            model, specs, numbers, _configurations(model, samples, seed, free), tols
        )[0]
        out: Float = _without(J, [J[:, c] @ k for c, k in removed]) * unit_tol
        return out

    ties = _hidden(residual(frozen), within, candidates, samples)
    if not ties:
        return {}
    held: dict[int, list[int]] = {}
    for j in frozen:
        shown = _hidden(residual([j]), within, candidates, samples)
        for i in ties:
            if i in shown:  # freeing this joint alone tells the number apart
                held.setdefault(i, []).append(j)
    return {i: (others, tuple(held.get(i, ()))) for i, others in ties.items()}


def _hidden(
    free: Float, within: Float, candidates: Sequence[bool], configurations: int
) -> dict[int, tuple[int, ...]]:
    """Numbers in combinations ``within`` hides and ``free`` shows: ``{i: (the others, …)}``.

    Among the combinations ``within`` shows under a tenth of (root mean square),
    those free joints do not leave a trade: ``free`` shows them at least a tenth
    (:data:`RESOLUTION_LIMIT`) root mean square, or at the worst configuration —
    the complement of :func:`_trades`' test, with no margin: a combination an
    error of :data:`RESOLUTION_LIMIT` tolerances of would show with the joints
    free describes other kinematics, which only the limits keep from failing the
    check. They are read in sparsest (reduced row echelon) bases: of those shown
    at :data:`BLAME_MARGIN` tenths and of those at one tenth (root mean square),
    and of the rest, those shown at a tenth at the worst configuration — each
    basis on its own, since the sparsest basis of a larger set can mix every
    combination the limits hide with one they do not. Each combination is kept
    when the worst configuration within limits shows it under a tenth too.
    """
    idx = [i for i, c in enumerate(candidates) if c]
    if len(idx) < 2:
        return {}
    strict = _weak(_spectrum(within[:, idx]), configurations, RESOLUTION_LIMIT)
    if not len(strict):
        return {}
    _, sv, vt = np.linalg.svd(free[:, idx] @ strict.T, full_matrices=False)
    bar = math.sqrt(configurations) / RESOLUTION_LIMIT  # a tenth, root mean square
    bases = [_rref(vt[sv >= level * bar] @ strict) for level in (BLAME_MARGIN, 1.0)]
    rest = _rref(vt[sv < bar] @ strict)
    if len(rest):  # shown at the worst configuration with the joints free
        effect = np.einsum("nrk,vk->vnr", free[:, idx].reshape(-1, 6, len(idx)), rest)
        worst = np.maximum(
            np.linalg.norm(effect[:, :, :3], axis=2), np.linalg.norm(effect[:, :, 3:], axis=2)
        ).max(axis=1)
        bases.append(rest[worst * RESOLUTION_LIMIT >= np.linalg.norm(rest, axis=1)])
    shown = np.vstack(bases)
    per = within[:, idx].reshape(-1, 6, len(idx))
    out: dict[int, set[int]] = {}
    for vec in shown:
        size = float(np.linalg.norm(vec))
        effect = np.einsum("nrk,k->nr", per, vec)
        shows = np.maximum(
            np.linalg.norm(effect[:, :3], axis=1), np.linalg.norm(effect[:, 3:], axis=1)
        )
        if float(shows.max()) * RESOLUTION_LIMIT >= size:
            continue
        support = [idx[k] for k in np.flatnonzero(np.abs(vec) > TRADE_SHARE * np.abs(vec).max())]
        for m in support:
            out.setdefault(m, set()).update(x for x in support if x != m)
    return {m: tuple(sorted(others)) for m, others in out.items()}


# ----------------------------------------------------------------------------- carrying


def _carries(offset: Offset, xi: Float, length_m: float) -> bool:
    """:func:`_carries_matrix` of an offset."""
    return _carries_matrix(offset.matrix, xi, length_m)


def _carries_matrix(M: Float, xi: Float, length_m: float) -> bool:
    """Whether ``offset`` may hold a component along the twist ``xi`` (its own axes, m and rad).

    Moved back along ``xi`` by ``s``, the offset's turn is ``R·exp(−s·ω)`` and its
    shift ``t − s·R·v`` (first order). It carries none of ``xi`` only when ``s = 0``
    is where both are strictly nearest the identity: the slope of ``angle²``
    (``−2 φ·ω``, ``φ`` its rotation vector) and of ``|t − s·R·v|²`` (``−2 (R·v)·t``)
    are both zero — each on its own, so a turn and a shift cannot cancel — and the
    angle is not flat there (a half turn about an axis across ``ω`` stays a half
    turn whatever ``s``: a wrong θ1 hides in it). Anything else may be an error
    fitted into the offset, and counts as carried.
    """
    from scipy.spatial.transform import Rotation

    R, t = M[:3, :3], M[:3, 3]
    v, w = xi[:3], xi[3:]
    w_norm, v_norm = float(np.linalg.norm(w)), float(np.linalg.norm(v)) / length_m
    size = max(w_norm, v_norm)
    if size == 0.0:
        return False
    # A part below the differences' noise is no part: d1's shift has no turn.
    w_norm = w_norm if w_norm > SPAN_RTOL * size else 0.0
    v_norm = v_norm if v_norm > SPAN_RTOL * size else 0.0
    phi = Rotation.from_matrix(R).as_rotvec()
    if w_norm > 0.0 and abs(float(phi @ w)) / w_norm > CARRY_EPS:
        return True
    if v_norm > 0.0 and abs(float((R @ v) @ t)) / (v_norm * length_m**2) > CARRY_EPS:
        return True
    if w_norm == 0.0:
        return False
    h = 1e-3  # rad along ω: the angle's second difference, against the identity's 2h²
    unit = w / w_norm

    def angle(s: float) -> float:
        turned = R @ Rotation.from_rotvec(-s * unit).as_matrix()
        return float(np.linalg.norm(Rotation.from_matrix(turned).as_rotvec()))

    curvature = angle(h) ** 2 + angle(-h) ** 2 - 2.0 * angle(0.0) ** 2
    return curvature < FLAT * 2.0 * h * h


def _describe(xi: Float, spec: FrameSpec) -> str:
    """``translation along z of DH frame 0`` for a twist ``xi`` in the frame's own axes."""
    M = spec.offset.matrix
    R, t = M[:3, :3], M[:3, 3]
    w = R @ xi[3:]  # in the anchor's axes
    v = R @ xi[:3] + np.cross(t, w)  # the same twist seen from the anchor's origin
    anchor = {"world": "the world", "tcp": "the TCP"}.get(str(spec.dh), f"DH frame {spec.dh}")

    def axis(u: Float) -> str:
        size = float(np.linalg.norm(u))
        if size == 0.0:
            return "(no direction)"
        u = u / size
        k = int(np.argmax(np.abs(u)))
        if abs(abs(u[k]) - 1.0) < 1e-6:
            return _AXES[k]
        return "(" + ", ".join(f"{x:.3g}" for x in u) + ")"

    wn, vn = float(np.linalg.norm(w)), float(np.linalg.norm(v))
    if wn <= 1e-9 * vn:
        return f"translation along {axis(v)} of {anchor}"
    through = np.cross(w, v) / (wn * wn)  # the axis' point nearest the anchor's origin
    where = "" if np.linalg.norm(through) < 1e-9 else " (an axis off its origin)"
    kind = "screw" if abs(v @ w) > 1e-9 * wn * max(vn, 1.0) else "rotation"
    return f"{kind} about {axis(w)} of {anchor}{where}"


# ----------------------------------------------------------------------------- the analysis


def coverage(
    model: Model,
    frame_from: str,
    frame_to: str,
    tol_pos_m: float,
    tol_rot_rad: float,
    *,
    samples: int = SAMPLES,
    seed: int = 0,
    q: Float | None = None,
    competitors: Mapping[str, Sequence[Competitor]] | None = None,
    time_limit_s: float | None = None,
) -> Coverage:
    """Every number of ``model`` against a check of ``frame_from → frame_to``.

    A check verifies only what its own configurations exercise: pass them as
    ``q`` (a seeded subset of :data:`CHECK_SAMPLES` of them when there are more;
    a few measured poses identify less than a thousand samples, and the
    analysis then says so). Without ``q``, ``samples`` seeded configurations
    within limits.

    Args:
        model: The model (its frames include any placed ``urdf:LINK``).
        frame_from: The frame the compared pose is expressed in.
        frame_to: The frame whose pose is compared.
        tol_pos_m: The check's position tolerance, metres.
        tol_rot_rad: The check's rotation tolerance, radians.
        samples: Configurations the sensitivities are taken at (at most).
        seed: Their seed (or of the subset of ``q``).
        q: The check's configurations ``(N, n)``, radians / metres.
        competitors: By compared frame name, the other links of the description
            rigidly attached to its link (:class:`Competitor`): where one sits
            exactly where a change of the table's numbers at that end would put
            the DH frame, those numbers are not identifiable (reason ``link``),
            unless a frame of the group is vouched for (then verified on its word).
        time_limit_s: The analysis' time limit, seconds (a check's ``--timeout``);
            ``None``: none.

    Raises:
        FrameError: An unknown frame.
        TimeLimitError: The analysis did not finish within ``time_limit_s``.
    """
    specs = {"from": resolve_frame(model, frame_from), "to": resolve_frame(model, frame_to)}
    numbers = _numbers(model, (specs["from"], specs["to"]))
    tols = (tol_pos_m, tol_rot_rad)
    clock = _Clock(time_limit_s, f"{model.name} ({frame_from} → {frame_to})")
    # What the pair can tell, over generic configurations (the kinematics) …
    generic = _configurations(model, samples, seed)
    J, moving, spanned = _sensitivities(model, specs, numbers, generic, tols, clock)
    norms = np.linalg.norm(J, axis=0)
    offsets = _absorption(specs, numbers, J, moving, norms, tols)
    word = _vouched_absorption(specs, numbers, J, moving, norms, tols, offsets)
    links = _link_choice(
        model, specs, numbers, (generic, J, moving), tols, competitors or {},
        set(offsets.absorbed), clock,
    )  # fmt: skip
    for i, frames in links.on_word.items():
        word.on_word.setdefault(i, []).extend(f for f in frames if f not in word.on_word[i])
    word.sources.update(links.sources)
    # A number a choice among links could hide is a discrete ambiguity: its continuous
    # direction is still seen, and still trades (or is held by the limits) with others.
    absorbed = offsets.absorbed
    unit_tol = np.array([tol_pos_m if n.unit == "m" else tol_rot_rad for n in numbers])
    candidates = [
        bool(moving[i] and n.table and n.kind != "flip" and i not in absorbed)
        for i, n in enumerate(numbers)
    ]
    rows = generic.shape[0]
    generic_residual = _without(J, [J[:, c] @ k for c, k in offsets.absorbing]) * unit_tol
    # One SVD of the candidates' generic columns: for the trades, and for what the
    # check's configurations hide that generic ones show.
    chosen = [i for i, c in enumerate(candidates) if c]
    spectrum = _spectrum(generic_residual[:, chosen]) if chosen else None
    trades = _trades(generic_residual, candidates, rows, clock=clock, spectrum=spectrum)
    # … and what the check's own configurations exercise: its resolution, its trades.
    if q is not None:
        checked = _subset(q, CHECK_SAMPLES, seed)
        J_check = _sensitivities(model, specs, numbers, checked, tols, clock)[0]
    else:
        checked, J_check = generic, J
    carried = [J_check[:, c] @ k for c, k in offsets.absorbing]
    residual = _without(J_check, carried)
    # Combinations the check's configurations hide that generic ones show at least
    # 1:1: its configurations, not the kinematics, leave those numbers apart.
    tied = (
        _unseen(
            generic_residual,
            residual * unit_tol,
            candidates,
            rows,
            checked.shape[0],
            clock,
            generic_spectrum=spectrum,
        )
        if q is not None
        else {}
    )
    # Combinations the joint limits hide that free joints show: the limits', not the table's.
    frozen = _held_still(model, specs, generic, spanned, tols)
    limited = _limited(
        model,
        specs,
        numbers,
        offsets.absorbing,
        generic_residual,
        candidates,
        frozen,
        rows,
        seed,
        tols,
    )
    alone = _worst(residual, checked.shape[0])  # with the carried directions only
    takers = _take(specs, numbers, offsets, J_check, carried, residual)
    findings = _Findings(
        specs=specs,
        numbers=numbers,
        moving=moving,
        spanned=spanned,
        offsets=offsets,
        links=links,
        tied=tied,
        limited=limited,
        takers=takers,
        alone=alone,
        worst=_worst(residual, checked.shape[0]),
        flips=_flip_errors(model, specs, checked, tols, clock),
        flips_within=_flip_errors(model, specs, generic, tols, clock),
        unit_tol=unit_tol,
        configurations=checked.shape[0],
        box=sampling_box(model),
        revolute=tuple(j.type != "prismatic" for j in model.joints),
    )
    out = [
        replace(
            _number_evidence(i, n, findings),
            trades_with=tuple(numbers[j].name for j in trades.get(i, ())),
        )
        for i, n in enumerate(numbers)
    ]
    out = [
        replace(e, on_word_of=tuple(word.on_word[i]))
        if e.status == "verified" and word.on_word.get(i)
        else e
        for i, e in enumerate(out)
    ]
    resting = _unique(f for e in out if e.status == "verified" for f in e.on_word_of)
    vouches = tuple((f, word.sources[f]) for f in resting)
    return Coverage(
        specs["from"].name, specs["to"].name, tuple(out), spanned, tol_pos_m, tol_rot_rad,
        vouches,
    )  # fmt: skip


@dataclass
class _Absorption:
    """What the compared frames' offsets can absorb of the table, over generic configurations.

    Attributes:
        absorbed: Table number → the offset carrying it (``[frames.NAME]``) and how.
        carrying: Offset component → the table numbers it trades with.
        absorbing: Offset columns and their combination, one per absorbed number.
        exempt: Number → the sides that could absorb it but carry none of it.
        carriers: Side → its offset's columns (a side whose offset is vouched has none).
    """

    absorbed: dict[int, tuple[str, str]] = field(default_factory=dict)
    carrying: dict[int, list[str]] = field(default_factory=dict)
    absorbing: list[tuple[list[int], Float]] = field(default_factory=list)
    exempt: dict[int, set[str]] = field(default_factory=dict)
    carriers: dict[str, list[int]] = field(default_factory=dict)


def _absorption(
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    J: Float,
    moving: Float,
    norms: Float,
    tols: tuple[float, float],
    *,
    sides: tuple[str, ...] = ("from", "to"),
    vouches: bool = True,
) -> _Absorption:
    """Which table numbers each compared frame's offset absorbs (see :class:`_Absorption`).

    A vouched offset absorbs nothing, unless ``vouches`` is false (what it would
    absorb is what the check takes on its word).
    """
    tol_pos_m, tol_rot_rad = tols
    to_si = np.array([tol_pos_m] * 3 + [tol_rot_rad] * 3)
    found = _Absorption()
    for side in sides:
        spec = specs[side]
        cols = [i for i, n in enumerate(numbers) if n.kind == side]
        if not cols or (spec.source and vouches):
            continue
        found.carriers[side] = cols
        A = J[:, cols]
        for i, n in enumerate(numbers):
            if not n.table or not moving[i] or n.kind == "flip":
                continue
            coef = np.asarray(np.linalg.lstsq(A, J[:, i], rcond=None)[0], dtype=np.float64)
            if np.linalg.norm(J[:, i] - A @ coef) > SPAN_RTOL * norms[i]:
                continue
            if not _carries(spec.offset, coef * to_si, tol_pos_m / tol_rot_rad):
                found.exempt.setdefault(i, set()).add(side)
                continue
            found.absorbed.setdefault(i, (f"[frames.{spec.name}]", _describe(coef * to_si, spec)))
            found.absorbing.append((cols, coef))
            weight = np.abs(coef) * norms[cols]
            for k, c in enumerate(cols):
                if weight[k] > SPAN_RTOL * weight.max():
                    found.carrying.setdefault(c, []).append(n.name)
    return found


@dataclass
class _Word:
    """Table numbers verified only on the word of a vouched frame.

    Attributes:
        on_word: Number → the vouched frames (``[frames.NAME]``) it rests on.
        sources: Vouched frame → its ``source``.
    """

    on_word: dict[int, list[str]] = field(default_factory=dict)
    sources: dict[str, str] = field(default_factory=dict)


def _vouched_absorption(
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    J: Float,
    moving: Float,
    norms: Float,
    tols: tuple[float, float],
    honoured: _Absorption,
) -> _Word:
    """What a vouched compared frame's offset would absorb were it not vouched for."""
    word = _Word()
    for side in ("from", "to"):
        spec = specs[side]
        if not spec.source or (side == "to" and specs["from"].name == spec.name):
            continue
        group = f"[frames.{spec.name}]"
        would = _absorption(specs, numbers, J, moving, norms, tols, sides=(side,), vouches=False)
        for i in would.absorbed:  # (the numbers it would carry are among these)
            if i not in honoured.absorbed:
                word.on_word.setdefault(i, []).append(group)
                word.sources[group] = spec.source
    return word


@dataclass
class _LinkChoice:
    """Numbers a choice among the description's links could hide (see :class:`Competitor`).

    Attributes:
        absorbed: Number → the compared frame (``[frames.NAME]``) and how.
        competing: Number → the competing links.
        on_word: Number → the vouched frames that settle the choice.
        sources: Vouched frame → its ``source``.
    """

    absorbed: dict[int, tuple[str, str]] = field(default_factory=dict)
    competing: dict[int, list[str]] = field(default_factory=dict)
    on_word: dict[int, list[str]] = field(default_factory=dict)
    sources: dict[str, str] = field(default_factory=dict)


#: At most this many places of competing links are solved for at one end (nearest
#: first); a description with more links fixed there has the end's numbers reported
#: not identifiable, unanalysed, rather than costing time out of proportion.
MAX_COMPETITORS = 128
#: Gauss–Newton iterations of the search for the numbers that put the DH frame on a
#: competing link; a turn about an axis the numbers produce converges in one or two.
PRODUCE_ITERATIONS = 12


def _link_choice(
    model: Model,
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    analysed: tuple[Float, Float, Float],
    tols: tuple[float, float],
    competitors: Mapping[str, Sequence[Competitor]],
    carried: set[int],
    clock: _Clock = _NO_LIMIT,
) -> _LinkChoice:
    """Which table numbers could put a competing link exactly on the compared frame's DH frame.

    At each end of the pair, the table numbers acting there (those whose effect a
    change of that frame's offset reproduces at every configuration: d1 and θ1 at
    DH frame 0, the last row's and ``[tool]``'s at the TCP) are solved for, so that
    a competing link would be the DH frame exactly. If they can (within the check's
    tolerances, at two configurations), the numbers that change are not
    identifiable — or, when a frame of the group is vouched for with an offset the
    description bears out, verified on its word.

    ``analysed`` is the generic configurations, the numbers' columns over them and
    which numbers move the pose; ``carried`` the numbers the compared frames'
    offsets already make not identifiable.
    """
    generic, J, moving = analysed
    found = _LinkChoice()
    if specs["from"].name == specs["to"].name:
        return found
    unit_tol = np.array([tols[0] if n.unit == "m" else tols[1] for n in numbers])
    pose = _Pose(model, generic, specs["from"], specs["to"])
    F_inv = invert(pose.pose())
    scale = np.array([1.0 / tols[0]] * 3 + [1.0 / tols[1]] * 3)
    for side in ("from", "to"):
        spec = specs[side]
        comps = competitors.get(spec.name, ())
        if not comps:
            continue
        group = f"[frames.{spec.name}]"
        end = _end_numbers(pose, F_inv, numbers, J, moving, side, scale)
        if not end:
            continue
        solved: dict[bytes, list[tuple[dict[int, float], bool]]] = {}  # each place once
        anchor = {"world": "the world", "tcp": "the TCP"}.get(str(spec.dh), f"DH frame {spec.dh}")
        places = {np.round(c.anchor_T_link, 9).tobytes() for c in comps}
        if len(places) > MAX_COMPETITORS:
            why = (
                f"{len(places)} places of links fixed beside {spec.urdf or spec.name} in the "
                f"description, more than the {MAX_COMPETITORS} fkcheck analyses: any of them "
                "could be the DH frame"
            )
            for i in end:
                if spec.source:  # the compared frame is vouched for: its word settles it
                    found.on_word.setdefault(i, []).append(group)
                    found.sources[group] = spec.source
                else:
                    found.absorbed.setdefault(i, (group, why))
                    found.competing.setdefault(i, [c.link for c in comps[:3]] + ["…"])
            continue
        for comp in comps:
            clock.check()
            key = np.round(comp.anchor_T_link, 9).tobytes()
            if key not in solved:
                exact = _fewest(pose, side, numbers, end, comp.anchor_T_link, tols, unit_tol)
                tidy = _turned(pose, side, numbers, end, comp.anchor_T_link, tols, carried)
                solved[key] = [(c, True) for c in exact] + [(c, False) for c in tidy]
            for changes, exactly in solved[key]:
                change = ", ".join(
                    f"{numbers[i].name} changed by {_amount(d, numbers[i].unit)}"
                    for i, d in changes.items()
                )
                how = (
                    f"would be {anchor} exactly with {change}"
                    if exactly
                    else f"would sit, with {change}, at an offset from {anchor} that carries "
                    "none of it"
                )
                unsettled = set(changes) - carried  # what the choice alone could hide
                pins = _pins(model, spec, comps, tols, (pose, side, numbers, end), unsettled)
                for i in changes:
                    if pins:
                        for frame, source in pins:
                            if frame not in found.on_word.setdefault(i, []):
                                found.on_word[i].append(frame)
                            found.sources[frame] = source
                        continue
                    found.absorbed.setdefault(
                        i,
                        (
                            group,
                            f"link {comp.link} of the description {how}: choosing "
                            f"{spec.urdf or spec.name} over it is a fit",
                        ),
                    )
                    if comp.link not in found.competing.setdefault(i, []):
                        found.competing[i].append(comp.link)
    return found


#: The turns of one angle of the table tried for a competing link that a turned table
#: would make as tidy as the compared one (a θn off by 180° moves a flange 0.2 m across
#: z to −0.2 m, and an offset across z carries nothing).
TURNS_RAD = (math.pi / 2, math.pi, -math.pi / 2)


def _turned(
    pose: _Pose,
    side: str,
    numbers: Sequence[_Number],
    end: Sequence[int],
    target: Float,
    tols: tuple[float, float],
    carried: set[int],
) -> list[dict[int, float]]:
    """Angles of the end whose turn leaves a competing link at an offset that carries none of it.

    The compared link's offset carries none of the angle (else it is not identifiable
    already); a competing link whose offset carries it now, but would carry none of it
    were the angle a quarter or half turn different, is as tidy a choice under that
    other table: poses through either cannot tell the two tables apart.
    """
    from scipy.spatial.transform import Rotation

    two = _first(pose, 1)
    P0 = two.changed(())
    length_m = tols[0] / tols[1]

    def placed(number: _Number, delta: float) -> Float:
        E = _anchor_change(two, side, P0, two.changed([(number, delta)]))[0]
        out: Float = invert(E) @ target
        return out

    def log(X: Float) -> Float:
        out: Float = np.concatenate([X[:3, 3], Rotation.from_matrix(X[:3, :3]).as_rotvec()])
        return out

    def carries(number: _Number, delta: float) -> bool:
        # The number's motion of the link, in the link's own axes at ``delta``: central
        # differences (a one-sided one leaves ~h·|ξ| across the shift, above CARRY_EPS).
        here = placed(number, delta)
        back = invert(here)
        ahead, behind = back @ placed(number, delta + STEP), back @ placed(number, delta - STEP)
        xi = (log(ahead) - log(behind)) / (2.0 * STEP)
        return _carries_matrix(here, xi, length_m)

    out = []
    for i in end:
        n = numbers[i]
        if i in carried or n.kind != "row" or n.unit != "rad" or not carries(n, 0.0):
            continue
        for delta in TURNS_RAD:
            if not carries(n, delta):
                out.append({i: delta})
                break
    return out


#: At most this many of an end's numbers (a ``[base]`` or ``[tool]`` counts as one) are
#: tried together for the fewest that put the DH frame on a competing link; beyond,
#: all of them at once (a least-norm change).
FEWEST = 3


def _fewest(
    pose: _Pose,
    side: str,
    numbers: Sequence[_Number],
    end: Sequence[int],
    target: Float,
    tols: tuple[float, float],
    unit_tol: Float,
) -> list[dict[int, float]]:
    """The smallest sets of ``end`` numbers whose change puts the DH frame on ``target``.

    Each solution maps a number to its change (only those beyond one tolerance).
    With several numbers able to do it, a least-norm change would spread over all
    of them; the fewest that do it alone are what could hide behind the choice.
    Empty when not even all of them together reach ``target``.
    """
    every = _produce(pose, side, [numbers[i] for i in end], target, tols)
    if every is None:
        return []
    groups: dict[str, list[int]] = {}
    for i in end:
        key = numbers[i].group if numbers[i].kind in ("base", "tool") else numbers[i].name
        groups.setdefault(key, []).append(i)
    units = list(groups.values())
    for size in range(1, min(FEWEST, len(units)) + 1):
        found = []
        for combo in itertools.combinations(units, size):
            chosen = [i for unit in combo for i in unit]
            delta = _produce(pose, side, [numbers[i] for i in chosen], target, tols)
            if delta is None:
                continue
            changes = {i: float(d) for i, d in zip(chosen, delta, strict=True)
                       if abs(d) > unit_tol[i]}  # fmt: skip
            if changes:
                found.append(changes)
        if found:
            return found
    changes = {i: float(d) for i, d in zip(end, every, strict=True) if abs(d) > unit_tol[i]}
    return [changes] if changes else []


def _end_numbers(
    pose: _Pose,
    F_inv: Float,
    numbers: Sequence[_Number],
    J: Float,
    moving: Float,
    side: str,
    scale: Float,
) -> list[int]:
    """Table numbers whose effect a change of ``side``'s offset reproduces at every configuration.

    ``J`` holds the numbers' columns over ``pose``'s configurations (in tolerances).
    """
    comps = [_Number("", "", _unit(c), side, c) for c in range(6)]  # type: ignore[arg-type]
    A = np.stack([_twists(pose, F_inv, c) for c in comps], axis=2)
    A = (A * scale[None, :, None]).reshape(-1, 6)
    idx = [i for i, n in enumerate(numbers) if n.table and n.kind != "flip" and moving[i]]
    if not idx:
        return []
    cols = J[:, idx]
    left = cols - A @ np.linalg.lstsq(A, cols, rcond=None)[0]
    inside = np.linalg.norm(left, axis=0) <= SPAN_RTOL * np.linalg.norm(cols, axis=0)
    return [i for i, ok in zip(idx, inside, strict=True) if ok]


def _first(pose: _Pose, k: int) -> _Pose:
    """``pose`` on its first ``k`` configurations, for :meth:`_Pose.changed` alone.

    The search for a competing link's change evaluates finite changes of several
    numbers at a time, the whole chain each time: a few configurations, not all of
    them, and none of :class:`_Pose`'s incremental state.
    """
    few = _Pose.__new__(_Pose)
    few.chain, few.q, few.spec = pose.chain, pose.q[:k], pose.spec
    return few


def _anchor_change(pose: _Pose, side: str, P0: Float, P: Float) -> Float:
    """How a change of the table moves ``side``'s DH frame (right-multiplied), ``(N, 4, 4)``."""
    M = pose.spec[side].offset.matrix
    if side == "from":  # P = M⁻¹·E⁻¹·M·P0
        return invert(M @ P @ invert(P0) @ invert(M))
    return M @ invert(P0) @ P @ invert(M)  # P = P0·M⁻¹·E·M


def _produce(
    pose: _Pose,
    side: str,
    end: Sequence[_Number],
    target: Float,
    tols: tuple[float, float],
) -> Float | None:
    """The change of the ``end`` numbers that moves ``side``'s DH frame onto ``target``.

    Gauss–Newton on the group over two configurations: each step linearises the
    frame's motion about where it is (smooth even half a turn away, where the
    rotation vector of the rest flips sign). ``None`` when no change reaches
    ``target`` within the check's tolerances.
    """
    from scipy.spatial.transform import Rotation

    two = _first(pose, 2)
    P0 = two.changed(())
    scale = np.array([1.0 / tols[0]] * 3 + [1.0 / tols[1]] * 3)

    def frame(delta: Float) -> Float:
        P = two.changed(list(zip(end, (float(d) for d in delta), strict=True)))
        return _anchor_change(two, side, P0, P)

    def log(X: Float) -> Float:
        rot = Rotation.from_matrix(X[:, :3, :3]).as_rotvec()
        out: Float = (np.concatenate([X[:, :3, 3], rot], axis=1) * scale).reshape(-1)
        return out

    delta = np.zeros(len(end))
    here = frame(delta)
    rest = log(invert(here) @ target)
    for _ in range(PRODUCE_ITERATIONS):
        if np.abs(rest).max() <= 1e-3:
            break
        inv_here = invert(here)
        Jl = np.stack([log(inv_here @ frame(delta + STEP * e)) / STEP for e in np.eye(len(end))], 1)
        step = delta + np.linalg.lstsq(Jl, rest, rcond=None)[0]
        there = frame(step)
        rest_there = log(invert(there) @ target)
        if not np.linalg.norm(rest_there) < 0.5 * np.linalg.norm(rest):  # no way there: stop
            break
        delta, here, rest = step, there, rest_there
    if not np.all(np.isfinite(rest)) or np.abs(rest).max() > 1.0:
        return None
    return delta


def _pins(
    model: Model,
    spec: FrameSpec,
    comps: Sequence[Competitor],
    tols: tuple[float, float],
    where: tuple[_Pose, str, Sequence[_Number], Sequence[int]],
    hidden: set[int],
) -> list[tuple[str, str]]:
    """The vouched frames that settle which link is the DH frame: ``[(group, source)]``.

    The compared frame itself when vouched for; else any frame of the model at the
    same DH frame, on a competing link, vouched for with an offset the description
    bears out — where the compared frame's offset and the description put it, up to
    what numbers other than the ``hidden`` ones produce (a d1 fitted into the
    compared frame's offset, already not identifiable through it, leaves a vouch
    for a half turn standing; a vouch off by the half turn itself settles nothing).
    """
    if spec.source:
        return [(f"[frames.{spec.name}]", spec.source)]
    pose, side, numbers, end = where
    placed = {c.link: c.anchor_T_link for c in comps}
    others = [numbers[i] for i in end if i not in hidden]
    out = []
    for other in model.frames.values():
        if not other.source or other.dh != spec.dh or other.urdf not in placed:
            continue
        declared, described = other.offset.matrix, placed[other.urdf]
        agrees = (
            float(position_error_m(declared, described)) <= tols[0]
            and float(rotation_error_rad(declared, described)) <= tols[1]
        )
        if not agrees and others:  # off only by what other numbers produce?
            agrees = _produce(pose, side, others, described @ invert(declared), tols) is not None
        if agrees:
            out.append((f"[frames.{other.name}]", other.source))
    return out


def _amount(value: float, unit: Unit) -> str:
    """``-180°`` or ``+10 mm``: a change as a person reads it."""
    if unit == "rad":
        return f"{math.degrees(value):+.6g}°"
    return f"{value * 1000.0:+.6g} mm"


def _take(
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    offsets: _Absorption,
    J_check: Float,
    carried: Sequence[Float],
    residual: Float,
) -> dict[int, list[str]]:
    """Table number → the offsets that could take it; ``residual`` loses what they take.

    Any offset the map could have fitted takes what it can of a table number over
    the check's configurations, unless the number is one it structurally takes
    whole but carries none of (d1 against a shift across the first axis).
    """
    takers: dict[int, list[str]] = {}
    for i, n in enumerate(numbers):
        if not n.table or n.kind == "flip":
            continue
        sides = [side for side in offsets.carriers if side not in offsets.exempt.get(i, set())]
        full = [J_check[:, c] for side in sides for c in offsets.carriers[side]]
        if full:
            residual[:, i] = _without(J_check[:, i : i + 1], [*carried, *full])[:, 0]
            takers[i] = [f"[frames.{specs[side].name}]" for side in sides]
    return takers


@dataclass(frozen=True)
class _Findings:
    """What the analysis of one frame pair found, for deciding each number's status.

    Attributes:
        specs: The compared frames, ``"from"`` and ``"to"``.
        numbers: The model's numbers, in column order.
        moving: Per number, whether the compared pose depends on it.
        spanned: The joints (1-based) that move the compared pose.
        offsets: What the compared frames' offsets absorb.
        links: What a choice among the description's links could hide.
        tied: Number → the numbers the check's configurations cannot tell it from.
        limited: Number → the numbers the joint limits keep it from being told
            from, and the joints whose limits do (free joints would tell them apart).
        takers: Number → the offsets that could take it over the check's configurations.
        alone: Per number, its worst effect with the carried directions only removed.
        worst: Per number, its worst effect once every offset took what it can.
        flips: Per joint, the worst error of the joint turned the other way, in tolerances.
        flips_within: The same over generic configurations within limits.
        unit_tol: Per number, the tolerance of its unit.
        configurations: How many of the check's configurations were analysed.
        box: The joints' sampling box (lower, upper), radians / metres.
        revolute: Per joint, whether it is revolute.
    """

    specs: dict[str, FrameSpec]
    numbers: Sequence[_Number]
    moving: Float
    spanned: tuple[int, ...]
    offsets: _Absorption
    links: _LinkChoice
    tied: dict[int, tuple[int, ...]]
    limited: dict[int, tuple[tuple[int, ...], tuple[int, ...]]]
    takers: dict[int, list[str]]
    alone: Float
    worst: Float
    flips: Float
    flips_within: Float
    unit_tol: Float
    configurations: int
    box: tuple[Float, Float]
    revolute: tuple[bool, ...]


def _number_evidence(i: int, n: _Number, f: _Findings) -> NumberEvidence:
    """Number ``i``'s status, and why (its ``trades_with`` left empty)."""
    absorbed, carrying = f.offsets.absorbed, f.offsets.carrying
    if n.kind in ("from", "to") and f.specs[n.kind].source:
        return _evidence(n, "vouched", source=f.specs[n.kind].source)
    if n.kind == "flip":
        return _flip_evidence(n, f)
    if not f.moving[i]:
        return _evidence(n, "not-covered")
    if i in absorbed:
        return _evidence(
            n,
            "not-identifiable",
            why=f"{absorbed[i][0]}: {absorbed[i][1]}",
            reason="offset",
            by=(absorbed[i][0],),
        )
    if i in f.links.absorbed:
        frame, why = f.links.absorbed[i]
        return replace(
            _evidence(n, "not-identifiable", why=f"{frame}: {why}", reason="link", by=(frame,)),
            competing=tuple(f.links.competing.get(i, ())),
        )
    if i in carrying:
        return _evidence(
            n,
            "not-identifiable",
            why=f"{n.group}: carries what {', '.join(carrying[i])} produce",
            reason="offset",
            by=(n.group,),
        )
    if i in f.limited:
        return _limited_evidence(i, n, f)
    if i in f.tied:
        others = ", ".join(f.numbers[j].name for j in f.tied[i]) or "the others"
        return _evidence(
            n,
            "not-identifiable",
            why=(
                f"the check's {f.configurations} configurations cannot tell it from {others} "
                "(more configurations would)"
            ),
            reason="configurations",
        )
    return _resolved_evidence(i, n, f)


def _limited_evidence(i: int, n: _Number, f: _Findings) -> NumberEvidence:
    """A number the joint limits keep from others (a joint frozen at ``[0, 0]``)."""
    tied, joints = f.limited[i]
    others = ", ".join(f.numbers[j].name for j in tied) or "the others"
    lo, hi = f.box
    held = ", ".join(
        f"joint {j + 1} ([{math.degrees(lo[j]):.3g}°, {math.degrees(hi[j]):.3g}°])"
        if f.revolute[j]
        else f"joint {j + 1} ([{lo[j]:.3g}, {hi[j]:.3g}] m)"
        for j in joints
    )
    whose = f"the limits of {held}" if held else "the joint limits"
    return _evidence(
        n,
        "not-identifiable",
        why=(
            f"{whose} keep any configuration from telling it from {others} "
            "(free joints would: are the limits right?)"
        ),
        reason="limits",
    )


def _flip_evidence(n: _Number, f: _Findings) -> NumberEvidence:
    """A joint's direction: not covered, told apart by the check's configurations or not."""
    if n.index + 1 not in f.spanned:
        return _evidence(n, "not-covered")
    if f.flips_within[n.index] <= 1.0:  # no configuration within limits tells it
        lo, hi = f.box
        span = (
            f"[{math.degrees(lo[n.index]):.3g}°, {math.degrees(hi[n.index]):.3g}°]"
            if f.revolute[n.index]
            else f"[{lo[n.index]:.3g}, {hi[n.index]:.3g}] m"
        )
        return _evidence(
            n,
            "not-identifiable",
            why=(
                f"joint {n.index + 1} turned the other way would pass: its limits {span} keep "
                "any configuration from telling its direction (are the limits right?)"
            ),
            reason="limits",
        )
    if f.flips[n.index] <= 1.0:
        return _evidence(
            n,
            "not-identifiable",
            why=(
                f"joint {n.index + 1} turned the other way would pass: the check's "
                f"{f.configurations} configurations cannot tell its direction"
            ),
            reason="direction",
        )
    return _evidence(n, "verified")


def _resolved_evidence(i: int, n: _Number, f: _Findings) -> NumberEvidence:
    """A number the check sees: verified to its resolution, or too faint (or taken) if beyond."""
    unit_tol, worst = f.unit_tol, f.worst
    resolution = 1.0 / float(worst[i]) if worst[i] > 0 else None
    if resolution is not None and resolution <= RESOLUTION_LIMIT * unit_tol[i]:
        return _evidence(n, "verified", resolution=resolution)
    why = (
        f"an error up to {resolution:.3g} {n.unit} would stay within tolerance"
        if resolution is not None
        else "no error of it would show"
    )
    if i in f.takers and f.alone[i] * RESOLUTION_LIMIT * unit_tol[i] > 1.0:
        why = (  # it shows alone: an offset fitted over these configurations takes it
            f"over the check's {f.configurations} configurations the offset of "
            f"{', '.join(f.takers[i])} could take it ({why})"
        )
        return _evidence(n, "not-identifiable", why=why, reason="taken", by=tuple(f.takers[i]))
    return _evidence(n, "not-identifiable", why=why, reason="faint")


def _evidence(
    n: _Number,
    status: Status,
    *,
    resolution: float | None = None,
    why: str = "",
    source: str = "",
    reason: Reason = "",
    by: tuple[str, ...] = (),
) -> NumberEvidence:
    """Number ``n``'s evidence (its ``trades_with`` left empty)."""
    return NumberEvidence(
        n.name, n.group, n.unit, status, n.table, resolution, why, (), source, reason, by
    )


def _sensitivities(
    model: Model,
    specs: dict[str, FrameSpec],
    numbers: Sequence[_Number],
    q: Float,
    tol: tuple[float, float],
    clock: _Clock = _NO_LIMIT,
) -> tuple[Float, Float, tuple[int, ...]]:
    """Columns in tolerances per unit ``(N·6, P)``, which numbers move the pose, joints spanned."""
    pose = _Pose(model, q, specs["from"], specs["to"])
    F_inv = invert(pose.pose())
    twists = np.stack([_twists(pose, F_inv, n, clock) for n in numbers], axis=2)  # (N, 6, P)
    moving = np.abs(twists).max(axis=(0, 1)) > MOVING_EPS
    joints = [_Number("", "", "rad", "joint", i) for i in range(model.dof)]
    spanned = tuple(
        i + 1
        for i, j in enumerate(joints)
        if np.abs(_twists(pose, F_inv, j, clock)).max() > MOVING_EPS
    )
    scale = np.array([1.0 / tol[0]] * 3 + [1.0 / tol[1]] * 3)
    J: Float = (twists * scale[None, :, None]).reshape(-1, len(numbers))
    return J, moving, spanned


def _worst(residual: Float, configurations: int) -> Float:
    """Per column, the worst configuration's ``max(|Δp| / tol_pos, angle / tol_rot)`` per unit."""
    per = residual.reshape(configurations, 6, -1)
    worst: Float = np.maximum(
        np.linalg.norm(per[:, :3], axis=1), np.linalg.norm(per[:, 3:], axis=1)
    ).max(axis=0)
    return worst


def _without(J: Float, directions: Sequence[Float]) -> Float:
    """``J`` with the span of ``directions`` projected out."""
    if not directions:
        return J
    basis, sv, _ = np.linalg.svd(np.stack(directions, axis=1), full_matrices=False)
    basis = basis[:, sv > SPAN_RTOL * sv.max()]
    out: Float = J - basis @ (basis.T @ J)
    return out


def _needs_full(J: Float) -> bool:
    """Whether ``svd(J)`` needs ``full_matrices`` for all of ``Vᵀ`` (fewer rows than columns).

    With at least as many rows, the reduced SVD has the whole ``Vᵀ`` already;
    the full one would also build ``U`` of rows × rows (6N × 6N: 3.6·10⁹ numbers
    at the 10⁴ configurations of a check), which nothing reads.
    """
    return bool(J.shape[0] < J.shape[1])


def _spectrum(J: Float) -> tuple[Float, Float]:
    """``J``'s singular values, one per column (zeros past its row count), and all of ``Vᵀ``.

    One SVD that :func:`_trades` and :func:`_unseen` both read (the same generic
    ``J``, each against its own threshold).
    """
    _, sv, vt = np.linalg.svd(J, full_matrices=_needs_full(J))
    sv = np.concatenate([sv, np.zeros(J.shape[1] - len(sv))]) if len(sv) < J.shape[1] else sv
    return sv, vt


def _weak(spectrum: tuple[Float, Float], configurations: int, limit: float) -> Float:
    """Orthonormal rows spanning the combinations a ``J`` shows under ``1/limit`` of (RMS).

    ``spectrum`` is that ``J``'s :func:`_spectrum`.
    """
    sv, vt = spectrum
    weak: Float = vt[sv < math.sqrt(configurations) / limit]
    return weak


def _unseen(
    generic: Float,
    checked: Float,
    candidates: Sequence[bool],
    generic_configurations: int,
    checked_configurations: int,
    clock: _Clock = _NO_LIMIT,
    generic_spectrum: tuple[Float, Float] | None = None,
) -> dict[int, tuple[int, ...]]:
    """Numbers in combinations the check's configurations hide but generic ones show.

    Both ``J`` in tolerances per tolerance of each number. A combination the
    check's configurations show less than a tenth of (:data:`RESOLUTION_LIMIT`,
    root mean square, and at the worst configuration) and that lies well outside
    what generic configurations show less than :data:`BLAME_MARGIN` tenths of
    (a margin, so a borderline near-trade is no fault of the check) is theirs:
    its numbers are ``{i: (the others in it, …)}``. ``generic_spectrum``: the
    :func:`_spectrum` of ``generic``'s candidate columns, when already computed.
    """
    idx = [i for i, c in enumerate(candidates) if c]
    if not idx:
        return {}
    spectrum = generic_spectrum if generic_spectrum is not None else _spectrum(generic[:, idx])
    loose = _weak(spectrum, generic_configurations, RESOLUTION_LIMIT / BLAME_MARGIN)
    clock.check()
    strict = _weak(_spectrum(checked[:, idx]), checked_configurations, RESOLUTION_LIMIT)
    clock.check()
    if not len(strict):
        return {}
    extra = strict - (strict @ loose.T) @ loose if len(loose) else strict
    _, sv, vt = np.linalg.svd(extra, full_matrices=False)
    clock.check()
    per = checked[:, idx].reshape(-1, 6, len(idx))
    supports = _supports(per, vt[sv > 0.5])  # at least half outside what generic ones blur
    # Each number with the others of every combination it is in: one product of
    # the supports, not a set per pair (a whole table is ~10⁶ pairs per combination).
    together = (supports.T.astype(np.int64) @ supports.astype(np.int64)) > 0
    return {
        idx[k]: tuple(idx[j] for j in np.flatnonzero(together[k]) if j != k)
        for k in np.flatnonzero(supports.any(axis=0))
    }


def _supports(per: Float, vecs: Float, limit: float = RESOLUTION_LIMIT) -> NDArray[np.bool_]:
    """Per combination the check cannot see, the numbers taking part in it, ``(V, K)``.

    ``per`` is ``J`` as ``(N, 6, K)``, ``vecs`` the combinations ``(V, K)``. A
    combination is kept when its worst configuration shows it under ``1/limit``
    of its length; its numbers are those with a share above :data:`TRADE_SHARE`
    of its largest. Rows of combinations not kept are empty.
    """
    if not len(vecs):
        return np.zeros((0, per.shape[2]), dtype=np.bool_)
    effect = np.einsum("nrk,vk->vnr", per, vecs)
    shows = np.maximum(
        np.linalg.norm(effect[:, :, :3], axis=2), np.linalg.norm(effect[:, :, 3:], axis=2)
    ).max(axis=1)
    kept = shows * limit < np.linalg.norm(vecs, axis=1)
    share = np.abs(vecs)
    out: NDArray[np.bool_] = (share > TRADE_SHARE * share.max(axis=1, keepdims=True)) & kept[
        :, None
    ]
    return out


def _trades(
    J: Float,
    candidates: Sequence[bool],
    configurations: int,
    limit: float = RESOLUTION_LIMIT,
    clock: _Clock = _NO_LIMIT,
    spectrum: tuple[Float, Float] | None = None,
) -> dict[int, tuple[int, ...]]:
    """Numbers whose columns depend on each other only: ``{i: (j, …)}``.

    ``J`` is in tolerances of the pose per tolerance of each number. A set of
    numbers trades when some combination of them, :data:`RESOLUTION_LIMIT`
    tolerances large, moves the pose by less than one tolerance over the
    configurations: found among the singular directions below ``√N /
    RESOLUTION_LIMIT`` (the columns' length is at most ``√N`` times the worst
    configuration's), kept when the worst configuration shows under a tenth.
    Exact dependencies (UR's parallel d2, d3, d4) and near ones (a calibrated
    arm's almost parallel axes) alike. The reduced row echelon basis of those
    combinations has the smallest supports, so independent groups stay apart.
    ``spectrum``: the :func:`_spectrum` of ``J``'s candidate columns, when already computed.
    """
    idx = [i for i, c in enumerate(candidates) if c]
    if len(idx) < 2:
        return {}
    weak = _weak(spectrum if spectrum is not None else _spectrum(J[:, idx]), configurations, limit)
    clock.check()
    parent = list(range(len(idx)))

    def root(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]  # path halving: the trees stay shallow
            k = parent[k]
        return k

    per = J[:, idx].reshape(-1, 6, len(idx))
    # The singular value bounds the columns' length; the check sees the worst
    # configuration: a combination counts only if that stays under a tenth.
    for support in _supports(per, _rref(weak, clock), limit):
        members = np.flatnonzero(support)
        for k in members[1:]:
            parent[root(int(k))] = root(int(members[0]))
    groups: dict[int, list[int]] = {}
    for k, i in enumerate(idx):
        groups.setdefault(root(k), []).append(i)
    return {
        m: tuple(x for x in members if x != m)
        for members in groups.values()
        if len(members) > 1
        for m in members
    }


def _rref(rows: Float, clock: _Clock = _NO_LIMIT) -> Float:
    """Reduced row echelon form of a few orthonormal rows (partial pivoting)."""
    M = np.array(rows, dtype=np.float64)
    r = 0
    for c in range(M.shape[1]):
        clock.check()
        if r == M.shape[0]:
            break
        p = r + int(np.argmax(np.abs(M[r:, c])))
        if abs(M[p, c]) < TRADE_SHARE:
            continue
        M[[r, p]] = M[[p, r]]
        M[r] /= M[r, c]
        factors = M[:, c].copy()
        factors[r] = 0.0
        M -= np.outer(factors, M[r])  # every other row at once: the same arithmetic
        r += 1
    return M[:r]
