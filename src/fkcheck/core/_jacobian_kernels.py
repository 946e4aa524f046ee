"""Numba kernel for the batched geometric Jacobian: DH frames and columns in one pass.

What :func:`fkcheck.core.jacobian.geometric_jacobian` computes from a stack of
``(N, n+1, 4, 4)`` DH frames, this kernel computes block by block without that
intermediate. It reuses the FK kernel's machinery (:mod:`fkcheck.core._kernels`):
the same scratch layout of twelve columns per block of :data:`~fkcheck.core._kernels.BLOCK`
poses, the same joint steps with the polynomial ``sincos`` (and libm beyond
:data:`~fkcheck.core._kernels.CODY_WAITE_LIMIT`), and the same work sharing
between threads. Per block it

1. runs the chain over the ``moving`` joints, copying the ``z`` axis and origin
   of the frame each joint moves about (frame ``i−1`` before joint ``i`` in
   standard DH, frame ``i`` after it in modified DH) into six scratch rows per
   joint;
2. right-multiplies the last frame by the target's fixed offset (the tool for
   the TCP, the named frame's offset otherwise);
3. turns each joint's six rows into its column — ``s·z × (p − o)`` and ``s·z``
   (revolute) or ``s·z`` and ``0`` (prismatic) — re-expressed in the reference
   frame, every loop running over the block's poses, into ``6·n`` result rows
   (the columns of joints after ``moving`` stay zero);
4. writes them into the ``(N, 6, n)`` output with 8 × 8 shuffle transposes.

Like the FK kernel it runs with FMA contraction and its own ``sincos``, so its
last bits differ from the NumPy path's (tested to
:data:`fkcheck.core.tolerances.FAST_CORE`). Imported only on demand, by
:mod:`fkcheck.core.jacobian`, after :func:`fkcheck.core.dh.load_jit` succeeded.
"""

from __future__ import annotations

from typing import Any

import numba as nb
import numpy as np
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic

from fkcheck.core._kernels import (
    _FASTMATH,
    _P,
    _ROWS,
    _STRIDE,
    _U,
    _V8,
    _X,
    _Y,
    _Z,
    BLOCK,
    PARALLEL_MIN_BLOCKS,
    _fetch_add,
    _first_revolute,
    _is_identity,
    _joint_rows,
    _lanes,
    _revolute_fused,
    _rows_step,
    _start,
    _tool,
    _transpose8,
)
from fkcheck.core.typing import Float

__all__ = ["REFERENCE_CODES", "jacobian_batch", "warm_up"]

#: The reference frames as the kernel's integer argument.
REFERENCE_CODES = {"world-aligned": 0, "local": 1, "world": 2}

# Scratch rows after the FK's: joint i's six rows start at row _J + 6·i: z axis
# (3 rows), then origin (3 rows) of the frame it moves about. Then, from row
# _J + 6·k, the 6·n rows of the result in its own order (row r·n + i holds entry
# (r, i) of the 6 × n Jacobian), so that writing it out is a plain transpose.
_J = _ROWS


@nb.njit(cache=True)
def _scratch(k: int, n: int) -> Float:  # pragma: no cover - compiled
    """One worker's scratch, its result rows zero (those of joints after ``k`` stay so).

    The result rows are padded to a multiple of eight: the output's 8 × 8
    transposes read whole groups of eight rows.
    """
    rows = _J + 6 * k + (6 * n + 7) // 8 * 8
    w = np.empty(rows * _STRIDE)
    w[(_J + 6 * k) * _STRIDE :] = 0.0
    return w


@nb.njit(cache=True, fastmath=_FASTMATH)
def _record(w: Float, m: int, i: int) -> None:  # pragma: no cover - compiled
    """Copy the running frame's ``z`` axis and origin into joint ``i``'s rows."""
    for r in range(3):
        src_z, src_p = (_Z + r) * _STRIDE, (_P + r) * _STRIDE
        dst_z, dst_p = (_J + 6 * i + r) * _STRIDE, (_J + 6 * i + 3 + r) * _STRIDE
        for j in range(m):
            w[dst_z + j] = w[src_z + j]
            w[dst_p + j] = w[src_p + j]


@nb.njit(cache=True, fastmath=_FASTMATH)
def _record_base(w: Float, m: int, base: Float) -> None:  # pragma: no cover - compiled
    """Joint 0's rows from ``world_T_base`` (standard DH: it moves about frame 0)."""
    for r in range(3):
        z, p = base[r, 2], base[r, 3]
        dst_z, dst_p = (_J + r) * _STRIDE, (_J + 3 + r) * _STRIDE
        for j in range(m):
            w[dst_z + j] = z
            w[dst_p + j] = p


@nb.njit(cache=True, fastmath=_FASTMATH)
def _chain(
    q: Float, start: int, m: int, prog: Float, modified: bool, k: int, fused: bool, w: Float
) -> bool:  # pragma: no cover - compiled
    """Joints ``0 … k-1`` for one block, recording each joint's axis frame.

    ``fused``: revolute joints with the in-loop polynomial (``False`` if an angle
    is beyond its range: then call again with ``fused=False``, which uses libm
    there). Returns ``False`` if that happened, or if a value is not finite.
    """
    n = q.shape[1]
    base = prog[n : n + 4, :4]
    first = 0
    if fused and prog[0, 0] == 0.0 and _is_identity(base):
        if not modified:
            _record_base(w, m, base)
        if not _first_revolute(q, start, m, modified, prog[0], w):
            return False
        if modified:
            _record(w, m, 0)
        first = 1
    else:
        _start(w, m, base)
    for i in range(first, k):
        if not modified:
            _record(w, m, i)
        if fused and prog[i, 0] == 0.0:
            if not _revolute_fused(q, start, m, i, modified, prog[i], w):
                return False
        else:
            if not _joint_rows(q, start, m, i, prog[i], w):
                return False
            _rows_step(w, m, modified, prog[i])
        if modified:
            _record(w, m, i)
    return True


@nb.njit(cache=True, fastmath=_FASTMATH, inline="always")
def _column(
    w: Float, j: int, o: int, res: int, n: int, sign: float, prismatic: bool, reference: int
) -> None:  # pragma: no cover - compiled
    """Pose ``j``'s column from the rows at ``o`` (axis, origin) into rows ``res + r·n``.

    The operation order of :func:`fkcheck.core.jacobian.geometric_jacobian` and
    ``re_express`` (NumPy's ``cross``, ``R.T @ v``), so only FMA contraction and
    the frames' own last bits make the results differ.
    """
    S = _U(_STRIDE)
    base = _U(o * _STRIDE) + j
    z0 = w[base] * sign
    z1 = w[base + S] * sign
    z2 = w[base + 2 * S] * sign
    p0 = w[_U(_P * _STRIDE) + j]
    p1 = w[_U((_P + 1) * _STRIDE) + j]
    p2 = w[_U((_P + 2) * _STRIDE) + j]
    if prismatic:
        l0, l1, l2 = z0, z1, z2
        a0, a1, a2 = 0.0, 0.0, 0.0
    else:
        d0 = p0 - w[base + 3 * S]
        d1 = p1 - w[base + 4 * S]
        d2 = p2 - w[base + 5 * S]
        l0 = z1 * d2 - z2 * d1
        l1 = z2 * d0 - z0 * d2
        l2 = z0 * d1 - z1 * d0
        a0, a1, a2 = z0, z1, z2
    if reference == 1:  # local: Rᵀ v, Rᵀ ω (R's columns are the X, Y, Z rows)
        x0, x1, x2 = w[_U(_X * S) + j], w[_U((_X + 1) * S) + j], w[_U((_X + 2) * S) + j]
        y0, y1, y2 = w[_U(_Y * S) + j], w[_U((_Y + 1) * S) + j], w[_U((_Y + 2) * S) + j]
        u0, u1, u2 = w[_U(_Z * S) + j], w[_U((_Z + 1) * S) + j], w[_U((_Z + 2) * S) + j]
        l0, l1, l2 = (
            x0 * l0 + x1 * l1 + x2 * l2,
            y0 * l0 + y1 * l1 + y2 * l2,
            u0 * l0 + u1 * l1 + u2 * l2,
        )
        a0, a1, a2 = (
            x0 * a0 + x1 * a1 + x2 * a2,
            y0 * a0 + y1 * a1 + y2 * a2,
            u0 * a0 + u1 * a1 + u2 * a2,
        )
    elif reference == 2:  # world: v + p × ω
        l0 = l0 + (p1 * a2 - p2 * a1)
        l1 = l1 + (p2 * a0 - p0 * a2)
        l2 = l2 + (p0 * a1 - p1 * a0)
    dst = _U(res * _STRIDE) + j
    N = _U(n * _STRIDE)
    w[dst] = l0
    w[dst + N] = l1
    w[dst + 2 * N] = l2
    w[dst + 3 * N] = a0
    w[dst + 4 * N] = a1
    w[dst + 5 * N] = a2


@nb.njit(cache=True, fastmath=_FASTMATH)
def _columns(
    w: Float, m: int, prog: Float, k: int, n: int, reference: int
) -> None:  # pragma: no cover - compiled
    """Every moving joint's column, for every pose of the block (loops over poses)."""
    for i in range(k):
        o = _J + 6 * i
        res = _J + 6 * k + i
        sign = prog[i, 1]
        # Literal flags per loop, so each loop is branch-free and vectorises.
        if prog[i, 0] != 0.0:
            if reference == 1:
                for j in range(_U(m)):
                    _column(w, j, o, res, n, sign, True, 1)
            elif reference == 2:
                for j in range(_U(m)):
                    _column(w, j, o, res, n, sign, True, 2)
            else:
                for j in range(_U(m)):
                    _column(w, j, o, res, n, sign, True, 0)
        elif reference == 1:
            for j in range(_U(m)):
                _column(w, j, o, res, n, sign, False, 1)
        elif reference == 2:
            for j in range(_U(m)):
                _column(w, j, o, res, n, sign, False, 2)
        else:
            for j in range(_U(m)):
                _column(w, j, o, res, n, sign, False, 0)


# --------------------------------------------------------------------------- output
# As in the FK kernel, the result leaves the scratch (one row per entry, poses
# along the row) through 8 × 8 transposes: eight entries of eight poses loaded
# as eight vectors, shuffled, stored as eight contiguous runs. Scalar stores
# took half the kernel's time (measured: 44 of 85 ns per UR5 Jacobian).


def _transpose_store_typer(lanes: int) -> Any:
    """The typer of an intrinsic ``store(w, src, flat, dst, size)`` writing ``lanes`` entries.

    For ``p`` in ``0 … 7`` and ``e`` in ``0 … lanes-1``:
    ``flat[dst + p·size + e] = w[src + e·_STRIDE + p]`` (it reads eight rows).
    """

    def typer(typingctx: Any, w: Any, src: Any, flat: Any, dst: Any, size: Any) -> Any:
        sig = types.void(w, src, flat, dst, size)

        def codegen(context: Any, builder: ir.IRBuilder, signature: Any, args: Any) -> Any:
            w_arr = context.make_array(signature.args[0])(context, builder, args[0])
            out_arr = context.make_array(signature.args[2])(context, builder, args[2])
            intp = context.get_value_type(types.intp)
            vec = ir.VectorType(ir.DoubleType(), lanes)

            def load(row: int) -> ir.Value:
                idx = builder.add(args[1], ir.Constant(intp, row * _STRIDE))
                ptr = builder.gep(w_arr.data, [idx], inbounds=True)
                return builder.load(builder.bitcast(ptr, _V8.as_pointer()), align=8)

            rows = _transpose8(builder, [load(e) for e in range(8)])
            for p in range(8):
                value = rows[p]
                if lanes < 8:
                    value = builder.shuffle_vector(value, value, _lanes(*range(lanes)))
                idx = builder.add(args[3], builder.mul(args[4], ir.Constant(intp, p)))
                ptr = builder.gep(out_arr.data, [idx], inbounds=True)
                builder.store(value, builder.bitcast(ptr, vec.as_pointer()), align=8)
            return context.get_dummy_value()

        return sig, codegen

    return typer


# Eight entries at a time, and the 2, 4 or 6 left over when 6·n is not a multiple of 8.
_store_8: Any = intrinsic(_transpose_store_typer(8))
_store_6: Any = intrinsic(_transpose_store_typer(6))
_store_4: Any = intrinsic(_transpose_store_typer(4))
_store_2: Any = intrinsic(_transpose_store_typer(2))


@nb.njit(cache=True, fastmath=_FASTMATH)
def _store(
    w: Float, m: int, k: int, n: int, flat: Float, start: int
) -> None:  # pragma: no cover - compiled
    """Write the block's ``(6, n)`` Jacobians into ``flat``, pose ``start`` first."""
    size = 6 * n
    res = _J + 6 * k
    whole = size - size % 8  # the last 2, 4 or 6 entries read padding rows (never stored)
    rest = size - whole
    j = 0
    while j + 8 <= m:
        o = (start + j) * size
        for e in range(0, whole, 8):
            _store_8(w, (res + e) * _STRIDE + j, flat, o + e, size)
        src = (res + whole) * _STRIDE + j
        if rest == 6:
            _store_6(w, src, flat, o + whole, size)
        elif rest == 4:
            _store_4(w, src, flat, o + whole, size)
        elif rest == 2:
            _store_2(w, src, flat, o + whole, size)
        j += 8
    for jj in range(j, m):
        o = (start + jj) * size
        for e in range(size):
            flat[o + e] = w[(res + e) * _STRIDE + jj]


@nb.njit(cache=True, fastmath=_FASTMATH)
def _block(
    q: Float,
    start: int,
    m: int,
    prog: Float,
    modified: bool,
    k: int,
    target: Float,
    reference: int,
    out: Float,
    w: Float,
) -> bool:  # pragma: no cover - compiled
    """Jacobians of poses ``start … start+m-1`` into ``out``; ``False`` if a value is not finite."""
    if not _chain(q, start, m, prog, modified, k, True, w) and not _chain(
        q, start, m, prog, modified, k, False, w
    ):
        return False
    if not _is_identity(target):
        _tool(w, m, target)
    n = q.shape[1]
    _columns(w, m, prog, k, n, reference)
    _store(w, m, k, n, out.reshape(-1), start)
    return True


@nb.njit(cache=True, parallel=True, fastmath=_FASTMATH)
def jacobian_batch(
    q: Float,
    prog: Float,
    modified: bool,
    k: int,
    target: Float,
    reference: int,
    out: Float,
    workers: int,
) -> bool:  # pragma: no cover - compiled
    """The geometric Jacobian of a frame for every row of ``q`` into ``out``.

    Args:
        q: ``(N, n)`` finite joint values, C-contiguous.
        prog: The chain program (``fkcheck.core.dh.DHChain.program``; its tool rows
            are not used).
        modified: Modified DH.
        k: Joints that move the frame (``1 … n``): it sits on DH frame ``k``.
        target: ``(4, 4)`` the frame in DH frame ``k``.
        reference: :data:`REFERENCE_CODES` value.
        out: ``(N, 6, n)`` C-contiguous, written in full.
        workers: Tasks run in parallel (blocks shared through an atomic counter,
            as in :func:`fkcheck.core._kernels.fk_tcp`).

    Returns:
        ``False`` if a joint angle (``s·q + θ``) is not finite (``out`` partly written).
    """
    N = q.shape[0]
    nblocks = (N + BLOCK - 1) // BLOCK
    n = q.shape[1]
    bad = 0
    if workers <= 1 or nblocks < PARALLEL_MIN_BLOCKS:
        w = _scratch(k, n)
        for b in range(nblocks):
            start = b * BLOCK
            m = min(BLOCK, N - start)
            if not _block(q, start, m, prog, modified, k, target, reference, out, w):
                bad += 1
        return bad == 0
    counter = np.zeros(1, dtype=np.int64)
    for _ in nb.prange(min(nblocks, workers)):
        w = _scratch(k, n)
        b = _fetch_add(counter)
        while b < nblocks:
            start = b * BLOCK
            m = min(BLOCK, N - start)
            if not _block(q, start, m, prog, modified, k, target, reference, out, w):
                bad += 1
            b = _fetch_add(counter)
    return bad == 0


def warm_up() -> None:
    """Compile (first run on a machine) or load from the cache the kernel, now."""
    prog = np.zeros((9, 9))
    prog[1:5, :4] = np.eye(4)
    prog[5:9, :4] = np.eye(4)
    q = np.zeros((1, 1))
    out = np.empty((1, 6, 1))
    jacobian_batch(q, prog, False, 1, np.eye(4), 0, out, 1)
