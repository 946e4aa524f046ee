"""The ``rtb-model:<Name>`` backends: a DH model that Robotics Toolbox ships, as a black box.

``rtb-model:UR5`` runs ``roboticstoolbox.models.DH.UR5()`` — Robotics Toolbox's
*own* table, base and tool, not the model file's — so it checks the table
itself: a transcription error in either table shows up as a difference.
It gives only ``world_T_tcp`` of RTB's model (with RTB's base and tool), so
only frames rigidly attached to the world or to the TCP can be compared
(:func:`~fkcheck.backends.blackbox.frame_poses_from_tcp`); for DH frames 0 and ``n`` that
helper uses *our* base and tool.

The comparison is honest about what differs, including conventions, e.g.
(read in roboticstoolbox-python 1.5.0):

* ``UR5``: ``d1 = 0.089459`` against the 0.089159 of Universal Robots' table
  (every other number is the same), so every TCP pose is 0.3 mm higher;
* ``Panda``: the 0.107 m flange is in ``d7`` and RTB adds a tool
  ``Tz(0.103)·Rz(−45°)``, where our model has ``d7 = 0`` and the flange as its
  tool, so RTB's TCP is our TCP times ``Tz(0.103)·Rz(−45°)``;
* ``Puma560``: the same numbers as our ``puma560`` table.

Joint values are passed unchanged, in the model's joint order.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from fkcheck.backends.base import BackendDefaults, Evidence, Reads, validated_q
from fkcheck.backends.blackbox import frame_poses_from_tcp
from fkcheck.backends.registry import BackendOptions
from fkcheck.backends.rtb_common import (
    RTB_IMPORTS,
    eval_batch,
    import_rtb,
    padded_q,
    rtb_unavailable_reason,
)
from fkcheck.core.typing import Float
from fkcheck.errors import BackendNotFoundError, FkcheckError
from fkcheck.model.types import Model

__all__ = ["RtbModel", "rtb_dh_model_names"]


PREFIX = "rtb-model:"


def rtb_dh_model_names() -> list[str]:
    """The DH models Robotics Toolbox ships (``roboticstoolbox.models.DH.__all__``).

    Imports Robotics Toolbox.

    Raises:
        BackendUnavailable: Robotics Toolbox is not installed.
    """
    import_rtb()
    from roboticstoolbox.models import DH

    return [str(name) for name in DH.__all__]


class RtbModel(BackendDefaults):
    """Reference FK from a DH model shipped with Robotics Toolbox.

    The model name is checked when the backend is built (importing Robotics
    Toolbox, if it is installed): an unknown name raises
    :class:`~fkcheck.errors.BackendNotFoundError` listing the valid ones. A
    case-insensitive match is accepted (``rtb-model:ur5`` is ``UR5``).

    Attributes:
        name: ``"rtb-model:<Name>"``.
        method: The Robotics Toolbox call used.
        options: The options the backend was built with.
        evidence: ``"table"``: a table published elsewhere, not the model's.
    """

    evidence: Evidence = "table"
    distributions = ("roboticstoolbox-python", "spatialmath-python")
    reads: Reads = "published"
    imports = (*RTB_IMPORTS, "scipy.spatial.transform")

    def __init__(self, arg: str, options: BackendOptions | None = None) -> None:
        """Build the backend for RTB's DH model ``arg`` (``"UR5"``).

        Raises:
            BackendNotFoundError: Robotics Toolbox is installed and ships no DH
                model of that name.
        """
        self.options = options or BackendOptions()
        self.model_name = arg.strip()
        if rtb_unavailable_reason() is None:
            self.model_name = _canonical(self.model_name)
        self.name = f"{PREFIX}{self.model_name}"
        self.method = f"roboticstoolbox.models.DH.{self.model_name}().ets().eval (C fknm, batched)"
        self._robot: Any = None

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot run here: only if Robotics Toolbox is missing."""
        return rtb_unavailable_reason()

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """Named-frame poses from RTB's model's ``world_T_tcp``, ``(len(frames), N, 4, 4)``.

        Raises:
            BackendUnavailable: Robotics Toolbox is not installed.
            FkcheckError: RTB's model has a different number or type of joints
                than ``model``.
            FrameError: A name is not a frame of the model.
            FrameUnavailable: A requested frame sits mid-chain.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        q2 = validated_q(model, q)
        robot = self._get_robot()
        _check_joints(self.name, robot, model)
        world_T_tcp = eval_batch(robot.ets(), padded_q(q2, model.dof))
        return frame_poses_from_tcp(model, world_T_tcp, frames)

    def _get_robot(self) -> Any:
        if self._robot is None:
            import_rtb()
            from roboticstoolbox.models import DH

            self._robot = getattr(DH, _canonical(self.model_name))()
        return self._robot


def _canonical(name: str) -> str:
    """RTB's spelling of a DH model name (exact, else a unique case-insensitive match).

    Raises:
        BackendNotFoundError: No such model; the message lists them all.
    """
    names = rtb_dh_model_names()
    if name in names:
        return name
    folded = [n for n in names if n.lower() == name.lower()]
    if len(folded) == 1:
        return folded[0]
    raise BackendNotFoundError(f"{PREFIX}{name}", [f"{PREFIX}{n}" for n in names])


def _check_joints(backend: str, robot: Any, model: Model) -> None:
    """Refuse to compare chains with different joint counts or types."""
    if int(robot.n) != model.dof:
        raise FkcheckError(
            f"{backend}: Robotics Toolbox's {robot.name} has {robot.n} joints but model "
            f"{model.name} has {model.dof}; compare it with a model of the same arm"
        )
    for i, (link, joint) in enumerate(zip(robot.links, model.joints, strict=True)):
        rtb_type = "prismatic" if link.isprismatic else "revolute"
        if rtb_type != joint.type:
            raise FkcheckError(
                f"{backend}: joint {i + 1} is {rtb_type} in Robotics Toolbox's {robot.name} "
                f"but {joint.type} in model {model.name}"
            )
