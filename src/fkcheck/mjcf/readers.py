"""Two readers of an MJCF, as plain functions: MuJoCo's own and Pinocchio's MJCF parser.

Each takes a description read by :func:`fkcheck.mjcf.tree.read_mjcf`, frame
names (a body or a site, or ``world``) and joint values, and returns the
frames' poses in MuJoCo's ``world`` (Pinocchio's ``universe``). Each reads the
screened text (:attr:`~fkcheck.mjcf.tree.MjcfDescription.text`) itself and
nothing else of the description: not fkcheck's tree, not fkcheck's kinematics
(an import contract in pyproject.toml and a test hold this), so each is a
reading independent of fkcheck's — and of each other's but for the screen.

**Joint values** are MuJoCo's ``qpos`` of the hinge and slide joints named by
``joints`` (default: all of them, in MuJoCo's order,
:attr:`~fkcheck.mjcf.tree.MjcfDescription.joints`), radians and metres; a joint
that is not named stays at its ``qpos0`` (its ``ref``). Pinocchio's MJCF parser
takes the same value (it builds ``ref`` into the joint's placement).

* :func:`mujoco_poses`: ``MjSpec.from_string`` and ``compile``, then one
  ``mj_kinematics`` per configuration; poses are ``xpos``/``xmat`` of a body,
  ``site_xpos``/``site_xmat`` of a site.
* :func:`pinocchio_poses`: ``pinocchio.buildModelFromMJCF`` on the screened text,
  written to a private temporary folder (Pinocchio reads MJCF from a file only;
  the text names no other file, so it opens none), then
  ``framesForwardKinematics``; a body is Pinocchio's ``BODY`` frame, a site its
  ``OP_FRAME``. Pinocchio 4.1.0's parser has known bugs that this reader does not
  hide (:mod:`fkcheck.mjcf.compare` names the reader that disagrees): it drops
  the placement of a root body without a joint (pinocchio#2782) and misreads
  ``eulerseq`` with an unnormalised ``axisangle``; its crash on an included
  defaults file cannot happen here, as the screen inlines includes.

A reader that fails raises :class:`ReaderError`, naming itself, its library's
version and the library's message — never the library's own exception.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.core.typing import Float
from fkcheck.errors import FrameError, JointInputError, MjcfError, failure_text, missing_extra
from fkcheck.mjcf.compile import compile_mjcf, mujoco_module, mujoco_names
from fkcheck.mjcf.tree import WORLD, MjcfDescription

__all__ = [
    "READERS",
    "Reader",
    "ReaderError",
    "library_version",
    "mujoco_poses",
    "pinocchio_poses",
]


class ReaderError(Exception):
    """A reader that could not compute what it was asked: a finding about the reader.

    Not an :class:`~fkcheck.errors.FkcheckError` (the input may be right: another
    reader reads it) and not a skip: a check reports the reader as failed.

    Attributes:
        reader: The reader's name (``pinocchio-mjcf``).
        version: Its library's version.
        problem: What went wrong, the library's message included.
    """

    def __init__(self, reader: str, version: str, problem: str) -> None:
        self.reader = reader
        self.version = version
        self.problem = problem
        super().__init__(f"{reader} ({version}) failed: {problem}")


#: A reader: ``(description, frames, q, joints=…) -> (len(frames), N, 4, 4)``.
Reader = Callable[..., Float]


def _pinocchio() -> Any:
    try:
        import pinocchio
    except ImportError as exc:
        missing = missing_extra(exc)
        if missing is None:
            raise
        raise missing from None
    return pinocchio


def library_version(reader: str) -> str:
    """``"MuJoCo 4.0.1"`` or ``"Pinocchio 4.1.0"``: the library behind a reader, and its version.

    Raises:
        MissingExtraError: The library is not installed.
        KeyError: ``reader`` is not one of :data:`READERS`.
    """
    if reader == "mujoco-mjcf":
        return f"MuJoCo {mujoco_module().__version__}"
    if reader == "pinocchio-mjcf":
        return f"Pinocchio {_pinocchio().__version__}"
    raise KeyError(reader)


def _inputs(
    desc: MjcfDescription, frames: Sequence[str], q: ArrayLike, joints: Sequence[str] | None
) -> tuple[Float, list[int], tuple[str, ...]]:
    """``(q as (N, m), the chosen joints' indices in desc.joints, the frames)``, checked."""
    chosen = tuple(desc.joints if joints is None else joints)
    index = []
    for name in chosen:
        if name not in desc.joints:
            raise MjcfError(
                desc.path, f"{name!r} is not a hinge or slide joint; its joints are: "
                f"{', '.join(desc.joints) or '(none)'}"
            )  # fmt: skip
        index.append(desc.joints.index(name))
    if len(set(chosen)) != len(chosen):
        raise MjcfError(desc.path, f"a joint is named twice in {list(chosen)}")
    values = np.asarray(q, dtype=np.float64)
    values = values.reshape(1, -1) if values.ndim == 1 else values
    if values.ndim != 2 or values.shape[1] != len(chosen):
        raise JointInputError(
            f"expected joint values of shape (N, {len(chosen)}) for {list(chosen)}, "
            f"got {np.shape(q)}"
        )
    if not np.isfinite(values).all():
        raise JointInputError("joint values must be finite")
    for frame in frames:
        if frame not in desc.frames:
            raise FrameError(frame, f"MJCF {desc.path.name}", desc.frames)
    return values, index, tuple(frames)


def _full(desc: MjcfDescription, values: Float, index: list[int]) -> Float:
    """Every hinge/slide joint's value per configuration: the given ones, the others at qpos0."""
    full = np.tile(np.asarray(desc.qpos0, dtype=np.float64), (values.shape[0], 1))
    full[:, index] = values
    return full


def mujoco_poses(
    desc: MjcfDescription,
    frames: Sequence[str],
    q: ArrayLike,
    *,
    joints: Sequence[str] | None = None,
) -> Float:
    """The frames' poses as MuJoCo computes them (``mj_kinematics``), in ``world``.

    Args:
        desc: The description (its screened text is what is read).
        frames: Body or site names, or ``world``.
        q: ``(N, m)`` or ``(m,)`` values (MuJoCo's ``qpos``, radians / metres) of
            ``joints``.
        joints: The hinge and slide joints ``q``'s columns are, by name (default:
            ``desc.joints``, MuJoCo's order); the others stay at ``qpos0``.

    Returns:
        ``(len(frames), N, 4, 4)``: ``world_T_frame``.

    Raises:
        FrameError: A frame that is not a named body or site.
        MjcfError: A joint that is not a hinge or slide joint of it.
        JointInputError: ``q`` of the wrong shape or not finite.
        ReaderError: MuJoCo failed on it.
        MissingExtraError: MuJoCo is not installed.
    """
    values, index, names = _inputs(desc, frames, q, joints)
    mujoco = mujoco_module()
    try:
        m = compile_mjcf(desc.text, desc.path)
    except MjcfError as exc:
        raise ReaderError("mujoco-mjcf", library_version("mujoco-mjcf"), exc.problem) from None
    d = mujoco.MjData(m)
    movable = [j for j in range(m.njnt) if int(m.jnt_type[j]) in (2, 3)]
    adr = np.array([m.jnt_qposadr[j] for j in movable], dtype=np.int64)
    bodies = mujoco_names(m, "body", m.nbody)
    sites = mujoco_names(m, "site", m.nsite)
    where = [("body", bodies.index(f)) if f in bodies else ("site", sites.index(f)) for f in names]
    full = _full(desc, values, index)
    out = np.zeros((len(names), values.shape[0], 4, 4))
    out[..., 3, 3] = 1.0
    for n, row in enumerate(full):
        d.qpos[:] = m.qpos0
        d.qpos[adr] = row
        mujoco.mj_kinematics(m, d)
        for f, (kind, i) in enumerate(where):
            xpos, xmat = (d.xpos, d.xmat) if kind == "body" else (d.site_xpos, d.site_xmat)
            out[f, n, :3, :3] = xmat[i].reshape(3, 3)
            out[f, n, :3, 3] = xpos[i]
    return out


def _pinocchio_model(pin: Any, text: str) -> Any:
    """Pinocchio's model of the screened text, read from a file in a private temporary folder."""
    with tempfile.TemporaryDirectory(prefix="fkcheck-mjcf-") as folder:
        file = os.path.join(folder, "model.xml")
        with open(file, "x", encoding="utf-8") as f:
            f.write(text)
        return pin.buildModelFromMJCF(file)


def pinocchio_poses(
    desc: MjcfDescription,
    frames: Sequence[str],
    q: ArrayLike,
    *,
    joints: Sequence[str] | None = None,
) -> Float:
    """The frames' poses as Pinocchio's MJCF parser reads them, in its ``universe`` (``world``).

    Args and returns as :func:`mujoco_poses`.

    Raises:
        FrameError: A frame that is not a named body or site.
        MjcfError: A joint that is not a hinge or slide joint of it.
        JointInputError: ``q`` of the wrong shape or not finite.
        ReaderError: Pinocchio failed to read it, has no such frame or joint,
            or has a ball or free joint (its ``q`` layout is not MuJoCo's).
        MissingExtraError: Pinocchio is not installed.
    """
    values, index, names = _inputs(desc, frames, q, joints)
    pin = _pinocchio()
    version = library_version("pinocchio-mjcf")
    try:
        model = _pinocchio_model(pin, desc.text)
    except Exception as exc:  # Pinocchio's C++ errors reach Python as several types
        raise ReaderError(
            "pinocchio-mjcf", version, f"cannot read it: {failure_text(exc)}"
        ) from None
    columns = _pinocchio_columns(model, desc, version)
    ids: list[int | None] = []
    for frame in names:
        if frame == WORLD:
            ids.append(None)
            continue
        kind = pin.FrameType.BODY if frame in desc.bodies else pin.FrameType.OP_FRAME
        if not model.existFrame(frame, kind):
            raise ReaderError("pinocchio-mjcf", version, f"its model has no frame {frame!r}")
        ids.append(model.getFrameId(frame, kind))
    data = model.createData()
    full = _full(desc, values, index)
    out = np.zeros((len(names), values.shape[0], 4, 4))
    out[..., :, :] = np.eye(4)
    qpin = pin.neutral(model)
    for n, row in enumerate(full):
        qpin[columns] = row
        pin.framesForwardKinematics(model, data, qpin)
        for f, frame_id in enumerate(ids):
            if frame_id is not None:
                out[f, n] = data.oMf[frame_id].homogeneous
    return out


def _pinocchio_columns(model: Any, desc: MjcfDescription, version: str) -> list[int]:
    """Where each of ``desc.joints`` is in Pinocchio's ``q``.

    Raises:
        ReaderError: A joint Pinocchio does not have, one that is not one
            value, or a ball or free joint (MuJoCo's ``qpos`` layout is not Pinocchio's).
    """
    columns = []
    for name in desc.joints:
        if not model.existJointName(name):
            raise ReaderError("pinocchio-mjcf", version, f"its model has no joint {name!r}")
        joint = model.joints[model.getJointId(name)]
        if joint.nq != 1:
            raise ReaderError(
                "pinocchio-mjcf", version, f"joint {name!r} has {joint.nq} values in its model"
            )
        columns.append(joint.idx_q)
    if model.nq != len(columns):
        raise ReaderError(
            "pinocchio-mjcf", version, f"its model has {model.nq} joint values, "
            f"{len(columns)} hinge and slide joints: a ball or free joint is not read"
        )  # fmt: skip
    return columns


#: The readers by the name a check would give them.
READERS: dict[str, Reader] = {"mujoco-mjcf": mujoco_poses, "pinocchio-mjcf": pinocchio_poses}
