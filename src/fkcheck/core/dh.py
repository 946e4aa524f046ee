"""The in-house Denavit–Hartenberg forward-kinematics core (batched).

This module is what the reference libraries check, so it shares no code with
them: it needs NumPy, and uses numba (optional) only to run the same arithmetic
faster.

Conventions (``A_i`` maps frame ``i-1`` to frame ``i``):

* standard:  ``A_i = Rz(θ_i) · Tz(d_i) · Tx(a_i) · Rx(α_i)``
* modified (Craig):  ``A_i = Rx(α_{i-1}) · Tx(a_{i-1}) · Rz(θ_i) · Tz(d_i)``
  (a modified table's row *i* holds ``a_{i-1}`` and ``α_{i-1}``).

For a revolute joint ``θ_i = s_i·q_i + θ_offset_i`` with ``d_i`` fixed; for a
prismatic joint ``d_i = s_i·q_i + d_offset_i`` with ``θ_i`` fixed. ``s_i`` is −1
for a flipped joint, else +1.

Every path works on the four columns of the running transform (x, y, z axes and
origin) and applies each elementary motion as column arithmetic: it never forms
the constant last row and never multiplies by a known zero.
:func:`fk_reference` is the straightforward 4×4 matrix-product chain they are
all tested against. :func:`fk` picks the path from the call alone, so a call's
result never depends on what ran before it:

* **JIT batch** (``fkcheck.core._kernels.fk_tcp``, numba): ``N >= JIT_MIN_POSES``
  poses, TCP only. Vectorised, with its own polynomial sin/cos and fused
  multiply-adds, so its last bits differ from the other paths (by at most
  :data:`fkcheck.core.tolerances.FAST_CORE`, tested). Loads numba on first use;
  compiled code is cached on disk, so compiling happens once per machine.
* **one pose**: scalar code with libm's ``cos``/``sin``: the JIT's ``fk_one``
  (~1.3 µs a call) once the JIT is loaded — by a large batch or by
  :func:`load_jit` — else the same arithmetic in Python (~6 µs). The two give
  the same bits, and the same bits as the NumPy path where NumPy's ``cos``/``sin``
  are libm's. One pose never loads numba itself: importing it costs ~0.3–0.5 s,
  more than a one-shot ``fkcheck fk ur5 --q …`` should pay.
* **NumPy** (:func:`fk_numpy`): everything else — small batches,
  ``all_frames=True``, and every batch on a machine without numba (or without a
  writable numba cache). Works in chunks of :data:`NUMPY_CHUNK` poses, so its
  temporaries stay a few MB whatever ``N``.
"""

from __future__ import annotations

import importlib
import logging
import math
import os
from dataclasses import dataclass
from functools import cached_property
from types import ModuleType
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from fkcheck.core.joint_array import joint_array, require_finite
from fkcheck.core.typing import Float
from fkcheck.process.threads import thread_limit

__all__ = [
    "JIT_MIN_POSES",
    "NUMPY_CHUNK",
    "Convention",
    "DHChain",
    "dh_matrix",
    "fk",
    "fk_numpy",
    "fk_reference",
    "jit_status",
    "jit_tasks",
    "joint_values",
    "kernels_cached",
    "load_jit",
]

_log = logging.getLogger(__name__)

Convention = Literal["standard", "modified"]

#: Batches of at least this many poses use the JIT kernel (loading numba if it is
#: installed). Loading it from numba's cache costs 0.5–2.3 s (numba's import and
#: the cached code; measured on the 2-core CI machine, quiet and loaded), NumPy
#: ~2 µs a pose, the kernel ~0.14 µs: below this size NumPy is done first (a
#: 10⁴-sample check: 10–30 ms on NumPy against ≥ 0.5 s to load the kernel).
JIT_MIN_POSES = 200_000

#: Poses per chunk of the NumPy path: its ~30 column temporaries of
#: ``3 × NUMPY_CHUNK`` floats stay around 6 MB, and larger chunks are no faster.
NUMPY_CHUNK = 8192


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

    @cached_property
    def dof(self) -> int:
        """Number of joints."""
        return int(self.a.shape[0])

    @cached_property
    def _one_pose(self) -> tuple[tuple[int], Float, bool]:
        """What a one-pose call needs, looked up once: q's shape, the program, modified?"""
        return (self.dof,), self.program, self.convention == "modified"

    @cached_property
    def program(self) -> Float:
        """The chain as one ``(n + 8, 9)`` array, the JIT kernels' input.

        Rows ``0 … n-1``, one per joint: ``prismatic (0/1), sign, θ, d, a, cos α,
        sin α, cos θ, sin θ``; rows ``n … n+3`` (columns 0–3): ``world_T_base``;
        rows ``n+4 … n+7``: ``flange_T_tool``. One array, because each array
        argument adds ~0.1 µs to a compiled call.
        """
        n = self.dof
        prog = np.zeros((n + 8, 9))
        prog[:n, 0] = self.prismatic
        prog[:n, 1] = self.sign
        prog[:n, 2] = self.theta
        prog[:n, 3] = self.d
        prog[:n, 4] = self.a
        prog[:n, 5] = np.cos(self.alpha)
        prog[:n, 6] = np.sin(self.alpha)
        prog[:n, 7] = np.cos(self.theta)
        prog[:n, 8] = np.sin(self.theta)
        prog[n : n + 4, :4] = self.world_T_base
        prog[n + 4 :, :4] = self.flange_T_tool
        return prog

    @cached_property
    def _python_program(self) -> tuple[tuple[tuple[float, ...], ...], tuple[float, ...]]:
        """:attr:`program` as Python floats: joint rows, then base and tool (row-major)."""
        prog = self.program.tolist()
        n = self.dof
        base_tool = tuple(v for row in prog[n:] for v in row[:4])
        return tuple(tuple(row) for row in prog[:n]), base_tool


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
    q_arr = joint_array(q, chain.dof)
    require_finite(q_arr)
    return q_arr


def fk(
    chain: DHChain, q: ArrayLike, *, all_frames: bool = False, out: Float | None = None
) -> Float:
    """Forward kinematics of a DH chain for one or many configurations.

    Picks the fastest available path (see the module docstring); all agree with
    :func:`fk_reference` to :data:`fkcheck.core.tolerances.FAST_CORE`.

    Args:
        chain: The chain.
        q: Joint values, shape ``(n,)`` or ``(N, n)``.
        all_frames: Return every DH frame instead of the TCP.
        out: Optional C-contiguous float64 array of the result's shape to write
            into (and return), e.g. to reuse one buffer across calls.

    Returns:
        ``all_frames=False``: ``world_T_tcp`` with shape ``(4, 4)`` or ``(N, 4, 4)``
        (base and tool transforms included).
        ``all_frames=True``: ``world_T_i`` for DH frames ``i = 0 … n`` with shape
        ``(n+1, 4, 4)`` or ``(N, n+1, 4, 4)`` (base included, tool not).

    Raises:
        JointInputError: ``q`` has the wrong shape or non-finite values.
        ValueError: ``out`` has the wrong shape, dtype or layout, or overlaps ``q``.
    """
    if not all_frames and out is None:
        T = _one_pose_fast(chain, q)
        if T is not None:
            return T
    q2 = joint_array(q, chain.dof)
    single = np.ndim(q) == 1
    N, n = q2.shape
    frame_shape: tuple[int, ...] = (n + 1, 4, 4) if all_frames else (4, 4)
    result = _output(out, frame_shape if single else (N, *frame_shape), q2)
    batch = result.reshape((N, *frame_shape))
    modified = chain.convention == "modified"
    if not all_frames and N >= JIT_MIN_POSES and load_jit():
        assert _jit is not None
        if not q2.flags.writeable:  # numba would compile read-only arrays as another type
            q2 = q2.copy()
        # The kernel checks finiteness on the way (saving a pass over q) and refuses
        # non-finite angles: then either q is not finite (raised below) or only
        # s·q + θ0 overflowed, and the NumPy path gives the reference's NaNs.
        if _jit.fk_tcp(q2, chain.program, modified, batch, jit_tasks()):
            return result
    require_finite(q2)
    if not all_frames and single and _jit is not None:
        _jit.fk_one(np.array(q2[0]), chain.program, modified, batch[0])
        return result
    _fk_numpy_into(chain, q2, batch, all_frames)
    return result


def fk_numpy(
    chain: DHChain, q: ArrayLike, *, all_frames: bool = False, out: Float | None = None
) -> Float:
    """:func:`fk` on the NumPy path only, whether or not the JIT is available.

    The fallback :func:`fk` uses without numba; public so that it can be timed and
    tested on its own. Same arguments, shapes and errors as :func:`fk`.
    """
    q2 = joint_values(chain, q)
    single = np.ndim(q) == 1
    N, n = q2.shape
    frame_shape: tuple[int, ...] = (n + 1, 4, 4) if all_frames else (4, 4)
    result = _output(out, frame_shape if single else (N, *frame_shape), q2)
    _fk_numpy_into(chain, q2, result.reshape((N, *frame_shape)), all_frames)
    return result


def _output(out: Float | None, shape: tuple[int, ...], q: Float) -> Float:
    """``out`` checked against the result's shape, or a new array of that shape."""
    if out is None:
        return np.empty(shape)
    if not isinstance(out, np.ndarray):
        raise ValueError(f"out must be a NumPy array, got {type(out).__name__}")
    if out.shape != shape or out.dtype != np.float64 or not out.flags.c_contiguous:
        raise ValueError(
            f"out must be a C-contiguous float64 array of shape {shape}, got "
            f"{out.dtype} {'C-contiguous' if out.flags.c_contiguous else 'strided'} "
            f"shape {out.shape}"
        )
    if not out.flags.writeable:
        raise ValueError("out is read-only")
    if np.may_share_memory(out, q):
        raise ValueError("out overlaps the joint values q")
    return out


# --------------------------------------------------------------------------- JIT loading

_jit: ModuleType | None = None
_jit_error: str | None = None


def jit_tasks() -> int:
    """Worker count of the numba kernels (FK and Jacobian): numba's thread count.

    No more than this process's share of the cores when it runs beside other checks
    (:func:`fkcheck.process.threads.thread_limit`).
    """
    assert _jit is not None
    limit = thread_limit()
    tasks = int(_jit.tasks())
    return tasks if limit is None else min(tasks, limit)


def load_jit() -> bool:
    """Load the numba kernels now (compiling them on the first run on a machine).

    :func:`fk` loads them by itself for its first large batch; call this first to
    make one-pose calls fast from the start (~1.3 µs instead of ~6 µs, same bits).

    Returns:
        Whether the JIT is usable. When it is not (numba missing, ``NUMBA_DISABLE_JIT``
        set, no writable cache directory, a compile error), :func:`fk` keeps the
        NumPy and scalar paths, and :func:`jit_status` says why.
    """
    global _jit, _jit_error
    if _jit is not None:
        return True
    if _jit_error is not None:
        return False
    try:
        kernels = importlib.import_module("fkcheck.core._kernels")
        kernels.warm_up()
    except Exception as exc:  # any failure means "no JIT": recorded, logged, and queryable
        _jit_error = f"{type(exc).__name__}: {exc}".strip()
        _log.info("fkcheck: JIT kernels unavailable (%s); using the NumPy path", _jit_error)
        return False
    _jit = kernels
    return True


def kernels_cached(*, jacobian: bool = False) -> bool | None:
    """Whether numba's on-disk cache holds the kernels (and the Jacobian's): no compile ahead.

    Looks for each kernel's cache index (``NUMBA_CACHE_DIR``, else ``__pycache__``
    beside the module, else numba's per-user directory), importing the kernels'
    modules but compiling nothing. ``None``: it cannot tell (numba missing or
    disabled, or numba's cache layout unknown).
    """
    entries: list[tuple[str, tuple[str, ...]]] = [
        ("fkcheck.core._kernels", ("fk_tcp", "fk_one", "sincos_array"))
    ]
    if jacobian:
        entries.append(("fkcheck.core._jacobian_kernels", ("jacobian_batch",)))
    try:
        found = []
        for name, kernels in entries:
            module = importlib.import_module(name)
            for kernel in kernels:
                index = getattr(module, kernel)._cache._cache_file._index_path
                found.append(os.path.exists(index))
    except Exception:  # no numba, NUMBA_DISABLE_JIT, another numba's layout: cannot tell
        return None
    return all(found)


def jit_status() -> str:
    """One line: whether the JIT kernels are loaded, not yet loaded, or unavailable and why."""
    if _jit is not None:
        return f"loaded (numba {_jit.nb.__version__}, {_jit.tasks()} threads)"
    if _jit_error is not None:
        return f"unavailable: {_jit_error}"
    return "not loaded"


# --------------------------------------------------------------------------- one pose, Python


def _one_pose_fast(chain: DHChain, q: object) -> Float | None:
    """``world_T_tcp`` for one plain configuration, skipping the general path's overhead.

    Handles a 1-D float64 array or a list/tuple of n numbers, finite; returns
    ``None`` for anything else, which the general path then handles (or rejects).
    """
    shape, program, modified = chain._one_pose
    if type(q) is np.ndarray:
        # Checked in order of cost. Strides (8,): C-contiguous, as the kernel was
        # compiled for (read-only arrays have their own compiled version, see warm_up).
        if q.shape != shape or q.dtype is not _FLOAT64:
            return None
        if _jit is None:
            return _fk_one_python(chain, q.tolist())
        if q.strides != _UNIT_STRIDE:
            return None
        q_arr = q
    elif type(q) is list or type(q) is tuple:
        values = _floats(q, shape[0])
        if values is None or _jit is None:
            return None if values is None else _fk_one_python(chain, values)
        q_arr = np.array(values)
    else:
        return None
    T = np.empty((4, 4))
    return T if _jit.fk_one(q_arr, program, modified, T) else None


_FLOAT64 = np.dtype(np.float64)
_UNIT_STRIDE = (8,)


def _floats(q: list[object] | tuple[object, ...], n: int) -> list[float] | None:
    """``q`` as n Python floats, or ``None`` if it is anything else (the general path decides)."""
    if len(q) != n:
        return None
    try:
        return [float(v) for v in q]  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return None


def _fk_one_python(chain: DHChain, q: list[float]) -> Float | None:
    """``world_T_tcp`` for one configuration with the ``math`` module.

    The same column arithmetic as the kernels, on Python floats: ~6 µs for six
    joints, against ~80 µs for NumPy on ``(3, 1)`` arrays. Returns ``None`` for
    non-finite input, which the caller sends down the general path to be rejected.
    """
    joints, bt = chain._python_program
    if not math.isfinite(sum(q)):
        return None
    x0, y0, z0, p0, x1, y1, z1, p1, x2, y2, z2, p2 = bt[:12]
    modified = chain.convention == "modified"
    cos, sin = math.cos, math.sin
    for qi, (prismatic, sign, theta, d0, a, ca, sa, ct, st) in zip(q, joints, strict=True):
        v = qi * sign
        if prismatic:
            c, s, d = ct, st, v + d0
        else:
            c, s, d = cos(v + theta), sin(v + theta), d0
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
    if bt[16:] != _IDENTITY:
        t = bt[16:]
        x0, y0, z0, p0 = _times_tool(x0, y0, z0, p0, t)
        x1, y1, z1, p1 = _times_tool(x1, y1, z1, p1, t)
        x2, y2, z2, p2 = _times_tool(x2, y2, z2, p2, t)
    T = np.array((x0, y0, z0, p0, x1, y1, z1, p1, x2, y2, z2, p2, 0.0, 0.0, 0.0, 1.0))
    return T.reshape(4, 4)


_IDENTITY = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)


def _times_tool(
    x: float, y: float, z: float, p: float, t: tuple[float, ...]
) -> tuple[float, float, float, float]:
    """One row ``(x, y, z, p)`` of a transform times the row-major 4×4 ``t``."""
    return (
        x * t[0] + y * t[4] + z * t[8],
        x * t[1] + y * t[5] + z * t[9],
        x * t[2] + y * t[6] + z * t[10],
        p + x * t[3] + y * t[7] + z * t[11],
    )


# --------------------------------------------------------------------------- NumPy path


def _fk_numpy_into(chain: DHChain, q: Float, out: Float, all_frames: bool) -> None:
    """The NumPy path, chunk by chunk, into ``out`` (``(N, 4, 4)`` or ``(N, n+1, 4, 4)``)."""
    for start in range(0, q.shape[0], NUMPY_CHUNK):
        stop = start + NUMPY_CHUNK
        _fk_numpy_chunk(chain, q[start:stop], out[start:stop], all_frames)


def _fk_numpy_chunk(chain: DHChain, q2: Float, out: Float, all_frames: bool) -> None:
    """Column arithmetic on ``(3, N)`` arrays for one chunk."""
    N, n = q2.shape
    B = chain.world_T_base
    ones = np.ones(N)
    # Columns of the running transform, each (3, N): x axis, y axis, z axis, origin.
    X = B[:3, 0, None] * ones
    Y = B[:3, 1, None] * ones
    Z = B[:3, 2, None] * ones
    P = B[:3, 3, None] * ones

    if all_frames:
        out[:, :, 3, :3] = 0.0
        out[:, :, 3, 3] = 1.0
        _store(out[:, 0], X, Y, Z, P)

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
        if all_frames:
            _store(out[:, i + 1], X, Y, Z, P)

    if all_frames:
        return
    t = chain.flange_T_tool
    if not np.array_equal(t, _EYE4):  # skipped, like every path, to keep the sign of zeros
        X, Y, Z, P = (
            X * t[0, 0] + Y * t[1, 0] + Z * t[2, 0],
            X * t[0, 1] + Y * t[1, 1] + Z * t[2, 1],
            X * t[0, 2] + Y * t[1, 2] + Z * t[2, 2],
            P + X * t[0, 3] + Y * t[1, 3] + Z * t[2, 3],
        )
    out[:, 3, :3] = 0.0
    out[:, 3, 3] = 1.0
    _store(out, X, Y, Z, P)


_EYE4 = np.eye(4)


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
