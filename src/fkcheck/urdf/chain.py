"""A description's kinematic tree: joint origins and axes, and FK along one chain (NumPy only).

:class:`KinematicTree` is format-neutral: links (a URDF's links; an MJCF's
bodies and sites) joined by :class:`JointGeometry` (origin in the parent, axis,
type, limits). Every description format reads its file into one
(:mod:`fkcheck.description`); :func:`urdf_kinematics` is URDF's reading.
(``UrdfKinematics`` is its former name, kept as an alias.)

Reference libraries compute poses for the *check*; this module is for
*geometry*: joint axes as lines (for ``table-from`` and for ``diagnose``'s
axis comparison), which none of the backends expose. URDF's reading builds on the
:class:`~fkcheck.urdf.tree.UrdfInfo` that :func:`fkcheck.urdf.tree.read_urdf`
produced — its checked tree, its screened text (never the raw file) and its one
chain walk — and follows the URDF specification: ``<origin xyz rpy>``
(fixed-axis rpy) places the joint frame in the parent link; a
revolute/continuous joint turns about ``<axis>`` (default ``1 0 0``,
normalised) in that frame, a prismatic joint slides along it; the child link's
frame is the joint frame after the motion. Its poses are
tested against Pinocchio's.
"""

from __future__ import annotations

import collections
import xml.etree.ElementTree as ET
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fkcheck.core.geometry import invert, matrix_from_xyz_rpy
from fkcheck.core.typing import Float
from fkcheck.errors import FrameError, UrdfError, XacroRefused
from fkcheck.model.coverage import Competitor
from fkcheck.model.types import FrameSpec, Model, resolve_frame
from fkcheck.urdf.tree import UrdfInfo, chain_between

__all__ = [
    "MOVABLE",
    "JointGeometry",
    "KinematicTree",
    "UrdfKinematics",
    "axis_rotation",
    "competing_links",
    "read_urdf_file",
    "read_urdf_source",
    "urdf_kinematics",
]


#: Joint types with one degree of freedom; ``fixed`` has none, others are refused.
MOVABLE = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True, eq=False)
class JointGeometry:
    """One joint's geometry (a URDF ``<joint>``, or a joint or fixed attachment of another format).

    Attributes:
        name: Joint name.
        type: ``revolute``, ``continuous``, ``prismatic``, ``fixed`` (or another
            URDF type, refused when it lies on a chain that is used).
        parent: Parent link.
        child: Child link.
        origin: ``parent_T_joint``, the joint frame in the parent link at q = 0 (4×4).
        axis: Unit axis in the joint frame (``(1, 0, 0)`` when the URDF gives none).
        limits: ``(lower, upper)`` from ``<limit>`` for revolute/prismatic joints, else ``None``.
        mimic: The joint this one mimics, or ``None``.
    """

    name: str
    type: str
    parent: str
    child: str
    origin: Float
    axis: Float
    limits: tuple[float, float] | None
    mimic: str | None

    @property
    def movable(self) -> bool:
        """Whether the joint has one degree of freedom."""
        return self.type in MOVABLE


def axis_rotation(axis: Float, angle: float | Float) -> Float:
    """4×4 rotations by ``angle`` (rad) about the unit ``axis`` (Rodrigues).

    Args:
        axis: ``(3,)`` unit axis.
        angle: A scalar, or an array of angles of shape ``S``.

    Returns:
        ``(*S, 4, 4)``: ``cos·I + sin·[axis]× + (1 − cos)·axis·axisᵀ`` in the rotation block.
    """
    x, y, z = axis
    angle = np.asarray(angle, dtype=np.float64)
    c, s = np.cos(angle)[..., None, None], np.sin(angle)[..., None, None]
    skew = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    T = np.zeros((*angle.shape, 4, 4))
    T[..., :3, :3] = c * np.eye(3) + s * skew + (1.0 - c) * np.outer(axis, axis)
    T[..., 3, 3] = 1.0
    return T


@dataclass(frozen=True, eq=False)
class KinematicTree:
    """The joints and links of one description, and FK along a chain of it.

    Attributes:
        path: The description's file.
        name: The robot's name (a URDF's ``<robot name>``, an MJCF's ``<mujoco model>``).
        joints: Joints by name.
        links: Link names (every frame a joint may join), in file order.
        root: The root link.
        kind: The format's name as messages show it (``"URDF"``, ``"MJCF"``).
    """

    path: Path
    name: str
    joints: Mapping[str, JointGeometry]
    links: tuple[str, ...]
    root: str
    kind: str = "URDF"

    def chain(self, base: str, tip: str) -> list[JointGeometry]:
        """The joints from link ``base`` to link ``tip``, in order.

        Usually ``tip`` is below ``base``. ``base`` may also hang off the chain by
        fixed joints (UR's ``base`` under ``base_link``): the path then climbs from
        ``base`` to the common ancestor through those fixed joints, inverted
        (entries named ``<joint>^-1``, parent and child swapped), and goes down to ``tip``.

        Raises:
            FrameError: ``base`` or ``tip`` is not a link.
            UrdfError: No such path, or climbing from ``base`` would cross a movable joint.
        """
        for link in (base, tip):
            if link not in self.links:
                raise FrameError(link, f"{self.kind} {self.path.name}", self.links)
        up_base = self._path_from_root(base)
        up_tip = self._path_from_root(tip)
        shared = 0
        while shared < min(len(up_base), len(up_tip)) and up_base[shared] is up_tip[shared]:
            shared += 1
        if (shared == len(up_tip) and len(up_base) > len(up_tip)) or base == tip:
            raise UrdfError(
                self.path,
                f"link {tip!r} is not below link {base!r}: no chain "
                f"leads from {base!r} down to {tip!r}",
            )
        climb = up_base[shared:][::-1]  # from base up to the common ancestor
        for joint in climb:
            if joint.type != "fixed":
                raise UrdfError(
                    self.path,
                    f"link {tip!r} is not below link {base!r}, and {base!r} is attached to "
                    f"their common ancestor through the movable joint {joint.name!r}: "
                    "choose a base link the tip hangs below",
                )
        inverted = [
            JointGeometry(
                name=f"{j.name}^-1",
                type="fixed",
                parent=j.child,
                child=j.parent,
                origin=invert(j.origin),
                axis=j.axis,
                limits=None,
                mimic=None,
            )
            for j in climb
        ]
        return inverted + up_tip[shared:]

    def rigid(self, link: str) -> dict[str, Float]:
        """The links attached to ``link`` by fixed joints alone, and where they sit.

        A breadth-first walk over fixed joints, up and down the tree. Such links
        keep their pose relative to ``link`` whatever the joints do.

        Returns:
            Link name → ``link_T_other`` (4×4, metres), ``link`` itself excluded,
            nearest (fewest joints away) first.
        """
        if link not in self.links:
            return {}
        around: dict[str, list[tuple[str, Float]]] = {}
        for j in self.joints.values():
            if j.type == "fixed":
                around.setdefault(j.parent, []).append((j.child, j.origin))
                around.setdefault(j.child, []).append((j.parent, invert(j.origin)))
        found: dict[str, Float] = {link: np.eye(4)}
        todo = collections.deque([link])
        while todo:  # breadth first: the nearest links first
            here = todo.popleft()
            for other, here_T_other in around.get(here, ()):
                if other not in found:
                    found[other] = found[here] @ here_T_other
                    todo.append(other)
        del found[link]
        return found

    def _path_from_root(self, link: str) -> list[JointGeometry]:
        """The joints from the root link down to ``link``.

        Raises:
            UrdfError: ``link`` does not hang below the root (a text that did not
                go through :func:`fkcheck.urdf.tree.read_urdf`'s tree check).
        """
        path = chain_between(self.joints, self.root, link)
        if path is None:  # detached, or a cycle
            raise UrdfError(self.path, f"link {link!r} does not hang below the root link")
        return path

    def chain_poses(self, chain: Sequence[JointGeometry], q: Float) -> Float:
        """Poses of every joint frame and child link of ``chain`` in the chain's first parent.

        Args:
            chain: From :meth:`chain`.
            q: ``(N, m)`` values of the chain's movable joints, in chain order
                (radians / metres).

        Returns:
            ``(N, len(chain), 4, 4)``: ``base_T_child`` of each joint (the child
            link's frame, the joint's motion included).

        Raises:
            UrdfError: A joint on the chain is not fixed/revolute/continuous/prismatic.
        """
        q = np.atleast_2d(np.asarray(q, dtype=np.float64))
        movable = self.movable(chain)
        if q.shape[1] != len(movable):
            raise ValueError(f"expected {len(movable)} joint values, got {q.shape[1]}")
        N = q.shape[0]
        out = np.empty((N, len(chain), 4, 4))
        T = np.broadcast_to(np.eye(4), (N, 4, 4))
        col = 0
        for i, joint in enumerate(chain):
            T = T @ joint.origin
            if joint.type != "fixed":
                value = q[:, col]
                col += 1
                if joint.type == "prismatic":
                    step = np.tile(np.eye(4), (N, 1, 1))
                    step[:, :3, 3] = value[:, None] * joint.axis
                else:
                    step = axis_rotation(joint.axis, value)
                T = T @ step
            out[:, i] = T
        return out

    def movable(self, chain: Sequence[JointGeometry]) -> list[JointGeometry]:
        """The joints of ``chain`` that move (all but ``fixed``), in chain order.

        Raises:
            UrdfError: A joint on the chain is not fixed/revolute/continuous/prismatic.
        """
        movable = [j for j in chain if j.type != "fixed"]
        for j in movable:
            if j.type not in MOVABLE:
                raise UrdfError(
                    self.path,
                    f"joint {j.name!r} is {j.type}: only fixed, revolute, continuous and "
                    "prismatic joints can be followed",
                )
        return movable

    def axes_at(self, chain: Sequence[JointGeometry], q: Float) -> tuple[Float, Float]:
        """Each movable joint's axis as a line in the chain's base frame, for one ``q``.

        Returns:
            ``(points, directions)``, each ``(m, 3)``: the joint frame's origin and
            its unit axis direction (for a prismatic joint, the line through the
            joint origin along the sliding direction).
        """
        poses = self.chain_poses(chain, np.asarray(q, dtype=np.float64).reshape(1, -1))[0]
        points, directions = [], []
        parent_T = np.eye(4)
        for i, joint in enumerate(chain):
            joint_T = parent_T @ joint.origin  # the joint frame, before its own motion
            if joint.type != "fixed":
                points.append(joint_T[:3, 3])
                directions.append(joint_T[:3, :3] @ joint.axis)
            parent_T = poses[i]
        return np.array(points).reshape(-1, 3), np.array(directions).reshape(-1, 3)


def _floats(text: str | None, default: tuple[float, ...]) -> tuple[float, ...]:
    """An attribute's numbers, ``default`` when absent.

    :func:`fkcheck.urdf.tree.read_urdf` has checked every numeric attribute
    (the right count of finite decimal numbers), so this only converts.
    """
    return default if text is None else tuple(float(p) for p in text.split(" ") if p)


#: The former name of :class:`KinematicTree` (the type is not URDF's alone).
UrdfKinematics = KinematicTree


def urdf_kinematics(info: UrdfInfo) -> KinematicTree:
    """The kinematic geometry of a URDF read by :func:`fkcheck.urdf.tree.read_urdf`.

    The links, the root, each joint's type, parent and child and the numbers
    come from ``info``, checked there; this adds the geometry: origins, unit
    axes, limits, mimics.

    Raises:
        UrdfError: A moving joint's axis is too short to give a direction (below 1e-12).
    """
    path = info.path
    root = ET.fromstring(info.text)  # fkcheck's own re-serialisation of the screened tree
    joints: dict[str, JointGeometry] = {}
    for el in root.findall("joint"):  # the robot's own: not those in <transmission>
        joint = info.joints[str(el.get("name"))]
        origin_el = el.find("origin")
        xyz, rpy = (
            _floats(None if origin_el is None else origin_el.get(key), (0.0, 0.0, 0.0))
            for key in ("xyz", "rpy")
        )
        axis = np.array(_floats(joint.axis, (1.0, 0.0, 0.0)))
        norm = float(np.linalg.norm(axis))
        if joint.type in MOVABLE and norm < 1e-12:
            raise UrdfError(path, f"joint {joint.name!r} has a zero axis")
        axis = axis / norm if norm > 0 else axis
        limits = None
        limit_el = el.find("limit")
        if joint.type in ("revolute", "prismatic") and limit_el is not None:
            (lo,), (hi,) = (_floats(limit_el.get(key), (0.0,)) for key in ("lower", "upper"))
            limits = (lo, hi) if lo < hi else None  # URDF: lower = upper = 0 means none given
        mimic_el = el.find("mimic")
        joints[joint.name] = JointGeometry(
            name=joint.name,
            type=joint.type,
            parent=joint.parent,
            child=joint.child,
            origin=matrix_from_xyz_rpy(xyz, rpy),
            axis=axis,
            limits=limits,
            mimic=str(mimic_el.get("joint")) if mimic_el is not None else None,
        )
    return KinematicTree(path, str(root.get("name", path.stem)), joints, info.links, info.root)


def read_urdf_source(
    spec: str | Path,
    *,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, Path] | None = None,
) -> UrdfInfo:
    """Resolve and screen a URDF given on the command line; expand it if it is xacro and allowed.

    Args:
        spec: A file path, or ``example-robot-data:<subpath>``.
        xacro_args: Given (even empty): the file may be xacro, expanded with
            these arguments (:func:`fkcheck.urdf.xacro.read_xacro`), as a
            model's ``xacro = true`` does — only if the screen finds xacro in it:
            a plain URDF is read as one, xacro never runs on it; ``None``: a
            xacro file is refused.
        packages: The packages ``$(find …)`` may resolve (with ``xacro_args``).

    Returns:
        The screened URDF, naming every file it was made of (:attr:`UrdfInfo.files`).

    Raises:
        UrdfError: Missing, not a regular file, too large, refused by the screen
            (:mod:`fkcheck.urdf.screen`), its expansion failed, or not a valid URDF tree.
        BackendUnavailable: ``example-robot-data:`` is used but not installed.
    """
    from fkcheck.urdf.locate import locate_urdf
    from fkcheck.urdf.tree import read_urdf

    path, package_dirs = locate_urdf(str(spec))
    try:
        # The one screening every URDF goes through (fkcheck.urdf.screen and the tree checks).
        return read_urdf(path.resolve(), package_dirs)
    except XacroRefused:
        if xacro_args is None:
            raise
        from fkcheck.urdf.xacro import read_xacro

        declared = dict(packages or {})
        dirs = package_dirs + tuple(d.parent for d in declared.values())  # as a model's
        return read_xacro(path.resolve(), xacro_args, declared, dirs)


def read_urdf_file(
    spec: str | Path,
    *,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, Path] | None = None,
) -> tuple[Path, str, KinematicTree]:
    """``(path, screened text, kinematics)`` of :func:`read_urdf_source`'s URDF.

    Raises:
        UrdfError: As :func:`read_urdf_source`.
        BackendUnavailable: ``example-robot-data:`` is used but not installed.
    """
    info = read_urdf_source(spec, xacro_args=xacro_args, packages=packages)
    return info.path, info.text, urdf_kinematics(info)


def competing_links(
    model: Model,
    pair: Sequence[str],
    kin: KinematicTree,
    twin: Callable[[FrameSpec], str | None] = lambda spec: spec.urdf,
) -> dict[str, list[Competitor]]:
    """For each compared frame with a twin in ``kin``, the other links fixed to its link.

    ``twin`` gives a frame's twin in that description (default: its ``urdf`` link).

    Each is placed relative to the frame's DH frame: the frame's offset composed
    with the URDF's fixed joints (:meth:`KinematicTree.rigid`). Which of them is
    the DH frame is a choice (:class:`~fkcheck.model.coverage.Competitor`).
    """
    out: dict[str, list[Competitor]] = {}
    for name in dict.fromkeys(pair):
        spec = resolve_frame(model, name)
        link = twin(spec)
        if link is None:
            continue
        anchor_T_frame = spec.offset.matrix
        out[spec.name] = [
            Competitor(other, anchor_T_frame @ frame_T_link)
            for other, frame_T_link in kin.rigid(link).items()
        ]
    return out
