"""Where the IK check's frames sit on the DH chain, for a solver that works between DH frames.

A library solver such as ur-analytic-ik answers for one frame pair of its own
(UR's DH frame 0, the controller's ``base``, to DH frame 6, ``tool0``). The check
hands every solver the pose between its own named frames; :func:`dh_anchor` says
on which DH frame a named frame sits and by which fixed transform, from the
model's ``[frames.NAME]`` (``world`` sits on DH frame 0 through the inverse base,
``tcp`` on the last through the tool), so a wrapper turns ``from_T_to`` into its
library's pose and refuses, in one line, a pair it cannot express.
"""

from __future__ import annotations

from fkcheck.core.geometry import invert
from fkcheck.core.typing import Float
from fkcheck.model.types import Model, resolve_frame

__all__ = ["dh_anchor", "dh_pose"]


def dh_anchor(model: Model, name: str) -> tuple[int, Float]:
    """The DH frame a named frame is fixed to and ``dh_T_frame``, ``(4, 4)``.

    Raises:
        FrameError: ``name`` is not one of the model's frames.
    """
    spec = resolve_frame(model, name)
    if spec.dh == "world":
        return 0, invert(model.base.matrix) @ spec.offset.matrix
    if spec.dh == "tcp":
        return model.dof, model.tool.matrix @ spec.offset.matrix
    return int(spec.dh), spec.offset.matrix


def dh_pose(model: Model, frame_from: str, frame_to: str, from_T_to: Float) -> Float:
    """``dh0_T_dhn`` (first DH frame to last) from ``from_T_to``.

    Only for a pair whose ``from`` is fixed to DH frame 0 and ``to`` to the last
    (:func:`dh_anchor`); the caller checks that.
    """
    _, dh0_T_from = dh_anchor(model, frame_from)
    _, dhn_T_to = dh_anchor(model, frame_to)
    dh0_T_dhn: Float = dh0_T_from @ from_T_to @ invert(dhn_T_to)
    return dh0_T_dhn
