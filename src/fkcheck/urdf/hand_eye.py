"""The hand–eye fit of a DH chain onto a URDF chain: ``M ≈ X·U·Y`` (:mod:`fkcheck.urdf.mapping`).

The closed form (rotation axes aligned, then the translation by least squares),
the free part of the split chosen, and the least-squares polish when the joints'
turns leave a spin free.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from fkcheck.core.geometry import invert
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.core.typing import Float

__all__: list[str] = []

#: Relative turns below this (rad, root-mean-square over the fit's pairs) leave a
#: translation direction of the hand–eye fit free: a pair's turn is ~0.1 rad
#: (:data:`~fkcheck.urdf.chain_fit._FIT_STEP`), round-off ~1e-15 rad, a URDF's
#: rounded π/2 ~4e-6 rad off.
_FREE_TURN_RAD = 1e-6
#: A turn of the split that leaves the fit this much worse (m + rad) is not free:
#: round-off of a fit is ~1e-15, a real change of the fit is of the reach's size.
_SAME_FIT = 1e-9
#: Hypotheses polished by least squares when no closed-form fit fits, and the
#: spins each starts from (:func:`_refine`).
_REFINE = 4
_SPINS = 8


def _hand_eye(M: Float, U: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` with ``M ≈ X·U·Y``, from configuration pairs ``(M[2i], M[2i+1])``.

    Each pair's relative motions satisfy ``Y·C = D·Y`` (``C = M_a⁻¹M_b``,
    ``D = U_a⁻¹U_b``): the rotation maps ``C``'s rotation vectors onto ``D``'s
    (pure translations use their translation instead), the translation solves
    ``(I − R_D)·t = t_D − R·t_C`` by least squares in the directions the turns
    determine; the others are left to :func:`_pinned`.
    """
    C = invert(M[0::2]) @ M[1::2]
    D = invert(U[0::2]) @ U[1::2]
    c = Rotation.from_matrix(C[:, :3, :3]).as_rotvec()
    d = Rotation.from_matrix(D[:, :3, :3]).as_rotvec()
    still = np.linalg.norm(d, axis=1) < 1e-9
    c[still], d[still] = C[still, :3, 3], D[still, :3, 3]
    with warnings.catch_warnings():  # a single axis (a one-joint prefix) leaves a spin free
        warnings.simplefilter("ignore", UserWarning)
        rotation, _ = Rotation.align_vectors(d, c)
    R = rotation.as_matrix()
    lhs = (np.eye(3) - D[:, :3, :3]).reshape(-1, 3)
    rhs = (D[:, :3, 3] - C[:, :3, 3] @ R.T).reshape(-1)
    _, sv, Vt = np.linalg.svd(lhs, full_matrices=False)
    fixed = sv > _FREE_TURN_RAD * math.sqrt(D.shape[0])
    # The least-squares t with no component in the free directions (no pseudo-inverse of
    # round-off: with slides only, every direction is free and t is 0 here).
    t = Vt[fixed].T @ ((Vt[fixed] @ (lhs.T @ rhs)) / sv[fixed] ** 2)
    Y = np.eye(4)
    Y[:3, :3], Y[:3, 3] = R, t
    return _pinned(M, U, M[0] @ invert(Y) @ invert(U[0]), Y)


def _free_directions(U: Float) -> Float:
    """Directions (rows, in the tip's frame) along which ``Y``'s translation is free.

    ``X·U·Y = X·T(s)·U·T(−Rᵀs)·Y`` whenever every turn of ``U`` keeps ``s``: a
    slide's offset can sit on either side of it. With slides only that is every
    direction; with turns about one axis (parallel axes, one revolute joint among
    slides), that axis. The rows are orthonormal (none: ``Y`` is determined).
    """
    D = invert(U[0::2]) @ U[1::2]
    lhs = (np.eye(3) - D[:, :3, :3]).reshape(-1, 3)
    _, sv, Vt = np.linalg.svd(lhs, full_matrices=False)
    free: Float = Vt[sv <= _FREE_TURN_RAD * math.sqrt(D.shape[0])]
    return free


def _pinned(M: Float, U: Float, X: Float, Y: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` with the free part of the split chosen: the least turn, then the nearest.

    The motion cannot tell where along a free direction (:func:`_free_directions`)
    the URDF chain's base link sits from DH frame 0 (it moves the tip link the
    other way), nor, when every joint turns about one line and slides along it, how
    far the base link is turned about that line (:func:`_spin`). The base link is
    turned as little from DH frame 0 and put as close to its origin as the motion
    leaves free — where a URDF that starts its chain at DH frame 0 has it, and
    never 10²⁰ m away.
    """
    X, Y = _spin(M, U, X, Y)
    N = _free_directions(U).T  # (3, k), orthonormal columns, in the tip's frame
    if N.shape[1] == 0:
        return X, Y
    # Y → T(N·c)·Y moves X to A·T(−N·c)·U₀⁻¹ (A = M₀·Y⁻¹): its translation by −R_A·N·c.
    A = M[0] @ invert(Y)
    c = (A[:3, :3] @ N).T @ X[:3, 3]
    Y = Y.copy()
    Y[:3, 3] += N @ c
    return M[0] @ invert(Y) @ invert(U[0]), Y


def _deviation(M: Float, U: Float, X: Float, Y: Float) -> float:
    """How far ``X·U·Y`` strays from ``M``: metres plus radians, at worst."""
    E = invert(M) @ X @ U @ Y
    eye = np.broadcast_to(np.eye(4), E.shape)
    return float(position_error_m(eye, E).max() + rotation_error_rad(eye, E).max())


def _spin(M: Float, U: Float, X: Float, Y: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` turned about the chain's one turning line, if that is free, by the least turn.

    When every joint turns about one line and slides along it (a lift under a
    turntable, a single slide), turning the base link about that line and the tip
    link back is the same motion: the turn that leaves ``X`` closest to no turn is
    kept, if the fit stays as good (it does not when the turns have several lines).
    """
    B = U[1::2] @ invert(U[0::2])  # relative motions in the base link's frame
    r = Rotation.from_matrix(B[:, :3, :3]).as_rotvec()
    turning = np.linalg.norm(r, axis=1) > 1e-9
    directions = r[turning] if turning.any() else B[:, :3, 3]
    if len(directions) == 0:
        return X, Y
    _, sv, Vt = np.linalg.svd(directions, full_matrices=False)
    if sv[0] == 0.0 or (len(sv) > 1 and sv[1] > _FREE_TURN_RAD * sv[0]):
        return X, Y  # turns (or slides) in more than one direction: the spin is set
    n = Vt[0]
    point: Float = np.zeros(3)
    if turning.any():  # the line's point: (I − R)·p = t across the axis, for every turn
        lhs = (np.eye(3) - B[turning, :3, :3]).reshape(-1, 3)
        t = B[turning, :3, 3]
        rhs = (t - np.outer(t @ n, n)).reshape(-1)
        point = np.asarray(np.linalg.lstsq(lhs, rhs, rcond=None)[0], dtype=np.float64)
    # The turn φ about n that leaves X least turned: max of trace(R_X·Rot(n, φ)).
    R = X[:3, :3]
    K = np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])
    phi = math.atan2(float(np.trace(R @ K)), float(np.trace(R) - n @ R @ n))
    about = np.eye(4)
    about[:3, :3] = Rotation.from_rotvec(phi * n).as_matrix()
    about[:3, 3] = point - about[:3, :3] @ point
    X2 = X @ about
    Y2 = invert(U[0]) @ invert(X2) @ M[0]
    if _deviation(M, U, X2, Y2) > _deviation(M, U, X, Y) + _SAME_FIT:
        return X, Y
    return X2, Y2


def _refine(M: Float, U: Float, X: Float, Y: Float) -> tuple[Float, Float]:
    """``X``, ``Y`` with ``M ≈ X·U·Y`` by least squares on every configuration.

    When every relative turn of ``U`` is about one direction (parallel axes, a
    single revolute joint among slides) the rotation fit leaves ``Y``'s spin about
    it free, and the closed form picks one at random: the translations decide it.
    Starts from :data:`_SPINS` spins of ``Y`` about that direction and keeps the best.
    """
    D = invert(U[0::2]) @ U[1::2]
    d = Rotation.from_matrix(D[:, :3, :3]).as_rotvec()
    d = d[np.linalg.norm(d, axis=1) > 1e-9]
    axis = np.linalg.svd(d)[2][0] if len(d) else np.array([0.0, 0.0, 1.0])
    M_inv = invert(M)

    def pose(p: Float) -> Float:
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = Rotation.from_rotvec(p[:3]).as_matrix(), p[3:]
        return T

    def residual(p: Float, X0: Float, Y0: Float) -> Float:
        E = M_inv @ (X0 @ pose(p[:6])) @ U @ (pose(p[6:]) @ Y0)
        rot = Rotation.from_matrix(E[:, :3, :3]).as_rotvec()
        return np.concatenate([rot.reshape(-1), E[:, :3, 3].reshape(-1)])

    best = (np.inf, X, Y)
    for spin in np.linspace(0.0, 2.0 * math.pi, _SPINS, endpoint=False):
        Y0 = pose(np.concatenate([spin * axis, np.zeros(3)])) @ Y
        X0 = M[0] @ invert(Y0) @ invert(U[0])
        sol = least_squares(residual, np.zeros(12), args=(X0, Y0), method="lm", xtol=1e-15)
        if sol.cost < best[0]:
            best = (float(sol.cost), X0 @ pose(sol.x[:6]), pose(sol.x[6:]) @ Y0)
    return best[1], best[2]
