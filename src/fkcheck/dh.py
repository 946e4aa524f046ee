"""The in-house Denavit–Hartenberg forward-kinematics core (NumPy only, batched).

This module is what the reference libraries check, so it depends on nothing but
NumPy and shares no code with them.

Conventions (``A_i`` maps frame ``i-1`` to frame ``i``):

* standard:  ``A_i = Rz(θ_i) · Tz(d_i) · Tx(a_i) · Rx(α_i)``
* modified (Craig):  ``A_i = Rx(α_{i-1}) · Tx(a_{i-1}) · Rz(θ_i) · Tz(d_i)``
  (a modified table's row *i* holds ``a_{i-1}`` and ``α_{i-1}``).

For a revolute joint ``θ_i = s_i·q_i + θ_offset_i`` with ``d_i`` fixed; for a
prismatic joint ``d_i = s_i·q_i + d_offset_i`` with ``θ_i`` fixed. ``s_i`` is −1
for a flipped joint, else +1.

The batched kernel works on the four columns of the running transform
(x, y, z axes and origin) as ``(3, N)`` arrays and applies each elementary
motion as column arithmetic: it never forms the constant last row and never
multiplies by a known zero. :func:`fk_reference` is the straightforward 4×4
matrix-product chain it is tested against.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from fkcheck.errors import JointInputError

__all__ = ["Convention", "DHChain", "dh_matrix", "fk", "fk_reference", "joint_values"]

Float = NDArray[np.float64]
Convention = Literal["standard", "modified"]


@dataclass(frozen=True, eq=False)
class DHChain:
    """A DH chain as arrays, the form the kernel consumes.

    Attributes:
        convention: ``"standard"`` or ``"modified"``.
        a: Link lengths, metres, shape ``(n,)``.
        alpha: Link twists, radians, shape ``(n,)``.
        d: Link offsets, metres (for prismatic joints: the offset added to q).
        theta: Joint angle offsets, radians (for prismatic joints: the fixed angle).
        prismatic: ``True`` where the joint is prismatic.
        sign: ``+1.0``, or ``-1.0`` for a joint that turns (slides) the other way.
        world_T_base: Fixed transform from the world to DH frame 0.
        flange_T_tool: Fixed transform from the last DH frame to the TCP.
    """

    convention: Convention
    a: Float
    alpha: Float
    d: Float
    theta: Float
    prismatic: NDArray[np.bool_]
    sign: Float
    world_T_base: Float
    flange_T_tool: Float

    @property
    def dof(self) -> int:
        """Number of joints."""
        return int(self.a.shape[0])


def joint_values(chain: DHChain, q: ArrayLike) -> Float:
    """Validate joint values and return them as a float64 ``(N, n)`` array.

    Args:
        chain: The chain the values are for.
        q: Shape ``(n,)`` or ``(N, n)``; radians (revolute) and metres (prismatic).

    Returns:
        A C-contiguous ``(N, n)`` float64 array.

    Raises:
        JointInputError: Wrong shape, not numeric, or not finite.
    """
    try:
        q_arr = np.asarray(q, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise JointInputError(f"joint values are not numbers: {exc}") from None
    n = chain.dof
    if q_arr.ndim == 1:
        q_arr = q_arr.reshape(1, -1)
    if q_arr.ndim != 2 or q_arr.shape[1] != n:
        raise JointInputError(
            f"expected {n} joint values per configuration (shape ({n},) or (N, {n})), "
            f"got shape {np.shape(q)}"
        )
    if not np.isfinite(q_arr).all():
        bad = np.argwhere(~np.isfinite(q_arr))[0]
        raise JointInputError(
            f"joint values must be finite; configuration {bad[0]} joint {bad[1] + 1} "
            f"is {q_arr[bad[0], bad[1]]}"
        )
    return np.ascontiguousarray(q_arr)


def fk(chain: DHChain, q: ArrayLike, *, all_frames: bool = False) -> Float:
    """Forward kinematics of a DH chain for one or many configurations.

    Args:
        chain: The chain.
        q: Joint values, shape ``(n,)`` or ``(N, n)``.
        all_frames: Return every DH frame instead of the TCP.

    Returns:
        ``all_frames=False``: ``world_T_tcp`` with shape ``(4, 4)`` or ``(N, 4, 4)``
        (base and tool transforms included).
        ``all_frames=True``: ``world_T_i`` for DH frames ``i = 0 … n`` with shape
        ``(n+1, 4, 4)`` or ``(N, n+1, 4, 4)`` (base included, tool not).

    Raises:
        JointInputError: ``q`` has the wrong shape or non-finite values.
    """
    single = np.ndim(q) == 1
    q2 = joint_values(chain, q)
    N, n = q2.shape

    B = chain.world_T_base
    ones = np.ones(N)
    # Columns of the running transform, each (3, N): x axis, y axis, z axis, origin.
    X = B[:3, 0, None] * ones
    Y = B[:3, 1, None] * ones
    Z = B[:3, 2, None] * ones
    P = B[:3, 3, None] * ones

    frames: Float | None = None
    if all_frames:
        frames = np.zeros((N, n + 1, 4, 4))
        frames[:, :, 3, 3] = 1.0
        _store(frames[:, 0], X, Y, Z, P)

    ca_all = np.cos(chain.alpha)
    sa_all = np.sin(chain.alpha)
    modified = chain.convention == "modified"
    for i in range(n):
        qi = q2[:, i] * chain.sign[i]
        if chain.prismatic[i]:
            theta = chain.theta[i]
            c: Float | float = float(np.cos(theta))
            s: Float | float = float(np.sin(theta))
            d: Float | float = qi + chain.d[i]
        else:
            angle = qi + chain.theta[i]
            c = np.cos(angle)
            s = np.sin(angle)
            d = float(chain.d[i])
        a = float(chain.a[i])
        ca = float(ca_all[i])
        sa = float(sa_all[i])
        if modified:
            # Rx(α) · Tx(a) · Rz(θ) · Tz(d)
            Y1 = ca * Y + sa * Z
            Z = ca * Z - sa * Y
            P = P + a * X
            Xn = c * X + s * Y1
            Y = c * Y1 - s * X
            X = Xn
            P = P + d * Z
        else:
            # Rz(θ) · Tz(d) · Tx(a) · Rx(α)
            Xn = c * X + s * Y
            Y1 = c * Y - s * X
            P = P + d * Z + a * Xn
            Y = ca * Y1 + sa * Z
            Z = ca * Z - sa * Y1
            X = Xn
        if frames is not None:
            _store(frames[:, i + 1], X, Y, Z, P)

    if frames is not None:
        return frames[0] if single else frames

    t = chain.flange_T_tool
    out = np.zeros((N, 4, 4))
    out[:, 3, 3] = 1.0
    _store(
        out,
        X * t[0, 0] + Y * t[1, 0] + Z * t[2, 0],
        X * t[0, 1] + Y * t[1, 1] + Z * t[2, 1],
        X * t[0, 2] + Y * t[1, 2] + Z * t[2, 2],
        P + X * t[0, 3] + Y * t[1, 3] + Z * t[2, 3],
    )
    return out[0] if single else out


def _store(out: Float, X: Float, Y: Float, Z: Float, P: Float) -> None:
    """Write four ``(3, N)`` columns into the top three rows of ``(N, 4, 4)``."""
    out[:, :3, 0] = X.T
    out[:, :3, 1] = Y.T
    out[:, :3, 2] = Z.T
    out[:, :3, 3] = P.T


def dh_matrix(
    convention: Convention, a: ArrayLike, alpha: ArrayLike, d: ArrayLike, theta: ArrayLike
) -> Float:
    """The DH link transform ``A_i`` as full 4×4 matrices (broadcasts over inputs).

    Args:
        convention: ``"standard"`` or ``"modified"``.
        a: Link length (m).
        alpha: Link twist (rad).
        d: Link offset (m).
        theta: Joint angle (rad).

    Returns:
        Shape ``broadcast(a, alpha, d, theta).shape + (4, 4)``.
    """
    a_, alpha_, d_, theta_ = np.broadcast_arrays(
        *(np.asarray(v, dtype=np.float64) for v in (a, alpha, d, theta))
    )
    ct, st = np.cos(theta_), np.sin(theta_)
    ca, sa = np.cos(alpha_), np.sin(alpha_)
    zero, one = np.zeros_like(ct), np.ones_like(ct)
    if convention == "standard":
        rows = [
            [ct, -st * ca, st * sa, a_ * ct],
            [st, ct * ca, -ct * sa, a_ * st],
            [zero, sa, ca, d_],
            [zero, zero, zero, one],
        ]
    else:
        rows = [
            [ct, -st, zero, a_],
            [st * ca, ct * ca, -sa, -d_ * sa],
            [st * sa, ct * sa, ca, d_ * ca],
            [zero, zero, zero, one],
        ]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def fk_reference(chain: DHChain, q: ArrayLike, *, all_frames: bool = False) -> Float:
    """The plain chain product ``world_T_base · A_1 ⋯ A_n · flange_T_tool``.

    Builds every ``A_i`` as a full 4×4 matrix with :func:`dh_matrix` and multiplies
    them in order with ``@``: slow and obvious, the yardstick for :func:`fk`.
    Same arguments and shapes as :func:`fk`.
    """
    single = np.ndim(q) == 1
    q2 = joint_values(chain, q)
    qs = q2 * chain.sign
    theta = np.where(chain.prismatic, chain.theta, qs + chain.theta)
    d = np.where(chain.prismatic, qs + chain.d, chain.d)
    A = dh_matrix(chain.convention, chain.a, chain.alpha, d, theta)  # (N, n, 4, 4)
    T = np.broadcast_to(chain.world_T_base, (q2.shape[0], 4, 4)).copy()
    frames = [T]
    for i in range(chain.dof):
        T = T @ A[:, i]
        frames.append(T)
    if all_frames:
        stacked = np.stack(frames, axis=1)
        return stacked[0] if single else stacked
    T = T @ chain.flange_T_tool
    return T[0] if single else T
