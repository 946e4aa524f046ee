"""The map itself: which URDF joints and links a DH model's joints and frames are.

Part of :mod:`fkcheck.urdf.mapping`, whose docstring says how they are found.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Literal

from fkcheck.errors import FkcheckError, UrdfError
from fkcheck.io.files import MAX_MODEL_FILE_BYTES, InputFileError, read_text
from fkcheck.model.coverage import Competitor, Coverage, coverage
from fkcheck.model.edits import TableEdits, half_turns_as_signs
from fkcheck.model.types import (
    CheckSpec,
    FrameSpec,
    Model,
    Offset,
)
from fkcheck.urdf.chain import UrdfKinematics
from fkcheck.urdf.chain_fit import DEFAULT_SAMPLES, Anchor, _Fit, _Problem
from fkcheck.urdf.map_frames import _builtin, _complexity, _frames
from fkcheck.urdf.map_result import JointMatch, MapResult, ProposedFrame
from fkcheck.urdf.tree import listed

__all__ = [
    "Reconciled",
    "map_model",
    "reconcile_table",
]

#: A chain still this far off (m + rad) once the flips and zeros are found is tried
#: for one number that differs; farther off, the table is another arm's.
_NUMBER_REACH = 0.1


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
    model: Model,
    kin: UrdfKinematics,
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    joints: Sequence[str] | None = None,
) -> Reconciled:
    """The table's edits that make it move like the description's joints it maps.

    ``joints``: the description's joint of each DH joint (an MJCF's ``[mjcf].joints``);
    default ``[urdf].joints``.

    As ``fkcheck map`` finds them, on the model's own mapping: each joint's
    direction, then (when no directions fit) quarter-turn zero offsets too, by a
    beam search over the chain's prefixes with a constant offset fitted at each
    end. The frames at the ends are not judged (a diagnosis fits them).

    Raises:
        FkcheckError: The model has no ``[urdf]``, or maps joints the URDF lacks.
    """
    if joints is None:
        if model.urdf is None:
            raise FkcheckError(f"model {model.name} has no [urdf]")
        joints = model.urdf.joints
    missing = [name for name in joints if name not in kin.joints]
    if missing:
        raise FkcheckError(
            f"model {model.name}'s joints name {listed(missing)}, which "
            f"{kin.path.name} does not have"
        )
    problem = _Problem(model, kin, samples, seed)
    edits, _, fit = _reconciled(problem, problem.search(tuple(joints), polish=False))
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


def _declares_check(model: Model) -> bool:
    """Whether the model's file has a ``[check]`` table (a model built in memory: not default)."""
    if model.path is None or model.path.suffix.lower() != ".toml":
        return model.check != CheckSpec()
    try:
        return "check" in tomllib.loads(read_text(model.path, MAX_MODEL_FILE_BYTES))
    except (InputFileError, FkcheckError, ValueError, RecursionError):  # it was read before
        return True
