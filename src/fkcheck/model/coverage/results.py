"""What an analysis found, and its wording: per-number evidence and the pair's coverage.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Literal

from fkcheck.core.typing import Float

__all__ = [
    "SOURCE_SHOWN",
    "Competitor",
    "Coverage",
    "NumberEvidence",
    "Reason",
    "Status",
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
