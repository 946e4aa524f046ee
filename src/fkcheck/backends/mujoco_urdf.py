"""The ``mujoco-urdf`` backend: the model's reference URDF, read by MuJoCo's own URDF importer.

A fourth URDF parser, independent of urdfdom (Pinocchio), yourdfpy and Robotics
Toolbox's reader. The URDF is first resolved and screened by
:func:`fkcheck.description.registry.load_description`; ``urdf_common.kinematic_text``
then keeps only its
tree — the ``<robot>`` element, every ``<link>`` *emptied* and every ``<joint>``
as written — and ``mujoco.MjSpec.from_string`` reads that text, which
``MjSpec.compile`` turns into an ``MjModel``. Facts about MuJoCo 4.0 this relies
on, each pinned by a test:

* **Fixed links are fused away by default** (the importer sets
  ``compiler.fusestatic``): the UR5's ``base``, ``base_link``, ``ee_link`` and
  ``tool0`` would vanish. ``spec.compiler.fusestatic = False`` keeps one body
  per link, named after it.
* **No geometry, so no file is opened.** MuJoCo cannot resolve ``package://``
  and would try to open every collision mesh when compiling; no ``<visual>``,
  ``<collision>``, top-level ``<material>`` or ``<mujoco>`` extension (which could
  set compiler options or mesh directories) reaches it, so the model has no
  mesh and no geom.
* **Massless moving bodies are refused** ("mass and inertia of moving bodies
  must be larger than mjMINVAL"), and so is an inertia that breaks the
  triangle inequality. Forward kinematics needs neither: ``<inertial>`` is
  dropped with the rest of the link's content, and ``compiler.boundmass`` /
  ``compiler.boundinertia`` give every body the same small mass and inertia.
  ``mj_kinematics`` does not read masses; ``mj_comPos`` uses them only for the
  point its motion subspaces are expressed at, which ``mj_jacBody`` moves back
  to the body's origin (exact up to round-off).
* The URDF's root link becomes a body at the world origin with identity
  orientation, or is MuJoCo's world body itself when it is named ``world``
  (the UR descriptions): either way, poses are ``root_T_link`` in the URDF's
  root, ``xpos``/``xmat`` of each twin's body after ``mj_kinematics``.
* ``revolute`` and ``continuous`` joints become ``hinge`` joints (continuous:
  unlimited), ``prismatic`` becomes ``slide``; axes are normalised. Values
  beyond ``<limit>`` are used as given: kinematics never clips ``qpos``.
* A ``<mimic joint multiplier offset>`` becomes a joint equality (``mjEQ_JOINT``,
  ``polycoef = (offset, multiplier, 0, 0, 0)``), which only the *dynamics*
  enforce. This backend enforces it for kinematics: an unmapped mimic joint is
  set from its leader (``offset + multiplier · leader``, in dependency order),
  and a DH joint mapped onto a mimic joint is refused
  (:class:`~fkcheck.errors.UrdfError`): its value would not be the robot's.

Each DH joint's value goes to the ``qpos`` (``jnt_qposadr``) of the MuJoCo joint
named in ``[urdf].joints``, unchanged; other joints (the Panda's fingers) stay
at ``qpos0`` unless they mimic one. Poses are computed with one ``mj_kinematics``
per configuration on one ``MjData``: 2–5 µs per UR5 configuration, about half of
``pinocchio-urdf``'s loop, and no slower than MuJoCo 4's ``mujoco.batch.Batch``
(``forward`` to ``mjSTAGE_POS`` on one thread), which also runs collision and
constraint stages and is not in MuJoCo 3. Jacobians come from ``mj_jacBody`` at
the twin body's origin after ``mj_kinematics`` and ``mj_comPos``; the columns of
mapped joints that mimic joints follow get those joints' columns added (chain
rule).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.registry import BackendOptions
from fkcheck.backends.urdf_common import (
    UrdfReader,
    kinematic_text,
    urdf_inputs,
    urdf_unavailable_reason,
)
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import INSTALL_REFERENCE, BackendUnavailable, FrameError, UrdfError
from fkcheck.model.types import Model
from fkcheck.urdf.tree import UrdfInfo

__all__ = ["MujocoUrdf"]


_INSTALL_HINT = f"mujoco is not installed ({INSTALL_REFERENCE})"

#: The mass [kg] and principal inertia [kg·m²] every body gets (the URDF's are dropped).
#: Any value above MuJoCo's mjMINVAL (1e-15) would do: kinematics reads neither.
_BODY_MASS = 1.0
_BODY_INERTIA = 1.0

#: Configurations whose whole ``xpos``/``xmat`` are kept at a time (:meth:`MujocoUrdf.frame_poses`).
_CHUNK = 4096


@dataclass(frozen=True)
class _Follower:
    """An unmapped mimic joint: ``qpos[adr] = qpos0 + offset + multiplier · (leader − leader0)``."""

    adr: int
    dof: int
    leader_adr: int
    leader_dof: int
    offset: float
    multiplier: float


class _Compiled:
    """A URDF compiled by MuJoCo, with the addresses of the model's joints in it."""

    def __init__(self, model: Model, info: UrdfInfo, mj: Any, mjmodel: Any) -> None:
        self.model = model
        self.info = info
        self.mjmodel = mjmodel
        self.bodies = _names(mj, mjmodel, mj.mjtObj.mjOBJ_BODY, mjmodel.nbody)
        joints = _names(mj, mjmodel, mj.mjtObj.mjOBJ_JOINT, mjmodel.njnt)
        assert model.urdf is not None
        ids = []
        for name in model.urdf.joints:
            if name not in joints:
                raise UrdfError(
                    info.path,
                    f"joint {name!r} is not a joint of MuJoCo's model; "
                    f"its joints are: {', '.join(joints)}",
                )
            ids.append(joints.index(name))
        follows = _mimics(mj, mjmodel, info, joints)
        for name, jid in zip(model.urdf.joints, ids, strict=True):
            if jid in follows:
                raise UrdfError(
                    info.path,
                    f"joint {name!r} mimics {joints[follows[jid][0]]!r} in the URDF, so it has "
                    "no value of its own; map the joint it mimics instead",
                )
        self.qposadr: NDArray[np.intp] = np.array(
            [mjmodel.jnt_qposadr[j] for j in ids], dtype=np.intp
        )
        self.dofadr: NDArray[np.intp] = np.array(
            [mjmodel.jnt_dofadr[j] for j in ids], dtype=np.intp
        )
        self.followers = [
            _Follower(
                adr=int(mjmodel.jnt_qposadr[f]),
                dof=int(mjmodel.jnt_dofadr[f]),
                leader_adr=int(mjmodel.jnt_qposadr[lead]),
                leader_dof=int(mjmodel.jnt_dofadr[lead]),
                offset=offset,
                multiplier=multiplier,
            )
            for f, (lead, offset, multiplier) in _in_dependency_order(follows, joints, info)
        ]

    def body_ids(self, links: Sequence[str]) -> list[int]:
        """MuJoCo's body id of each URDF link.

        Raises:
            FrameError: MuJoCo's model has no body of that name.
        """
        ids = []
        for link in links:
            if link not in self.bodies:
                where = f"MuJoCo's model of {self.info.path.name}"
                raise FrameError(link, where, [b for b in self.bodies if b])
            ids.append(self.bodies.index(link))
        return ids

    def qpos(self, q: Float) -> Float:
        """DH-order joint values ``(N, n)`` as MuJoCo ``qpos`` rows ``(N, nq)``."""
        mjmodel = self.mjmodel
        qpos = np.tile(np.asarray(mjmodel.qpos0, dtype=float), (q.shape[0], 1))
        qpos[:, self.qposadr] = q
        qpos0 = mjmodel.qpos0
        for f in self.followers:
            leader = qpos[:, f.leader_adr] - qpos0[f.leader_adr]
            qpos[:, f.adr] = qpos0[f.adr] + f.offset + f.multiplier * leader
        return qpos

    def dof_per_joint(self) -> Float:
        """``∂qvel/∂q``, ``(nv, n)``: 1 at each mapped joint's dof, and what mimic joints add."""
        d = np.zeros((self.mjmodel.nv, len(self.dofadr)))
        d[self.dofadr, np.arange(len(self.dofadr))] = 1.0
        for f in self.followers:
            d[f.dof] = f.multiplier * d[f.leader_dof]
        return d


class MujocoUrdf(UrdfReader):
    """Reference FK from the model's URDF, read and computed by MuJoCo.

    Attributes:
        name: ``"mujoco-urdf"``.
        method: The MuJoCo calls used.
        options: The options the backend was built with.
    """

    name = "mujoco-urdf"
    #: Declared cost, µs per configuration of a 6-joint arm (the plan: fkcheck.engine.plan).
    pose_cost_us = 10.0
    jacobian_cost_us = 25.0
    distributions = ("mujoco-core",)
    method = "MjSpec.from_string (fusestatic off) + mj_kinematics (loop over qpos)"
    isolated = False  # compiled C, a few µs per pose
    imports = ("mujoco",)
    jacobian_method: str | None = "mj_kinematics + mj_comPos + mj_jacBody at the body (loop)"
    jacobian_references: tuple[JacobianReference, ...] = ("world-aligned", "local", "world")

    def __init__(self, arg: str = "", options: BackendOptions | None = None) -> None:
        """Build the backend; ``arg`` is unused (built-in backends take none)."""
        self.options = options or BackendOptions()
        self._built: _Compiled | None = None

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot run: MuJoCo missing, or no ``[urdf]`` in the model."""
        return urdf_unavailable_reason(model, "mujoco", _INSTALL_HINT)

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``root_T_link`` of each frame's URDF twin, ``(len(frames), N, 4, 4)``.

        Raises:
            BackendUnavailable: MuJoCo is not installed or the model has no ``[urdf]``.
            FrameError: A name is not a frame of the model, or MuJoCo's model
                lacks the twin link.
            UnmappedFrameError: A frame has no ``urdf`` twin (the backend's error).
            UrdfError: The URDF is missing, unsafe, or does not fit the model (a
                mapped joint is a mimic joint).
            BackendUnavailable: MuJoCo cannot read a URDF fkcheck's screen accepts
                (a link named ``world`` that is not the root, an axis under 1e-15):
                its limit, not the input's; the other readers answer.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        info, q2, twins = urdf_inputs(model, q, frames, self.name)
        mj = _import_mujoco()
        with _warnings_in_memory(mj):
            built = self._build(mj, model, info)
            ids = built.body_ids(twins)
            qpos = built.qpos(q2)

            N, nbody = q2.shape[0], built.mjmodel.nbody
            out = np.zeros((len(ids), N, 4, 4))
            out[:, :, 3, 3] = 1.0
            # Whole xpos/xmat rows are copied per pose (a memcpy; picking the twins' rows
            # with a fancy index per pose costs several times more) and picked per chunk.
            pos = np.empty((min(N, _CHUNK), nbody, 3))
            rot = np.empty((min(N, _CHUNK), nbody, 9))
            mjmodel = built.mjmodel
            data = mj.MjData(mjmodel)
            kinematics = mj.mj_kinematics
            qpos_view, xpos, xmat = data.qpos, data.xpos, data.xmat  # live views of data's buffers
            for start in range(0, N, _CHUNK):
                stop = min(N, start + _CHUNK)
                for k in range(stop - start):
                    qpos_view[:] = qpos[start + k]
                    kinematics(mjmodel, data)
                    pos[k] = xpos
                    rot[k] = xmat
                n = stop - start
                out[:, start:stop, :3, 3] = pos[:n, ids].transpose(1, 0, 2)
                out[:, start:stop, :3, :3] = (
                    rot[:n, ids].reshape(n, len(ids), 3, 3).transpose(1, 0, 2, 3)
                )
            return out

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float:
        """``mj_jacBody`` of a frame's URDF twin, ``(N, 6, n)``, root = the URDF's root.

        Rows are linear then angular. ``mj_jacBody`` gives the body origin's
        velocity and the body's angular velocity in world (root) axes: that is
        ``"world-aligned"``; ``"local"`` turns both into the body's axes and
        ``"world"`` moves the linear part to the root's origin (``v + p × ω``).
        Columns are the mapped joints' dofs (``jnt_dofadr``), in DH order.

        Raises:
            ValueError: ``reference`` is not one of :attr:`jacobian_references`.
            The same as :meth:`frame_poses`.
        """
        if reference not in self.jacobian_references:
            known = ", ".join(self.jacobian_references)
            raise ValueError(f"unknown reference {reference!r}; references are: {known}")
        info, q2, twins = urdf_inputs(model, q, [frame], self.name)
        mj = _import_mujoco()
        with _warnings_in_memory(mj):
            built = self._build(mj, model, info)
            body = built.body_ids(twins)[0]
            qpos = built.qpos(q2)
            columns = built.dof_per_joint()

            mjmodel = built.mjmodel
            data = mj.MjData(mjmodel)
            N = q2.shape[0]
            jacp = np.zeros((N, 3, mjmodel.nv))
            jacr = np.zeros((N, 3, mjmodel.nv))
            pos = np.empty((N, 3))
            rot = np.empty((N, 9))
            qpos_view, xpos, xmat = data.qpos, data.xpos, data.xmat
            kinematics, com_pos, jac_body = mj.mj_kinematics, mj.mj_comPos, mj.mj_jacBody
            for k in range(N):
                qpos_view[:] = qpos[k]
                kinematics(mjmodel, data)
                com_pos(mjmodel, data)
                jac_body(mjmodel, data, jacp[k], jacr[k], body)
                pos[k] = xpos[body]
                rot[k] = xmat[body]
            v, w = jacp @ columns, jacr @ columns  # (N, 3, n): world-aligned
            if reference == "local":
                Rt = rot.reshape(N, 3, 3).transpose(0, 2, 1)
                v, w = Rt @ v, Rt @ w
            elif reference == "world":
                v = v + np.cross(pos[:, :, None], w, axis=1)
            out: Float = np.concatenate([v, w], axis=1)
            return out

    def _build(self, mj: Any, model: Model, info: UrdfInfo) -> _Compiled:
        built = self._built
        if built is None or built.model is not model or built.info is not info:
            built = self._built = _Compiled(model, info, mj, _compile(mj, info))
        return built


@contextlib.contextmanager
def _warnings_in_memory(mj: Any) -> Iterator[list[str]]:
    """MuJoCo's warnings kept in a list while the block runs, never written to a file.

    Without a handler of its own, MuJoCo appends every warning (a joint whose
    limits are equal, say) to ``MUJOCO_LOG.TXT`` in the working directory: a file
    the run never asked for. The handler is process-wide; the previous one (or
    none) is put back when the block ends.
    """
    said: list[str] = []
    previous = mj.get_mju_user_warning()
    mj.set_mju_user_warning(said.append)
    try:
        yield said
    finally:
        mj.set_mju_user_warning(previous)


def _import_mujoco() -> Any:
    try:
        import mujoco
    except ImportError as exc:
        raise BackendUnavailable(f"{_INSTALL_HINT}: {exc}") from None
    return mujoco


def _compile(mj: Any, info: UrdfInfo) -> Any:
    """MuJoCo's model of the URDF's tree: one body per link, fixed links kept.

    Raises:
        BackendUnavailable: MuJoCo's importer or compiler refuses it (its message, on
            one line): fkcheck's screen accepted the URDF, so this is MuJoCo's limit.
    """
    try:
        spec = mj.MjSpec.from_string(kinematic_text(info, inertials=False))
        spec.compiler.fusestatic = False  # keep fixed links (base, tool0, ...) as bodies
        spec.compiler.boundmass = _BODY_MASS
        spec.compiler.boundinertia = _BODY_INERTIA
        return spec.compile()
    except ValueError as exc:
        said = "; ".join(line.strip() for line in str(exc).splitlines() if line.strip())
        raise BackendUnavailable(
            f"MuJoCo cannot read {info.path.name}: {said or type(exc).__name__}"
        ) from None


def _names(mj: Any, mjmodel: Any, kind: Any, count: int) -> list[str]:
    """The names of MuJoCo's objects of one kind, by id (``""`` for an unnamed one)."""
    return [mj.mj_id2name(mjmodel, kind, i) or "" for i in range(count)]


def _mimics(
    mj: Any, mjmodel: Any, info: UrdfInfo, joints: list[str]
) -> dict[int, tuple[int, float, float]]:
    """MuJoCo's reading of the URDF's ``<mimic>`` tags.

    Returns:
        ``{follower: (leader, offset, multiplier)}``, by MuJoCo joint id.

    Raises:
        UrdfError: A joint equality is not one ``<mimic>`` makes (a polynomial, or no leader).
    """
    follows: dict[int, tuple[int, float, float]] = {}
    for e in range(mjmodel.neq):
        if mjmodel.eq_type[e] != mj.mjtEq.mjEQ_JOINT:
            continue
        follower, leader = int(mjmodel.eq_obj1id[e]), int(mjmodel.eq_obj2id[e])
        coef = np.asarray(mjmodel.eq_data[e, :5], dtype=float)
        if leader < 0 or coef[2:].any():
            raise UrdfError(
                info.path,
                f"MuJoCo made joint {joints[follower]!r} follow a polynomial {coef.tolist()} "
                "of another joint, which is no URDF <mimic>",
            )
        follows[follower] = (leader, float(coef[0]), float(coef[1]))
    return follows


def _in_dependency_order(
    follows: dict[int, tuple[int, float, float]], joints: list[str], info: UrdfInfo
) -> list[tuple[int, tuple[int, float, float]]]:
    """Mimic joints ordered so that each one's leader is set before it.

    Raises:
        UrdfError: Mimic joints follow each other round in a cycle.
    """
    ordered: list[tuple[int, tuple[int, float, float]]] = []
    pending = dict(follows)
    while pending:
        ready = [f for f, (lead, _, _) in pending.items() if lead not in pending]
        if not ready:
            cycle = ", ".join(repr(joints[f]) for f in pending)
            raise UrdfError(info.path, f"mimic joints follow each other in a cycle: {cycle}")
        for f in ready:
            ordered.append((f, pending.pop(f)))
    return ordered
