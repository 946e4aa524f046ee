"""One backend's Jacobian against the in-house core's, chunk by chunk (``check --jacobian``).

The compared Jacobian is the one of the check's ``to`` frame, velocities taken
relative to its ``from`` frame — which must be fixed to the base, so that the
velocity relative to it is the velocity relative to the backend's root — in one
of three reference frames (:mod:`fkcheck.core.jacobian`):

* ``"world-aligned"``: the ``to`` origin's velocity and the angular velocity, in
  ``from`` axes (Pinocchio ``LOCAL_WORLD_ALIGNED``, Robotics Toolbox ``jacob0``
  when ``from`` is the root);
* ``"local"``: the same twist in ``to`` axes (``LOCAL``, ``jacobe``);
* ``"world"``: the spatial twist at the ``from`` origin, in ``from`` axes (``WORLD``).

**Where each side comes from.** fkcheck's side is the core's own geometric
Jacobian in the reference asked (:func:`fkcheck.model.frames.frame_jacobian`),
moved from the world to ``from``. A backend whose library computes Jacobians
(one whose ``jacobian_method`` is set) is asked for the reference
itself (or, if its ``jacobian_references`` lack it, for ``world-aligned``), in
its own root; the engine then only moves the numbers from that root to
``from`` with the backend's *own* pose of ``from`` (nothing at all for
``local``), and re-expresses a ``world-aligned`` answer with the backend's own
``from_T_to`` and the engine's own few lines (:func:`_from_world_aligned`),
never the core's. A backend that has none for the frame asked (its
``frame_jacobian`` returns ``None``: a plugin without ``<function>_jacobian``)
or only gives poses (yourdfpy, rtb-urdf, ``cmd:`` programs) is differentiated:
central differences of *its* ``from_T_to`` with step
:data:`~fkcheck.core.tolerances.FINITE_DIFFERENCE_STEP`, the rotation part as
the rotation vector of ``R(q+h) R(q−h)ᵀ`` over ``2h`` (scipy), all its
``2n`` neighbours of a chunk in one call. Its truncation and round-off error
(:data:`~fkcheck.core.tolerances.FINITE_DIFFERENCE`, 1e-7) sets a floor under
the tolerance. Measured poses are left out: they hold no neighbouring
configurations.

**Poses too coarse to differentiate.** Differences of a backend whose poses
carry noise — a program printing six decimals, a float32 library — divide that
noise by the step: a pose off by 5e-7 m (within the pose tolerance) makes a
Jacobian off by ~0.5 m/rad. The same neighbours measure it: the backend's
second difference ``p(q+h) + p(q−h) − 2p(q)`` against the core's (a smooth
chain's is ~h²·reach ≈ 1e-12; the core's is subtracted, so the measure is the
backend's roughness, not a table difference) gives the noise's size, and
``roughness / h`` its size in the differences (for ``world``, the angular part's
times ``|p|`` counts as linear too). A failing differentiated Jacobian whose
error, configuration by configuration, is within its tolerance plus
:data:`NOISE_FACTOR` times that (at least the run's :data:`NOISE_QUANTILE`
level, so that a few rough configurations excuse only themselves) is not a
finding: it is reported as an *error* (the Jacobian could not be compared),
naming the roughness — not as a wrong Jacobian, and never as a pass.

**Errors** (:func:`fkcheck.core.metrics.jacobian_column_errors`). Per
configuration, the largest over the columns of the norm of the difference of
the linear 3-vectors (m/rad; m/m for a prismatic column) and of
the angular ones (rad/rad; 0 for a prismatic column); per column, the largest
over the configurations — the report names the first joint whose column
disagrees.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from fkcheck.backends.base import Backend, FixedConfigurations
from fkcheck.core.metrics import jacobian_column_errors
from fkcheck.core.tolerances import FINITE_DIFFERENCE, FINITE_DIFFERENCE_STEP, check_limit
from fkcheck.core.typing import JACOBIAN_REFERENCES, Float, JacobianReference
from fkcheck.errors import FkcheckError
from fkcheck.model.frames import frame_jacobian, reference_poses, relative_pose
from fkcheck.model.types import Model, resolve_frame

__all__ = [
    "NOISE_FACTOR",
    "NOISE_QUANTILE",
    "SAMPLES_KEPT",
    "Explain",
    "JacobianComparison",
    "JacobianSample",
    "JacobianSpec",
    "check_fixed_from",
    "finite_difference_jacobian",
    "method_of",
]

#: Configurations whose two Jacobians are kept for the diagnosis and the report
#: (the first ones compared, plus the worst).
SAMPLES_KEPT = 32


@dataclass(frozen=True)
class JacobianSpec:
    """What ``--jacobian`` compares.

    Attributes:
        reference: ``"world-aligned"``, ``"local"`` or ``"world"``.
        tol: Tolerance on both parts: linear (m/rad) and angular (rad/rad).
    """

    reference: JacobianReference
    tol: float

    def __post_init__(self) -> None:
        if self.reference not in JACOBIAN_REFERENCES:
            raise FkcheckError(
                f"Jacobian reference {self.reference!r} unknown; references are: "
                f"{', '.join(JACOBIAN_REFERENCES)}"
            )
        check_limit(self.tol, "tol_jacobian", "Jacobian tolerance")


@dataclass(frozen=True, eq=False)
class JacobianSample:
    """Both Jacobians at some configurations, kept for the diagnosis and the report.

    Attributes:
        index: ``(K,)`` indices into the check's configurations.
        ours: fkcheck's Jacobians there, ``(K, 6, n)``.
        theirs: The backend's, ``(K, 6, n)``.
        from_T_to: fkcheck's pose of the ``to`` frame there, ``(K, 4, 4)``.
    """

    index: tuple[int, ...]
    ours: Float
    theirs: Float
    from_T_to: Float


#: Names why two Jacobians differ, from the kept configurations: ``(sample, model,
#: spec, tolerance) → (headline, details)``. The engine cannot import the
#: diagnosis (a layer above it); :func:`fkcheck.check` hands it
#: :func:`fkcheck.diagnose.jacobian.explain_sample`.
Explain = Callable[["JacobianSample", Model, JacobianSpec, float], tuple[str, tuple[str, ...]]]


#: How far above the measured roughness a differentiated Jacobian's error may be and
#: still be put down to the backend's noise: the second difference only measures the
#: noise's size (its first difference, which reaches the Jacobian, is uncorrelated
#: with it), so one configuration's pair may be unlucky; 3 covers that.
NOISE_FACTOR = 3.0
#: The run-wide noise level is this quantile of the per-configuration roughness: a
#: few rough configurations (a backend that clamps at its limits) excuse only
#: themselves, not the whole run.
NOISE_QUANTILE = 0.9


def _noise_level(noise: Float) -> Float:
    """Per configuration: what its error may be and still be noise (see :data:`NOISE_FACTOR`)."""
    return NOISE_FACTOR * np.maximum(noise, np.quantile(noise, NOISE_QUANTILE))


def check_fixed_from(model: Model, frame_from: str) -> None:
    """Refuse a ``from`` frame that joints move: velocities relative to it are not a Jacobian's.

    Raises:
        FkcheckError: ``frame_from`` sits on a DH frame after a joint.
    """
    spec = resolve_frame(model, frame_from)
    if spec.dh not in (0, "world"):
        moving = model.dof if spec.dh == "tcp" else spec.dh
        raise FkcheckError(
            f"--jacobian: frame {frame_from!r} moves with joints 1–{moving}; the Jacobian is "
            "taken relative to a frame fixed to the base: use --from world, the base frame "
            "or a frame on DH frame 0"
        )


def method_of(backend: Backend, *, own: bool) -> str:
    """How a backend's Jacobian was obtained: its own (``own``), or finite differences."""
    if own:
        return backend.jacobian_method or f"{backend.method}: its own Jacobian"
    return f"central differences of its poses, step {FINITE_DIFFERENCE_STEP:g}"


@dataclass(frozen=True, eq=False)
class FiniteDifference:
    """A Jacobian by central differences, and how much the backend's pose noise can move it.

    Attributes:
        jacobian: ``(N, 6, n)``: linear then angular, in ``from`` axes.
        noise_linear: ``(N,)``: per configuration, the largest over the joints of
            the backend's roughness (its second difference less the core's, m)
            over the step: what noise can add to the linear part, m/rad.
        noise_angular: ``(N,)``: the same for the angular part, rad/rad.
    """

    jacobian: Float
    noise_linear: Float
    noise_angular: Float


def finite_difference_jacobian(
    backend: Backend,
    model: Model,
    q: Float,
    pair: tuple[str, str],
    theirs_from_T_to: Float,
    ours_from_T_to: Float,
) -> FiniteDifference:
    """Jacobian of ``to`` by central differences of the backend's ``from_T_to``.

    All ``2n`` neighbours of every configuration go to the backend in one call.
    The core's poses there are computed too, only to subtract a smooth chain's
    curvature from the backend's second difference (the noise bound, see the
    module docstring); the Jacobian itself is the backend's alone.

    Args:
        backend: The backend differentiated.
        model: The model.
        q: The configurations, ``(N, n)``.
        pair: The ``(from, to)`` frames.
        theirs_from_T_to: The backend's ``from_T_to`` at ``q``, ``(N, 4, 4)``.
        ours_from_T_to: The core's, ``(N, 4, 4)``.
    """
    from scipy.spatial.transform import Rotation  # only a check with --jacobian needs it

    n, h = model.dof, FINITE_DIFFERENCE_STEP
    steps = np.concatenate([np.eye(n), -np.eye(n)]) * h  # (2n, n)
    stacked = (q[None, :, :] + steps[:, None, :]).reshape(-1, n)  # (2n·N, n)
    poses = np.asarray(backend.frame_poses(model, stacked, pair), dtype=np.float64)
    if poses.shape != (2, stacked.shape[0], 4, 4):
        raise FkcheckError(
            f"returned shape {poses.shape} at the finite-difference neighbours, "
            f"expected {(2, stacked.shape[0], 4, 4)}"
        )
    from_T_to = relative_pose(poses[0], poses[1]).reshape(2, n, q.shape[0], 4, 4)
    plus, minus = from_T_to[0], from_T_to[1]  # (n, N, 4, 4)
    linear = (plus[..., :3, 3] - minus[..., :3, 3]) / (2 * h)  # (n, N, 3)
    turn = plus[..., :3, :3] @ np.swapaxes(minus[..., :3, :3], -1, -2)
    angular = Rotation.from_matrix(turn.reshape(-1, 3, 3)).as_rotvec().reshape(n, -1, 3) / (2 * h)
    jacobian = np.concatenate([linear, angular], axis=2).transpose(1, 2, 0)  # (N, 6, n)

    def second_difference(side: Float, center: Float) -> tuple[Float, Float]:
        """``p+ + p− − 2p0`` and ``rotvec(R+ R0ᵀ) + rotvec(R− R0ᵀ)``, ``(n, N, 3)`` each."""
        lin = side[0, ..., :3, 3] + side[1, ..., :3, 3] - 2 * center[None, :, :3, 3]
        back = np.swapaxes(center[:, :3, :3], -1, -2)[None]
        ang = [Rotation.from_matrix((s[..., :3, :3] @ back).reshape(-1, 3, 3)).as_rotvec()
               for s in side]  # fmt: skip
        return lin, (ang[0] + ang[1]).reshape(n, -1, 3)

    ours_root = reference_poses(model, stacked, pair)
    ours = relative_pose(ours_root[0], ours_root[1]).reshape(2, n, q.shape[0], 4, 4)
    b_lin, b_ang = second_difference(from_T_to, theirs_from_T_to)
    c_lin, c_ang = second_difference(ours, ours_from_T_to)
    noise_linear = np.linalg.norm(b_lin - c_lin, axis=2).max(axis=0) / h  # (N,)
    noise_angular = np.linalg.norm(b_ang - c_ang, axis=2).max(axis=0) / h
    return FiniteDifference(jacobian, noise_linear, noise_angular)


def _into_from(jac: Float, root_T_from: Float, reference: JacobianReference) -> Float:
    """A Jacobian in a root frame's terms moved to a fixed ``from`` frame of that root."""
    if reference == "local":
        return jac
    R_t = np.swapaxes(root_T_from[:, :3, :3], 1, 2)
    lin, ang = jac[:, :3], jac[:, 3:]
    if reference == "world":  # the body point at from's origin: v0 + ω × p_from
        lin = lin + np.cross(ang, root_T_from[:, :3, 3][:, :, None], axis=1)
    return np.concatenate([R_t @ lin, R_t @ ang], axis=1)


def _from_world_aligned(jac: Float, from_T_to: Float, reference: JacobianReference) -> Float:
    """A backend's world-aligned Jacobian (``from`` axes) in ``reference``, with its own pose.

    The engine's own few lines, on purpose: a backend's side never goes through
    the core's :func:`fkcheck.core.jacobian.re_express`, so a mistake there
    cannot cancel out.
    """
    if reference == "world-aligned":
        return jac
    lin, ang = jac[:, :3], jac[:, 3:]
    if reference == "local":
        R_t = np.swapaxes(from_T_to[:, :3, :3], 1, 2)
        return np.concatenate([R_t @ lin, R_t @ ang], axis=1)
    # world: the body point passing through from's origin, v_to + p_to × ω
    return np.concatenate([lin + np.cross(from_T_to[:, :3, 3][:, :, None], ang, axis=1), ang], 1)


@dataclass(eq=False)
class JacobianComparison:
    """Accumulates one backend's Jacobian errors over the chunks of a check.

    Call :meth:`add` with each chunk's configurations and both sides' root poses
    of ``(from, to)``; the arrays are then complete.
    """

    backend: Backend
    model: Model
    pair: tuple[str, str]
    spec: JacobianSpec
    total: int
    linear_error: Float = field(init=False)
    angular_error: Float = field(init=False)
    column_linear: Float = field(init=False)
    column_angular: Float = field(init=False)
    own: bool | None = field(init=False, default=None)
    noise_linear: Float = field(init=False)
    noise_angular: Float = field(init=False)
    _kept: list[tuple[int, Float, Float, Float]] = field(init=False, default_factory=list)
    _worst: tuple[float, int, Float, Float, Float] | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        self.linear_error = np.empty(self.total)
        self.angular_error = np.empty(self.total)
        self.column_linear = np.zeros(self.model.dof)
        self.column_angular = np.zeros(self.model.dof)
        self.noise_linear = np.zeros(self.total)  # stays 0 for a backend's own Jacobian
        self.noise_angular = np.zeros(self.total)

    @property
    def skip_reason(self) -> str | None:
        """Why this backend's Jacobian is not compared, or ``None``."""
        inner = getattr(self.backend, "backend", self.backend)  # an isolated one's own
        if isinstance(inner, FixedConfigurations):
            return "measured poses hold no neighbouring configurations to differentiate"
        return None

    @property
    def tolerance(self) -> float:
        """The tolerance applied: the asked one, floored by finite differences' accuracy."""
        if self.own:
            return self.spec.tol
        return max(self.spec.tol, FINITE_DIFFERENCE)

    @property
    def method(self) -> str:
        """How the backend's Jacobian was obtained (after :meth:`add`)."""
        return method_of(self.backend, own=bool(self.own))

    def add(
        self, first: int, q: Float, ours_root: Float, ours_from_T_to: Float, theirs: Float
    ) -> None:
        """Compare one chunk.

        Args:
            first: Index of the chunk's first configuration.
            q: The chunk's configurations, ``(m, n)``.
            ours_root: The core's world poses of ``(from, to)``, ``(2, m, 4, 4)``.
            ours_from_T_to: The core's ``from_T_to``, ``(m, 4, 4)``.
            theirs: The backend's root poses of ``(from, to)``, ``(2, m, 4, 4)``.
        """
        ref, frame_to = self.spec.reference, self.pair[1]
        # The core's own Jacobian in the reference asked (its local/world code runs too).
        ours = _into_from(frame_jacobian(self.model, q, frame_to, ref), ours_root[0], ref)
        native = None
        if self.backend.jacobian_method is not None and self.own is not False:
            references = self.backend.jacobian_references
            asked = ref if ref in references else "world-aligned"
            native = self.backend.frame_jacobian(self.model, q, frame_to, asked)
            self.own = native is not None
        theirs_from_T_to = relative_pose(theirs[0], theirs[1])
        if native is not None:
            native = np.asarray(native, dtype=np.float64)
            if native.shape != ours.shape:
                raise FkcheckError(
                    f"returned a Jacobian of shape {native.shape}, expected {ours.shape}"
                )
            in_from = _into_from(native, theirs[0], asked)
            if asked != ref:
                in_from = _from_world_aligned(in_from, theirs_from_T_to, ref)
        else:
            self.own = False
            fd = finite_difference_jacobian(self.backend, self.model, q, self.pair,
                                            theirs_from_T_to, ours_from_T_to)  # fmt: skip
            in_from = _from_world_aligned(fd.jacobian, theirs_from_T_to, ref)
            noise_linear = fd.noise_linear
            if ref == "world":  # v + p × ω: the angular noise, times |p|, is linear noise too
                reach = np.linalg.norm(theirs_from_T_to[:, :3, 3], axis=1)
                noise_linear = noise_linear + reach * fd.noise_angular
            self.noise_linear[first : first + q.shape[0]] = noise_linear
            self.noise_angular[first : first + q.shape[0]] = fd.noise_angular
        lin, ang = jacobian_column_errors(ours, in_from)  # (m, n) each
        m = q.shape[0]
        self.linear_error[first : first + m] = lin.max(axis=1, initial=0.0)
        self.angular_error[first : first + m] = ang.max(axis=1, initial=0.0)
        self.column_linear = np.maximum(self.column_linear, lin.max(axis=0, initial=0.0))
        self.column_angular = np.maximum(self.column_angular, ang.max(axis=0, initial=0.0))
        room = SAMPLES_KEPT - len(self._kept)
        for k in range(min(room, m)):
            self._kept.append((first + k, ours[k], in_from[k], ours_from_T_to[k]))
        score = np.maximum(lin.max(axis=1, initial=0.0), ang.max(axis=1, initial=0.0))
        k = int(np.argmax(score))
        if self._worst is None or score[k] > self._worst[0]:
            self._worst = (float(score[k]), first + k, ours[k], in_from[k], ours_from_T_to[k])

    def too_rough(self, tol: float) -> str | None:
        """Why a failing differentiated Jacobian is no finding: its poses are too rough.

        ``None`` when the backend gave its own Jacobian, or some disagreement
        exceeds the tolerance plus what the backend's pose noise can explain
        (a real finding); else the sentence the result reports as an error.
        """
        if self.own is not False:
            return None
        lin, ang = self.linear_error, self.angular_error
        explained = (lin <= tol + _noise_level(self.noise_linear)) & (
            ang <= tol + _noise_level(self.noise_angular)
        )
        if not explained.all():  # NaN is never explained
            return None
        rough_m = float(self.noise_linear.max()) * FINITE_DIFFERENCE_STEP
        rough_rad = float(self.noise_angular.max()) * FINITE_DIFFERENCE_STEP
        return (
            f"Jacobian ({self.spec.reference}) not compared: the backend's poses are too "
            f"coarse to differentiate (too few digits printed? float32?): between neighbours "
            f"{FINITE_DIFFERENCE_STEP:g} apart they stray from a smooth chain by up to "
            f"{rough_m:.2g} m / {rough_rad:.2g} rad, up to {self.noise_linear.max():.2g} m/rad / "
            f"{self.noise_angular.max():.2g} rad/rad in central differences, as large as every "
            f"difference seen ({lin.max():.2g} m/rad, {ang.max():.2g} rad/rad); print every "
            "digit (%.17g, repr) or give the backend a Jacobian of its own"
        )

    def sample(self) -> JacobianSample:
        """The kept configurations (the first ones, and the worst), both Jacobians."""
        rows = list(self._kept)
        if self._worst is not None and all(r[0] != self._worst[1] for r in rows):
            rows.append(self._worst[1:])
        n = self.model.dof
        return JacobianSample(
            index=tuple(r[0] for r in rows),
            ours=np.array([r[1] for r in rows]).reshape(-1, 6, n),
            theirs=np.array([r[2] for r in rows]).reshape(-1, 6, n),
            from_T_to=np.array([r[3] for r in rows]).reshape(-1, 4, 4),
        )
