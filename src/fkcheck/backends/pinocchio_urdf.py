"""The ``pinocchio-urdf`` backend: the model's reference URDF, parsed by Pinocchio (urdfdom).

The URDF is first resolved and screened by :func:`fkcheck.description.registry.load_description`;
Pinocchio then parses the screened text with ``buildModelFromXML`` (the kinematic
tree only: no geometry model, so no mesh file is ever opened). Each DH joint's
value goes to the Pinocchio joint named in ``[urdf].joints``, unchanged — a DH
``flip`` or ``theta`` offset describes the DH table, not the robot's joint
reading. A ``continuous`` joint is an unbounded revolute joint in Pinocchio,
with ``nq = 2`` holding ``(cos q, sin q)``. Joints the model does not map (the
Panda's fingers) stay at Pinocchio's neutral configuration; ``mimic`` tags are
ignored (Pinocchio's default, ``mimic=False``), which only matters for unmapped
joints.

Poses are ``universe_T_link`` for each named frame's URDF twin (``urdf = …``),
the universe being the URDF's root link. A named frame without a twin (such as
the always-present ``world`` and ``tcp``, unless mapped) raises
:class:`~fkcheck.errors.UnmappedFrameError`: the backend's error, since the URDF
the model declares would go unread.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from fkcheck.backends.pinocchio_dh import INSTALL_HINT, REFERENCE_FRAMES, import_pinocchio
from fkcheck.backends.registry import BackendOptions
from fkcheck.backends.urdf_common import (
    UrdfReader,
    captured_stderr,
    urdf_inputs,
    urdf_unavailable_reason,
)
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import FrameError, UrdfError
from fkcheck.model.types import Model
from fkcheck.urdf.tree import UrdfInfo

__all__ = ["PinocchioUrdf"]


class PinocchioUrdf(UrdfReader):
    """Reference FK from the model's URDF loaded by Pinocchio.

    Attributes:
        name: ``"pinocchio-urdf"``.
        method: The Pinocchio call path used per configuration.
        options: The options the backend was built with.
    """

    name = "pinocchio-urdf"
    #: Declared cost, µs per configuration of a 6-joint arm (the plan: fkcheck.engine.plan).
    pose_cost_us = 10.0
    jacobian_cost_us = 30.0
    distributions = ("pin",)
    method = "buildModelFromXML + framesForwardKinematics (loop)"
    jacobian_method = "computeFrameJacobian (LOCAL_WORLD_ALIGNED | LOCAL | WORLD, loop)"
    imports = ("pinocchio",)

    def __init__(self, arg: str = "", options: BackendOptions | None = None) -> None:
        """Build the backend; ``arg`` is unused (built-in backends take none)."""
        self.options = options or BackendOptions()

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot run: Pinocchio missing, or no ``[urdf]`` in the model."""
        return urdf_unavailable_reason(model, "pinocchio", INSTALL_HINT)

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``root_T_link`` of each frame's URDF twin, ``(len(frames), N, 4, 4)``.

        Raises:
            BackendUnavailable: Pinocchio is not installed or the model has no ``[urdf]``.
            FrameError: A name is not a frame of the model, or Pinocchio's model
                lacks the twin link.
            UnmappedFrameError: A frame has no ``urdf`` twin (the backend's error).
            UrdfError: The URDF is missing, unsafe, does not fit the model, or
                Pinocchio cannot parse it.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        info, q2, twins = urdf_inputs(model, q, frames, self.name)
        pin = import_pinocchio()
        pmodel = _build(pin, info)
        fids = [_frame_id(pin, pmodel, twin, info) for twin in twins]
        q_pin = _pinocchio_q(pin, pmodel, model, info, q2)

        N = q2.shape[0]
        out = np.empty((N, len(fids), 4, 4))
        data = pmodel.createData()
        fk, oMf = pin.framesForwardKinematics, data.oMf
        if len(fids) == 1:
            fid = fids[0]
            for k in range(N):
                fk(pmodel, data, q_pin[k])
                out[k, 0] = oMf[fid].homogeneous
        else:
            for k in range(N):
                fk(pmodel, data, q_pin[k])
                out[k] = [oMf[fid].homogeneous for fid in fids]
        return np.ascontiguousarray(out.transpose(1, 0, 2, 3))

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float:
        """``computeFrameJacobian`` of a frame's URDF twin, ``(N, 6, n)``, root = URDF root.

        The columns are Pinocchio's velocity columns of the URDF joints mapped
        onto the DH joints, in DH order (``idx_v`` of each); ``reference`` maps
        onto ``pin.ReferenceFrame`` as in
        :data:`fkcheck.backends.pinocchio_dh.REFERENCE_FRAMES`.

        Raises:
            The same as :meth:`frame_poses`.
        """
        info, q2, twins = urdf_inputs(model, q, [frame], self.name)
        pin = import_pinocchio()
        pmodel = _build(pin, info)
        fid = _frame_id(pin, pmodel, twins[0], info)
        q_pin = _pinocchio_q(pin, pmodel, model, info, q2)
        assert model.urdf is not None
        columns = [int(pmodel.joints[pmodel.getJointId(j)].idx_v) for j in model.urdf.joints]
        ref = getattr(pin.ReferenceFrame, REFERENCE_FRAMES[reference])
        data = pmodel.createData()
        out = np.empty((q2.shape[0], 6, model.dof))
        for k in range(q2.shape[0]):
            jac = pin.computeFrameJacobian(pmodel, data, q_pin[k], fid, ref)
            out[k] = np.reshape(jac, (6, pmodel.nv))[:, columns]  # (6,) when nv = 1
        return out


def _build(pin: Any, info: UrdfInfo) -> Any:
    """Pinocchio's kinematic model of the screened URDF text.

    urdfdom prints why it refuses a URDF on the process's standard error
    (``Error: … at line … in joint.cpp``) and Pinocchio then raises a generic
    "does not contain a valid URDF model"; the print is captured, and its first
    ``Error:`` line becomes the message. On success, what it printed is dropped.

    Raises:
        UrdfError: urdfdom or Pinocchio refuses the URDF.
    """
    failure: str | None = None
    with captured_stderr() as native:
        try:
            model = pin.buildModelFromXML(info.text)
        except (RuntimeError, ValueError) as exc:
            failure = " ".join(str(exc).split()) or type(exc).__name__
    if failure is None:
        return model
    said = native.first_error()
    reason = f"urdfdom says: {said} ({failure})" if said else failure
    raise UrdfError(info.path, f"Pinocchio cannot build a model from it: {reason}")


def _frame_id(pin: Any, pmodel: Any, link: str, info: UrdfInfo) -> int:
    """The id of the BODY frame Pinocchio made for URDF link ``link``.

    Raises:
        FrameError: Pinocchio has no such body frame (listing the ones it has).
    """
    body = pin.FrameType.BODY
    if not pmodel.existFrame(link, body):
        bodies = [f.name for f in pmodel.frames if f.type == body]
        raise FrameError(link, f"Pinocchio's model of {info.path.name}", bodies)
    return int(pmodel.getFrameId(link, body))


def _pinocchio_q(pin: Any, pmodel: Any, model: Model, info: UrdfInfo, q: Float) -> Float:
    """DH-order joint values ``(N, n)`` as Pinocchio configurations ``(N, nq)``.

    Unmapped joints keep the neutral configuration; a continuous joint (``nq = 2``)
    gets ``(cos q, sin q)``.
    """
    assert model.urdf is not None
    q_pin = np.tile(pin.neutral(pmodel), (q.shape[0], 1))
    for col, urdf_name in enumerate(model.urdf.joints):
        jid = int(pmodel.getJointId(urdf_name))
        if jid >= pmodel.njoints:
            names = [str(pmodel.names[i]) for i in range(1, pmodel.njoints)]
            raise UrdfError(
                info.path,
                f"joint {urdf_name!r} is not a joint of Pinocchio's model; "
                f"its joints are: {', '.join(names)}",
            )
        jmodel = pmodel.joints[jid]
        idx, nq = int(jmodel.idx_q), int(jmodel.nq)
        if nq == 1:
            q_pin[:, idx] = q[:, col]
        elif nq == 2:
            q_pin[:, idx] = np.cos(q[:, col])
            q_pin[:, idx + 1] = np.sin(q[:, col])
        else:
            raise UrdfError(
                info.path,
                f"joint {urdf_name!r} is a {jmodel.shortname()} with nq = {nq} in Pinocchio; "
                "only 1-DOF joints can be mapped onto a DH joint",
            )
    return np.ascontiguousarray(q_pin)
