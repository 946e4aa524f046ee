"""Numba kernels for the DH core: the batched TCP kernel and the one-pose kernel.

This module imports numba when it is imported, so :mod:`fkcheck.core.dh` imports it
only on demand: ``import fkcheck`` and ``fkcheck --help`` never pay numba's
import, and a machine without numba keeps the NumPy path. Compiled code is
cached on disk (``cache=True``): the compile time (seconds) is paid once per
machine, not once per process.

The kernels trust their inputs, which :mod:`fkcheck.core.dh` prepares: finite joint
values, C-contiguous float64 arrays, and a chain *program* (see
``fkcheck.core.dh.DHChain.program``) of shape ``(n + 8, 9)``:

* rows ``0 … n-1``, one per joint: ``prismatic (0/1), sign, θ, d, a, cos α,
  sin α, cos θ, sin θ`` (the last four computed by NumPy, as the reference does);
* rows ``n … n+3``, columns ``0 … 3``: ``world_T_base``;
* rows ``n+4 … n+7``, columns ``0 … 3``: ``flange_T_tool``.

Why the batched kernel looks the way it does: it works on blocks of
:data:`BLOCK` poses held as twelve contiguous columns (x, y, z axes and origin,
three rows each) in one scratch array, joint by joint, so that every inner loop
runs over poses with no data-dependent branch and LLVM vectorises it (AVX-512
here). For each revolute joint, one loop computes the angle's cosine and sine
with :func:`sincos` — a branch-free polynomial with Cody–Waite range reduction —
and applies the joint to the columns. A block with an angle beyond
:data:`CODY_WAITE_LIMIT` (or a non-finite one) is redone on a slower path that
uses libm for those angles. Each step is its own compiled function, so numba
optimises each loop on its own; an LLVM shuffle transpose writes the 4×4 results.
"""

from __future__ import annotations

import math
import os
from typing import Any

# GNU OpenMP (numba's "omp" threading layer) lets idle worker threads spin for a
# while after each parallel loop. On a machine shared with other work that
# spinning competes for the cores: a 20 000-pose batch took 15 ms instead of
# 0.4 ms (measured on 2 busy cores). Workers that sleep at once cost ~10 µs to
# wake. Set before numba loads libgomp; a value the user set is kept. (Child
# processes inherit it; it only affects OpenMP programs, and only their waiting.)
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import numba as nb  # after the environment above
import numpy as np
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic

from fkcheck.core.typing import Float

__all__ = [
    "BLOCK",
    "CODY_WAITE_LIMIT",
    "PARALLEL_MIN_BLOCKS",
    "fk_one",
    "fk_tcp",
    "sincos",
    "sincos_array",
    "tasks",
    "warm_up",
]

if nb.config.DISABLE_JIT:  # type: ignore[attr-defined]  # numba.config sets it at import
    # The kernels would run as (very slow) Python, and the intrinsic not at all.
    raise ImportError("NUMBA_DISABLE_JIT is set")


#: Poses per block of the batched kernel: 16 scratch rows (12 columns, 4 per-joint
#: rows) of 264 float64 are 33 KiB, which stay in a core's L1/L2 cache. A
#: compile-time constant, so the row offsets inside the scratch are too.
BLOCK = 256

#: Fewer blocks than this (16 384 poses, ~0.3 ms of work) run on the calling
#: thread: waking the other threads costs more than they would save, and far
#: more when the machine is busy and they have to wait for a core.
PARALLEL_MIN_BLOCKS = 64

# Rows of the scratch array: X0..X2, Y0..Y2, Z0..Z2, P0..P2, then per joint
# C, S, D (cos θ, sin θ, d) and Q (the joint's angle, copied out of q's strided column).
_X, _Y, _Z, _P, _C, _S, _D, _Q = 0, 3, 6, 9, 12, 13, 14, 15
_ROWS = 16
# Row stride: one cache line more than a block. With exactly 256 floats (2 KiB),
# the rows fall into the same two L1 cache sets and evict each other in the
# fused loops (measured: 6× slower).
_STRIDE = BLOCK + 8

# π/2 split into three 33-bit parts (fdlibm's pio2_1, pio2_2, pio2_3). For
# |k| <= 2**20, k·_PIO2_1, k·_PIO2_2 and k·_PIO2_3 are exact products (at most
# 20 + 33 bits), x − k·_PIO2_1 is exact (Sterbenz), and the reduced angle
# carries an absolute error of about two half-ulps of π/4 (~1.1e-16 rad); the
# truncation of π/2 after ~99 bits adds < 2**20 · 2**-100.
_PIO2_1 = 1.57079632673412561417e00
_PIO2_2 = 6.07710050630396597660e-11
_PIO2_3 = 2.02226624871116645580e-21
_TWO_OVER_PI = 6.36619772367581382433e-01
_ROUND = 6755399441055744.0  # 1.5 * 2**52

#: Largest |angle| (rad) the polynomial path takes: k = round(2x/π) stays below
#: 2**20 so the Cody–Waite products above are exact. Beyond it, libm's
#: ``cos``/``sin`` (exact argument reduction) are used instead.
CODY_WAITE_LIMIT = 2.0**19 * math.pi

# fdlibm __kernel_sin / __kernel_cos minimax coefficients on [-π/4, π/4]
# (errors below 2**-58 relative to the true function there).
_S1 = -1.66666666666666324348e-01
_S2 = 8.33333333332248946124e-03
_S3 = -1.98412698298579493134e-04
_S4 = 2.75573137070700676789e-06
_S5 = -2.50507602534068634195e-08
_S6 = 1.58969099521155010221e-10
_C1 = 4.16666666666666019037e-02
_C2 = -1.38888888888741095749e-03
_C3 = 2.48015872894767294178e-05
_C4 = -2.75573143513906633035e-07
_C5 = 2.08757232129817482790e-09
_C6 = -1.13596475577881948265e-11

# Floating-point contraction (a*b + c as one FMA) only: it never loses accuracy,
# and the compensated steps above rely on the operation order, so no reassociation.
_FASTMATH = {"contract"}


@nb.njit(cache=True, fastmath=_FASTMATH, inline="always")
def sincos(x: float) -> tuple[float, float]:  # pragma: no cover - compiled
    """Sine and cosine of ``x`` for ``|x| <= CODY_WAITE_LIMIT`` (branch-free).

    Args:
        x: Angle in radians, ``|x| <= CODY_WAITE_LIMIT``.

    Returns:
        ``(sin x, cos x)``, each within about 1e-16 of the correctly rounded value.
    """
    # Round to nearest with the 1.5·2**52 trick: branch-free and exact for |k| < 2**51.
    k = (x * _TWO_OVER_PI + _ROUND) - _ROUND
    r = ((x - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3
    z = r * r
    sin_r = r + r * z * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    hz = 0.5 * z
    w = 1.0 - hz
    tail = z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6)))))
    cos_r = w + (((1.0 - w) - hz) + tail)  # fdlibm's compensated 1 - z/2 + tail
    quadrant = np.int64(k) & 3
    swap = (quadrant & 1) != 0
    s = cos_r if swap else sin_r
    c = sin_r if swap else cos_r
    s = -s if (quadrant & 2) != 0 else s
    c = -c if ((quadrant + 1) & 2) != 0 else c
    return s, c


@nb.njit(cache=True, fastmath=_FASTMATH)
def sincos_array(x: Float, s: Float, c: Float) -> None:  # pragma: no cover - compiled
    """Write ``sin`` and ``cos`` of every ``x`` into ``s`` and ``c`` (the kernel's method).

    The same polynomial and libm fallback the batched kernel uses, exposed so the
    tests can check it directly against NumPy.
    """
    for j in range(x.shape[0]):
        s[j], c[j] = sincos(x[j])
    for j in range(x.shape[0]):
        if abs(x[j]) > CODY_WAITE_LIMIT:
            s[j] = math.sin(x[j])
            c[j] = math.cos(x[j])


@nb.njit(cache=True, fastmath=_FASTMATH)
def _start(w: Float, m: int, base: Float) -> None:  # pragma: no cover - compiled
    """Set every pose's running transform to ``world_T_base``."""
    for r in range(3):
        for col in range(4):
            v = base[r, col]
            o = (3 * col + r) * _STRIDE
            for j in range(m):
                w[o + j] = v


@nb.njit(cache=True)
def _is_identity(T: Float) -> bool:  # pragma: no cover - compiled
    """Whether the 4×4 ``T`` is exactly the identity."""
    for r in range(4):
        for c in range(4):
            if T[r, c] != (1.0 if r == c else 0.0):
                return False
    return True


# --------------------------------------------------------------------------- joints
# One joint, one pose: the column arithmetic of fkcheck.core.dh, on scratch columns.
# Inlined into the loops below (numba IR inlining), where `twist` is a literal.
# Scratch indices are unsigned (`_U`): numba then leaves out its negative-index
# wraparound, which would otherwise hide the access pattern from LLVM's
# vectoriser (measured: these loops run scalar with signed indices).

_U = np.uint64


@nb.njit(cache=True, fastmath=_FASTMATH, inline="always")
def _standard_step(
    w: Float, j: int, c: float, s: float, d: float, a: float, ca: float, sa: float, twist: bool
) -> None:  # pragma: no cover - compiled
    """Pose ``j`` times ``Rz(θ) · Tz(d) · Tx(a) · Rx(α)``; ``twist=False`` when α = 0."""
    for r in range(3):
        ox, oy = _U((_X + r) * _STRIDE) + j, _U((_Y + r) * _STRIDE) + j
        oz, op = _U((_Z + r) * _STRIDE) + j, _U((_P + r) * _STRIDE) + j
        x, y, z = w[ox], w[oy], w[oz]
        xn = c * x + s * y
        y1 = c * y - s * x
        w[op] = w[op] + d * z + a * xn
        w[ox] = xn
        if twist:
            w[oy] = ca * y1 + sa * z
            w[oz] = ca * z - sa * y1
        else:
            w[oy] = y1


@nb.njit(cache=True, fastmath=_FASTMATH, inline="always")
def _modified_step(
    w: Float, j: int, c: float, s: float, d: float, a: float, ca: float, sa: float, twist: bool
) -> None:  # pragma: no cover - compiled
    """Pose ``j`` times ``Rx(α) · Tx(a) · Rz(θ) · Tz(d)``; ``twist=False`` when α = 0."""
    for r in range(3):
        ox, oy = _U((_X + r) * _STRIDE) + j, _U((_Y + r) * _STRIDE) + j
        oz, op = _U((_Z + r) * _STRIDE) + j, _U((_P + r) * _STRIDE) + j
        x, y, z = w[ox], w[oy], w[oz]
        if twist:
            y1 = ca * y + sa * z
            z = ca * z - sa * y
            w[oz] = z
        else:
            y1 = y
        w[ox] = c * x + s * y1
        w[oy] = c * y1 - s * x
        w[op] = w[op] + a * x + d * z


@nb.njit(cache=True, fastmath=_FASTMATH)
def _revolute_fused(
    q: Float, start: int, m: int, i: int, modified: bool, joint: Float, w: Float
) -> bool:  # pragma: no cover - compiled
    """Revolute joint ``i`` for poses ``start … start+m-1``, sin/cos computed in the loop.

    Returns ``False`` if an angle is beyond :data:`CODY_WAITE_LIMIT` or not
    finite; the columns are then wrong and the block must take :func:`_chain_rows`.
    """
    sign, theta, d, a, ca, sa = joint[1], joint[2], joint[3], joint[4], joint[5], joint[6]
    # A contiguous copy first: the loops below vectorise only over unit-stride data.
    q_i = q[start : start + m, i]
    for j in range(m):
        w[_Q * _STRIDE + j] = q_i[j] * sign + theta
    far = False
    twist = not (ca == 1.0 and sa == 0.0)
    if modified and twist:
        for j in range(_U(m)):
            x = w[_U(_Q * _STRIDE) + j]
            far |= not abs(x) <= CODY_WAITE_LIMIT
            s, c = sincos(x)
            _modified_step(w, j, c, s, d, a, ca, sa, True)
    elif modified:
        for j in range(_U(m)):
            x = w[_U(_Q * _STRIDE) + j]
            far |= not abs(x) <= CODY_WAITE_LIMIT
            s, c = sincos(x)
            _modified_step(w, j, c, s, d, a, ca, sa, False)
    elif twist:
        for j in range(_U(m)):
            x = w[_U(_Q * _STRIDE) + j]
            far |= not abs(x) <= CODY_WAITE_LIMIT
            s, c = sincos(x)
            _standard_step(w, j, c, s, d, a, ca, sa, True)
    else:
        for j in range(_U(m)):
            x = w[_U(_Q * _STRIDE) + j]
            far |= not abs(x) <= CODY_WAITE_LIMIT
            s, c = sincos(x)
            _standard_step(w, j, c, s, d, a, ca, sa, False)
    return not far


@nb.njit(cache=True, fastmath=_FASTMATH)
def _joint_rows(
    q: Float, start: int, m: int, i: int, joint: Float, w: Float
) -> bool:  # pragma: no cover - compiled
    """Rows C, S, D of joint ``i``: cos θ, sin θ and d for each pose, any finite q.

    Revolute: θ = s·q + θ0, with the polynomial and libm beyond its range;
    prismatic: the fixed angle, d = s·q + d0. Returns ``False`` if a value is not
    finite.
    """
    sign = joint[1]
    q_i = q[start : start + m, i]
    finite = True
    if joint[0] != 0.0:
        for j in range(m):
            v = q_i[j] * sign + joint[3]
            finite &= math.isfinite(v)
            w[_D * _STRIDE + j] = v
            w[_C * _STRIDE + j] = joint[7]
            w[_S * _STRIDE + j] = joint[8]
        return finite
    for j in range(m):
        x = q_i[j] * sign + joint[2]
        finite &= math.isfinite(x)
        if abs(x) <= CODY_WAITE_LIMIT:
            s, c = sincos(x)
        else:
            s, c = math.sin(x), math.cos(x)
        w[_S * _STRIDE + j] = s
        w[_C * _STRIDE + j] = c
        w[_D * _STRIDE + j] = joint[3]
    return finite


@nb.njit(cache=True, fastmath=_FASTMATH)
def _rows_step(w: Float, m: int, modified: bool, joint: Float) -> None:  # pragma: no cover
    """Every pose times joint's transform, with cos θ, sin θ, d from rows C, S, D."""
    a, ca, sa = joint[4], joint[5], joint[6]
    if modified:
        for j in range(_U(m)):
            c, s, d = w[_U(_C * _STRIDE) + j], w[_U(_S * _STRIDE) + j], w[_U(_D * _STRIDE) + j]
            _modified_step(w, j, c, s, d, a, ca, sa, True)
    else:
        for j in range(_U(m)):
            c, s, d = w[_U(_C * _STRIDE) + j], w[_U(_S * _STRIDE) + j], w[_U(_D * _STRIDE) + j]
            _standard_step(w, j, c, s, d, a, ca, sa, True)


@nb.njit(cache=True, fastmath=_FASTMATH)
def _first_revolute(
    q: Float, start: int, m: int, modified: bool, joint: Float, w: Float
) -> bool:  # pragma: no cover - compiled
    """Revolute joint 0 on an identity base: its transform ``A_1`` written straight in.

    What :func:`_start` and :func:`_revolute_fused` would compute, with the
    products by the identity's zeros and ones left out. Same return as the latter.
    """
    sign, theta, d, a, ca, sa = joint[1], joint[2], joint[3], joint[4], joint[5], joint[6]
    q_0 = q[start : start + m, 0]
    for j in range(m):
        w[_Q * _STRIDE + j] = q_0[j] * sign + theta
    far = False
    for j in range(_U(m)):
        x = w[_U(_Q * _STRIDE) + j]
        far |= not abs(x) <= CODY_WAITE_LIMIT
        s, c = sincos(x)
        if modified:  # Rx(α) · Tx(a) · Rz(θ) · Tz(d)
            col_x, col_y = (c, ca * s, sa * s), (-s, ca * c, sa * c)
            col_z, col_p = (0.0, -sa, ca), (a, -sa * d, ca * d)
        else:  # Rz(θ) · Tz(d) · Tx(a) · Rx(α)
            col_x, col_y = (c, s, 0.0), (-ca * s, ca * c, sa)
            col_z, col_p = (sa * s, -sa * c, ca), (a * c, a * s, d)
        for r in range(3):
            w[_U((_X + r) * _STRIDE) + j] = col_x[r]
            w[_U((_Y + r) * _STRIDE) + j] = col_y[r]
            w[_U((_Z + r) * _STRIDE) + j] = col_z[r]
            w[_U((_P + r) * _STRIDE) + j] = col_p[r]
    return not far


@nb.njit(cache=True, fastmath=_FASTMATH)
def _chain_fused(
    q: Float, start: int, m: int, prog: Float, modified: bool, w: Float
) -> bool:  # pragma: no cover - compiled
    """The whole chain for one block, revolute joints fused; ``False``: take the rows path."""
    n = q.shape[1]
    first = 0
    if prog[0, 0] == 0.0 and _is_identity(prog[n : n + 4, :4]):
        if not _first_revolute(q, start, m, modified, prog[0], w):
            return False
        first = 1
    else:
        _start(w, m, prog[n : n + 4, :4])
    for i in range(first, n):
        if prog[i, 0] != 0.0:
            if not _joint_rows(q, start, m, i, prog[i], w):
                return False
            _rows_step(w, m, modified, prog[i])
        elif not _revolute_fused(q, start, m, i, modified, prog[i], w):
            return False
    return True


@nb.njit(cache=True, fastmath=_FASTMATH)
def _chain_rows(
    q: Float, start: int, m: int, prog: Float, modified: bool, w: Float
) -> bool:  # pragma: no cover - compiled
    """The whole chain for one block, any finite q; ``False`` if a value is not finite."""
    n = q.shape[1]
    _start(w, m, prog[n : n + 4, :4])
    for i in range(n):
        if not _joint_rows(q, start, m, i, prog[i], w):
            return False
        _rows_step(w, m, modified, prog[i])
    return True


@nb.njit(cache=True, fastmath=_FASTMATH)
def _tool(w: Float, m: int, tool: Float) -> None:  # pragma: no cover - compiled
    """Right-multiply every pose by ``flange_T_tool``."""
    for r in range(3):
        ox = (_X + r) * _STRIDE
        oy = (_Y + r) * _STRIDE
        oz = (_Z + r) * _STRIDE
        op = (_P + r) * _STRIDE
        for j in range(m):
            x = w[ox + j]
            y = w[oy + j]
            z = w[oz + j]
            w[ox + j] = x * tool[0, 0] + y * tool[1, 0] + z * tool[2, 0]
            w[oy + j] = x * tool[0, 1] + y * tool[1, 1] + z * tool[2, 1]
            w[oz + j] = x * tool[0, 2] + y * tool[1, 2] + z * tool[2, 2]
            w[op + j] = w[op + j] + x * tool[0, 3] + y * tool[1, 3] + z * tool[2, 3]


# --------------------------------------------------------------------------- output
# The last step turns twelve columns of poses (structure of arrays) into 4×4
# matrices (array of structures). Written as scalar code, LLVM stores one float
# at a time, and that store loop costs as much as all the joints together. So
# eight poses at a time are moved with vector loads, an 8×8 transpose made of
# `shufflevector`s (LLVM picks the instructions for the CPU: AVX-512 permutes
# here, narrower ones elsewhere) and sixteen contiguous vector stores.

_V8 = ir.VectorType(ir.DoubleType(), 8)
_I32 = ir.IntType(32)


def _lanes(*idx: int) -> ir.Constant:
    """A constant shuffle mask."""
    return ir.Constant(ir.VectorType(_I32, len(idx)), [ir.Constant(_I32, i) for i in idx])


def _transpose8(builder: ir.IRBuilder, v: list[ir.Value]) -> list[ir.Value]:
    """Transpose eight 8-lane vectors: ``out[p][k] = v[k][p]`` (three shuffle stages)."""
    # Stage 1, pairs (v0,v1), (v2,v3), …: even lanes and odd lanes interleaved.
    a = []
    for k in range(0, 8, 2):
        a.append(builder.shuffle_vector(v[k], v[k + 1], _lanes(0, 8, 2, 10, 4, 12, 6, 14)))
        a.append(builder.shuffle_vector(v[k], v[k + 1], _lanes(1, 9, 3, 11, 5, 13, 7, 15)))
    # Stage 2, quads: (v0..v3) and (v4..v7) for lanes p and p+4, p = 0…3.
    b = {}
    for half, (x, y) in enumerate(((0, 2), (4, 6))):
        for parity in (0, 1):
            lo, hi = a[x + parity], a[y + parity]
            b[half, parity] = builder.shuffle_vector(lo, hi, _lanes(0, 1, 8, 9, 4, 5, 12, 13))
            b[half, parity + 2] = builder.shuffle_vector(lo, hi, _lanes(2, 3, 10, 11, 6, 7, 14, 15))
    # Stage 3: lane p of all eight vectors, and lane p+4.
    out: list[ir.Value] = [ir.Constant(_V8, None)] * 8
    for p in range(4):
        out[p] = builder.shuffle_vector(b[0, p], b[1, p], _lanes(0, 1, 2, 3, 8, 9, 10, 11))
        out[p + 4] = builder.shuffle_vector(b[0, p], b[1, p], _lanes(4, 5, 6, 7, 12, 13, 14, 15))
    return out


def _store8_typer(typingctx: Any, w: Any, j: Any, flat: Any, k: Any) -> Any:  # pragma: no cover
    """Typing and code of ``_store8(w, j, flat, k)``.

    Stores poses ``j … j+7`` of the scratch ``w`` as ``flat[16k : 16k+128]``: eight
    row-major 4×4 matrices.
    """
    sig = types.void(w, j, flat, k)

    def codegen(context: Any, builder: ir.IRBuilder, signature: Any, args: Any) -> Any:
        w_arr = context.make_array(signature.args[0])(context, builder, args[0])
        out_arr = context.make_array(signature.args[2])(context, builder, args[2])
        intp = context.get_value_type(types.intp)

        def load(row: int) -> ir.Value:
            idx = builder.add(args[1], ir.Constant(intp, row * _STRIDE))
            ptr = builder.gep(w_arr.data, [idx], inbounds=True)
            return builder.load(builder.bitcast(ptr, _V8.as_pointer()), align=8)

        zero = ir.Constant(_V8, [0.0] * 8)
        one = ir.Constant(_V8, [1.0] * 8)
        # A pose's 16 floats are rows 0–1 of its matrix (X0 Y0 Z0 P0 X1 Y1 Z1 P1),
        # then row 2 and the constant last row (X2 Y2 Z2 P2 0 0 0 1).
        rows01 = _transpose8(builder, [load(3 * col + r) for r in (0, 1) for col in range(4)])
        rows23 = _transpose8(builder, [load(3 * col + 2) for col in range(4)] + [zero] * 3 + [one])
        first = builder.mul(args[3], ir.Constant(intp, 16))
        for p in range(8):
            for h, vec in enumerate((rows01[p], rows23[p])):
                idx = builder.add(first, ir.Constant(intp, 16 * p + 8 * h))
                ptr = builder.gep(out_arr.data, [idx], inbounds=True)
                builder.store(vec, builder.bitcast(ptr, _V8.as_pointer()), align=8)
        return context.get_dummy_value()

    return sig, codegen


_store8: Any = intrinsic(_store8_typer)


@nb.njit(cache=True, fastmath=_FASTMATH)
def _store(w: Float, m: int, flat: Float, start: int) -> None:  # pragma: no cover - compiled
    """Write the ``m`` poses as 4×4 matrices into ``flat[16·start : 16·(start+m)]``."""
    j = 0
    while j + 8 <= m:
        _store8(w, j, flat, start + j)
        j += 8
    for jj in range(j, m):
        o = 16 * (start + jj)
        for r in range(3):
            for col in range(4):
                flat[o + 4 * r + col] = w[(3 * col + r) * _STRIDE + jj]
        flat[o + 12] = 0.0
        flat[o + 13] = 0.0
        flat[o + 14] = 0.0
        flat[o + 15] = 1.0


@nb.njit(cache=True, fastmath=_FASTMATH)
def _block(
    q: Float, start: int, m: int, prog: Float, modified: bool, out: Float, w: Float
) -> bool:  # pragma: no cover - compiled
    """Poses ``start … start+m-1`` (``m <= BLOCK``) into ``out``, using scratch ``w``.

    Returns ``False`` (``out`` unwritten) if a joint value is not finite.
    """
    fast = _chain_fused(q, start, m, prog, modified, w)  # false if an angle is beyond ~1.6e6 rad
    if not fast and not _chain_rows(q, start, m, prog, modified, w):
        return False
    n = q.shape[1]
    tool = prog[n + 4 : n + 8, :4]
    if not _is_identity(tool):
        _tool(w, m, tool)
    _store(w, m, out.reshape(-1), start)
    return True


def _fetch_add_typer(typingctx: Any, counter: Any) -> Any:  # pragma: no cover
    """Typing and code of ``_fetch_add(counter)``: atomically ``counter[0] += 1``.

    Returns the value before the increment (LLVM ``atomicrmw add``).
    """
    sig = types.int64(counter)

    def codegen(context: Any, builder: ir.IRBuilder, signature: Any, args: Any) -> Any:
        arr = context.make_array(signature.args[0])(context, builder, args[0])
        one = ir.Constant(ir.IntType(64), 1)
        return builder.atomic_rmw("add", arr.data, one, "monotonic")

    return sig, codegen


_fetch_add: Any = intrinsic(_fetch_add_typer)


@nb.njit(cache=True, parallel=True, fastmath=_FASTMATH)
def fk_tcp(
    q: Float, prog: Float, modified: bool, out: Float, workers: int
) -> bool:  # pragma: no cover - compiled
    """``world_T_tcp`` for every row of ``q`` (``(N, n)``) into ``out`` (``(N, 4, 4)``).

    ``workers`` tasks run in parallel (one per numba thread) and take blocks from
    a shared atomic counter until none is left: a thread slowed down by other
    programs on the machine just takes fewer blocks, instead of holding up the
    batch with a fixed share. Each worker allocates its scratch once (33 KiB),
    so memory beyond ``out`` stays bounded whatever ``N``. Returns ``False`` if
    a joint value is not finite (then ``out`` is partly written).
    """
    N = q.shape[0]
    nblocks = (N + BLOCK - 1) // BLOCK
    bad = 0
    if workers <= 1 or nblocks < PARALLEL_MIN_BLOCKS:
        w = np.empty(_ROWS * _STRIDE)
        for b in range(nblocks):
            start = b * BLOCK
            if not _block(q, start, min(BLOCK, N - start), prog, modified, out, w):
                bad += 1
        return bad == 0
    counter = np.zeros(1, dtype=np.int64)
    for _ in nb.prange(min(nblocks, workers)):
        w = np.empty(_ROWS * _STRIDE)
        b = _fetch_add(counter)
        while b < nblocks:
            start = b * BLOCK
            if not _block(q, start, min(BLOCK, N - start), prog, modified, out, w):
                bad += 1
            b = _fetch_add(counter)
    return bad == 0


@nb.njit(cache=True)
def fk_one(q: Float, prog: Float, modified: bool, out: Float) -> bool:  # pragma: no cover
    """``world_T_tcp`` for one configuration ``q`` (``(n,)``) into ``out`` (``(4, 4)``).

    Plain scalar code with libm's ``cos``/``sin``, no FMA contraction and the
    operation order of ``fkcheck.core.dh``'s Python and NumPy paths, so its result is
    bit-for-bit theirs: loading the JIT changes how fast one pose is, not its
    digits. For one pose the cost is the call from Python, not the arithmetic.
    Checks finiteness itself (so the caller need not) and returns ``False``,
    leaving ``out`` unwritten, if a value is not finite.
    """
    n = q.shape[0]
    for i in range(n):
        if not math.isfinite(q[i]):
            return False
    x0, x1, x2 = prog[n, 0], prog[n + 1, 0], prog[n + 2, 0]
    y0, y1, y2 = prog[n, 1], prog[n + 1, 1], prog[n + 2, 1]
    z0, z1, z2 = prog[n, 2], prog[n + 1, 2], prog[n + 2, 2]
    p0, p1, p2 = prog[n, 3], prog[n + 1, 3], prog[n + 2, 3]
    for i in range(n):
        v = q[i] * prog[i, 1]
        if prog[i, 0] != 0.0:
            c, s, d = prog[i, 7], prog[i, 8], v + prog[i, 3]
        else:
            c, s, d = math.cos(v + prog[i, 2]), math.sin(v + prog[i, 2]), prog[i, 3]
        a, ca, sa = prog[i, 4], prog[i, 5], prog[i, 6]
        if modified:  # Rx(α) · Tx(a) · Rz(θ) · Tz(d)
            u0, u1, u2 = ca * y0 + sa * z0, ca * y1 + sa * z1, ca * y2 + sa * z2
            z0, z1, z2 = ca * z0 - sa * y0, ca * z1 - sa * y1, ca * z2 - sa * y2
            p0, p1, p2 = p0 + a * x0, p1 + a * x1, p2 + a * x2
            y0, y1, y2 = c * u0 - s * x0, c * u1 - s * x1, c * u2 - s * x2
            x0, x1, x2 = c * x0 + s * u0, c * x1 + s * u1, c * x2 + s * u2
            p0, p1, p2 = p0 + d * z0, p1 + d * z1, p2 + d * z2
        else:  # Rz(θ) · Tz(d) · Tx(a) · Rx(α)
            u0, u1, u2 = c * y0 - s * x0, c * y1 - s * x1, c * y2 - s * x2
            x0, x1, x2 = c * x0 + s * y0, c * x1 + s * y1, c * x2 + s * y2
            p0, p1, p2 = p0 + d * z0 + a * x0, p1 + d * z1 + a * x1, p2 + d * z2 + a * x2
            y0, y1, y2 = ca * u0 + sa * z0, ca * u1 + sa * z1, ca * u2 + sa * z2
            z0, z1, z2 = ca * z0 - sa * u0, ca * z1 - sa * u1, ca * z2 - sa * u2
    t = prog[n + 4 : n + 8, :4]
    tool = not _is_identity(t)
    for r, (x, y, z, p) in enumerate(((x0, y0, z0, p0), (x1, y1, z1, p1), (x2, y2, z2, p2))):
        if tool:
            x, y, z, p = (
                x * t[0, 0] + y * t[1, 0] + z * t[2, 0],
                x * t[0, 1] + y * t[1, 1] + z * t[2, 1],
                x * t[0, 2] + y * t[1, 2] + z * t[2, 2],
                p + x * t[0, 3] + y * t[1, 3] + z * t[2, 3],
            )
        out[r, 0] = x
        out[r, 1] = y
        out[r, 2] = z
        out[r, 3] = p
    out[3, 0] = 0.0
    out[3, 1] = 0.0
    out[3, 2] = 0.0
    out[3, 3] = 1.0
    return True


def tasks() -> int:
    """Worker count for :func:`fk_tcp`: numba's thread count (``NUMBA_NUM_THREADS``)."""
    return int(nb.get_num_threads())


def warm_up() -> None:
    """Compile (first run on a machine) or load from the cache every kernel, now.

    Uses the argument types :mod:`fkcheck.core.dh` calls with, so later calls never compile.
    """
    prog = np.zeros((9, 9))
    prog[1:5, :4] = np.eye(4)
    prog[5:9, :4] = np.eye(4)
    q = np.zeros((1, 1))
    out = np.empty((1, 4, 4))
    fk_tcp(q, prog, False, out, 1)
    fk_one(q[0], prog, False, out[0])
    q_read_only = q[0].copy()
    q_read_only.flags.writeable = False  # numba types these apart: compile both now
    fk_one(q_read_only, prog, False, out[0])
    sincos_array(q[0], out[0, 0, :1], out[0, 1, :1])
