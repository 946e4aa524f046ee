"""The ``pinocchio-dh`` backend: a Pinocchio model built by hand from the DH table.

Each DH row becomes one Pinocchio joint that moves about (or along) the z axis
of DH frame ``i-1`` — ``JointModelRZ`` / ``JointModelPZ``, or the ``…Unaligned``
joint with axis ``(0, 0, -1)`` for a flipped joint, so ``q`` reaches Pinocchio
unchanged and the flip lives in the model. Every DH link transform is split
around its joint motion into a fixed part *before* it (which goes into the
joint's placement) and a fixed part *after* it (which goes into the next
joint's placement, and into the operational frame of DH frame ``i``):

=========================  ================================  ==============  ====================
convention, joint type     before the motion                 motion          after the motion
=========================  ================================  ==============  ====================
standard, revolute         ``Rz(θ_off)``                     ``Rz(±q)``      ``Tz(d) Tx(a) Rx(α)``
standard, prismatic        ``Rz(θ) Tz(d_off)``               ``Tz(±q)``      ``Tx(a) Rx(α)``
modified, revolute         ``Rx(α) Tx(a) Rz(θ_off)``         ``Rz(±q)``      ``Tz(d)``
modified, prismatic        ``Rx(α) Tx(a) Rz(θ) Tz(d_off)``   ``Tz(±q)``      identity
=========================  ================================  ==============  ====================

So the placement of joint ``i`` is ``after_{i-1} · before_i`` (with
``after_0`` the model's base), DH frame ``i`` is an operational frame on joint
``i`` placed at ``after_i``, DH frame 0 is an operational frame on the universe
placed at the base, and the TCP is an operational frame on joint ``n`` placed
at ``after_n · tool``. Every named frame (``[frames.NAME]``) is one more
operational frame, on the joint of the DH frame it sits on, placed at that DH
frame's placement times its offset. The base, tool and frame offsets are built
from their ``xyz``/``rpy`` with Pinocchio's own ``rpy.rpyToMatrix`` and ``SE3``,
never taken from fkcheck's matrices or frame helpers.

Pinocchio has no batched FK: :meth:`PinocchioDH.frame_poses` loops in Python
over configurations, calling ``forwardKinematics`` and
``updateFramePlacements`` once each and reading only the frames asked for
(about 2 µs per configuration for the TCP of a UR5 on the project machine).
Pinocchio keeps the GIL during these calls, so threads do not speed it up.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Sequence
from typing import Any

import numpy as np

from fkcheck.backends.base import BackendDefaults, Evidence, Reads, validated_q
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import INSTALL_REFERENCE, BackendUnavailable
from fkcheck.model.types import Joint, Model, Offset, resolve_frame

__all__ = [
    "INSTALL_HINT",
    "REFERENCE_FRAMES",
    "PinocchioChain",
    "PinocchioDH",
    "import_pinocchio",
]


#: The reason given when Pinocchio is not installed (both Pinocchio backends).
INSTALL_HINT = f"pinocchio is not installed ({INSTALL_REFERENCE})"


class PinocchioDH(BackendDefaults):
    """Reference FK from a Pinocchio model assembled from the DH table.

    Attributes:
        name: ``"pinocchio-dh"``.
        method: The Pinocchio call path used per configuration.
        options: The options the backend was built with.
    """

    name = "pinocchio-dh"
    #: Declared cost, µs per configuration of a 6-joint arm (the plan: fkcheck.engine.plan).
    pose_cost_us = 15.0
    jacobian_cost_us = 25.0
    distributions = ("pin",)
    method = "forwardKinematics + updateFramePlacements (loop)"
    jacobian_method = "computeFrameJacobian (LOCAL_WORLD_ALIGNED | LOCAL | WORLD, loop)"
    evidence: Evidence = "implementation"
    reads: Reads = "dh"
    imports = ("pinocchio",)

    def __init__(self, arg: str = "", options: BackendOptions | None = None) -> None:
        """Build the backend; ``arg`` is unused (built-in backends take none)."""
        self.options = options or BackendOptions()

    def unavailable_reason(self, model: Model) -> str | None:
        """``None`` when Pinocchio is importable; every DH model can be built."""
        if importlib.util.find_spec("pinocchio") is None:
            return INSTALL_HINT
        return None

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """World poses of named frames, ``(len(frames), N, 4, 4)``, root = DH world.

        Raises:
            BackendUnavailable: Pinocchio is not installed.
            FrameError: A name is not a frame of the model.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        for name in frames:
            resolve_frame(model, name)
        q2 = validated_q(model, q)
        chain = PinocchioChain(model)
        ids = [chain.named_frame_ids[name] for name in frames]
        return np.moveaxis(chain.poses(q2, ids), 1, 0)

    def dh_frames(self, model: Model, q: Float) -> Float:
        """``world_T_i`` for DH frames ``0…n``: shape ``(N, n+1, 4, 4)``, base included.

        Raises:
            BackendUnavailable: Pinocchio is not installed.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        q2 = validated_q(model, q)
        chain = PinocchioChain(model)
        return chain.poses(q2, chain.dh_frame_ids)

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float:
        """Pinocchio's ``computeFrameJacobian`` of a named frame, ``(N, 6, n)``, root = DH world.

        ``reference`` maps onto ``pin.ReferenceFrame`` by name (see
        :data:`REFERENCE_FRAMES`). One Pinocchio joint per DH joint, in order, so
        the columns are the DH joints' (a flipped joint's axis is reversed in the
        model, so its column already has the flip's sign).

        Raises:
            BackendUnavailable: Pinocchio is not installed.
            FrameError: A name is not a frame of the model.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        spec = resolve_frame(model, frame)
        q2 = validated_q(model, q)
        chain = PinocchioChain(model)
        return chain.jacobians(q2, chain.named_frame_ids[spec.name], reference)


#: fkcheck's reference frames → the names of Pinocchio's ``ReferenceFrame`` values.
REFERENCE_FRAMES = {
    "world": "WORLD",
    "local": "LOCAL",
    "world-aligned": "LOCAL_WORLD_ALIGNED",
}


def import_pinocchio() -> Any:
    """Import and return :mod:`pinocchio`.

    Raises:
        BackendUnavailable: It is not installed or fails to import.
    """
    try:
        import pinocchio
    except ImportError as exc:
        raise BackendUnavailable(f"{INSTALL_HINT}: {exc}") from None
    return pinocchio


class PinocchioChain:
    """One DH table as a Pinocchio model, with operational frames to read poses from.

    fkcheck's one Pinocchio-from-DH builder: the ``pinocchio-dh`` backend and the
    benchmark (:func:`fkcheck.bench.peers.pinocchio_model`) both use it.

    Attributes:
        pin: The imported :mod:`pinocchio`.
        pmodel: The ``pinocchio.Model``.
        data: Its ``pinocchio.Data``.
        dh_frame_ids: Frame ids of DH frames ``0…n`` (empty when ``tcp_only``).
        named_frame_ids: Frame id of each ``[frames.NAME]`` (empty when ``tcp_only``).
        tcp_frame_id: Frame id of the operational frame ``"tcp"`` (``None`` unless
            ``tcp_only``).
    """

    def __init__(self, model: Model, *, tcp_only: bool = False) -> None:
        """Build the model.

        Args:
            model: The DH model.
            tcp_only: Add only one operational frame, ``"tcp"``, at the TCP (what the
                benchmark times: ``updateFramePlacements`` then updates that frame
                alone); otherwise add the DH frames and the named frames.

        Raises:
            BackendUnavailable: Pinocchio is not installed.
        """
        pin = self.pin = import_pinocchio()
        pmodel = pin.Model()
        pmodel.name = model.name
        op = pin.FrameType.OP_FRAME
        modified = model.convention == "modified"
        after = _se3(pin, model.base)
        # (parent joint, placement) of DH frames 0…n.
        anchors = [(0, after)]
        parent = 0
        for joint in model.joints:
            before, joint_model, after_i = _split(pin, joint, modified)
            parent = pmodel.addJoint(parent, joint_model, after * before, joint.name)
            after = after_i
            anchors.append((parent, after))
        tcp_anchor = (parent, after * _se3(pin, model.tool))

        def add_frame(name: str, joint_id: int, placement: Any) -> int:
            return int(pmodel.addFrame(pin.Frame(name, joint_id, placement, op), False))

        self.dh_frame_ids: list[int] = []
        self.named_frame_ids: dict[str, int] = {}
        self.tcp_frame_id: int | None = None
        if tcp_only:
            self.tcp_frame_id = add_frame("tcp", *tcp_anchor)
        else:
            self.dh_frame_ids = [add_frame(f"dh{i}", *anchor) for i, anchor in enumerate(anchors)]
            for name, spec in model.frames.items():
                if spec.dh == "world":
                    joint_id, placement = 0, pin.SE3.Identity()
                elif spec.dh == "tcp":
                    joint_id, placement = tcp_anchor
                else:
                    joint_id, placement = anchors[spec.dh]
                placement = placement * _se3(pin, spec.offset)
                self.named_frame_ids[name] = add_frame(f"named:{name}", joint_id, placement)
        self.pmodel = pmodel
        self.data = pmodel.createData()

    def poses(self, q: Float, frame_ids: Sequence[int]) -> Float:
        """Run FK for every row of ``q`` and read the given frames: ``(N, len(ids), 4, 4)``."""
        N = q.shape[0]
        out = np.empty((N, len(frame_ids), 4, 4))
        if not frame_ids or N == 0:
            return out
        pin, pmodel, data = self.pin, self.pmodel, self.data
        forward, update, oMf = pin.forwardKinematics, pin.updateFramePlacements, data.oMf
        if len(frame_ids) == 1:
            fid = frame_ids[0]
            for k in range(N):
                forward(pmodel, data, q[k])
                update(pmodel, data)
                out[k, 0] = oMf[fid].homogeneous
        else:
            for k in range(N):
                forward(pmodel, data, q[k])
                update(pmodel, data)
                out[k] = [oMf[fid].homogeneous for fid in frame_ids]
        return out

    def jacobians(self, q: Float, frame_id: int, reference: JacobianReference) -> Float:
        """``computeFrameJacobian`` for every row of ``q``: ``(N, 6, nv)``, linear rows first."""
        pin, pmodel, data = self.pin, self.pmodel, self.data
        frame = getattr(pin.ReferenceFrame, REFERENCE_FRAMES[reference])
        out = np.empty((q.shape[0], 6, pmodel.nv))
        for k in range(q.shape[0]):  # a one-joint model's Jacobian comes back as (6,)
            jac = pin.computeFrameJacobian(pmodel, data, q[k], frame_id, frame)
            out[k] = np.reshape(jac, (6, pmodel.nv))
        return out


def _split(pin: Any, joint: Joint, modified: bool) -> tuple[Any, Any, Any]:
    """One DH row as (fixed part before the motion, Pinocchio joint, fixed part after)."""
    zero = np.zeros(3)
    eye = np.eye(3)
    rot_z = pin.SE3(pin.utils.rotate("z", joint.theta), zero)
    tz_d = pin.SE3(eye, np.array([0.0, 0.0, joint.d]))
    tx_a = pin.SE3(eye, np.array([joint.a, 0.0, 0.0]))
    rot_x = pin.SE3(pin.utils.rotate("x", joint.alpha), zero)
    prismatic = joint.type == "prismatic"
    if joint.flip:
        axis = np.array([0.0, 0.0, -1.0])
        joint_model = (
            pin.JointModelPrismaticUnaligned(axis)
            if prismatic
            else pin.JointModelRevoluteUnaligned(axis)
        )
    else:
        joint_model = pin.JointModelPZ() if prismatic else pin.JointModelRZ()
    # Rz(θ) and Tz(d) commute, so a revolute joint's Rz(θ_off)·Rz(q) and a
    # prismatic joint's Tz(d_off)·Tz(q) keep the offset on the fixed side.
    if modified:
        before = rot_x * tx_a * rot_z * (tz_d if prismatic else pin.SE3.Identity())
        after = pin.SE3.Identity() if prismatic else tz_d
    else:
        before = rot_z * tz_d if prismatic else rot_z
        after = tx_a * rot_x if prismatic else tz_d * tx_a * rot_x
    return before, joint_model, after


def _se3(pin: Any, offset: Offset) -> Any:
    """A model's base/tool offset as a Pinocchio SE3, rotation from Pinocchio's rpyToMatrix."""
    rotation = pin.rpy.rpyToMatrix(*(float(v) for v in offset.rpy))
    return pin.SE3(rotation, np.array(offset.xyz, dtype=np.float64))
