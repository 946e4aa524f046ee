"""Named frames: where they sit on the DH chain, and how any backend's poses map onto them.

A model's ``[frames.NAME]`` tables say, for each name, which DH frame it is
attached to (``0…n``, ``"tcp"`` after the tool, or ``"world"``), a fixed offset
from that DH frame, and the frame's twin in the URDF. ``world`` and ``tcp`` are
always defined. These helpers give the *in-house* side of the comparison: the
poses of named frames from the core's DH frames, and the relative pose the engine
compares. Reference backends never use them (each places named frames with its
own library's constructs; see :mod:`fkcheck.backends.base`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from fkcheck.core import dh
from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.model.types import Model, resolve_frame

__all__ = [
    "frame_jacobian",
    "frame_poses_from_dh",
    "relative_pose",
    "resolve_frame",
]


def frame_poses_from_dh(
    model: Model, world_T_dh: Float, world_T_tcp: Float, frames: Sequence[str]
) -> Float:
    """Named-frame poses from the in-house core's DH frames.

    Args:
        model: The model.
        world_T_dh: ``(N, n+1, 4, 4)`` DH frames 0…n in the world (base included).
        world_T_tcp: ``(N, 4, 4)`` the TCP in the world (tool included).
        frames: Named frames to return.

    Returns:
        ``(len(frames), N, 4, 4)`` world_T_frame.
    """
    N = world_T_tcp.shape[0]
    out = np.empty((len(frames), N, 4, 4))
    for k, name in enumerate(frames):
        spec = resolve_frame(model, name)
        if spec.dh == "world":
            anchor: Float = np.broadcast_to(np.eye(4), (N, 4, 4))
        elif spec.dh == "tcp":
            anchor = world_T_tcp
        else:
            anchor = world_T_dh[:, spec.dh]
        out[k] = anchor @ spec.offset.matrix
    return out


def relative_pose(root_T_from: Float, root_T_to: Float) -> Float:
    """``from_T_to = (root_T_from)⁻¹ · root_T_to`` for batches ``(..., 4, 4)``."""
    return invert(root_T_from) @ root_T_to


#: Configurations handed to the core (and to a backend) per call: bounds memory for large runs.
CHUNK = 65_536


def reference_poses(
    model: Model, q: Float, frames: Sequence[str], *, chain: dh.DHChain | None = None
) -> Float:
    """Named-frame poses from the in-house core: ``(len(frames), N, 4, 4)``.

    Runs only the core calls the frames are placed on: every DH frame when one is
    on a DH frame (or none is on the TCP: ``q`` is validated there), the TCP when
    one is on the TCP. The diagnosis calls this thousands of times per failing check.

    Args:
        model: The model: its frames, and its table unless ``chain`` is given.
        q: ``(N, n)`` configurations.
        frames: Named frames to return.
        chain: The table to compute instead of ``model.chain`` (same frames): a
            one-number fit changes one array entry per evaluation, cheaper than a
            new :class:`~fkcheck.model.types.Model` and its chain.
    """

    def fk(chunk: Float, all_frames: bool = False) -> Float:
        if chain is None:
            return model.fk(chunk, all_frames)
        return dh.fk(chain, chunk, all_frames=all_frames)

    anchors = [resolve_frame(model, name).dh for name in frames]
    on_tcp = "tcp" in anchors
    on_dh = any(isinstance(a, int) for a in anchors) or not on_tcp
    out = np.empty((len(frames), q.shape[0], 4, 4))
    for start in range(0, q.shape[0], CHUNK):
        chunk = q[start : start + CHUNK]
        N = chunk.shape[0]
        # A frame not asked for is NaN, never read: frame_poses_from_dh reads only anchors.
        world_T_dh = (
            fk(chunk, all_frames=True)
            if on_dh
            else np.broadcast_to(np.nan, (N, model.dof + 1, 4, 4))
        )
        world_T_tcp = fk(chunk) if on_tcp else np.broadcast_to(np.nan, (N, 4, 4))
        out[:, start : start + CHUNK] = frame_poses_from_dh(model, world_T_dh, world_T_tcp, frames)
    return out


def frame_jacobian(
    model: Model, q: Float, frame: str = "tcp", reference: JacobianReference = "world-aligned"
) -> Float:
    """The in-house geometric Jacobian of a named frame, ``(N, 6, n)``.

    :meth:`Model.jacobian <fkcheck.model.types.Model.jacobian>` for a batch (a
    single ``(n,)`` configuration gives ``(1, 6, n)``). See
    :mod:`fkcheck.core.jacobian` for the formula, the reference frames and the
    paths (numba kernel for large batches, NumPy otherwise).

    Args:
        model: The model.
        q: ``(N, n)`` configurations, radians / metres.
        frame: A named frame (``tcp``, ``tool0``, ``urdf:LINK``…).
        reference: ``"world-aligned"``, ``"local"`` or ``"world"``.
    """
    jac = model.jacobian(q, frame, reference)
    return jac[np.newaxis] if np.ndim(q) == 1 else jac
