"""Diagnose two Jacobians that disagree: which convention would make them agree.

When a backend's pose agrees with fkcheck's but its Jacobian does not, the
mistake is usually a convention, not a number. Each convention is a
:class:`JacobianMistake`: a transformation applied to the *expected* Jacobian
(fkcheck's, in ``reference``) that is then compared with the *observed* one
(the backend's), entry by entry, at worst over the configurations — the
linear rows (m/rad, m/m for a prismatic joint) and the angular rows (rad/rad,
rad/m) separately. A mistake *explains* the disagreement when both are within
the tolerances. Tried: each reference frame with each row order (six
combinations, the expected one included), and on each of them the column
matching and the point-offset fit (a column mistake and an offset together are
not tried):

* ``reference``: the other two reference frames (any of the six ordered pairs
  among ``"world-aligned"``, ``"local"`` and ``"world"``, moved with
  :func:`fkcheck.core.jacobian.re_express`) — the frame's own axes (Robotics
  Toolbox ``jacobe``, Pinocchio ``LOCAL``) where world axes were expected, or the
  spatial twist at the world origin (``WORLD``: the reference point at the base)
  where the frame origin's velocity was expected;
* ``blocks``: the angular rows first, as many textbooks write it;
* ``sign``, ``columns``, ``missing``: each observed column matched to the
  expected column (and sign) it equals — a joint's column with the opposite
  sign, the columns in another order, a joint's column left zero;
* ``offset``: the linear part is the velocity of another point of the last
  link, offset by a constant vector ``r`` in the target frame's axes —
  ``v_obs − v_exp = ω × (R r)`` — typically the flange's origin where the TCP
  was expected (the tool offset left out). ``r`` is fitted by linear least
  squares over every configuration and column (:func:`numpy.linalg.lstsq`); in
  ``"world"`` it cannot show (the spatial twist is the same for every point of
  the link), and a tool that also rotates makes ``"local"`` columns differ in
  their angular rows too, which this hypothesis does not fit.

:func:`diagnose_jacobian` works on arrays alone (no model, no backend);
:func:`explain_sample` is the hook ``fkcheck check --jacobian`` calls with the
configurations the engine kept. Differences are measured as the check measures
them (:func:`fkcheck.core.metrics.jacobian_column_errors`: the length of a
column's linear and angular 3-vectors). The mistakes and the diagnosis's types
are :mod:`fkcheck.diagnose.jacobian_mistakes` (re-exported here).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from fkcheck.core.jacobian import REFERENCES, Reference, re_express
from fkcheck.core.metrics import jacobian_column_errors
from fkcheck.core.typing import Float
from fkcheck.diagnose.jacobian_mistakes import (
    ANGULAR_FIRST,
    MISTAKE_ORDER,
    REFERENCE_NAMES,
    ColumnError,
    JacobianDiagnosis,
    JacobianExplanation,
    JacobianMistake,
    JacobianResidual,
    MistakeKind,
)
from fkcheck.engine.jacobian import JacobianSample, JacobianSpec
from fkcheck.io.format import format_fixed
from fkcheck.model.types import Model

__all__ = [
    "MISTAKE_ORDER",
    "REFERENCE_NAMES",
    "ColumnError",
    "JacobianDiagnosis",
    "JacobianExplanation",
    "JacobianMistake",
    "JacobianResidual",
    "MistakeKind",
    "column_errors",
    "diagnose_jacobian",
    "explain_sample",
]


def column_errors(expected: ArrayLike, observed: ArrayLike) -> tuple[Float, Float]:
    """The largest difference of each column over the configurations, linear and angular.

    Args:
        expected: ``(N, 6, n)`` (or ``(6, n)``), linear rows first.
        observed: The same shape.

    Returns:
        ``(linear, angular)``, each ``(n,)``: the largest length of the difference
        of the column's 3-vectors (:func:`~fkcheck.core.metrics.jacobian_column_errors`);
        a non-finite entry counts as ``inf``.

    Raises:
        ValueError: The shapes differ or are not ``(N, 6, n)``.
    """
    exp, obs = _pair(expected, observed)
    linear, angular = jacobian_column_errors(exp, obs)
    return linear.max(axis=0), angular.max(axis=0)


def _pair(expected: ArrayLike, observed: ArrayLike) -> tuple[Float, Float]:
    exp = np.asarray(expected, dtype=float)
    obs = np.asarray(observed, dtype=float)
    if exp.ndim == 2:
        exp = exp[None]
    if obs.ndim == 2:
        obs = obs[None]
    if exp.ndim != 3 or exp.shape[1] != 6 or exp.shape[0] == 0 or exp.shape[2] == 0:
        raise ValueError(f"expected Jacobian has shape {exp.shape}; a Jacobian is (N, 6, n)")
    if obs.shape != exp.shape:
        raise ValueError(
            f"observed Jacobian has shape {obs.shape}, the expected one {exp.shape}; "
            "they must match"
        )
    return exp, obs


def _residual(a: Float, b: Float) -> JacobianResidual:
    linear, angular = jacobian_column_errors(a, b)
    return JacobianResidual(float(linear.max()), float(angular.max()))


def _joint(names: Sequence[str], j: int) -> str:
    return f"joint {j + 1} ({names[j]})"


def _joints(names: Sequence[str], js: Sequence[int]) -> str:
    texts = [_joint(names, j) for j in js]
    return texts[0] if len(texts) == 1 else ", ".join(texts[:-1]) + " and " + texts[-1]


def _mm(r: Sequence[float]) -> str:
    return "(" + ", ".join(format_fixed(v * 1e3, 3) for v in r) + ") mm"


def _describe(m: JacobianMistake, expected_ref: Reference, names: Sequence[str]) -> str:
    parts: list[str] = []
    if m.reference is not None:
        parts.append(
            f"the backend's Jacobian is {REFERENCE_NAMES[m.reference]} where "
            f"{REFERENCE_NAMES[expected_ref]} was expected"
        )
    if m.angular_first:
        parts.append(
            "the backend's rows are angular first, then linear (the textbook order), "
            "where fkcheck's are linear first"
        )
    if m.flipped:
        whose = _joints(names, m.flipped)
        verb = "has" if len(m.flipped) == 1 else "have"
        parts.append(
            f"the column of {whose} {verb} the opposite sign (the joint turns the other way "
            "in the backend)"
        )
    if m.moved and m.columns is not None:
        holds = ", ".join(
            f"column {j + 1} holds {_joint(names, k)}'s"
            for j in m.moved
            if (k := m.columns[j]) is not None
        )
        parts.append(f"the backend's columns are in another order: {holds}")
    if m.missing:
        whose = _joints(names, m.missing)
        verb = "is" if len(m.missing) == 1 else "are"
        parts.append(f"the column of {whose} {verb} zero in the backend (the joint is left out)")
    if m.point_offset_m is not None:
        r = m.point_offset_m
        parts.append(
            f"the backend's linear part is the velocity of the point {_mm(r)} from the frame's "
            f"origin, in its axes — a tool offset of {_mm([-v for v in r])} left out (the "
            "flange's origin where the TCP was expected)"
        )
    return "; and ".join(parts)


def _match_columns(
    predicted: Float, observed: Float, tol_l: float, tol_a: float
) -> tuple[tuple[int | None, ...], tuple[int, ...]] | None:
    """Each observed column matched to a predicted column and sign, or zero; ``None`` if not all.

    Preference for each column: itself, itself negated, zero, another column,
    another column negated — the first that agrees within the tolerances.
    """
    n = predicted.shape[2]

    def agrees(diff: Float) -> NDArray[np.bool_]:
        """``(N, 6, m)`` differences → ``(m,)``: each column within both tolerances."""
        linear, angular = jacobian_column_errors(np.zeros_like(diff), diff)
        ok: NDArray[np.bool_] = (linear.max(axis=0) <= tol_l) & (angular.max(axis=0) <= tol_a)
        return ok

    columns: list[int | None] = []
    signs: list[int] = []
    for j in range(n):
        column = observed[:, :, j : j + 1]  # one observed column at a time: O(N·6·n) memory
        same = {s: agrees(column - s * predicted) for s in (1, -1)}
        options: list[tuple[int | None, int]] = [(j, 1), (j, -1), (None, 1)]
        options += [(k, s) for s in (1, -1) for k in range(n) if k != j]
        for k, s in options:
            if agrees(column)[0] if k is None else same[s][k]:
                columns.append(k)
                signs.append(s)
                break
        else:
            return None
    return tuple(columns), tuple(signs)


def _fit_offset(
    expected: Float,
    observed: Float,
    from_T_to: Float,
    reference: Reference,
    frame: JacobianMistake,
) -> tuple[float, float, float] | None:
    """The point offset ``r`` that best explains the linear part, under ``frame``."""
    obs = observed[:, list(ANGULAR_FIRST)] if frame.angular_first else observed
    obs_ref = frame.reference or reference
    obs_aligned = re_express(obs, from_T_to, obs_ref, "world-aligned")
    exp_aligned = re_express(expected, from_T_to, reference, "world-aligned")
    b = obs_aligned[:, :3] - exp_aligned[:, :3]  # (N, 3, n)
    omega = np.moveaxis(exp_aligned[:, 3:], 1, 2)  # (N, n, 3)
    R = from_T_to[:, :3, :3]
    # ω × (R r) = Σᵢ rᵢ · ω × R[:, i]: one matrix column per component of r.
    A = np.stack([np.cross(omega, R[:, None, :, i]) for i in range(3)], axis=-1)  # (N, n, 3, 3)
    if not (np.isfinite(A).all() and np.isfinite(b).all()) or not np.any(A):
        return None
    sol, *_ = np.linalg.lstsq(A.reshape(-1, 3), np.moveaxis(b, 1, 2).reshape(-1), rcond=None)
    return (float(sol[0]), float(sol[1]), float(sol[2]))


def _poses(from_T_to: ArrayLike, N: int) -> Float:
    """``from_T_to`` as ``(N, 4, 4)`` (one ``(4, 4)`` pose is one configuration's).

    Raises:
        ValueError: Another shape.
    """
    T = np.asarray(from_T_to, dtype=float)
    if T.shape == (4, 4):
        T = T[None]
    if T.shape != (N, 4, 4):
        raise ValueError(
            f"from_T_to has shape {T.shape}; expected ({N}, 4, 4), one per configuration"
        )
    return T


def _columns(
    prismatic: ArrayLike, joint_names: Sequence[str], n: int
) -> tuple[NDArray[np.bool_], tuple[str, ...]]:
    """Which of the ``n`` columns are prismatic, and their joints' names (``j1…jn`` if none).

    Raises:
        ValueError: Either has not ``n`` entries.
    """
    is_prismatic = np.asarray(prismatic, dtype=bool).reshape(-1)
    if is_prismatic.shape != (n,):
        raise ValueError(
            f"prismatic has {is_prismatic.size} entries; the Jacobians have {n} columns"
        )
    names = tuple(joint_names) or tuple(f"j{j + 1}" for j in range(n))
    if len(names) != n:
        raise ValueError(f"joint_names has {len(names)} names; the Jacobians have {n} columns")
    return is_prismatic, names


def diagnose_jacobian(
    expected: ArrayLike,
    observed: ArrayLike,
    *,
    from_T_to: ArrayLike,
    reference: Reference,
    prismatic: ArrayLike,
    tolerance: float,
    angular_tolerance: float | None = None,
    joint_names: Sequence[str] = (),
) -> JacobianDiagnosis:
    """Say which convention, if any, makes the observed Jacobian agree with the expected one.

    Args:
        expected: fkcheck's Jacobian, ``(N, 6, n)``, linear rows first, in ``reference``.
        observed: The backend's, same shape, meant to be in ``reference`` too.
        from_T_to: The target frame's pose in the Jacobians' root, ``(N, 4, 4)``.
        reference: ``"world-aligned"``, ``"local"`` or ``"world"``.
        prismatic: ``(n,)`` booleans, the prismatic joints (their columns are per metre).
        tolerance: Linear tolerance (m/rad), > 0.
        angular_tolerance: Angular tolerance (rad/rad), > 0; ``tolerance`` when ``None``.
        joint_names: The joints' names (``j1…jn`` when empty).

    Returns:
        The diagnosis; its :attr:`~JacobianDiagnosis.headline` says it in one sentence.

    Raises:
        ValueError: Shapes that do not match, an unknown reference, a tolerance
            that is not positive, non-finite expected values or poses.
    """
    exp, obs = _pair(expected, observed)
    N, _, n = exp.shape
    T = _poses(from_T_to, N)
    if reference not in REFERENCES:
        raise ValueError(
            f"unknown reference {reference!r}; references are: {', '.join(REFERENCES)}"
        )
    is_prismatic, names = _columns(prismatic, joint_names, n)
    tol_l = float(tolerance)
    tol_a = tol_l if angular_tolerance is None else float(angular_tolerance)
    if not (tol_l > 0 and tol_a > 0):
        raise ValueError(f"tolerances must be positive, got {tol_l!r} and {tol_a!r}")
    if not (np.isfinite(exp).all() and np.isfinite(T).all()):
        raise ValueError("the expected Jacobian and the poses must be finite")

    lin, ang = column_errors(exp, obs)
    columns = tuple(
        ColumnError(
            j,
            names[j],
            bool(is_prismatic[j]),
            float(lin[j]),
            float(ang[j]),
            bool(lin[j] <= tol_l and ang[j] <= tol_a),
        )
        for j in range(n)
    )
    before = _residual(exp, obs)
    others = [r for r in REFERENCES if r != reference]
    tried = (
        f"the observed Jacobian in another reference frame ({', '.join(others)})",
        "angular rows first",
        "column signs, order and zero columns (a joint left out)",
        "a constant point offset in the frame's axes, fitted by least squares (tool left out)",
        "each alone and combined with a reference frame and a row order",
    )
    found: list[JacobianExplanation] = []
    if not before.within(tol_l, tol_a):
        for ref in (None, *others):
            for angular_first in (False, True):
                frame = JacobianMistake(reference=ref, angular_first=angular_first)
                found += _explain(exp, obs, T, reference, frame, names, tol_l, tol_a)
    found.sort(key=lambda e: (len(e.kinds), [MISTAKE_ORDER.index(k) for k in e.kinds]))
    return JacobianDiagnosis(reference, N, before, tol_l, tol_a, columns, tuple(found), tried)


def _explain(
    exp: Float,
    obs: Float,
    T: Float,
    reference: Reference,
    frame: JacobianMistake,
    names: Sequence[str],
    tol_l: float,
    tol_a: float,
) -> list[JacobianExplanation]:
    """The explanations built on one reference frame and row order."""
    out: list[JacobianExplanation] = []

    def accept(m: JacobianMistake, details: tuple[str, ...] = ()) -> bool:
        residual = _residual(m.apply(exp, T, reference), obs)
        if residual.within(tol_l, tol_a):
            out.append(JacobianExplanation(m, _describe(m, reference, names), residual, details))
            return True
        return False

    if frame.kinds and accept(frame):
        return out
    framed = frame.apply(exp, T, reference)
    matched = _match_columns(framed, obs, tol_l, tol_a)  # columns and rows commute
    if matched is not None:
        cols, signs = matched
        if cols != tuple(range(exp.shape[2])) or any(s < 0 for s in signs):
            accept(JacobianMistake(frame.reference, frame.angular_first, cols, signs))
    if (frame.reference or reference) == "world":
        return out  # the spatial twist is the same for every point of the link
    r = _fit_offset(exp, obs, T, reference, frame)
    if r is not None:
        m = JacobianMistake(frame.reference, frame.angular_first, point_offset_m=r)
        accept(
            m,
            (
                f"fitted by least squares: r = {_mm(r)} in the frame's axes; the tool offset "
                "left out is −r in the TCP's axes (the tool's xyz when the tool does not rotate)",
            ),
        )
    return out


def explain_sample(
    sample: JacobianSample, model: Model, spec: JacobianSpec, tolerance: float
) -> tuple[str, tuple[str, ...]]:
    """Diagnose the kept configurations (the engine's hook: ``Explain`` in engine.jacobian).

    Returns:
        ``(headline, details)``: the diagnosis's sentence and its further lines.
    """
    diagnosis = diagnose_jacobian(
        sample.ours,
        sample.theirs,
        from_T_to=sample.from_T_to,
        reference=spec.reference,
        prismatic=model.chain.prismatic,
        tolerance=tolerance,
        joint_names=[j.name for j in model.joints],
    )
    best = diagnosis.best
    details = () if best is None else best.details
    also = tuple(f"also explains it: {e.title}" for e in diagnosis.explanations[1:])
    return diagnosis.headline, (*details, *also)
