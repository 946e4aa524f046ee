"""Named frames: where they sit on the DH chain, and how any backend's poses map onto them.

A model's ``[frames.NAME]`` tables say, for each name, which DH frame it is
attached to (``0…n``, ``"tcp"`` after the tool, or ``"world"``), a fixed offset
from that DH frame, and the frame's twin in the URDF. ``world`` and ``tcp`` are
always defined. These helpers turn the poses a backend can compute into the
poses of named frames, in one place for every backend.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.base import FrameUnavailable
from fkcheck.errors import FrameError
from fkcheck.model import FrameSpec, Model
from fkcheck.transforms import invert

__all__ = [
    "frame_poses_from_dh",
    "frame_poses_from_tcp",
    "relative_pose",
    "resolve_frame",
]

Float = NDArray[np.float64]


def resolve_frame(model: Model, name: str) -> FrameSpec:
    """The named frame, or :class:`FrameError` listing the model's frames."""
    try:
        return model.frames[name]
    except KeyError:
        raise FrameError(name, f"model {model.name}", model.frames) from None


def frame_poses_from_dh(
    model: Model, world_T_dh: Float, world_T_tcp: Float, frames: Sequence[str]
) -> Float:
    """Named-frame poses from every DH frame (for backends built from the DH table).

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


def frame_poses_from_tcp(model: Model, world_T_tcp: Float, frames: Sequence[str]) -> Float:
    """Named-frame poses from the TCP pose alone (for black-box backends).

    A black box (plugin, external program, another library's packaged model)
    gives only ``world_T_tcp``. Frames rigidly attached to the world (``world``,
    DH frame 0) or to the TCP (``tcp``, DH frame n) follow from it and the
    model's fixed base/tool transforms; mid-chain frames do not.

    Raises:
        FrameUnavailable: A requested frame sits mid-chain.
    """
    N = world_T_tcp.shape[0]
    n = model.dof
    tcp_T_flange = invert(model.tool.matrix)
    out = np.empty((len(frames), N, 4, 4))
    for k, name in enumerate(frames):
        spec = resolve_frame(model, name)
        offset = spec.offset.matrix
        if spec.dh == "world":
            out[k] = offset
        elif spec.dh == 0:
            out[k] = model.base.matrix @ offset
        elif spec.dh == "tcp":
            out[k] = world_T_tcp @ offset
        elif spec.dh == n:
            out[k] = world_T_tcp @ (tcp_T_flange @ offset)
        else:
            raise FrameUnavailable(
                f"frame {name!r} sits at DH frame {spec.dh}, mid-chain; this backend only "
                "gives the TCP pose (frames at DH 0, n, world or tcp can be compared)"
            )
    return out


def relative_pose(root_T_from: Float, root_T_to: Float) -> Float:
    """``from_T_to = (root_T_from)⁻¹ · root_T_to`` for batches ``(..., 4, 4)``."""
    return invert(root_T_from) @ root_T_to
