"""An MJCF read into fkcheck's kinematic tree: MuJoCo's reading of it, as links and joints.

:func:`read_mjcf` screens the file (:mod:`fkcheck.mjcf.screen`), compiles the
screened text with MuJoCo (:mod:`fkcheck.mjcf.compile`) and turns the compiled
``mjModel`` into the tree fkcheck already follows for URDFs
(:class:`~fkcheck.urdf.chain.UrdfKinematics`, :class:`~fkcheck.urdf.chain.JointGeometry`).
The tree is **MuJoCo's reading** of the MJCF: every MJCF rule (default classes,
angle units, ``eulerseq``, the orientation forms, ``<frame>``, ``ref``) is
applied by MuJoCo's compiler, not by fkcheck. What fkcheck adds is the mapping:

* **Links** are MuJoCo's bodies and sites. MuJoCo's ``world`` body is the root
  link, named ``world``. A site is a link fixed to its body (a joint named
  ``site:<name>``). An unnamed body is ``(body <id>)``; unnamed sites are left out.
* **Joints**: ``hinge`` → ``revolute`` when it is limited (its ``range``, in
  radians), else ``continuous``; ``slide`` → ``prismatic``; a body without a
  joint hangs from its parent by a ``fixed`` joint named ``<body>:fixed``;
  ``ball`` and ``free`` joints are kept as types ``ball`` and ``floating``,
  which no chain can follow (:meth:`~fkcheck.urdf.chain.UrdfKinematics.movable`
  refuses them).
* **The joint value is MuJoCo's** ``qpos``. A joint's ``ref`` is the ``qpos`` at
  which the body sits where the MJCF places it (``qpos0``): at ``qpos`` the
  hinge has turned by ``qpos − ref`` from there (a slide has moved by
  ``qpos − ref`` along its axis). The tree builds this in: the joint's origin is
  the body's placement turned by ``−ref`` about the axis (moved by ``−ref``
  along it), so the tree at ``q`` is MuJoCo's body at ``qpos = q``.
* **A joint's anchor** (``pos``, in the body's frame) is where a hinge turns
  about; the body's frame is elsewhere when it is not zero. The joint frame
  then sits at the anchor, and an **intermediate link** named
  ``<body>:<joint>`` is the child of the joint, with the body hung from it by a
  fixed joint named ``<joint>:body`` (``origin`` a shift by ``−pos``). A slide's
  ``pos`` moves nothing, and is not used. Several joints in one body follow
  each other, each about its own anchor, as MuJoCo composes them: the joints
  are chained through intermediate links ``<body>:<joint>``.

Frame names (:attr:`MjcfDescription.frames`) are ``world``, the named bodies and
the named sites: what a model's ``[frames.X] mjcf =`` may name.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.errors import MjcfError
from fkcheck.mjcf.compile import compile_mjcf, mujoco_names
from fkcheck.mjcf.screen import ScreenedMjcf, screen_mjcf
from fkcheck.urdf.chain import JointGeometry, UrdfKinematics, axis_rotation

__all__ = [
    "WORLD",
    "MjcfDescription",
    "kinematics_from_mjmodel",
    "matrix_from_quat",
    "read_mjcf",
]

#: MuJoCo's world body: the root link of every MJCF tree, and a frame name.
WORLD = "world"

#: MuJoCo's joint types (``mjtJoint``) as the tree names them.
_TYPES = {0: "floating", 1: "ball", 2: "prismatic", 3: "revolute"}


@dataclass(frozen=True, eq=False)
class MjcfDescription:
    """An MJCF, screened and read.

    Attributes:
        path: The main MJCF file, resolved.
        text: The screened text: what every reader is given.
        files: Every file it was made of: the main file, then its includes.
        kinematics: The tree, MuJoCo's reading of it (module docstring).
        joints: The hinge and slide joints in MuJoCo's order (their ``qpos``
            order): the order of a reader's joint values unless told otherwise.
        bodies: The named bodies, ``world`` first, in MuJoCo's order.
        sites: The named sites, in MuJoCo's order.
        qpos0: Each joint of :attr:`joints`'s ``qpos0`` (its ``ref``): where the
            readers hold a joint that is not given a value.
    """

    path: Path
    text: str
    files: tuple[Path, ...]
    kinematics: UrdfKinematics
    joints: tuple[str, ...]
    bodies: tuple[str, ...]
    sites: tuple[str, ...]
    qpos0: tuple[float, ...]

    @property
    def frames(self) -> tuple[str, ...]:
        """The frame names a reader computes: the named bodies (``world`` first), then the sites."""
        return self.bodies + self.sites


def matrix_from_quat(quat: Sequence[float] | Float) -> Float:
    """The 3×3 rotation of a quaternion ``w x y z`` (MuJoCo's order), normalised first."""
    w, x, y, z = np.asarray(quat, dtype=np.float64) / np.linalg.norm(quat)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _pose(pos: Float, quat: Float) -> Float:
    T = np.eye(4)
    T[:3, :3] = matrix_from_quat(quat)
    T[:3, 3] = pos
    return T


def _shift(v: Float) -> Float:
    T = np.eye(4)
    T[:3, 3] = v
    return T


def _fixed(name: str, parent: str, child: str, origin: Float) -> JointGeometry:
    return JointGeometry(name, "fixed", parent, child, origin, np.array([1.0, 0, 0]), None, None)


class _Builder:
    """Links and joints of the tree, added body by body."""

    def __init__(self, path: Path, m: Any) -> None:
        self.path = path
        self.m = m
        self.joints: dict[str, JointGeometry] = {}
        self.links: list[str] = [WORLD]
        bodies = mujoco_names(m, "body", m.nbody)
        self.bodies = [WORLD] + [name or f"(body {i})" for i, name in enumerate(bodies) if i]
        self.joint_names = [
            name or f"(joint {i})" for i, name in enumerate(mujoco_names(m, "joint", m.njnt))
        ]

    def link(self, name: str) -> str:
        if name in self.links:
            raise MjcfError(
                self.path, f"{name!r} names two frames (a body, a site or a joint's "
                "intermediate frame): fkcheck needs each body and site named once"
            )  # fmt: skip
        self.links.append(name)
        return name

    def joint(self, joint: JointGeometry) -> None:
        if joint.name in self.joints:
            raise MjcfError(self.path, f"joint name {joint.name!r} is used twice")
        self.joints[joint.name] = joint

    def body(self, i: int) -> None:
        """Add body ``i`` and the joints that carry it."""
        m = self.m
        body = self.bodies[i]
        parent = self.bodies[int(m.body_parentid[i])]
        placed = _pose(m.body_pos[i], m.body_quat[i])  # parent_T_body at qpos0
        first, count = int(m.body_jntadr[i]), int(m.body_jntnum[i])
        if count == 0:
            self.joint(_fixed(f"{body}:fixed", parent, self.link(body), placed))
            return
        previous_anchor = np.zeros(3)
        origin_before = placed  # what comes before the next joint's anchor
        for k, j in enumerate(range(first, first + count)):
            name = self.joint_names[j]
            kind = _TYPES[int(m.jnt_type[j])]
            axis = np.array(m.jnt_axis[j], dtype=np.float64)
            anchor = np.array(m.jnt_pos[j], dtype=np.float64) if kind == "revolute" else np.zeros(3)
            ref = float(m.qpos0[m.jnt_qposadr[j]]) if kind in ("revolute", "prismatic") else 0.0
            origin = origin_before @ _shift(anchor - previous_anchor)
            if kind == "revolute":
                origin = origin @ axis_rotation(axis, -ref)
            elif kind == "prismatic":
                origin = origin @ _shift(-ref * axis)
            last = k == count - 1
            child = body if last and not anchor.any() else f"{body}:{name}"
            limits = None
            if kind in ("revolute", "prismatic") and bool(m.jnt_limited[j]):
                limits = (float(m.jnt_range[j][0]), float(m.jnt_range[j][1]))
            elif kind == "revolute":
                kind = "continuous"
            self.joint(
                JointGeometry(name, kind, parent, self.link(child), origin, axis, limits, None)
            )
            parent, previous_anchor, origin_before = child, anchor, np.eye(4)
        if parent != body:
            self.joint(_fixed(f"{self.joint_names[first + count - 1]}:body", parent,
                              self.link(body), _shift(-previous_anchor)))  # fmt: skip

    def sites(self) -> list[str]:
        m = self.m
        named = []
        for s, name in enumerate(mujoco_names(m, "site", m.nsite)):
            if not name:
                continue
            body = self.bodies[int(m.site_bodyid[s])]
            origin = _pose(m.site_pos[s], m.site_quat[s])
            self.joint(_fixed(f"site:{name}", body, self.link(name), origin))
            named.append(name)
        return named


def kinematics_from_mjmodel(path: Path, m: Any) -> tuple[UrdfKinematics, list[str], list[str]]:
    """The tree of a compiled ``mjModel`` (module docstring), with its named bodies and sites.

    Raises:
        MjcfError: A name used by two frames, or by two joints.
    """
    builder = _Builder(path, m)
    for i in range(1, m.nbody):  # parents come before their children in MuJoCo's order
        builder.body(i)
    sites = builder.sites()
    name = bytes(m.names).split(b"\0", 1)[0].decode("utf-8", "replace") or path.stem
    kin = UrdfKinematics(path, name, builder.joints, tuple(builder.links), WORLD)
    bodies = [b for b in builder.bodies if not b.startswith("(body ")]
    return kin, bodies, sites


def read_mjcf(path: Path | str, *, root: Path | str | None = None) -> MjcfDescription:
    """Screen an MJCF, compile it with MuJoCo and read its kinematic tree.

    Args:
        path: The main MJCF file.
        root: The folder its ``<include>`` elements are held to (default: the
            file's own folder), e.g. the folder of the model file naming it.

    Returns:
        The description: screened text, files, tree, joints and frame names.

    Raises:
        MjcfError: The screen refuses it (:func:`fkcheck.mjcf.screen.screen_mjcf`),
            MuJoCo cannot compile it, or a name is used twice.
        MissingExtraError: MuJoCo is not installed.
    """
    screened: ScreenedMjcf = screen_mjcf(path, root=root)
    m = compile_mjcf(screened.text, screened.path)
    kin, bodies, sites = kinematics_from_mjmodel(screened.path, m)
    movable = [j for j in range(m.njnt) if int(m.jnt_type[j]) in (2, 3)]
    names = mujoco_names(m, "joint", m.njnt)
    return MjcfDescription(
        path=screened.path,
        text=screened.text,
        files=screened.files,
        kinematics=kin,
        joints=tuple(names[j] or f"(joint {j})" for j in movable),
        bodies=tuple(bodies),
        sites=tuple(sites),
        qpos0=tuple(float(m.qpos0[m.jnt_qposadr[j]]) for j in movable),
    )
