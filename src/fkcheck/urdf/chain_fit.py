"""A DH table and a URDF chain evaluated at seeded configurations, and fitted.

Part of :mod:`fkcheck.urdf.mapping`: the fit problem the map,
:func:`~fkcheck.urdf.mapping.reconcile_table` and ``urdf:LINK`` placement share —
a window of URDF joints with axis directions (and zeros) found by a beam search,
and each link's offset from a DH frame over the samples.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from fkcheck.core.geometry import invert
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.errors import UrdfError
from fkcheck.model.names import PARAMS, Param
from fkcheck.model.sampling import sample_configurations, sampling_box
from fkcheck.model.types import (
    Model,
    Offset,
)
from fkcheck.urdf.chain import UrdfKinematics
from fkcheck.urdf.hand_eye import _REFINE, _hand_eye, _pinned, _refine
from fkcheck.urdf.to_dh import clean_offset

__all__ = [
    "DEFAULT_SAMPLES",
    "Anchor",
    "LinkFit",
]

#: Random configurations tried on top of the structured ones (poses, corners, edges).
DEFAULT_SAMPLES = 64
#: Configuration pairs the hand–eye fit uses, and the largest step between the two
#: of a pair (rad or m per joint, shrunk for long chains so the motion stays below π).
_FIT_PAIRS = 48
_FIT_STEP = 0.2
#: Sign hypotheses kept per chain prefix while the axis directions are searched.
_BEAM = 8
#: Zero offsets tried per joint when no chain moves like the table as it is (the
#: vendor's zero and the URDF's differ by quarter turns: KUKA's A2, A3), and the
#: hypotheses kept per prefix then (offsets that undo each other through an
#: intersecting axis tie on a prefix and part only further down).
_QUARTERS = (0.0, math.pi / 2, -math.pi / 2, math.pi)
_WIDE_BEAM = 16

Anchor = int | Literal["world", "tcp"]  # a DH frame 0…n, "tcp" or "world"


@dataclass(frozen=True)
class LinkFit:
    """A URDF link seen from one DH frame over the samples.

    Attributes:
        link: The URDF link.
        anchor: The DH frame (``0…n``, ``"tcp"`` or ``"world"``).
        offset: The offset anchor → link at the first sample, round numbers snapped.
        spread_m: How far the offset's origin moves over the samples, metres.
        spread_rad: How far its orientation turns over the samples, radians.
    """

    link: str
    anchor: Anchor
    offset: Offset
    spread_m: float
    spread_rad: float

    def fits(self, tol_pos_m: float, tol_rot_rad: float) -> bool:
        """Whether the offset is constant within the tolerances."""
        return self.spread_m <= tol_pos_m and self.spread_rad <= tol_rot_rad

    def evidence(self) -> str:
        """``max deviation 2.2e-16 m, 4.4e-16 rad over the samples`` or the like."""
        return f"max deviation {self.spread_m:.2g} m, {self.spread_rad:.2g} rad"


# ----------------------------------------------------------------------------- geometry


def _with_thetas(model: Model, thetas: Sequence[float]) -> Model:
    """The model with ``thetas`` (radians) added to its first joints' θ (zeros moved)."""
    joints = tuple(
        replace(j, theta=j.theta + thetas[k]) if k < len(thetas) and thetas[k] else j
        for k, j in enumerate(model.joints)
    )
    return replace(model, joints=joints)


def _dh_in_frame0(model: Model, q: Float) -> Float:
    """``dh0_T_dhk`` for k = 0…n, ``(N, n+1, 4, 4)``, from the in-house core."""
    frames = np.asarray(model.fk(q, all_frames=True)).reshape(q.shape[0], model.dof + 1, 4, 4)
    return invert(frames[:, :1]) @ frames


def _anchor_poses(model: Model, dh0: Float, anchor: Anchor) -> Float:
    """The anchor frame in DH frame 0, ``(N, 4, 4)``."""
    if anchor == "world":
        return np.broadcast_to(invert(model.base.matrix), dh0[:, 0].shape)
    if anchor == "tcp":
        return dh0[:, -1] @ model.tool.matrix
    return dh0[:, int(anchor)]


def _joint_values(
    kin: UrdfKinematics,
    mapped: Sequence[str],
    signs: Sequence[float],
    q: Float,
    rng: np.random.Generator | None,
) -> dict[str, Float]:
    """Every movable URDF joint's values: the mapped ones from ``q``, the others random or 0."""
    N = q.shape[0]
    values: dict[str, Float] = {}
    for joint in kin.joints.values():
        if joint.type == "fixed":
            continue
        if rng is None:
            values[joint.name] = np.zeros(N)
            continue
        default = 0.5 if joint.type == "prismatic" else math.pi
        lo, hi = joint.limits or (-default, default)
        values[joint.name] = lo + (hi - lo) * np.asarray(rng.random(N), dtype=np.float64)
    for col, (name, sign) in enumerate(zip(mapped, signs, strict=True)):
        values[name] = sign * q[:, col]
    return values


def _root_poses(
    kin: UrdfKinematics, links: Sequence[str], values: Mapping[str, Float], N: int
) -> dict[str, Float]:
    """``root_T_link`` ``(N, 4, 4)`` of ``links`` (and of the links on their way).

    Links below a joint fkcheck cannot follow (``floating``, ``planar``) are left out.
    """
    out: dict[str, Float] = {kin.root: np.broadcast_to(np.eye(4), (N, 4, 4))}
    for link in links:
        if link in out:
            continue
        chain = kin.chain(kin.root, link)
        try:
            movable = kin.movable(chain)
        except UrdfError:
            continue
        q = np.column_stack([values[j.name] for j in movable]) if movable else np.zeros((N, 0))
        poses = kin.chain_poses(chain, q)
        for i, joint in enumerate(chain):
            out.setdefault(joint.child, poses[:, i])
    return out


def _spread(offsets: Float) -> tuple[float, float]:
    """How far the offsets ``(N, 4, 4)`` stray from the first one: ``(m, rad)``."""
    ref = np.broadcast_to(offsets[0], offsets.shape)
    return (
        float(position_error_m(ref, offsets).max()),
        float(rotation_error_rad(ref, offsets).max()),
    )


@dataclass(frozen=True, eq=False)
class _Fit:
    """A joint window with axis directions, fitted: ``dh0_T_dhn = X · base_T_tip · Y``.

    ``thetas``: radians added to the table's θ of each joint of the prefix (empty:
    none), the zero offsets :meth:`_Problem.reconcile` tries.
    """

    joints: tuple[str, ...]
    signs: tuple[float, ...]
    base: str
    X: Float
    Y: Float
    dev_m: float
    dev_rad: float
    thetas: tuple[float, ...] = ()

    @property
    def changes(self) -> int:
        """How many edits of the table it asks for: flips toggled, zeros moved.

        Two neighbouring zeros half a turn away count once: they are one sign typed
        the other way (:func:`fkcheck.model.edits.half_turns_as_signs`).
        """
        pairs, k = 0, 0
        while k + 1 < len(self.thetas):
            if (
                abs(abs(self.thetas[k]) - math.pi) < 1e-12
                and abs(abs(self.thetas[k + 1]) - math.pi) < 1e-12
            ):
                pairs, k = pairs + 1, k + 2
            else:
                k += 1
        return sum(s < 0 for s in self.signs) + sum(t != 0.0 for t in self.thetas) - pairs

    def score(self, tol: tuple[float, float]) -> tuple[int, int, int, float, float]:
        """Sort key: fitting first, then fewer edits (flips), then the smaller deviation.

        Between fits with as many flips (slides at right angles: flipping the x or
        the y slide is the same motion seen from a base turned 180°), the one whose
        URDF base link is turned least from DH frame 0 comes first.
        """
        fits = self.dev_m <= tol[0] and self.dev_rad <= tol[1]
        turn = math.acos(min(1.0, max(-1.0, (np.trace(self.X[:3, :3]) - 1.0) / 2.0)))
        return (
            0 if fits else 1,
            self.changes,
            sum(t != 0.0 for t in self.thetas),
            round(turn, 6) if fits else 0.0,
            self.dev_m + self.dev_rad,
        )

    def near(self, tol: tuple[float, float]) -> tuple[int, int, int, int, float]:
        """Sort key of :meth:`_Problem.reconcile`: fitting, then as near within a factor of ten.

        A wrong flip or zero leaves the chain off by a link's length; a table number
        off by a millimetre leaves a millimetre whatever else is tried: among
        hypotheses that leave the same order of magnitude, fewer edits come first.
        """
        fits = self.dev_m <= tol[0] and self.dev_rad <= tol[1]
        dev = self.dev_m + self.dev_rad
        magnitude = 0 if fits else math.floor(math.log10(max(dev, 1e-15)))
        # Among as many edits, a reversed joint before a zero moved: a half turn of the
        # zero before an intersecting axis reverses that axis as a flip does.
        turns = sum(t != 0.0 for t in self.thetas)
        return (0 if fits else 1, magnitude, self.changes, turns, dev)


class _Problem:
    """A model, a URDF and the configurations both are evaluated at."""

    def __init__(self, model: Model, kin: UrdfKinematics, samples: int, seed: int) -> None:
        self.model, self.kin = model, kin
        self.tol = (model.check.tol_pos_m, model.check.tol_rot_rad)
        self.q = sample_configurations(model, samples, seed).q
        rng = np.random.default_rng(seed)
        n = model.dof
        step = min(_FIT_STEP, 2.0 / max(n, 1))
        lo, hi = sampling_box(model)
        first = lo + (hi - lo) * rng.random((_FIT_PAIRS, n))
        pairs = np.empty((2 * _FIT_PAIRS, n))
        pairs[0::2], pairs[1::2] = first, first + rng.uniform(-step, step, first.shape)
        self.fit_q = pairs
        self.dh_fit = _dh_in_frame0(model, pairs)
        self.dh = _dh_in_frame0(model, self.q)
        self.seed = seed
        self.samples = samples
        self._turned: dict[tuple[float, ...], Float] = {}

    def turned(self, thetas: Sequence[float]) -> Float:
        """:attr:`dh_fit` of the table with ``thetas`` added to its first joints' θ."""
        if not any(thetas):
            return self.dh_fit
        key = tuple(thetas)
        if key not in self._turned:
            model = _with_thetas(self.model, key)
            self._turned[key] = _dh_in_frame0(model, self.fit_q)
        return self._turned[key]

    def relative(
        self,
        q: Float,
        joints: Sequence[str],
        signs: Sequence[float],
        base: str,
        links: Sequence[str],
        rng: np.random.Generator | None,
    ) -> dict[str, Float]:
        """``base_T_link`` for ``links`` at ``q`` (unmapped joints random with ``rng``, else 0)."""
        values = _joint_values(self.kin, joints, signs, q, rng)
        poses = _root_poses(self.kin, [base, *links], values, q.shape[0])
        base_inv = invert(poses[base])
        return {link: base_inv @ poses[link] for link in links if link in poses}

    def fit(
        self,
        joints: Sequence[str],
        signs: Sequence[float],
        refine: bool = False,
        thetas: Sequence[float] = (),
    ) -> _Fit:
        """Fit the first ``len(signs)`` joints of ``joints``: DH frame k vs their last child.

        With ``refine``, the closed-form fit is polished by least squares on every
        pair (:func:`_refine`): needed when the joints' turns leave a spin free.
        ``thetas`` are added to the table's θ first (:meth:`reconcile`).
        """
        k = len(signs)
        used = tuple(joints[:k])
        base = self.kin.joints[used[0]].parent
        tip = self.kin.joints[used[-1]].child
        U = self.relative(self.fit_q[:, :k], used, signs, base, [tip], None)[tip]
        M = self.turned(thetas)[:, k]
        X, Y = _hand_eye(M, U)
        if refine:
            X, Y = _pinned(M, U, *_refine(M, U, X, Y))
        E = invert(M) @ X @ U @ Y
        eye = np.broadcast_to(np.eye(4), E.shape)
        return _Fit(
            used, tuple(signs), base, X, Y,
            float(position_error_m(eye, E).max()), float(rotation_error_rad(eye, E).max()),
            tuple(thetas),
        )  # fmt: skip

    def search(self, joints: Sequence[str], polish: bool = True) -> _Fit:
        """The axis directions of a window of joints, by a beam search over its prefixes.

        When no directions fit, zeros too (:meth:`reconcile`); then, with
        ``polish``, the likeliest directions polished by least squares.
        """
        beam: list[tuple[float, ...]] = [()]
        best: list[_Fit] = []
        for _ in joints:
            fits = [self.fit(joints, (*signs, s)) for signs in beam for s in (1.0, -1.0)]
            best = sorted(fits, key=lambda f: f.score(self.tol))[:_BEAM]
            beam = [f.signs for f in best]
        if best[0].score(self.tol)[0] == 0:
            return best[0]
        # Zeros that differ (a vendor's convention), then parallel turns and slides
        # (the closed form leaves a spin free): polish the likeliest.
        reconciled = self.reconcile(joints)
        if reconciled.score(self.tol)[0] == 0 or not polish:
            return min(best[0], reconciled, key=lambda f: f.near(self.tol))
        polished = [self.fit(joints, f.signs, refine=True) for f in best[:_REFINE]]
        best = sorted([*polished, *best], key=lambda f: f.score(self.tol))
        return min(best[0], reconciled, key=lambda f: f.near(self.tol))

    def reconcile(self, joints: Sequence[str]) -> _Fit:
        """Flips and quarter-turn zero offsets together: the fewest that make the chain fit.

        A beam search over the chain's prefixes, as :meth:`search`, where each step
        also tries the previous revolute joint's θ turned by each of
        :data:`_QUARTERS` (its zero shows only once the next joint moves; the last
        joint's is the tip frame's business). Kept: :data:`_WIDE_BEAM` per prefix,
        by :meth:`_Fit.near`.
        """
        n = len(joints)
        if not any(j.type == "revolute" for j in self.model.joints[: n - 1]):
            return self.fit(joints, (1.0,) * n)  # no zero to move
        beam = [self.fit(joints, (s,), thetas=(0.0,) * n) for s in (1.0, -1.0)]
        for k in range(1, n):
            turns = _QUARTERS if self.model.joints[k - 1].type == "revolute" else (0.0,)
            fits = []
            for prev in beam:
                for turn in turns:
                    thetas = list(prev.thetas)
                    thetas[k - 1] = turn
                    for s in (1.0, -1.0):
                        fits.append(self.fit(joints, (*prev.signs, s), thetas=thetas))
            beam = sorted(fits, key=lambda f: f.near(self.tol))[:_WIDE_BEAM]
        return beam[0]

    def evaluate(self, fit: _Fit, links: Sequence[str], anchor: Anchor) -> list[LinkFit]:
        """Each link's offset from ``anchor`` over the evaluation samples.

        DH frame 0 and ``world`` hold the tip to the URDF (``dh0_T_link = M·Y⁻¹·U⁻¹·…``),
        every other DH frame holds the base (``X·…``): either way the offset stays
        constant only when the whole chain moves as the URDF does.
        """
        q = self.q
        n = len(fit.joints)
        rng = np.random.default_rng(self.seed + 1)
        tip = self.kin.joints[fit.joints[-1]].child
        rel = self.relative(q[:, :n], fit.joints, fit.signs, fit.base, [tip, *links], rng)
        if anchor in (0, "world"):
            W = self.dh[:, -1] @ invert(fit.Y) @ invert(rel[tip])
        else:
            W = np.broadcast_to(fit.X, (q.shape[0], 4, 4))
        P_inv = invert(_anchor_poses(self.model, self.dh, anchor))
        out = []
        for link in links:
            if link not in rel:
                continue
            offsets = P_inv @ W @ rel[link]
            spread_m, spread_rad = _spread(offsets)
            out.append(LinkFit(link, anchor, clean_offset(offsets[0]), spread_m, spread_rad))
        return out

    def one_number(self, fit: _Fit) -> tuple[int, Param, float, _Fit] | None:
        """The one table number that, set to another value, makes the whole chain fit.

        Each ``a``, ``α``, ``d``, ``θ`` in turn is fitted alone (least squares from
        the table's value) to the chain's motion, the end offsets fitted anew at
        each step: as a diagnosis's single-parameter fits, but on the URDF's chain,
        so the end frames need not be known. Numbers an end offset carries (d1, θ1,
        the last row's) do not change the motion and are never the answer.

        Returns:
            ``(joint index, parameter, value, fit)`` of the number that makes the
            chain fit (the smallest change, if several do), or ``None``.
        """
        n = len(fit.joints)
        tip = self.kin.joints[fit.joints[-1]].child
        U = self.relative(self.fit_q[:, :n], fit.joints, fit.signs, fit.base, [tip], None)[tip]

        def evaluate(model: Model) -> tuple[Float, _Fit]:
            M = _dh_in_frame0(model, self.fit_q)[:, n]
            X, Y = _hand_eye(M, U)
            E = invert(M) @ X @ U @ Y
            eye = np.broadcast_to(np.eye(4), E.shape)
            vector = np.concatenate(
                [
                    Rotation.from_matrix(E[:, :3, :3]).as_rotvec().reshape(-1),
                    E[:, :3, 3].reshape(-1),
                ]
            )
            dev = (float(position_error_m(eye, E).max()), float(rotation_error_rad(eye, E).max()))
            return vector, replace(fit, X=X, Y=Y, dev_m=dev[0], dev_rad=dev[1])

        found: list[tuple[float, int, Param, float, _Fit]] = []
        for k, joint in enumerate(self.model.joints[:n]):
            for param in PARAMS:
                old = float(getattr(joint, param))

                def residual(x: Float, k: int = k, param: Param = param) -> Float:
                    return evaluate(_with_value(self.model, k, param, float(x[0])))[0]

                sol = least_squares(
                    residual, [old], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=60
                )
                new = float(sol.x[0])
                if abs(new - old) <= 1e-9:
                    continue
                _, trial = evaluate(_with_value(self.model, k, param, new))
                if trial.score(self.tol)[0] == 0:
                    found.append((abs(new - old), k, param, new, trial))
        if not found:
            return None
        _, k, param, new, trial = min(found, key=lambda f: f[0])
        return k, param, new, trial


def _with_value(model: Model, k: int, param: str, value: float) -> Model:
    joints = list(model.joints)
    joints[k] = replace(joints[k], **{param: value})  # type: ignore[arg-type]
    return replace(model, joints=tuple(joints))
