"""The ``[frames.*]`` ``fkcheck map`` proposes: the links at a constant offset from the ends.

Part of :mod:`fkcheck.urdf.mapping`.
"""

from __future__ import annotations

import fnmatch
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import replace

import numpy as np

from fkcheck.io.format import format_deg, format_mm
from fkcheck.model.types import (
    FrameSpec,
    Offset,
)
from fkcheck.urdf.chain import UrdfKinematics
from fkcheck.urdf.chain_fit import Anchor, LinkFit, _Fit, _Problem
from fkcheck.urdf.map_result import ProposedFrame

__all__ = [
    "COMMON_NAMES",
]

#: Link names by how common they are as a robot's base or tool frame (glob patterns,
#: most common first); other names follow in the URDF's order.
COMMON_NAMES = (
    "base",
    "base_link",
    "tool0",
    "flange",
    "ee_link",
    "tcp",
    "*_link0",
    "*_link8",
    "*_base",
    "*_base_link",
    "*_tool0",
    "*_flange",
    "*_ee_link",
    "*_hand",
    "*_tcp",
    "world",
)


def _rank(link: str, order: Mapping[str, int]) -> tuple[int, int]:
    """Sort key of a link: how common its name is, then its place in the URDF."""
    common = next(
        (i for i, pattern in enumerate(COMMON_NAMES) if fnmatch.fnmatchcase(link, pattern)),
        len(COMMON_NAMES),
    )
    return common, order.get(link, 0)


def _complexity(offset: Offset) -> int:
    return sum(1 for v in (*offset.xyz, *offset.rpy) if v != 0.0)


_NAME = re.compile(r"^[A-Za-z0-9_-]+$")


def _frame_name(link: str, taken: set[str]) -> str:
    """A frame name for an undeclared link: the link's own, unless taken or reserved."""
    base = (
        link
        if _NAME.match(link) and link not in ("world", "tcp")
        else "urdf_" + re.sub(r"[^A-Za-z0-9_-]", "_", link)
    )
    name, k = base, 2
    while name in taken:
        name, k = f"{base}_{k}", k + 1
    return name


def _frames(problem: _Problem, fit: _Fit) -> tuple[list[ProposedFrame], list[LinkFit]]:
    """The frames at DH frame 0 and at the tip, then the model's other declared frames."""
    model, kin, tol = problem.model, problem.kin, problem.tol
    n = model.dof
    links = list(kin.links)
    order = {link: i for i, link in enumerate(links)}
    declared = {s.name: s for s in model.frames.values() if not _builtin(s)}
    table = _link_table(problem, fit, links, declared.values())
    chain_ok = fit.score(tol)[0] == 0

    def fits(f: LinkFit | None) -> bool:
        return f is not None and chain_ok and f.fits(*tol)

    proposals = [_declared(spec, table, fits, kin) for spec in declared.values()]
    used = {p.fit.link for p in proposals if p.fit is not None}
    taken = set(model.frames)
    nearest: list[LinkFit] = []
    ranked = sorted(links, key=lambda name: _rank(name, order))
    # On a tie the outer anchor wins where the model has a base or a tool: a frame
    # there covers [base] / [tool], one on the DH frame leaves it out of the check.
    base_side: tuple[Anchor, ...] = (0, "world") if model.base.is_identity else ("world", 0)
    tip_side: tuple[Anchor, ...] = (n, "tcp") if model.tool.is_identity else ("tcp", n)
    for group in (base_side, tip_side):
        found = _undeclared(group, ranked, table, fits, used, taken)
        if found is None:
            nearest.append(
                min(
                    (f for a in group for f in table[a].values()),
                    key=lambda f: f.spread_m + f.spread_rad,
                )
            )
        else:
            proposals += found
    proposals.sort(key=lambda p: _frame_order(p, n, order))
    return proposals, nearest


def _link_table(
    problem: _Problem, fit: _Fit, links: Sequence[str], declared: Iterable[FrameSpec]
) -> dict[Anchor, dict[str, LinkFit]]:
    """Each link's fit at DH frame 0, the world, the last DH frame, the TCP and declared frames."""
    n = problem.model.dof
    anchors: list[Anchor] = [0, "world", n, "tcp"]
    for spec in declared:
        if spec.dh not in anchors:
            anchors.append(spec.dh)
    return {anchor: {f.link: f for f in problem.evaluate(fit, links, anchor)} for anchor in anchors}


def _undeclared(
    group: tuple[Anchor, ...],
    ranked: Sequence[str],
    table: Mapping[Anchor, Mapping[str, LinkFit]],
    fits: Callable[[LinkFit | None], bool],
    used: set[str],
    taken: set[str],
) -> list[ProposedFrame] | None:
    """A frame for each link that fits at one end and no declared frame maps.

    ``taken`` (the frame names in use) grows by the names given. Returns ``None``
    when no link fits at that end at all (a declared frame's included).
    """
    out: list[ProposedFrame] = []
    found = False
    for link in ranked:
        candidates = [table[a][link] for a in group if fits(table[a].get(link))]
        if not candidates:
            continue
        found = True
        if link in used:
            continue
        pick = min(candidates, key=lambda f: (_complexity(f.offset), group.index(f.anchor)))
        name = _frame_name(link, taken)
        taken.add(name)
        out.append(ProposedFrame(FrameSpec(name, pick.anchor, pick.offset, link), pick, False))
    return out if found else None


def _frame_order(p: ProposedFrame, n: int, order: Mapping[str, int]) -> tuple[int, int, int]:
    """Sort key of a proposed frame: DH frame 0's end, the middle, the tip's; then :func:`_rank`."""
    end = 0 if p.spec.dh in (0, "world") else 2 if p.spec.dh in (n, "tcp") else 1
    return (end, *_rank(p.spec.urdf or p.spec.name, order))


def _builtin(spec: FrameSpec) -> bool:
    return spec.name in ("world", "tcp") and spec.dh == spec.name and spec.urdf is None


def _declared(
    spec: FrameSpec,
    table: Mapping[Anchor, Mapping[str, LinkFit]],
    fits: Callable[[LinkFit | None], bool],
    kin: UrdfKinematics,
) -> ProposedFrame:
    """A declared frame, checked: its link at its DH frame, or why not."""
    if spec.urdf is None:
        return ProposedFrame(spec, None, True, "declared without a URDF link: kept as it is")
    if spec.urdf not in kin.links:
        return ProposedFrame(
            replace(spec, urdf=None),
            None,
            True,
            f"its URDF link {spec.urdf!r} is not a link of {kin.path.name}: kept without one",
        )
    here = table[spec.dh].get(spec.urdf)
    if fits(here):
        assert here is not None
        if _same(here.offset, spec.offset):  # the declared numbers, as written
            return ProposedFrame(spec, replace(here, offset=spec.offset), True)
        note = (
            f"the model had xyz {list(spec.offset.xyz)}, rpy {list(spec.offset.rpy)} (rad): "
            "the URDF says otherwise"
        )
        return ProposedFrame(replace(spec, offset=here.offset), here, True, note)
    elsewhere = [row[spec.urdf] for row in table.values() if fits(row.get(spec.urdf))]
    if elsewhere:
        moved = elsewhere[0]
        return ProposedFrame(
            replace(spec, dh=moved.anchor, offset=moved.offset),
            moved,
            True,
            f"declared at DH frame {spec.dh}, but {spec.urdf!r} is rigid to DH frame "
            f"{moved.anchor}",
        )
    shown = (
        f"{format_mm(here.spread_m)} / {format_deg(here.spread_rad)}" if here is not None else "?"
    )
    return ProposedFrame(
        replace(spec, urdf=None),
        None,
        True,
        f"{spec.urdf!r} is at no constant offset from DH frame {spec.dh} (it moves by "
        f"{shown} over the samples): kept without a URDF link",
    )


def _same(a: Offset, b: Offset) -> bool:
    return bool(np.allclose(a.matrix, b.matrix, atol=1e-9, rtol=0.0))
