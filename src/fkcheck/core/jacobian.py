"""The in-house geometric Jacobian, from the DH frames of :mod:`fkcheck.core.dh` (batched).

Like the forward kinematics it shares no code with the reference libraries:
its own formula on the DH frames the core computes. Joint ``i`` (1-based) moves
about — or, prismatic, along — the ``z`` axis of DH frame ``i−1`` in standard
DH, of DH frame ``i`` in modified DH, through that frame's origin ``oᵢ``, with
``sᵢ = −1`` for a flipped joint. For a point ``p`` carried by the last link
(the TCP, or a named frame's origin) its column is, in world axes,

* revolute:  linear ``sᵢ · zᵢ × (p − oᵢ)``, angular ``sᵢ · zᵢ``;
* prismatic: linear ``sᵢ · zᵢ``, angular ``0``;

and ``0`` for every joint after the frame ``p`` sits on. Rows are **linear
first, then angular** — ``(…, 6, n)`` — as in Pinocchio and Robotics Toolbox
(many textbooks put the angular rows first). Three reference frames, named and
defined as Pinocchio's ``ReferenceFrame``:

* ``"world-aligned"`` (``LOCAL_WORLD_ALIGNED``; Robotics Toolbox ``jacob0``):
  the velocity of the target frame's **origin** and its angular velocity, both
  in world axes — the columns above;
* ``"local"`` (``LOCAL``; Robotics Toolbox ``jacobe``): the same twist in the
  target frame's own axes: ``[Rᵀ v; Rᵀ ω]``;
* ``"world"`` (``WORLD``): the spatial twist at the **world origin**, in world
  axes: linear ``v + p × ω`` (the velocity of the body point passing through
  the world origin), angular ``ω``.

:func:`jacobian` computes it for a chain and a batch of configurations, picking
the path from the call alone, with the FK's rules (:mod:`fkcheck.core.dh`):

* **JIT batch** (``fkcheck.core._jacobian_kernels``, numba): ``N >=``
  :data:`~fkcheck.core.dh.JIT_MIN_POSES`. The DH frames and the columns in one
  pass per block of configurations, no ``(N, n+1, 4, 4)`` stack of frames, on
  numba's threads. Its own sin/cos and fused multiply-adds: its last bits differ
  from the NumPy path's, by at most :data:`fkcheck.core.tolerances.FAST_CORE`
  (tested).
* **NumPy**: everything else, and every batch without numba: the DH frames of
  :func:`fkcheck.core.dh.fk` (``all_frames=True``) and :func:`geometric_jacobian`,
  in chunks of :data:`~fkcheck.core.dh.NUMPY_CHUNK` configurations so the
  frames' stack stays a few MB whatever ``N``.
"""

from __future__ import annotations

import importlib
import logging
from types import ModuleType

import numpy as np
from numpy.typing import NDArray

from fkcheck.core import dh
from fkcheck.core.typing import JACOBIAN_REFERENCES as REFERENCES
from fkcheck.core.typing import Float
from fkcheck.core.typing import JacobianReference as Reference

__all__ = [
    "REFERENCES",
    "Reference",
    "geometric_jacobian",
    "jacobian",
    "jacobian_numpy",
    "kernel_status",
    "load_kernel",
    "re_express",
]

_log = logging.getLogger(__name__)


def jacobian(
    chain: dh.DHChain,
    q: Float,
    *,
    moving: int,
    target: Float,
    reference: Reference = "world-aligned",
    out: Float | None = None,
) -> Float:
    """The geometric Jacobian of a frame carried by the chain, for every row of ``q``.

    Picks the path from the call alone (see the module docstring); both agree
    with :func:`geometric_jacobian` on the frames of :func:`fkcheck.core.dh.fk`.

    Args:
        chain: The chain.
        q: ``(N, n)`` joint values (validated: see :func:`fkcheck.core.dh.joint_values`).
        moving: How many joints, from the base, move the frame: it sits on DH
            frame ``moving`` (``0`` for a frame fixed to the base or the world:
            the Jacobian is zero).
        target: ``(4, 4)`` the frame in DH frame ``moving`` (for the TCP:
            ``flange_T_tool`` times the TCP's offset).
        reference: ``"world-aligned"``, ``"local"`` or ``"world"``.
        out: Optional C-contiguous float64 ``(N, 6, n)`` array to write into (and return).

    Returns:
        ``(N, 6, n)``: linear rows then angular rows.

    Raises:
        JointInputError: ``q`` has the wrong shape or non-finite values.
        ValueError: An unknown ``reference``, ``moving`` outside ``0 … n``, or a bad ``out``.
    """
    q2, result, target = _prepare(chain, q, moving, target, reference, out)
    if moving and q2.shape[0] >= dh.JIT_MIN_POSES and load_kernel():
        assert _kernel is not None
        if not q2.flags.writeable:  # numba would compile read-only arrays as another type
            q2 = q2.copy()
        code = _kernel.REFERENCE_CODES[reference]
        modified = chain.convention == "modified"
        if _kernel.jacobian_batch(q2, chain.program, modified, moving, target, code, result,
                                  dh.jit_tasks()):  # fmt: skip
            return result
        # s·q + θ overflowed: the NumPy path gives the reference's NaNs.
    _jacobian_numpy_into(chain, q2, moving, target, reference, result)
    return result


def jacobian_numpy(
    chain: dh.DHChain,
    q: Float,
    *,
    moving: int,
    target: Float,
    reference: Reference = "world-aligned",
    out: Float | None = None,
) -> Float:
    """:func:`jacobian` on the NumPy path only, whether or not the JIT is available.

    The fallback :func:`jacobian` uses without numba; public so that it can be timed
    and tested on its own. Same arguments, shapes and errors as :func:`jacobian`.
    """
    q2, result, target = _prepare(chain, q, moving, target, reference, out)
    _jacobian_numpy_into(chain, q2, moving, target, reference, result)
    return result


def _prepare(
    chain: dh.DHChain,
    q: Float,
    moving: int,
    target: Float,
    reference: Reference,
    out: Float | None,
) -> tuple[Float, Float, Float]:
    """Validated ``(q, out, target)`` for :func:`jacobian`."""
    if reference not in REFERENCES:
        raise ValueError(
            f"unknown reference {reference!r}; references are: {', '.join(REFERENCES)}"
        )
    n = chain.dof
    if not 0 <= moving <= n:
        raise ValueError(f"moving must be between 0 and {n} (the joints), got {moving}")
    q2 = dh.joint_values(chain, q)
    # A fresh, writeable copy (16 numbers): a read-only one would make numba compile again.
    target = np.array(target, dtype=np.float64, order="C")
    if target.shape != (4, 4):
        raise ValueError(f"target must be a 4×4 transform, got shape {target.shape}")
    # The FK's check of an out= buffer (shape, dtype, layout, overlap with q).
    result = dh._output(out, (q2.shape[0], 6, n), q2)
    return q2, result, target


def _jacobian_numpy_into(
    chain: dh.DHChain, q: Float, moving: int, target: Float, reference: Reference, out: Float
) -> None:
    """The NumPy path, chunk by chunk: DH frames, then :func:`geometric_jacobian`.

    ``q`` was validated (:func:`fkcheck.core.dh.joint_values`); a frame fixed to
    the base (``moving == 0``) has a zero Jacobian.
    """
    if moving == 0:
        out[...] = 0.0
        return
    modified = chain.convention == "modified"
    for start in range(0, q.shape[0], dh.NUMPY_CHUNK):
        chunk = q[start : start + dh.NUMPY_CHUNK]
        world_T_dh = dh.fk_numpy(chain, chunk, all_frames=True)
        out[start : start + dh.NUMPY_CHUNK] = geometric_jacobian(
            world_T_dh,
            world_T_dh[:, moving] @ target,
            modified=modified,
            prismatic=chain.prismatic,
            sign=chain.sign,
            moving=moving,
            reference=reference,
        )


# --------------------------------------------------------------------------- JIT loading

_kernel: ModuleType | None = None
_kernel_error: str | None = None


def load_kernel() -> bool:
    """Load the Jacobian's numba kernel now (compiling it on the first run on a machine).

    Loads the FK kernels first (:func:`fkcheck.core.dh.load_jit`): the Jacobian's
    kernel is built from their steps.

    Returns:
        Whether the kernel is usable; when it is not, :func:`jacobian` keeps the
        NumPy path and :func:`kernel_status` says why.
    """
    global _kernel, _kernel_error
    if _kernel is not None:
        return True
    if _kernel_error is not None:
        return False
    if not dh.load_jit():
        _kernel_error = f"the FK kernels are {dh.jit_status()}"
        return False
    try:
        kernel = importlib.import_module("fkcheck.core._jacobian_kernels")
        kernel.warm_up()
    except Exception as exc:  # any failure means "no JIT": recorded, logged, and queryable
        _kernel_error = f"{type(exc).__name__}: {exc}".strip()
        _log.info("fkcheck: Jacobian kernel unavailable (%s); using NumPy", _kernel_error)
        return False
    _kernel = kernel
    return True


def kernel_status() -> str:
    """One line: whether the Jacobian kernel is loaded, not yet loaded, or unavailable and why."""
    if _kernel is not None:
        return f"loaded (numba {_kernel.nb.__version__}, {_kernel.nb.get_num_threads()} threads)"
    if _kernel_error is not None:
        return f"unavailable: {_kernel_error}"
    return "not loaded"


def geometric_jacobian(
    world_T_dh: Float,
    world_T_target: Float,
    *,
    modified: bool,
    prismatic: NDArray[np.bool_],
    sign: Float,
    moving: int,
    reference: Reference = "world-aligned",
) -> Float:
    """The geometric Jacobian of a frame carried by the chain.

    Args:
        world_T_dh: DH frames ``0…n`` in the world, ``(N, n+1, 4, 4)``.
        world_T_target: The target frame in the world, ``(N, 4, 4)``.
        modified: Modified (Craig) DH: joint ``i`` moves about ``z`` of frame ``i``.
        prismatic: ``(n,)`` booleans, the prismatic joints.
        sign: ``(n,)`` ``±1``, −1 for a flipped joint.
        moving: How many joints, from the base, move the target (``n`` for the
            TCP; ``k`` for a frame on DH frame ``k``; ``0`` for one fixed in
            the world).
        reference: ``"world-aligned"``, ``"local"`` or ``"world"`` (see the module).

    Returns:
        ``(N, 6, n)``: linear rows (m per rad, or per m) then angular rows.

    Raises:
        ValueError: An unknown ``reference``.
    """
    if reference not in REFERENCES:
        raise ValueError(
            f"unknown reference {reference!r}; references are: {', '.join(REFERENCES)}"
        )
    n = world_T_dh.shape[1] - 1
    first = 1 if modified else 0
    axes = world_T_dh[:, first : first + n]  # the frame each joint moves about
    z = axes[:, :, :3, 2] * sign[None, :, None]  # (N, n, 3)
    origin = axes[:, :, :3, 3]
    p = world_T_target[:, None, :3, 3]
    revolute = ~prismatic
    linear = np.where(revolute[None, :, None], np.cross(z, p - origin), z)
    angular = np.where(revolute[None, :, None], z, 0.0)
    linear[:, moving:] = 0.0
    angular[:, moving:] = 0.0
    jac = np.concatenate([linear, angular], axis=2).transpose(0, 2, 1)  # (N, 6, n)
    return re_express(jac, world_T_target, "world-aligned", reference)


def re_express(jac: Float, world_T_target: Float, source: Reference, target: Reference) -> Float:
    """A Jacobian ``(N, 6, n)`` of a frame, moved from one reference frame to another.

    Args:
        jac: The Jacobian in ``source``.
        world_T_target: The frame it belongs to, ``(N, 4, 4)``.
        source: Its reference frame.
        target: The reference frame wanted.
    """
    if source == target:
        return jac
    R = world_T_target[:, :3, :3]
    p = world_T_target[:, :3, 3]
    lin, ang = jac[:, :3], jac[:, 3:]
    # To world-aligned: the velocity of the frame's origin in world axes.
    if source == "local":
        lin, ang = R @ lin, R @ ang
    elif source == "world":
        lin = lin - np.cross(p[:, :, None], ang, axis=1)
    if target == "local":
        lin, ang = R.transpose(0, 2, 1) @ lin, R.transpose(0, 2, 1) @ ang
    elif target == "world":
        lin = lin + np.cross(p[:, :, None], ang, axis=1)
    return np.concatenate([lin, ang], axis=1)
