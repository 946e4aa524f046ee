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
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.typing import JACOBIAN_REFERENCES as REFERENCES
from fkcheck.core.typing import Float
from fkcheck.core.typing import JacobianReference as Reference

__all__ = ["REFERENCES", "Reference", "geometric_jacobian", "re_express"]


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
