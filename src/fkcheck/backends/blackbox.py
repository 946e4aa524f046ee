"""Named frames for black-box backends, which give only ``world_T_tcp``.

A black box (a plugin, an external program, another library's packaged model)
gives the pose of the TCP in the world. Frames rigidly attached to the world
(``world``, DH frame 0) or to the TCP (``tcp``, DH frame n) follow from it and
the model's fixed base and tool; mid-chain frames do not.

The fixed transforms are built here from the model's ``xyz``/``rpy`` numbers
with SciPy's rotations (``Rotation.from_euler("xyz", rpy)``: extrinsic x, y, z,
the URDF ``rpy`` convention), never with fkcheck's own rotation helpers: a
reference that borrowed the core's maths would agree with the core's mistakes.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.errors import FrameUnavailable
from fkcheck.model.types import Model, Offset, resolve_frame

__all__ = ["frame_poses_from_tcp", "offset_matrix", "require_tcp_frames"]


def offset_matrix(offset: Offset) -> Float:
    """A model's fixed offset as a 4×4 matrix, rotation by SciPy (URDF rpy: extrinsic xyz)."""
    from scipy.spatial.transform import Rotation

    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("xyz", offset.rpy).as_matrix()
    T[:3, 3] = offset.xyz
    return T


def _inverse(T: Float) -> Float:
    """Inverse of one rigid 4×4 transform (``Rᵀ``, ``-Rᵀp``)."""
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def frame_poses_from_tcp(model: Model, world_T_tcp: Float, frames: Sequence[str]) -> Float:
    """Named-frame poses from the TCP pose alone.

    Args:
        model: The model (its base, tool and frame offsets).
        world_T_tcp: ``(N, 4, 4)`` the black box's TCP poses.
        frames: Names from ``model.frames``.

    Returns:
        ``(len(frames), N, 4, 4)`` ``world_T_frame``.

    Raises:
        FrameError: A name is not a frame of the model.
        FrameUnavailable: A requested frame sits mid-chain.
    """
    N = world_T_tcp.shape[0]
    n = model.dof
    out = np.empty((len(frames), N, 4, 4))
    for k, name in enumerate(frames):
        spec = resolve_frame(model, name)
        offset = offset_matrix(spec.offset)
        if spec.dh == "world":
            out[k] = offset
        elif spec.dh == 0:
            out[k] = offset_matrix(model.base) @ offset
        elif spec.dh == "tcp":
            out[k] = world_T_tcp @ offset
        elif spec.dh == n:
            tcp_T_flange = _inverse(offset_matrix(model.tool))
            out[k] = world_T_tcp @ (tcp_T_flange @ offset)
        else:
            raise FrameUnavailable(
                f"frame {name!r} sits at DH frame {spec.dh}, mid-chain; this backend only "
                "gives the TCP pose (frames at DH 0, n, world or tcp can be compared)"
            )
    return out


def require_tcp_frames(model: Model, frames: Sequence[str]) -> None:
    """Refuse, before a black box is run, any frame it cannot give.

    Raises:
        FrameError: A name is not a frame of the model.
        FrameUnavailable: A requested frame sits mid-chain.
    """
    frame_poses_from_tcp(model, np.empty((0, 4, 4)), frames)
