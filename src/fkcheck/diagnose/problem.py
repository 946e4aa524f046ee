"""The thing every diagnosis step works on: reference poses, and how far a table is from them.

A :class:`Problem` holds configurations ``q``, the frame pair, and the
reference's ``from_T_to(q)`` computed *once* by the reference backend. Every
hypothesis is then a modified copy of the table, evaluated with the in-house
core alone (:meth:`Problem.errors`), so trying fifty of them costs fifty batched
DH evaluations, not fifty runs of a reference library.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from fkcheck.backends.base import Backend
from fkcheck.core.dh import DHChain
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float
from fkcheck.model.frames import reference_poses, relative_pose, resolve_frame
from fkcheck.model.sampling import sample_configurations
from fkcheck.model.types import KnownDifference, Model

__all__ = [
    "SPREAD_CONFIGURATIONS",
    "Problem",
    "Residual",
    "diagnosis_configurations",
    "pose_residuals",
    "se3_from_rotvec_translation",
]


#: Configurations a least-squares fit evaluates at each step, at most: a diagnosis of
#: a long recording runs on its kept rows (up to ~20,000), and a fit on all of them
#: would take tens of seconds where a thousand spread over the recording find the same
#: numbers. Each fit's result is then judged on all of the problem's configurations.
#: Above a diagnosis's own sampling (200 random configurations and the named poses),
#: so a diagnosis of sampled configurations fits on all of them.
SPREAD_CONFIGURATIONS = 1024
#: Rotation errors enter least-squares fits multiplied by this length (m per rad):
#: one milliradian weighs as much as one millimetre, the scale of an arm's reach.
ROTATION_WEIGHT_M = 1.0


@dataclass(frozen=True)
class Residual:
    """How far a table's poses are from the reference's, at worst.

    Attributes:
        position_m: Largest position error, metres.
        rotation_rad: Largest rotation error, radians.
    """

    position_m: float
    rotation_rad: float

    def within(self, tol_pos_m: float, tol_rot_rad: float) -> bool:
        """Whether both are within the tolerances."""
        return self.position_m <= tol_pos_m and self.rotation_rad <= tol_rot_rad

    def text(self) -> str:
        """``"0.300 mm, 0.000°"``; values below 0.01 µm / 0.6 µ° in scientific notation."""
        pos = self.position_m
        rot = self.rotation_rad
        pos_text = f"{pos * 1e3:.3f} mm" if pos >= 1e-5 else f"{pos:.2g} m"
        rot_text = f"{np.degrees(rot):.3f}°" if rot >= 1e-5 else f"{rot:.2g} rad"
        return f"{pos_text}, {rot_text}"


def pose_residuals(T: Float, T_ref: Float) -> Float:
    """Stacked position (m) and rotation-vector (rad × :data:`ROTATION_WEIGHT_M`) errors.

    Args:
        T: ``(N, 4, 4)`` poses to fit.
        T_ref: ``(N, 4, 4)`` reference poses.

    Returns:
        A flat ``(6N,)`` vector for :func:`scipy.optimize.least_squares`.
    """
    from scipy.spatial.transform import Rotation

    dp = T[:, :3, 3] - T_ref[:, :3, 3]
    dR = np.swapaxes(T_ref[:, :3, :3], -1, -2) @ T[:, :3, :3]
    dr = Rotation.from_matrix(dR).as_rotvec() * ROTATION_WEIGHT_M
    return np.concatenate([dp, dr], axis=1).reshape(-1)


def se3_from_rotvec_translation(xi: Float) -> Float:
    """The 4×4 transform of ``xi = (rotation vector (rad), translation (m))``, shape ``(6,)``.

    How the least-squares fits parametrise a small SE(3) increment: no gimbal lock,
    no constraint.
    """
    from scipy.spatial.transform import Rotation

    T = np.eye(4)
    T[:3, :3] = Rotation.from_rotvec(xi[:3]).as_matrix()
    T[:3, 3] = xi[3:]
    return T


def diagnosis_configurations(model: Model, samples: int, seed: int) -> Float:
    """Named poses, zero, mid-range and ``samples`` seeded random configurations.

    The limit corners and edges a check adds are left out: the diagnosis fits
    parameters, and a few hundred well-spread configurations determine them.
    """
    s = sample_configurations(model, samples, seed)
    keep = [k for k, origin in enumerate(s.origin) if origin not in ("corner", "edge")]
    return s.q[keep]


@dataclass(frozen=True, eq=False)
class Problem:
    """A disagreement to explain.

    Attributes:
        model: The table as given.
        backend: The reference backend's name.
        frame_from: Frame the pose is expressed in.
        frame_to: Frame whose pose is compared.
        q: ``(N, n)`` configurations.
        reference: ``(N, 4, 4)`` the reference's ``from_T_to``.
        tol_pos_m: Position tolerance (m): below it a hypothesis "explains".
        tol_rot_rad: Rotation tolerance (rad).
        source: The reference backend itself, to verify a fix with (see :meth:`verify`).
        known: The model's recorded difference with this reference, when the
            disagreement goes beyond it: a change that leaves no more than the
            recorded difference explains the rest (see :meth:`explained`).
    """

    model: Model
    backend: str
    frame_from: str
    frame_to: str
    q: Float
    reference: Float
    tol_pos_m: float
    tol_rot_rad: float
    source: Backend | None = None
    known: KnownDifference | None = None

    @classmethod
    def build(
        cls,
        model: Model,
        backend: Backend,
        q: Float,
        pair: tuple[str, str],
        tol: tuple[float, float],
    ) -> Problem:
        """Compute the reference poses once.

        Raises:
            BackendUnavailable, FrameUnavailable, FkcheckError: From the backend.
        """
        for name in pair:
            resolve_frame(model, name)
        poses = np.asarray(backend.frame_poses(model, q, pair), dtype=np.float64)
        reference = relative_pose(poses[0], poses[1])
        return cls(model, backend.name, pair[0], pair[1], q, reference, tol[0], tol[1], backend)

    @property
    def pair(self) -> tuple[str, str]:
        """``(frame_from, frame_to)``."""
        return self.frame_from, self.frame_to

    def subset(self, count: int) -> Problem:
        """The same problem on its first ``count`` configurations (for costly fits)."""
        return replace(self, q=self.q[:count], reference=self.reference[:count])

    def spread(self, count: int = SPREAD_CONFIGURATIONS) -> Problem:
        """The same problem on at most ``count`` configurations evenly spread over its own.

        For least-squares fits (see :data:`SPREAD_CONFIGURATIONS`): a recording's kept
        rows are in its order, so its first rows would see only its first minutes.
        """
        total = self.q.shape[0]
        if total <= count:
            return self
        keep = np.linspace(0, total - 1, count).round().astype(np.intp)
        return replace(self, q=self.q[keep], reference=self.reference[keep])

    def poses(self, model: Model, chain: DHChain | None = None) -> Float:
        """``from_T_to(q)`` of a (modified) table, with the in-house core.

        ``chain``: the table to compute instead of ``model.chain``, ``model``'s frames
        (see :func:`~fkcheck.model.frames.reference_poses`).
        """
        ref = reference_poses(model, self.q, self.pair, chain=chain)
        return relative_pose(ref[0], ref[1])

    def errors(self, poses: Float) -> Residual:
        """Largest errors of ``poses`` against the reference."""
        return self.errors_against(poses, self.reference)

    def residual(self, model: Model) -> Residual:
        """Largest errors of a (modified) table against the reference."""
        return self.errors(self.poses(model))

    def verify(self, model: Model) -> Residual:
        """A changed model against the reference *recomputed for it* by the backend.

        Hypotheses are compared with the reference poses computed once for the
        original model. That is right when the reference does not depend on the
        table (a URDF), but a black box that only gives the TCP places mid-frames
        with the table's own base and tool, so a fix that changes those must be
        checked against a fresh reference run. Without a backend this is
        :meth:`residual`.
        """
        if self.source is None:
            return self.residual(model)
        poses = np.asarray(self.source.frame_poses(model, self.q, self.pair), dtype=np.float64)
        return self.errors_against(self.poses(model), relative_pose(poses[0], poses[1]))

    @staticmethod
    def errors_against(poses: Float, reference: Float) -> Residual:
        """Largest errors of ``poses`` against another ``reference``."""
        return Residual(
            float(position_error_m(poses, reference).max()),
            float(rotation_error_rad(poses, reference).max()),
        )

    def exact(self, residual: Residual) -> bool:
        """Whether a residual is within the tolerances."""
        return residual.within(self.tol_pos_m, self.tol_rot_rad)

    def explained(self, residual: Residual) -> bool:
        """Within the tolerances, or within the recorded known difference (:attr:`known`)."""
        return self.exact(residual) or (
            self.known is not None
            and residual.within(self.known.max_position_m, self.known.max_angle_rad)
        )
