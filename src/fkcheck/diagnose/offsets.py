"""Constant frame offsets: is the disagreement only a different base or tip frame?

If two tables describe the same robot but name different frames, their poses
differ by constant transforms on each side: ``T_ref(q) = X · T_dh(q) · Y`` for
every ``q``. :func:`fit_offsets` finds ``X`` (base side) and ``Y`` (tip side):

1. closed-form starting points — the hand-eye equation ``A·X = X·B`` between pairs of
   configurations (``A = T_ref,i·T_ref,j⁻¹``, ``B = T_dh,i·T_dh,j⁻¹``; rotation by
   orthogonal Procrustes on the rotation vectors, translation by linear least
   squares), and the base-only and tip-only averages;
2. a least-squares polish on SE(3) (:func:`scipy.optimize.least_squares`, each
   offset parametrised as a rotation vector and a translation applied on the right
   of its starting point, so there is no gimbal lock and no constraint).

If the fitted offsets leave nothing, the tables agree and only the frames differ.
:func:`explain_offsets` says which (a pure ``Rz(π)`` at the base is ROS
``base_link`` vs the controller's ``base``; a fixed rotation at the tip is
``flange``/``ee_link`` vs ``tool0``), and prints the model-file tables that make
the check pass. A constant translation along the first joint axis is honestly
ambiguous: it is exactly what a wrong ``d1`` does, and the text says both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.diagnose.findings import Explanation, Kind
from fkcheck.diagnose.problem import (
    Problem,
    Residual,
    pose_residuals,
    se3_from_rotvec_translation,
)
from fkcheck.model.offsets import offset_from_matrix
from fkcheck.model.types import Model, Offset
from fkcheck.model.write import frame_toml, offset_toml

__all__ = ["OffsetFit", "explain_offsets", "fit_offsets"]


#: Offsets this close to a multiple of 90° / to zero are tried in their exact form.
_CLEAN_ANGLE_RAD = 1e-5
_CLEAN_LENGTH_M = 1e-6


@dataclass(frozen=True, eq=False)
class OffsetFit:
    """``T_ref ≈ X · T_dh · Y``.

    Attributes:
        X: Base-side offset (4×4).
        Y: Tip-side offset (4×4).
        residual: What is left.
    """

    X: Float
    Y: Float
    residual: Residual


def _project_rotation(M: Float) -> Float:
    U, _, Vt = np.linalg.svd(M)
    R: Float = U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt
    return R


def _mean_pose(T: Float) -> Float:
    out = np.eye(4)
    out[:3, :3] = _project_rotation(T[:, :3, :3].sum(axis=0))
    out[:3, 3] = T[:, :3, 3].mean(axis=0)
    return out


def _hand_eye(T_dh: Float, T_ref: Float, rng: np.random.Generator) -> tuple[Float, Float] | None:
    """Closed-form ``X`` from ``A·X = X·B`` over configuration pairs, then ``Y`` by averaging."""
    from scipy.spatial.transform import Rotation

    N = T_dh.shape[0]
    if N < 3:
        return None
    i = rng.integers(0, N, size=4 * N)
    j = rng.integers(0, N, size=4 * N)
    keep = i != j
    i, j = i[keep], j[keep]
    A = T_ref[i] @ invert(T_ref[j])
    B = T_dh[i] @ invert(T_dh[j])
    a = Rotation.from_matrix(A[:, :3, :3]).as_rotvec()
    b = Rotation.from_matrix(B[:, :3, :3]).as_rotvec()
    na, nb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    ok = (na > 0.05) & (na < math.pi - 0.05) & (nb > 0.05) & (nb < math.pi - 0.05)
    if ok.sum() < 3:
        return None
    a, b, A, B = a[ok], b[ok], A[ok], B[ok]
    if np.linalg.matrix_rank(b / nb[ok, None], tol=1e-3) < 2:
        return None  # all relative rotations about one axis: X is not determined this way
    R_X = _project_rotation(a.T @ b)  # Procrustes: R b ≈ a
    lhs = (A[:, :3, :3] - np.eye(3)).reshape(-1, 3)
    rhs = (np.einsum("ij,kj->ki", R_X, B[:, :3, 3]) - A[:, :3, 3]).reshape(-1)
    t_X = np.linalg.lstsq(lhs, rhs, rcond=None)[0]
    X = np.eye(4)
    X[:3, :3], X[:3, 3] = R_X, t_X
    Y = _mean_pose(invert(X @ T_dh) @ T_ref)
    return X, Y


def fit_offsets(T_dh: Float, T_ref: Float, seed: int = 0) -> OffsetFit:
    """Fit constant ``X``, ``Y`` with ``T_ref(q) ≈ X · T_dh(q) · Y``.

    Args:
        T_dh: ``(N, 4, 4)`` the table's poses.
        T_ref: ``(N, 4, 4)`` the reference's poses for the same configurations.
        seed: Seed for choosing configuration pairs.

    Returns:
        The best fit found from the closed-form starting points.
    """
    from scipy.optimize import least_squares

    rng = np.random.default_rng(seed)
    starts: list[tuple[Float, Float]] = [
        (np.eye(4), np.eye(4)),
        (_mean_pose(T_ref @ invert(T_dh)), np.eye(4)),  # base side only
        (np.eye(4), _mean_pose(invert(T_dh) @ T_ref)),  # tip side only
    ]
    hand_eye = _hand_eye(T_dh, T_ref, rng)
    if hand_eye is not None:
        starts.append(hand_eye)

    def residuals(xi: Float, X0: Float, Y0: Float) -> Float:
        return pose_residuals(
            X0
            @ se3_from_rotvec_translation(xi[:6])
            @ T_dh
            @ Y0
            @ se3_from_rotvec_translation(xi[6:]),
            T_ref,
        )

    best: tuple[float, Float, Float] | None = None
    for X0, Y0 in starts:
        cost0 = float(np.sum(residuals(np.zeros(12), X0, Y0) ** 2))
        if best is not None and cost0 > 100 * best[0] + 1e-20:
            continue  # a poor start: not worth a polish
        sol = least_squares(
            residuals,
            np.zeros(12),
            args=(X0, Y0),
            method="lm",
            xtol=1e-15,
            ftol=1e-15,
            gtol=1e-15,
            max_nfev=2000,
        )
        X, Y = (
            X0 @ se3_from_rotvec_translation(sol.x[:6]),
            Y0 @ se3_from_rotvec_translation(sol.x[6:]),
        )
        cost = float(np.sum(residuals(np.zeros(12), X, Y) ** 2))
        if best is None or cost < best[0]:
            best = (cost, X, Y)
    assert best is not None
    _, X, Y = best
    return OffsetFit(X, Y, Problem.errors_against(X @ T_dh @ Y, T_ref))


def _snap_rotation(R: Float, tol: float) -> Float | None:
    """``R`` as an exact signed permutation (quarter turns only), if it is within ``tol``."""
    rounded = np.round(R)
    if np.abs(R - rounded).max() < tol and np.allclose(rounded @ rounded.T, np.eye(3)):
        return rounded + 0.0
    return None


def _single_axis(R: Float) -> tuple[int, float] | None:
    """``(axis index, angle)`` if ``R`` turns about one coordinate axis, else ``None``."""
    for k in range(3):
        if abs(R[k, k] - 1.0) < 1e-12:
            i, j = [m for m in range(3) if m != k]
            return k, math.atan2(R[j, i], R[i, i])
    return None


def _clean(
    T: Float,
    angle_tol: float = _CLEAN_ANGLE_RAD,
    length_tol: float = _CLEAN_LENGTH_M,
    step_deg: float = 90.0,
) -> Float:
    """``T`` with round-off removed, rotations snapped to round values.

    Quarter turns and single-axis turns by multiples of ``step_deg`` (within
    ``angle_tol``) are made exact, lengths below ``length_tol`` zero.

    Works on the matrix, not on rpy angles: at pitch = ±90° (UR's flange) the rpy
    angles are individually ill-defined and cannot be rounded one by one.
    """
    out = np.eye(4)
    out[:3, 3] = np.where(np.abs(T[:3, 3]) < length_tol, 0.0, T[:3, 3])
    R = T[:3, :3]
    exact = _snap_rotation(R, angle_tol)
    if exact is not None:
        out[:3, :3] = exact
        return out
    out[:3, :3] = R
    single = _single_axis(_snap_rotation_axis(R, angle_tol))
    if single is not None:
        k, angle = single
        step = math.radians(step_deg)
        rounded = round(angle / step) * step
        if abs(angle - rounded) < angle_tol:
            i, j = [m for m in range(3) if m != k]
            c, s_ = math.cos(rounded), math.sin(rounded)
            M = np.eye(3)
            M[i, i], M[i, j], M[j, i], M[j, j] = c, -s_, s_, c
            out[:3, :3] = M
    return out


def _snap_rotation_axis(R: Float, tol: float) -> Float:
    """``R`` with a coordinate axis it (nearly) keeps fixed made exactly fixed."""
    for k in range(3):
        if abs(R[k, k] - 1.0) < tol:
            i, j = [m for m in range(3) if m != k]
            angle = math.atan2(R[j, i] - R[i, j], R[i, i] + R[j, j])
            c, s_ = math.cos(angle), math.sin(angle)
            M = np.eye(3)
            M[i, i], M[i, j], M[j, i], M[j, j] = c, -s_, s_, c
            return M
    return R


def _is_identity(T: Float) -> bool:
    from fkcheck.core.metrics import rotation_error_rad

    return bool(
        np.linalg.norm(T[:3, 3]) < _CLEAN_LENGTH_M
        and rotation_error_rad(T, np.eye(4)) < _CLEAN_ANGLE_RAD
    )


def _describe_rotation(T: Float) -> str:
    from scipy.spatial.transform import Rotation

    rv = Rotation.from_matrix(T[:3, :3]).as_rotvec()
    angle = float(np.linalg.norm(rv))
    if angle < 1e-12:
        return "no rotation"
    axis = rv / angle
    for name, unit in (("x", (1, 0, 0)), ("y", (0, 1, 0)), ("z", (0, 0, 1))):
        if abs(abs(axis @ np.array(unit)) - 1) < 1e-9:
            sign = "" if axis @ np.array(unit) > 0 else "-"
            return f"R{name}({sign}{math.degrees(angle):.6g}°)"
    return f"{math.degrees(angle):.6g}° about ({axis[0]:.4f}, {axis[1]:.4f}, {axis[2]:.4f})"


def _side_text(T: Float, side: str) -> str:
    rot = _describe_rotation(T)
    t = T[:3, 3] * 1e3
    trans = (
        "no translation"
        if np.linalg.norm(t) < 1e-6
        else (f"translation ({t[0]:.3f}, {t[1]:.3f}, {t[2]:.3f}) mm")
    )
    return f"{side}: {rot}, {trans}"


def _tidy(T: Float) -> Offset:
    """An offset for a model file: round-off (1e-9 rad, 1e-12 m) removed from a composition."""
    cleaned = _clean(T, angle_tol=1e-9, length_tol=1e-12, step_deg=15.0)
    off = offset_from_matrix(cleaned)

    def half_turn(v: float) -> float:
        # Rx/Ry/Rz(−π) = Rx/Ry/Rz(π): write the positive half-turn people expect.
        return math.pi if v == -math.pi else v

    x, y, z = (round(v, 12) + 0.0 for v in off.xyz)
    roll, pitch, yaw = (half_turn(v) for v in off.rpy)
    return Offset((x, y, z), (roll, pitch, yaw))


def _fix_side(model: Model, frame: str, T: Float, base_side: bool) -> tuple[Model, str]:
    """Apply one side's offset to the model; return the new model and its TOML."""
    spec = model.frames[frame]
    unit = model.angle_unit
    if base_side and spec.dh == "world" and spec.offset.is_identity:
        # from = world: the base transform absorbs X (world_T_base' = X⁻¹·… on this side).
        base = _tidy(invert(T) @ model.base.matrix)
        return replace(model, base=base), offset_toml("base", base, unit)
    if not base_side and spec.dh == "tcp" and spec.offset.is_identity:
        tool = _tidy(model.tool.matrix @ T)
        return replace(model, tool=tool), offset_toml("tool", tool, unit)
    matrix = spec.offset.matrix @ (invert(T) if base_side else T)
    new_spec = replace(spec, offset=_tidy(matrix))
    frames = dict(model.frames)
    frames[frame] = new_spec
    return replace(model, frames=frames), frame_toml(new_spec, unit)


def _first_axis_in_from(problem: Problem) -> Float | None:
    """Joint 1's axis direction in the ``from`` frame, if ``from`` is fixed to the base."""
    spec = problem.model.frames[problem.frame_from]
    if spec.dh not in ("world", 0):
        return None
    from fkcheck.model.frames import reference_poses

    q0 = np.zeros((1, problem.model.dof))
    frames = problem.model.fk(q0, all_frames=True)[0]
    world_T_from = reference_poses(problem.model, q0, [problem.frame_from])[0, 0]
    k = 0 if problem.model.convention == "standard" else 1
    z: Float = (invert(world_T_from) @ frames[k])[:3, 2]
    return z * (-1.0 if problem.model.joints[0].flip else 1.0)


def _rotations_in_steps(X: Float, Y: Float) -> bool:
    """Both offsets are rotations by multiples of 15° (or none), without a translation."""
    pure_rotation = all(np.linalg.norm(T[:3, 3]) < _CLEAN_LENGTH_M for T in (X, Y))
    return pure_rotation and all(
        _is_identity(T) or np.array_equal(T, _clean(T, step_deg=15.0)) for T in (X, Y)
    )


def _like_d1(problem: Problem, X: Float) -> str | None:
    """A detail when the base offset is a shift along joint 1's axis: d1 may be the error."""
    axis = _first_axis_in_from(problem)
    t = X[:3, 3]
    if axis is None or np.linalg.norm(np.cross(t, axis)) >= 1e-9:
        return None
    shift = float(t @ axis)
    return (
        f"ambiguous: a constant shift of {shift * 1e3:+.3f} mm along joint 1's axis at "
        f"the base is exactly what d1 {'+' if shift >= 0 else '-'} "
        f"{abs(shift) * 1e3:.3f} mm does — the table's d1 may be the error, not the frame"
    )


def explain_offsets(problem: Problem) -> list[Explanation]:
    """Constant base/tip offsets, as an explanation (with the fixing model-file text).

    Fitted on up to :data:`~fkcheck.diagnose.problem.SPREAD_CONFIGURATIONS` of the
    problem's configurations, judged on all of them.
    """
    T_dh = problem.poses(problem.model)
    spread = problem.spread()
    fit = fit_offsets(spread.poses(problem.model), spread.reference)
    X, Y = fit.X, fit.Y
    clean_X, clean_Y = _clean(X, step_deg=15.0), _clean(Y, step_deg=15.0)
    cleaned = problem.errors(clean_X @ T_dh @ clean_Y)
    if problem.explained(cleaned):
        X, Y, residual = clean_X, clean_Y, cleaned
    else:
        residual = problem.errors(X @ T_dh @ Y)
    explains = problem.explained(residual)
    base_same, tip_same = _is_identity(X), _is_identity(Y)
    if base_same and tip_same:
        return []  # no constant offset helps: not a frame problem
    model, fixes = problem.model, []
    details: list[str] = []
    if not base_same:
        model, text = _fix_side(model, problem.frame_from, X, base_side=True)
        fixes.append(text)
        details.append(_side_text(X, f"base side ({problem.frame_from})"))
    if not tip_same:
        model, text = _fix_side(model, problem.frame_to, Y, base_side=False)
        fixes.append(text)
        details.append(_side_text(Y, f"tip side ({problem.frame_to})"))

    clean = explains and _rotations_in_steps(X, Y)
    title = _title(problem, X, Y, base_same, tip_same, explains, clean)
    if explains and not base_same and np.linalg.norm(X[:3, 3]) > _CLEAN_LENGTH_M:
        ambiguous = _like_d1(problem, X)
        if ambiguous is not None:
            details.append(ambiguous)
    if explains:
        check = problem.residual(model)
        details.append(f"with the fix applied, the table is {check.text()} from the reference")
    kind: Kind = "frames" if clean else "offset"
    numbers = sum(_components(T) for T, same in ((X, base_same), (Y, tip_same)) if not same)
    return [
        Explanation(
            kind,
            title,
            residual,
            explains,
            tuple(details),
            fix_toml="\n".join(fixes),
            model=model,
            numbers=numbers,
        )
    ]


def _components(T: Float) -> int:
    """How many of an offset's xyz/rpy numbers are not zero (round-off aside)."""
    off = offset_from_matrix(T)
    return sum(abs(v) > _CLEAN_LENGTH_M for v in off.xyz) + sum(
        abs(v) > _CLEAN_ANGLE_RAD for v in off.rpy
    )


def _title(
    problem: Problem,
    X: Float,
    Y: Float,
    base_same: bool,
    tip_same: bool,
    explains: bool,
    clean: bool,
) -> str:
    parts = []
    if not base_same:
        rz_pi = np.linalg.norm(X[:3, 3]) < _CLEAN_LENGTH_M and np.allclose(
            X[:3, :3], np.diag([-1.0, -1.0, 1.0]), atol=1e-9
        )
        if rz_pi:
            parts.append(
                f"the reference's {problem.frame_from} is the table's turned Rz(π): "
                "base_link vs base (ROS base_link is the controller's base turned 180° about z)"
            )
        elif np.allclose(X[:3, :3], np.eye(3), atol=1e-9):
            t = X[:3, 3] * 1e3
            parts.append(
                f"the base frames ({problem.frame_from}) differ by a translation "
                f"({t[0]:.3f}, {t[1]:.3f}, {t[2]:.3f}) mm"
            )
        else:
            parts.append(f"the base frames ({problem.frame_from}) differ by a constant transform")
    if not tip_same:
        if np.linalg.norm(Y[:3, 3]) < _CLEAN_LENGTH_M:
            parts.append(
                f"the tip frames ({problem.frame_to}) differ by a fixed rotation: "
                "flange/ee_link vs tool0?"
            )
        else:
            parts.append(f"the tip frames ({problem.frame_to}) differ by a constant transform")
    if not explains:
        lead = "constant offsets remove part of it: "
    elif clean:
        lead = "only the frames differ: "
    else:
        lead = "a constant offset explains it: "
    return lead + "; ".join(parts)
