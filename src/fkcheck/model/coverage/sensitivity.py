"""The numbers of a model as columns of the compared pose's sensitivity, and the configurations.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from fkcheck.core import dh
from fkcheck.core.geometry import invert
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.model.coverage.clock import _NO_LIMIT, _Clock
from fkcheck.model.coverage.results import Unit
from fkcheck.model.coverage.tuning import _COMPONENTS, FREED_PRISMATIC_M, STEP
from fkcheck.model.names import PARAMS, param_symbol
from fkcheck.model.sampling import sampling_box
from fkcheck.model.types import FrameSpec, Model

__all__: list[str] = []


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
    :data:`~fkcheck.model.coverage.tuning.FREED_PRISMATIC_M` either side of its
    range's middle, or that middle's own distance from zero when larger
    (prismatic: a slide has no natural range, and what a change hides at one
    displacement shows in proportion to the displacement — and, held far out, in
    proportion to the displacement's share of the held one): what the kinematics
    could tell, whatever the limits.
    """
    lo, hi = sampling_box(model)
    for j in range(model.dof) if free is None else free:
        if model.joints[j].type == "prismatic":
            mid = (lo[j] + hi[j]) / 2.0
            half = max(FREED_PRISMATIC_M, abs(mid))
            lo[j], hi[j] = min(lo[j], mid - half), max(hi[j], mid + half)
        else:
            lo[j], hi[j] = min(lo[j], -math.pi), max(hi[j], math.pi)
    rng = np.random.default_rng(seed)
    q: Float = lo + (hi - lo) * rng.random((samples, model.dof))
    return q
