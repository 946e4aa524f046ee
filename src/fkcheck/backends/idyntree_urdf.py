"""The ``idyntree-urdf`` backend: the model's reference URDF, parsed by iDynTree.

A fourth URDF reader, independent of urdfdom (Pinocchio), yourdfpy and
Robotics Toolbox's: iDynTree's own parser (on libxml2). The URDF is resolved and
screened by :func:`fkcheck.description.registry.load_description`; its ``<visual>``,
``<collision>`` and ``<material>`` elements are removed from the in-memory text
(:func:`fkcheck.backends.urdf_common.kinematic_text`), so no ``package://`` mesh
path is ever resolved or opened; ``ModelLoader.loadReducedModelFromString``
then builds the model with the joints of ``[urdf].joints`` as its only degrees
of freedom, and ``KinDynComputations`` computes its kinematics.

Facts about iDynTree 15.1 this relies on, checked in its headers and in the tests:

* **Fixed links become frames.** The loader keeps a massless link hanging on a
  fixed joint (UR's ``world``, ``base``, ``tool0``, ``ee_link``) as an
  *additional frame* of a link, not as a link; in the reduced model every link
  below an unmapped joint is lumped the same way. Every URDF link is looked up
  by name with ``getFrameIndex``, which finds links and additional frames alike.
* **Joint order.** The reduced model's degrees of freedom come in the order of
  the joints given to it; each DH joint's value still goes to the DOF offset
  iDynTree reports for the URDF joint named in ``[urdf].joints`` (the full
  model's order is a tree traversal: Baxter's arms are not its first DOFs).
* **Unmapped joints** are fixed at 0 in the reduced model (the Panda's fingers).
* **Mimic joints are ignored**: a DH joint mapped onto a ``<mimic>`` joint is
  refused (:class:`~fkcheck.errors.UrdfError`), since iDynTree would move it
  apart from its leader; an unmapped mimic joint sits at 0, which the URDF
  agrees with only when its leader is unmapped and its offset is 0 — a frame
  below one that is not is refused, naming the joint.
* **The root.** ``setFloatingBase`` takes links only; the URDF's root link
  (``world`` on UR's URDFs, an additional frame there) is made the world by
  setting ``world_T_base`` to the inverse of its pose on its link (iDynTree's
  own ``Transform``), with zero base velocity. Poses are ``root_T_link`` for
  each named frame's URDF twin, the root being the URDF's root link.
* **Jacobians** (``getFrameFreeFloatingJacobian``) are floating-base: ``6 + n``
  columns, the first six for the base's twist; they are dropped. Rows are linear
  then angular. ``MIXED_REPRESENTATION`` is Pinocchio's ``LOCAL_WORLD_ALIGNED``,
  ``BODY_FIXED_REPRESENTATION`` its ``LOCAL`` and
  ``INERTIAL_FIXED_REPRESENTATION`` its ``WORLD``.
* **Temporaries.** A chained call on a temporary returns garbage:
  ``kinDyn.getRelativeTransform(a, b).getPosition().toNumPy()`` reads a position
  out of a ``Transform`` already freed. Every iDynTree object is kept in a
  variable before it is read (a test checks this module's source for chains).
* **Importing** ``idyntree.bindings`` where warnings are errors (``-W error``,
  pytest's ``filterwarnings = ["error"]``) kills the process: SWIG's import-time
  ``DeprecationWarning`` raised inside the extension's initialisation is a
  segmentation fault. It is imported through :mod:`fkcheck.backends._idyntree`,
  which silences exactly those warnings.
* The loader reports its complaints on standard error (``[ERROR] …``) and
  returns ``False``; they are captured and the first one becomes the message.

Per configuration: ``setJointPos`` (the base stays as set once), then
``getWorldTransform`` per frame, from a Python loop like ``pinocchio-urdf``'s:
on a UR5 at N = 10,000, 6–11 µs per pose for one frame and about 4 µs more per
further frame, two to three times ``pinocchio-urdf``'s (best of 7, three runs on
a loaded two-core machine).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.registry import BackendOptions
from fkcheck.backends.urdf_common import (
    UrdfReader,
    captured_stderr,
    kinematic_text,
    urdf_inputs,
    urdf_unavailable_reason,
)
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import INSTALL_REFERENCE, BackendUnavailable, FrameError, UrdfError
from fkcheck.model.types import Model
from fkcheck.urdf.tree import UrdfInfo

__all__ = ["INSTALL_HINT", "REPRESENTATIONS", "IdyntreeUrdf"]


INSTALL_HINT = f"idyntree is not installed ({INSTALL_REFERENCE})"

#: fkcheck's Jacobian references → iDynTree's frame velocity representations.
REPRESENTATIONS: dict[JacobianReference, str] = {
    "world-aligned": "MIXED_REPRESENTATION",
    "local": "BODY_FIXED_REPRESENTATION",
    "world": "INERTIAL_FIXED_REPRESENTATION",
}

#: The floating base's six columns, in front of the joints' in a free-floating Jacobian.
_BASE_COLUMNS = 6


@dataclass(frozen=True)
class _Mimic:
    """A ``<mimic>`` tag: the joint follows ``multiplier · leader + offset``."""

    leader: str
    multiplier: float
    offset: float


class IdyntreeUrdf(UrdfReader):
    """Reference FK (and Jacobians) from the model's URDF loaded by iDynTree.

    Attributes:
        name: ``"idyntree-urdf"``.
        method: The iDynTree calls used per configuration.
        options: The options the backend was built with.
    """

    name = "idyntree-urdf"
    #: Declared cost, µs per configuration of a 6-joint arm (the plan: fkcheck.engine.plan).
    pose_cost_us = 25.0
    jacobian_cost_us = 45.0
    distributions = ("idyntree",)
    method = (
        "ModelLoader.loadReducedModelFromString + KinDynComputations.setJointPos "
        "+ getWorldTransform (loop)"
    )
    jacobian_method: str | None = (
        "KinDynComputations.getFrameFreeFloatingJacobian (MIXED | BODY_FIXED | "
        "INERTIAL_FIXED representation, base columns dropped, loop)"
    )
    jacobian_references: tuple[JacobianReference, ...] = ("world-aligned", "local", "world")
    #: ~8 µs per pose (UR5), C++ behind a short Python loop, as pinocchio-urdf: a thread
    #: of the engine's process is enough (yourdfpy's 370 µs of pure Python are not).
    isolated = False
    #: ``idyntree.bindings`` through :mod:`fkcheck.backends._idyntree` first: importing it
    #: directly crashes where warnings are errors; once imported, the second is a look-up
    #: (and names the distribution whose version the reports show).
    imports = ("fkcheck.backends._idyntree", "idyntree.bindings")

    def __init__(self, arg: str = "", options: BackendOptions | None = None) -> None:
        """Build the backend; ``arg`` is unused (built-in backends take none)."""
        self.options = options or BackendOptions()
        self._built: _Chain | None = None

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot run: iDynTree missing, or no ``[urdf]`` in the model."""
        return urdf_unavailable_reason(model, "idyntree", INSTALL_HINT)

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``root_T_link`` of each frame's URDF twin, ``(len(frames), N, 4, 4)``.

        Raises:
            BackendUnavailable: iDynTree is not installed or the model has no ``[urdf]``.
            FrameError: A name is not a frame of the model, or iDynTree's model
                lacks the twin link.
            UnmappedFrameError: A frame has no ``urdf`` twin (the backend's error).
            UrdfError: The URDF is missing, unsafe or does not fit the model,
                a DH joint is mapped onto a mimic joint, or a twin lies below a
                mimic joint iDynTree would misplace.
            BackendUnavailable: iDynTree cannot load a URDF fkcheck's screen accepts
                (a floating joint outside the mapped chain): its limit, not the
                input's; the other readers answer.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        info, q2, twins = urdf_inputs(model, q, frames, self.name)
        chain = self._chain(model, info)
        indices = [chain.frame_index(twin) for twin in twins]
        out = np.empty((len(twins), q2.shape[0], 4, 4))
        kin_dyn, set_joints, vector = chain.kin_dyn, chain.kin_dyn.setJointPos, chain.vector
        for k, row in enumerate(chain.dof_rows(q2)):
            joints = vector(row)
            set_joints(joints)
            for f, index in enumerate(indices):
                world_T_frame = kin_dyn.getWorldTransform(index)
                matrix = world_T_frame.asHomogeneousTransform()
                out[f, k] = matrix.toNumPy()
        return out

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float:
        """``getFrameFreeFloatingJacobian`` of a frame's URDF twin, ``(N, 6, n)``, root = URDF root.

        The six floating-base columns are dropped; the remaining ones are taken
        at the DOF offsets of the URDF joints mapped onto the DH joints, in DH
        order. ``reference`` selects the representation (:data:`REPRESENTATIONS`).

        Raises:
            The same as :meth:`frame_poses`.
        """
        info, q2, twins = urdf_inputs(model, q, [frame], self.name)
        chain = self._chain(model, info)
        index = chain.frame_index(twins[0])
        idt, kin_dyn = chain.idt, chain.kin_dyn
        if not kin_dyn.setFrameVelocityRepresentation(getattr(idt, REPRESENTATIONS[reference])):
            raise RuntimeError(f"iDynTree refused the {REPRESENTATIONS[reference]}")
        columns = _BASE_COLUMNS + chain.columns
        jacobian = idt.MatrixDynSize(6, _BASE_COLUMNS + chain.dofs)
        out = np.empty((q2.shape[0], 6, model.dof))
        for k, row in enumerate(chain.dof_rows(q2)):
            joints = chain.vector(row)
            kin_dyn.setJointPos(joints)
            if not kin_dyn.getFrameFreeFloatingJacobian(index, jacobian):
                raise RuntimeError(f"iDynTree computed no Jacobian for frame {twins[0]!r}")
            full = jacobian.toNumPy()
            out[k] = full[:, columns]
        return out

    def _chain(self, model: Model, info: UrdfInfo) -> _Chain:
        """The URDF as iDynTree's model, loaded once per model and URDF (not per chunk)."""
        built = self._built
        if built is None or built.source is not model or built.info is not info:
            built = self._built = _Chain(model, info)
        return built


class _Chain:
    """The model's URDF as iDynTree's ``KinDynComputations``, its root made the world.

    Attributes:
        source: The fkcheck model it was built for.
        info: That model's screened URDF.
        idt: The ``idyntree.bindings`` module.
        kin_dyn: The ``KinDynComputations``, state set with the root at the identity.
        dofs: iDynTree's number of degrees of freedom (the model's ``n``).
        columns: iDynTree's DOF offset of each DH joint's URDF joint, DH order.
        vector: ``idt.VectorDynSize.FromPython``, for joint values.
    """

    def __init__(self, model: Model, info: UrdfInfo) -> None:
        assert model.urdf is not None  # urdf_inputs refuses a model without one
        self.source = model
        self.info = info
        self.idt = idt = _import_idyntree()
        text = kinematic_text(info)
        self.mimics = _mimics(text)
        self.mapped = tuple(model.urdf.joints)
        for name in self.mapped:
            mimic = self.mimics.get(name)
            if mimic is not None:
                raise UrdfError(
                    info.path,
                    f"joint {name!r} mimics {mimic.leader!r} in the URDF, which iDynTree "
                    "ignores (it would move the joint apart from its leader); map the joint "
                    "it mimics instead",
                )
        # loader.model() is a reference into the loader: the loader must outlive it.
        self.loader = _load(idt, info, text, list(self.mapped))
        self.model = self.loader.model()
        self.frames = [self.model.getFrameName(i) for i in range(self.model.getNrOfFrames())]
        self.dofs = int(self.model.getNrOfDOFs())
        self.columns = _columns(self.model, info, self.mapped)
        self.kin_dyn = _kin_dyn(idt, self.model, info, self.dofs)
        self.vector = idt.VectorDynSize.FromPython

    def frame_index(self, link: str) -> int:
        """The frame index iDynTree gives URDF link ``link`` (a link or an additional frame).

        Raises:
            FrameError: iDynTree's model has no frame of that name.
            UrdfError: A mimic joint iDynTree leaves at 0 while the URDF does
                not lies between the root and ``link``.
        """
        if link not in self.frames:
            raise FrameError(link, f"iDynTree's model of {self.info.path.name}", self.frames)
        for joint in self.info.chain(self.info.root, link):
            mimic = self.mimics.get(joint.name)
            if mimic is not None and not self._at_zero(joint.name):
                raise UrdfError(
                    self.info.path,
                    f"link {link!r} lies below joint {joint.name!r}, which mimics "
                    f"{mimic.leader!r} (× {mimic.multiplier:g} + {mimic.offset:g}); iDynTree "
                    "ignores <mimic> and leaves the joint at 0, where the URDF does not",
                )
        return int(self.model.getFrameIndex(link))

    def _at_zero(self, joint: str, depth: int = 0) -> bool:
        """Whether the URDF puts unmapped ``joint`` at 0 when every unmapped leader is at 0."""
        if joint in self.mapped:
            return False
        mimic = self.mimics.get(joint)
        if mimic is None:
            return True
        if mimic.offset != 0.0 or depth > len(self.mimics):  # a cycle is not at rest either
            return False
        return mimic.multiplier == 0.0 or self._at_zero(mimic.leader, depth + 1)

    def dof_rows(self, q: Float) -> list[list[float]]:
        """DH-order joint values ``(N, n)`` as rows of iDynTree joint positions."""
        s = np.zeros((q.shape[0], self.dofs))
        s[:, self.columns] = q
        rows: list[list[float]] = s.tolist()
        return rows


def _import_idyntree() -> Any:
    """``idyntree.bindings``, or :class:`BackendUnavailable` with the install command.

    Imported through :mod:`fkcheck.backends._idyntree`, which keeps SWIG's
    import-time warnings from crashing a process whose warnings are errors.
    """
    try:
        from fkcheck.backends._idyntree import bindings
    except ImportError as exc:
        raise BackendUnavailable(f"{INSTALL_HINT}: {exc}") from None
    return bindings


def _mimics(text: str) -> dict[str, _Mimic]:
    """The URDF's ``<mimic>`` tags, by follower joint."""
    found: dict[str, _Mimic] = {}
    for joint in ET.fromstring(text).iter("joint"):
        tag = joint.find("mimic")
        if tag is not None:
            found[joint.get("name", "")] = _Mimic(
                tag.get("joint", ""),
                float(tag.get("multiplier", "1")),
                float(tag.get("offset", "0")),
            )
    return found


def _load(idt: Any, info: UrdfInfo, text: str, joints: list[str]) -> Any:
    """The ``ModelLoader`` holding iDynTree's model of the URDF, ``joints`` its only DOFs.

    Its ``model()`` is a reference into the loader, valid only while the loader lives.

    Raises:
        BackendUnavailable: The loader refuses the URDF (its first ``[ERROR]`` line is
            the reason): fkcheck's screen accepted it, so this is iDynTree's limit.
    """
    loader = idt.ModelLoader()
    with captured_stderr() as native:
        ok = loader.loadReducedModelFromString(text, joints)
    if not ok:
        errors = [ln.strip() for ln in native.text.splitlines() if "[ERROR]" in ln]
        said = errors[0].removeprefix("[ERROR]").strip() if errors else "no reason given"
        raise BackendUnavailable(f"iDynTree cannot load {info.path.name}: {said}")
    return loader


def _columns(imodel: Any, info: UrdfInfo, joints: Sequence[str]) -> NDArray[np.intp]:
    """The DOF offset iDynTree gives each mapped URDF joint, in DH order.

    Raises:
        UrdfError: A mapped joint is not a one-DOF joint of iDynTree's model.
    """
    columns = []
    for name in joints:
        index = int(imodel.getJointIndex(name))
        joint = imodel.getJoint(index) if index >= 0 else None
        if joint is None or int(joint.getNrOfDOFs()) != 1:
            raise UrdfError(info.path, f"joint {name!r} is not a one-DOF joint in iDynTree's model")
        columns.append(int(joint.getDOFsOffset()))
    return np.array(columns, dtype=np.intp)


def _kin_dyn(idt: Any, imodel: Any, info: UrdfInfo, dofs: int) -> Any:
    """``KinDynComputations`` of ``imodel`` with the URDF's root link as the world.

    The floating base is the link carrying the root (the root itself when
    iDynTree kept it as a link); ``world_T_base`` is the inverse of the root's
    pose on that link, so the root sits at the identity. Base velocity, joint
    velocities and gravity are zero.

    Raises:
        UrdfError: iDynTree's model lacks the root, or refuses the state.
    """
    root = imodel.getFrameIndex(info.root) if imodel.isFrameNameUsed(info.root) else -1
    if root < 0:
        raise UrdfError(info.path, f"iDynTree's model has no frame for the root {info.root!r}")
    link = imodel.getFrameLink(root)
    link_T_root = imodel.getFrameTransform(root)
    world_T_base = link_T_root.inverse()
    kin_dyn = idt.KinDynComputations()
    zeros = idt.VectorDynSize(dofs)
    zeros.zero()
    gravity = idt.Vector3()
    gravity.zero()
    ok = (
        kin_dyn.loadRobotModel(imodel)
        and kin_dyn.setFloatingBase(imodel.getLinkName(link))
        and kin_dyn.setRobotState(world_T_base, zeros, idt.Twist.Zero(), zeros, gravity)
    )
    if not ok:
        raise UrdfError(info.path, "iDynTree's KinDynComputations refused the model")
    return kin_dyn
