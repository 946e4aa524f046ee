"""The map itself: which URDF joints and links a DH model's joints and frames are.

Part of :mod:`fkcheck.urdf.mapping`, whose docstring says how they are found.
"""

from __future__ import annotations

import fnmatch
import re
import tomllib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np

from fkcheck.errors import FkcheckError, UrdfError
from fkcheck.io.files import MAX_MODEL_FILE_BYTES, InputFileError, read_text
from fkcheck.io.format import format_deg, format_mm
from fkcheck.model.coverage import Competitor, Coverage, coverage
from fkcheck.model.edits import TableEdits, half_turns_as_signs
from fkcheck.model.types import (
    CheckSpec,
    FrameSpec,
    Model,
    Offset,
)
from fkcheck.urdf.chain import UrdfKinematics
from fkcheck.urdf.chain_fit import DEFAULT_SAMPLES, Anchor, LinkFit, _Fit, _Problem
from fkcheck.urdf.tree import listed

__all__ = [
    "COMMON_NAMES",
    "JointMatch",
    "MapResult",
    "ProposedFrame",
    "Reconciled",
    "map_model",
    "reconcile_table",
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
#: A chain still this far off (m + rad) once the flips and zeros are found is tried
#: for one number that differs; farther off, the table is another arm's.
_NUMBER_REACH = 0.1


@dataclass(frozen=True)
class JointMatch:
    """One DH joint and the URDF joint that moves like it.

    Attributes:
        dh: The DH joint's name.
        urdf: The URDF joint's name.
        flipped: The URDF joint turns (slides) the other way from the DH joint as
            the table has it: the table needs ``flip`` toggled on that joint.
    """

    dh: str
    urdf: str
    flipped: bool


@dataclass(frozen=True)
class ProposedFrame:
    """A ``[frames.NAME]`` table the map proposes.

    Attributes:
        spec: The frame (name, DH frame, offset, URDF link or ``None``).
        fit: The evidence for its URDF link, or ``None`` without one.
        declared: The model already declares a frame of this name.
        note: What changed from the model's declaration, or why there is no link.
    """

    spec: FrameSpec
    fit: LinkFit | None
    declared: bool
    note: str = ""


@dataclass(frozen=True)
class MapResult:
    """What ``fkcheck map`` found.

    Attributes:
        model: The model mapped.
        urdf_path: The ``[urdf] path`` to write.
        joints: The matched joints in DH order (the best window when none fits).
        fit_m: How far the last DH frame strays from its URDF link, metres, over the samples.
        fit_rad: The same for orientation, radians.
        also_fit: Other joint windows that fit as well (a two-armed robot).
        frames: The proposed frames, DH frame 0's first, each group ranked by name.
        nearest: When no link fits DH frame 0 (or the last DH frame): the nearest one.
        configurations: How many configurations were compared.
        seed: The sampling seed.
        xacro_args: The URDF is xacro, expanded with these arguments (``None``: plain).
        packages: The packages its ``$(find …)`` resolves, directories as ``[urdf]``
            writes them (relative to the model file).
        pair: The proposed ``[check]`` frame pair: the outermost frames whose offsets
            hide the fewest table numbers (``None`` when an end has no link).
        numbers: What that pair can verify of the table (:mod:`fkcheck.model.coverage`).
        absorbs: Proposed frame → the table numbers its offset could absorb
            (``d1: translation along z of DH frame 0``): a table error there and an
            offset fitted around it look the same, so fkcheck cannot tell them apart.
        check_declared: The model's file has a ``[check]`` table of its own, so the
            block's ``[check]`` is written as comments (a second one would not parse).
        twins: ``[frames.world]`` / ``[frames.tcp]`` the block declares, each the URDF
            link that sits exactly on it, so that the model's own ``[check]`` (which
            compares ``world`` → ``tcp`` unless it says otherwise) has URDF twins.
        edits: The edits of the table's rows that make it move like the chain
            (:func:`reconcile_table`): the flips of :attr:`joints`, and zeros moved
            or signs changed when no chain moves like the table as it is. The
            frames are those of the table so edited.
    """

    model: Model
    urdf_path: str
    joints: tuple[JointMatch, ...]
    fit_m: float
    fit_rad: float
    also_fit: tuple[tuple[str, ...], ...]
    frames: tuple[ProposedFrame, ...]
    nearest: tuple[LinkFit, ...]
    configurations: int
    seed: int
    xacro_args: dict[str, str] | None = None
    packages: dict[str, str] = field(default_factory=dict)
    pair: tuple[str, str] | None = None
    numbers: Coverage | None = None
    absorbs: dict[str, tuple[str, ...]] = field(default_factory=dict)
    check_declared: bool = False
    twins: tuple[FrameSpec, ...] = ()
    edits: TableEdits = field(default_factory=TableEdits)

    @property
    def tolerances(self) -> tuple[float, float]:
        """The model's check tolerances ``(m, rad)``, by which "constant" is judged."""
        return self.model.check.tol_pos_m, self.model.check.tol_rot_rad

    @property
    def joints_fit(self) -> bool:
        """Whether the table moves like the URDF chain found (directions aside)."""
        return (
            bool(self.joints)
            and self.fit_m <= self.tolerances[0]
            and (self.fit_rad <= self.tolerances[1])
        )

    @property
    def complete(self) -> bool:
        """Whether ``fkcheck check`` can pass on the block as pasted.

        The joints fit with no flip, and both ends have a link.
        """
        return (
            self.joints_fit
            and not any(j.flipped for j in self.joints)
            and not self.edits
            and not self.nearest
            and any(f.fit is not None and f.spec.dh in (0, "world") for f in self.frames)
        )

    @property
    def unmapped_ends(self) -> tuple[str, ...]:
        """Ends of the model's own ``[check]`` that have no URDF twin, the block pasted.

        Empty when the block's ``[check]`` is live (the model declares none).
        """
        if not self.check_declared:
            return ()
        mapped = {f.spec.name for f in self.frames if f.fit is not None}
        mapped |= {t.name for t in self.twins}
        mapped |= {s.name for s in self.model.frames.values() if s.urdf is not None}
        ends = dict.fromkeys((self.model.check.frame_from, self.model.check.frame_to))
        return tuple(end for end in ends if end not in mapped)

    @property
    def check_flags(self) -> tuple[str, ...]:
        """What ``fkcheck check MODEL`` needs, the block pasted, to compare mapped frames.

        ``()`` when the check the model then runs has a URDF twin at both ends (the
        block's live ``[check]``, or the model's own ``[check]`` with its frames
        mapped); else ``("--from", A, "--to", B)``, the proposed pair.
        """
        if self.pair is None or not self.unmapped_ends:
            return ()
        return ("--from", self.pair[0], "--to", self.pair[1])


def _windows(kin: UrdfKinematics, model: Model) -> list[tuple[str, ...]]:
    """Every run of ``n`` consecutive movable joints down from the root whose types fit."""
    n = model.dof
    want = [("prismatic",) if j.type == "prismatic" else ("revolute", "continuous")
            for j in model.joints]  # fmt: skip
    out: dict[tuple[str, ...], None] = {}
    for joint in kin.joints.values():
        if joint.type == "fixed":
            continue
        try:
            movable = kin.movable(kin.chain(kin.root, joint.child))
        except UrdfError:
            continue
        window = tuple(j.name for j in movable[-n:])
        if len(window) == n and all(
            kin.joints[name].type in types for name, types in zip(window, want, strict=True)
        ):
            out.setdefault(window)
    return list(out)


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


# ----------------------------------------------------------------------------- the map


def map_model(
    model: Model,
    kin: UrdfKinematics,
    urdf_path: str,
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, str] | None = None,
) -> MapResult:
    """Find the model's joints and frames in a URDF.

    Args:
        model: The DH model (its ``[urdf]`` and ``[frames]`` are only used for names).
        kin: The URDF's geometry (:func:`fkcheck.urdf.chain.urdf_kinematics`).
        urdf_path: What ``[urdf] path`` should say.
        samples: Random configurations on top of the structured ones.
        seed: Seed of the samples.
        xacro_args: The URDF is xacro, expanded with these arguments: the block
            opts in (``xacro = true``) with them. ``None``: a plain URDF.
        packages: With ``xacro_args``: the ``packages`` line, as written.

    Returns:
        The proposal; :attr:`MapResult.complete` says whether it can pass as pasted.

    Raises:
        UrdfError: The URDF has no run of ``n`` movable joints of the table's types.
    """
    windows = _windows(kin, model)
    if not windows:
        movable = [j.name for j in kin.joints.values() if j.type != "fixed"]
        raise UrdfError(
            kin.path,
            f"has no chain of {model.dof} consecutive movable joints of the types of model "
            f"{model.name}'s table; movable joints are: {listed(movable)}",
        )
    problem = _Problem(model, kin, samples, seed)
    fits = sorted((problem.search(w) for w in windows), key=lambda f: f.score(problem.tol))
    best = fits[0]
    fitting = [f for f in fits if f.score(problem.tol)[0] == 0]
    joints = tuple(
        JointMatch(dh.name, urdf, sign < 0)
        for dh, urdf, sign in zip(model.joints, best.joints, best.signs, strict=True)
    )
    edits, problem, best = _reconciled(problem, best)
    edited = problem.model
    frames, nearest = _frames(problem, best)
    pair, numbers, absorbs = _check_pair(edited, frames, best.score(problem.tol)[0] == 0)
    declared = _declares_check(model)
    return MapResult(
        model=model,
        urdf_path=urdf_path,
        joints=joints,
        fit_m=best.dev_m,
        fit_rad=best.dev_rad,
        also_fit=tuple(f.joints for f in fitting[1:]),
        frames=tuple(frames),
        nearest=tuple(nearest),
        configurations=problem.q.shape[0],
        seed=seed,
        xacro_args=None if xacro_args is None else dict(xacro_args),
        packages=dict(packages or {}) if xacro_args is not None else {},
        pair=pair,
        numbers=numbers,
        absorbs=absorbs,
        check_declared=declared,
        twins=_default_twins(model, frames) if declared and pair is not None else (),
        edits=edits,
    )


def _reconciled(problem: _Problem, fit: _Fit) -> tuple[TableEdits, _Problem, _Fit]:
    """The fit's edits of the table, the problem of the table so edited, and its fit there.

    Zeros moved and signs changed are made in the table (flips stay in the fit's
    signs); when the chain still does not fit, the one number that makes it fit
    (:meth:`_Problem.one_number`), if any, is set too.
    """
    model = problem.model
    edits = _edits(model, fit)
    if edits.thetas or edits.negated:
        problem = _Problem(replace(edits, flips=()).apply(model), problem.kin,
                           problem.samples, problem.seed)  # fmt: skip
        fit = problem.fit(fit.joints, fit.signs)
    if fit.score(problem.tol)[0] != 0 and fit.dev_m + fit.dev_rad < _NUMBER_REACH:
        number = problem.one_number(fit)
        if number is not None:
            k, param, value, fit = number
            edits = replace(edits, values=((model.joints[k].name, param, value),))
            problem = _Problem(replace(edits, flips=()).apply(model), problem.kin,
                               problem.samples, problem.seed)  # fmt: skip
            fit = problem.fit(fit.joints, fit.signs)
    return edits, problem, fit


def _edits(model: Model, fit: _Fit) -> TableEdits:
    """The fit's flips and zeros as edits of the table; half-turn pairs said as signs."""
    thetas = list(fit.thetas or (0.0,) * model.dof)
    negated = half_turns_as_signs(model.joints, model.convention, thetas)
    names = [j.name for j in model.joints]
    return TableEdits(
        flips=tuple(n for n, s in zip(names, fit.signs, strict=True) if s < 0),
        thetas=tuple((n, t) for n, t in zip(names, thetas, strict=True) if t),
        negated=tuple((names[k], p) for k, p in negated),
    )


@dataclass(frozen=True)
class Reconciled:
    """How a table's rows must change to move like its URDF chain.

    Attributes:
        edits: The fewest flips, quarter-turn zeros and signs found (empty: none needed).
        fit_m: How far the last DH frame of the edited table then strays from the
            chain's last link (over the samples, a constant offset fitted), metres.
        fit_rad: The same for orientation, radians.
    """

    edits: TableEdits
    fit_m: float
    fit_rad: float


def reconcile_table(
    model: Model, kin: UrdfKinematics, *, samples: int = DEFAULT_SAMPLES, seed: int = 0
) -> Reconciled:
    """The table's edits that make it move like the URDF joints its ``[urdf]`` maps.

    As ``fkcheck map`` finds them, on the model's own mapping: each joint's
    direction, then (when no directions fit) quarter-turn zero offsets too, by a
    beam search over the chain's prefixes with a constant offset fitted at each
    end. The frames at the ends are not judged (a diagnosis fits them).

    Raises:
        FkcheckError: The model has no ``[urdf]``, or maps joints the URDF lacks.
    """
    if model.urdf is None:
        raise FkcheckError(f"model {model.name} has no [urdf]")
    missing = [name for name in model.urdf.joints if name not in kin.joints]
    if missing:
        raise FkcheckError(
            f"model {model.name}'s [urdf] joints name {listed(missing)}, which "
            f"{kin.path.name} does not have"
        )
    problem = _Problem(model, kin, samples, seed)
    edits, _, fit = _reconciled(problem, problem.search(model.urdf.joints, polish=False))
    return Reconciled(edits, fit.dev_m, fit.dev_rad)


def _default_twins(model: Model, frames: Sequence[ProposedFrame]) -> tuple[FrameSpec, ...]:
    """``world`` / ``tcp`` of the model's own check, each given the link sitting exactly on it.

    A link on DH frame 0 is on the world when the model has no ``[base]`` (and on
    the last DH frame, the TCP, without a ``[tool]``). Ends that already have a
    twin, and ends no link sits exactly on, get none.
    """
    n = model.dof
    on: dict[Literal["world", "tcp"], tuple[Anchor, ...]] = {
        "world": ("world", 0) if model.base.is_identity else ("world",),
        "tcp": ("tcp", n) if model.tool.is_identity else ("tcp",),
    }
    twins: list[FrameSpec] = []
    for end in on:
        spec = model.frames.get(end)
        if end not in (model.check.frame_from, model.check.frame_to) or spec is None:
            continue
        if not _builtin(spec):
            continue
        exact = [
            p.spec.urdf
            for p in frames
            if p.fit is not None and p.spec.dh in on[end] and p.spec.offset.is_identity
        ]
        if exact and exact[0] is not None:
            twins.append(FrameSpec(end, end, Offset(), exact[0]))
    return tuple(twins)


def _check_pair(
    model: Model, frames: Sequence[ProposedFrame], chain_ok: bool
) -> tuple[tuple[str, str] | None, Coverage | None, dict[str, tuple[str, ...]]]:
    """The ``[check]`` pair to propose, what it verifies, and what each frame could hide.

    Each end is judged alone against the other end of the chain (the TCP, the
    world): a frame whose offset carries what a table number produces could be
    hiding an error in that number. The pair takes, at each end, the linked frame
    hiding the fewest table numbers, then the outermost (``world`` over DH frame
    0, the TCP over the last DH frame: they cover ``[base]`` and ``[tool]``).
    """
    n = model.dof
    linked = [p.spec for p in frames if p.fit is not None]
    specs = {s.name: s for s in model.frames.values() if s.name in ("world", "tcp")}
    specs.update({s.name: s for s in linked})
    mapped = replace(model, frames=specs)
    tol = (model.check.tol_pos_m, model.check.tol_rot_rad)
    absorbs: dict[str, tuple[str, ...]] = {}
    score: dict[str, tuple[int, int, int]] = {}
    rivals = _rivals(model, linked)
    for spec in linked:
        judged = _hidden_at_end(mapped, spec, tol, rivals)
        if judged is None:
            continue
        hidden, outer = judged
        if hidden:
            absorbs[spec.name] = hidden
        score[spec.name] = (len(hidden), outer, _complexity(spec.offset))
    base = sorted((s for s in linked if s.dh in (0, "world") and s.name in score),
                  key=lambda s: score[s.name])  # fmt: skip
    tip = sorted((s for s in linked if s.dh in (n, "tcp") and s.name in score),
                 key=lambda s: score[s.name])  # fmt: skip
    if not (chain_ok and base and tip):
        return None, None, absorbs
    pair = (base[0].name, tip[0].name)
    return pair, coverage(mapped, pair[0], pair[1], *tol, competitors=rivals), absorbs


def _rivals(model: Model, linked: Sequence[FrameSpec]) -> dict[str, list[Competitor]]:
    """For each linked frame, the other linked frames at its end: which is the DH frame is a choice.

    Frames at DH frame 0 and at the world are at one place when the model has no
    ``[base]``; at the last DH frame and the TCP when it has no ``[tool]``.
    """
    n = model.dof
    same: dict[Anchor, Anchor] = {}
    if model.base.is_identity:
        same["world"] = 0
    if model.tool.is_identity:
        same["tcp"] = n

    def place(spec: FrameSpec) -> Anchor:
        return same.get(spec.dh, spec.dh)

    return {
        spec.name: [
            Competitor(str(other.urdf), other.offset.matrix)
            for other in linked
            if other is not spec and place(other) == place(spec)
        ]
        for spec in linked
    }


def _hidden_at_end(
    mapped: Model,
    spec: FrameSpec,
    tol: tuple[float, float],
    rivals: Mapping[str, Sequence[Competitor]],
) -> tuple[tuple[str, ...], int] | None:
    """What a frame at one end of the chain hides, judged against the other end.

    Returns:
        The table numbers its offset carries, or that another link at its end
        could take (``"d1: translation along z of …"``), and ``0`` for the
        outermost end (``world``, ``tcp``), ``1`` for a DH frame; ``None`` for a
        frame at neither end.
    """
    n = mapped.dof
    if spec.dh in (0, "world"):
        c = coverage(mapped, spec.name, "tcp", *tol, competitors=rivals)
        outer = 0 if spec.dh == "world" else 1
    elif spec.dh in (n, "tcp"):
        c = coverage(mapped, "world", spec.name, *tol, competitors=rivals)
        outer = 0 if spec.dh == "tcp" else 1
    else:
        return None
    mine = f"[frames.{spec.name}]"
    hidden = tuple(
        f"{e.name}: {e.absorbed_by.removeprefix(mine + ': ')}"
        for e in c.table_numbers
        if e.status == "not-identifiable" and e.reason in ("offset", "link") and mine in e.by
    )
    return hidden, outer


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


def _declares_check(model: Model) -> bool:
    """Whether the model's file has a ``[check]`` table (a model built in memory: not default)."""
    if model.path is None or model.path.suffix.lower() != ".toml":
        return model.check != CheckSpec()
    try:
        return "check" in tomllib.loads(read_text(model.path, MAX_MODEL_FILE_BYTES))
    except (InputFileError, FkcheckError, ValueError, RecursionError):  # it was read before
        return True
