"""The bench's peers: other libraries timed on the in-house core's poses.

Each peer is built the way its backend builds it, by the backend's own builder,
so the bench times what the check compares with: Robotics Toolbox
(``DHRobot.fkine`` and the C path ``ETS.eval`` behind it, on the ``DHRobot``
:func:`fkcheck.backends.rtb_dh.dh_robot` builds), Pinocchio
(``forwardKinematics`` + ``updateFramePlacements`` per pose on the model
:class:`fkcheck.backends.pinocchio_dh.PinocchioChain` builds, with only a
``tcp`` frame so no other frame is updated) and yourdfpy (``update_cfg`` +
``get_transform`` per pose, on the model's URDF loaded as the ``yourdfpy-urdf``
backend loads it). What is timed is the library call and nothing else.

A measure raises :class:`ImportError` or
:class:`~fkcheck.backends.base.BackendUnavailable` when its library is missing
and :class:`LookupError` when the model lacks what it needs (no URDF); the
harness reports both as skipped. This module imports no peer library at import time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from fkcheck.bench.timing import LIKE_FOR_LIKE, Timing, max_pos_err, median_seconds
from fkcheck.core import dh
from fkcheck.core.typing import Float
from fkcheck.model.frames import frame_poses_from_dh, relative_pose
from fkcheck.model.types import Model

__all__ = ["PEERS", "Measure", "pinocchio_chain", "pinocchio_model", "rtb_robot"]

#: Times one peer: ``(model, q, in-house poses for q, repeat) -> Timing``.
Measure = Callable[[Model, Float, Float, int], Timing]


def rtb_robot(model: Model) -> Any:
    """A Robotics Toolbox ``DHRobot`` from the model's table, base and tool (``rtb-dh``'s).

    Raises:
        BackendUnavailable: Robotics Toolbox is not installed.
    """
    from fkcheck.backends.rtb_dh import dh_robot

    return dh_robot(model)


def pinocchio_chain(model: Model) -> Any:
    """The ``pinocchio-dh`` backend's ``PinocchioChain`` of the DH chain with only a ``tcp`` frame.

    Raises:
        BackendUnavailable: Pinocchio is not installed.
    """
    from fkcheck.backends.pinocchio_dh import PinocchioChain

    return PinocchioChain(model, tcp_only=True)


def pinocchio_model(model: Model) -> Any:
    """The ``pinocchio-dh`` backend's Pinocchio model of the DH chain with only a ``tcp`` frame.

    Raises:
        BackendUnavailable: Pinocchio is not installed.
    """
    return pinocchio_chain(model).pmodel


def _rtb_eval(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    ets = rtb_robot(model).ets()
    poses = np.asarray(ets.eval(q))
    note = "robot.ets().eval(Q): the fastest RTB path (its C fknm)"
    return _rtb_row("RTB ETS.eval (C batch)", ets.eval, poses, q, ours, repeat, note)


def _rtb_fkine(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    robot = rtb_robot(model)
    poses = np.asarray(robot.fkine(q).A).reshape(-1, 4, 4)
    note = "robot.fkine(Q): an SE3 of N poses"
    return _rtb_row("RTB DHRobot.fkine", robot.fkine, poses, q, ours, repeat, note)


def _rtb_row(
    name: str,
    call: Callable[[Float], object],
    poses: Float,
    q: Float,
    ours: Float,
    repeat: int,
    note: str,
) -> Timing:
    """Time one batched Robotics Toolbox ``call(q)``; ``poses`` is what it returned."""
    seconds = median_seconds(lambda: call(q), repeat)
    return Timing(
        name, "peer", q.shape[0], seconds, max_pos_err(poses, ours), note=note, mode=LIKE_FOR_LIKE
    )


def _pinocchio(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    import pinocchio as pin

    pm = pinocchio_model(model)
    data = pm.createData()
    tcp = pm.getFrameId("tcp")
    rows = list(np.ascontiguousarray(q))
    poses = np.empty((len(rows), 4, 4))

    def loop() -> None:
        for k, row in enumerate(rows):
            pin.forwardKinematics(pm, data, row)
            pin.updateFramePlacements(pm, data)
            poses[k] = data.oMf[tcp].homogeneous

    seconds = median_seconds(loop, repeat)
    return Timing(
        "Pinocchio FK loop",
        "peer",
        len(rows),
        seconds,
        max_pos_err(poses, ours),
        note="forwardKinematics + updateFramePlacements per pose",
        mode="1 thread, loop",
    )


def _yourdfpy(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    from fkcheck.backends.yourdfpy_urdf import _load  # the backend's loader: no meshes
    from fkcheck.description.registry import load_description
    from fkcheck.description.urdf import urdf_info

    if model.urdf is None:
        raise LookupError("the model has no [urdf]")
    robot = _load(urdf_info(load_description(model)))
    frames = (model.check.frame_from, model.check.frame_to)
    twin_from, twin_to = (model.frames[f].urdf for f in frames)
    if twin_from is None or twin_to is None:
        raise LookupError(f"check frames {frames} have no URDF twins")
    names = list(model.urdf.joints)
    rows = q.tolist()
    poses = np.empty((len(rows), 4, 4))

    def loop() -> None:
        for k, row in enumerate(rows):
            robot.update_cfg(dict(zip(names, row, strict=True)))
            poses[k] = robot.get_transform(frame_to=twin_to, frame_from=twin_from)

    seconds = median_seconds(loop, repeat)
    world_T = frame_poses_from_dh(model, dh.fk(model.chain, q, all_frames=True), ours, frames)
    expected = relative_pose(world_T[0], world_T[1])
    return Timing(
        "yourdfpy loop (URDF)",
        "peer",
        len(rows),
        seconds,
        max_pos_err(poses, expected),
        note=f"update_cfg + get_transform({twin_to}, {twin_from}) per pose",
        mode="1 thread, loop",
    )


#: ``(row name, key in PEER_POSES, measure)`` of every peer, in the table's order.
PEERS: list[tuple[str, str, Measure]] = [
    ("RTB ETS.eval (C batch)", "rtb-eval", _rtb_eval),
    ("RTB DHRobot.fkine", "rtb-fkine", _rtb_fkine),
    ("Pinocchio FK loop", "pinocchio", _pinocchio),
    ("yourdfpy loop (URDF)", "yourdfpy", _yourdfpy),
]
