"""A URDF's robot tree: read, screened, checked and summarised, and walked (stdlib only).

Every URDF backend parses the URDF with its own parser (urdfdom, lxml, Robotics
Toolbox's reader); :func:`read_urdf` runs first, for all of them and for
``table-from`` and ``diagnose``:

* it reads and screens the document with :mod:`fkcheck.urdf.screen` (regular files
  only, no DTD or entities, no xacro, no includes, size and nesting bounds) and
  hands on only the screened tree re-serialised (:attr:`UrdfInfo.text`): no
  parser ever gets the file's path or bytes;
* it checks the robot's structure, so a broken tree is one clear error before any
  parser (whose own messages are obscure, or whose parse never ends) sees it:
  every link and joint has a name, no name is used twice, a joint has a known
  type and a parent and a child that are links, no link has two parents, the
  joints form no cycle and there is one root link; every number in a URDF
  attribute (origins, axes, limits, inertials, geometry, colours) is a finite
  decimal number, the right count of them, and a moving joint's axis is not zero
  (:mod:`fkcheck.urdf.tree_numbers`);
* it bounds the robot: at most :data:`MAX_URDF_LINKS` links (so as many joints) and
  at most :data:`MAX_URDF_DEPTH` joints from the root link to any link. Chains
  deeper than that exhaust the parsers' recursion: Pinocchio (urdfdom) overflows
  the C stack and kills the process at about 3,700 nested links with an 8 MiB
  stack, Robotics Toolbox's reader and yourdfpy raise RecursionError at 1,024
  and yourdfpy already needs 14 s at 512.

:func:`chain_between` is fkcheck's one walk down a URDF joint chain, for
:meth:`UrdfInfo.chain` and :class:`fkcheck.urdf.chain.UrdfKinematics` alike.
Mesh files are never opened here or by the backends.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, TypeVar

from fkcheck.errors import UrdfError
from fkcheck.urdf.screen import ScreenedUrdf, check_urdf_path, read_urdf_bytes, screen_urdf
from fkcheck.urdf.tree_numbers import MAX_AXIS_LENGTH, MIN_AXIS_LENGTH, at_line, check_numbers

__all__ = [
    "JOINT_TYPES",
    "MAX_AXIS_LENGTH",
    "MAX_URDF_DEPTH",
    "MAX_URDF_LINKS",
    "MIN_AXIS_LENGTH",
    "UrdfInfo",
    "UrdfJoint",
    "chain_between",
    "listed",
    "read_urdf",
    "urdf_info_from_bytes",
]

#: Links in one URDF (joints: at most one fewer). Humanoids have about a hundred.
MAX_URDF_LINKS = 4096
#: Joints between the root link and any link. Serial arms have 10 to 20; see the
#: module docstring for what deeper chains do to the parsers.
MAX_URDF_DEPTH = 256
#: The joint types of the URDF specification (urdfdom refuses any other).
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_ONE_DOF = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class UrdfJoint:
    """One ``<joint>`` of a URDF.

    Attributes:
        name: The joint's name.
        type: ``revolute``, ``continuous``, ``prismatic``, ``fixed``, ``floating`` or ``planar``.
        parent: The parent link.
        child: The child link.
        axis: The ``<axis xyz>`` text as written (screened: three finite numbers),
            ``"1 0 0"`` for an ``<axis>`` without ``xyz``, ``None`` without ``<axis>``.
    """

    name: str
    type: str
    parent: str
    child: str
    axis: str | None = None


class _Edge(Protocol):
    """A joint as the chain walk sees it: a parent link and a child link."""

    @property
    def parent(self) -> str: ...

    @property
    def child(self) -> str: ...


_JointT = TypeVar("_JointT", bound=_Edge)


def chain_between(joints: Mapping[str, _JointT], base: str, tip: str) -> list[_JointT] | None:
    """The joints from link ``base`` down to link ``tip``, in order: fkcheck's one chain walk.

    Climbs from ``tip`` through each link's parent joint until it reaches ``base``.
    Used by :meth:`UrdfInfo.chain` and :class:`fkcheck.urdf.chain.UrdfKinematics`.

    Args:
        joints: Joints by name; each child link has at most one joint (a tree).
        base: The upper link.
        tip: The lower link (``tip == base`` gives ``[]``).

    Returns:
        The joints, ``base``'s child joint first; ``None`` when ``tip`` does not
        hang below ``base`` (or the walk meets a cycle).
    """
    by_child = {j.child: j for j in joints.values()}
    out: list[_JointT] = []
    link = tip
    while link != base:
        joint = by_child.get(link)
        if joint is None or len(out) > len(by_child):  # not below base, or a cycle
            return None
        out.append(joint)
        link = joint.parent
    return out[::-1]


@dataclass(frozen=True)
class UrdfInfo:
    """A screened URDF: where it is, what it holds, where its packages live.

    Attributes:
        path: The URDF file.
        text: The screened document re-serialised (:meth:`ScreenedUrdf.text
            <fkcheck.urdf.screen.ScreenedUrdf.text>`): elements, attributes and
            text only, no DTD, comment or processing instruction. The only form
            in which any parser gets the URDF.
        package_dirs: Directories that contain the ``package://`` packages it names.
        joints: Joints by name.
        links: Link names.
        root: The root link.
        files: Every file it was made of, ``path`` first: a plain URDF is its
            file alone; a xacro file expanded by :func:`fkcheck.urdf.xacro.read_xacro`
            adds each file its expansion read (includes, ``load_yaml`` files). An
            expansion screened again from kept text names the xacro file only.
    """

    path: Path
    text: str
    package_dirs: tuple[Path, ...]
    joints: dict[str, UrdfJoint]
    links: tuple[str, ...]
    root: str
    files: tuple[Path, ...] = ()

    def chain(self, base: str, tip: str) -> list[UrdfJoint]:
        """The joints from link ``base`` down to link ``tip``.

        Raises:
            UrdfError: ``tip`` is not below ``base``.
        """
        chain = chain_between(self.joints, base, tip)
        if chain is None:
            raise UrdfError(self.path, f"no chain connects {base!r} to {tip!r}")
        return chain


def read_urdf(path: Path, package_dirs: tuple[Path, ...] = ()) -> UrdfInfo:
    """Read, screen and summarise a URDF file (no model mapping checks).

    Not kept: a model's description is kept by
    :func:`fkcheck.description.registry.load_description`.

    Raises:
        UrdfError: Missing, not a regular file, too large, not XML, refused by the
            screen (:mod:`fkcheck.urdf.screen`), not a valid tree, or beyond
            :data:`MAX_URDF_LINKS` / :data:`MAX_URDF_DEPTH`.
    """
    check_urdf_path(path)
    return urdf_info_from_bytes(path, read_urdf_bytes(path), package_dirs)


def urdf_info_from_bytes(path: Path, data: bytes, package_dirs: tuple[Path, ...] = ()) -> UrdfInfo:
    """Screen, check and summarise a URDF document already in memory.

    What :func:`read_urdf` does once it has the file's bytes; also the way an
    expanded xacro (:mod:`fkcheck.urdf.xacro`) goes through the same screen.

    Args:
        path: The file the document is, or came from (for messages).
        data: The document's bytes.
        package_dirs: Directories that contain the ``package://`` packages it names.

    Raises:
        UrdfError: Not XML, refused by the screen, not a valid tree, or beyond
            :data:`MAX_URDF_LINKS` / :data:`MAX_URDF_DEPTH`.
    """
    doc = screen_urdf(path, data)
    root = doc.root
    if root.tag != "robot":
        raise UrdfError(path, f"root element is <{root.tag}>, expected <robot>")
    links, joints = _links_and_joints(path, doc)
    check_numbers(path, doc)
    _check_mimics(path, doc, joints)
    return UrdfInfo(
        path=path,
        text=doc.text(),
        package_dirs=package_dirs,
        joints=joints,
        links=tuple(links),
        root=_check_tree(path, links, joints),
        files=(path,),
    )


def listed(names: Iterable[str], limit: int = 20) -> str:
    """Names for a message: the first ``limit``, then how many more."""
    names = list(names)
    shown = ", ".join(names[:limit]) or "(none)"
    return shown + (f", … ({len(names) - limit} more)" if len(names) > limit else "")


def _links(path: Path, doc: ScreenedUrdf, elements: list[ET.Element]) -> dict[str, int]:
    """Each ``<link>``'s line (``0`` if unknown) by name, in file order.

    Raises:
        UrdfError: A link without a name, or a name defined twice.
    """
    links: dict[str, int] = {}
    for el in elements:
        name = el.get("name")
        if not name:
            raise UrdfError(path, f"{at_line(doc, el)}a <link> has no name")
        if name in links:
            raise UrdfError(
                path,
                f"{at_line(doc, el)}link {name!r} is defined twice (first on line {links[name]})",
            )
        links[name] = doc.line(el) or 0
    return links


def _joint_end(
    path: Path, doc: ScreenedUrdf, el: ET.Element, name: str, role: str, links: dict[str, int]
) -> str:
    """The link named by joint ``name``'s ``<parent>`` or ``<child>`` (``role``).

    Raises:
        UrdfError: The element or its ``link`` attribute is missing, or names no link.
    """
    where = at_line(doc, el)
    end = el.find(role)
    link = end.get("link") if end is not None else None
    if not link:
        raise UrdfError(path, f'{where}joint {name!r} has no <{role} link="…">')
    if link not in links:
        raise UrdfError(
            path,
            f"{where}joint {name!r} names {role} link {link!r}, which is not a link; "
            f"links are: {listed(links)}",
        )
    return link


def _links_and_joints(path: Path, doc: ScreenedUrdf) -> tuple[dict[str, int], dict[str, UrdfJoint]]:
    """The ``<link>`` and ``<joint>`` children of ``<robot>``, checked one by one.

    (A ``<joint>`` inside ``<transmission>`` or ``<gazebo>`` is not a joint of
    the robot; urdfdom reads only the robot's own children, as here.)

    Returns:
        ``(links, joints)``: each link's line (``0`` if unknown) by name, in file
        order, and the joints by name.
    """
    elements = doc.root.findall("link")
    joint_elements = doc.root.findall("joint")
    for what, found in (("links", elements), ("joints", joint_elements)):
        if len(found) > MAX_URDF_LINKS:
            raise UrdfError(
                path,
                f"has {len(found)} {what}, more than the {MAX_URDF_LINKS} a URDF may have "
                "(fkcheck's limit)",
            )
    links = _links(path, doc, elements)
    joints: dict[str, UrdfJoint] = {}
    lines: dict[str, int] = {}
    parent_of: dict[str, str] = {}  # child link → the joint that has it as child
    for el in joint_elements:
        where = at_line(doc, el)
        name = el.get("name")
        if not name:
            raise UrdfError(path, f"{where}a <joint> has no name")
        if name in joints:
            raise UrdfError(
                path, f"{where}joint {name!r} is defined twice (first on line {lines[name]})"
            )
        jtype = el.get("type")
        if jtype is None or jtype not in JOINT_TYPES:
            shown = "no type" if jtype is None else f"type {jtype!r}"
            raise UrdfError(
                path,
                f"{where}joint {name!r} has {shown}; URDF joint types are: "
                f"{', '.join(JOINT_TYPES)}",
            )
        parent, child = (
            _joint_end(path, doc, el, name, role, links) for role in ("parent", "child")
        )
        if parent == child:
            raise UrdfError(path, f"{where}joint {name!r} connects link {child!r} to itself")
        if child in parent_of:
            other = joints[parent_of[child]]
            raise UrdfError(
                path,
                f"{where}link {child!r} has two parents: joint {other.name!r} hangs it from "
                f"{other.parent!r} and joint {name!r} from {parent!r}; a URDF is a tree",
            )
        parent_of[child] = name
        axis_el = el.find("axis")
        axis = None if axis_el is None else axis_el.get("xyz", "1 0 0")
        joints[name] = UrdfJoint(name=name, type=jtype, parent=parent, child=child, axis=axis)
        lines[name] = doc.line(el) or 0
    return links, joints


def _check_tree(path: Path, links: dict[str, int], joints: dict[str, UrdfJoint]) -> str:
    """The root link, once the joints are known to form one tree of bounded depth.

    Each link has at most one parent (checked before), so the links not
    reachable from a link without a parent are exactly those on or below a cycle.

    Raises:
        UrdfError: A cycle, no or several root links, or a chain deeper than
            :data:`MAX_URDF_DEPTH`.
    """
    if not links:
        raise UrdfError(path, "has no <link>")
    by_child = {j.child: j for j in joints.values()}
    children: dict[str, list[str]] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j.child)
    roots = [link for link in links if link not in by_child]
    depth = dict.fromkeys(roots, 0)
    todo = list(roots)
    while todo:
        link = todo.pop()
        for child in children.get(link, ()):
            depth[child] = depth[link] + 1
            if depth[child] > MAX_URDF_DEPTH:
                raise UrdfError(
                    path,
                    f"link {child!r} is more than {MAX_URDF_DEPTH} joints below the root link: "
                    f"fkcheck reads URDF chains up to {MAX_URDF_DEPTH} joints deep",
                )
            todo.append(child)
    if len(depth) < len(links):
        link = next(link for link in links if link not in depth)
        seen: dict[str, None] = {}  # ordered
        while link not in seen:  # climb until a link repeats: that is the cycle
            seen[link] = None
            link = by_child[link].parent
        seen_list = list(seen)
        cycle = seen_list[seen_list.index(link) :][::-1]  # each link's parent, then it
        order = {name: i for i, name in enumerate(links)}
        first = min(range(len(cycle)), key=lambda i: order[cycle[i]])  # earliest in the file
        cycle = cycle[first:] + cycle[:first]
        down = [*cycle, cycle[0]]  # parent → child → … → back to the first
        names = listed((repr(by_child[c].name) for c in down[1:]), limit=8)
        if len(down) > 9:  # a long cycle: its start and how it closes
            down = [*down[:8], "…", down[-1]]
        raise UrdfError(path, f"joints {names} form a cycle ({' → '.join(down)}); a URDF is a tree")
    if len(roots) != 1:
        raise UrdfError(path, f"expected one root link, found {len(roots)}: {listed(roots)}")
    return roots[0]


def _check_mimics(path: Path, doc: ScreenedUrdf, joints: dict[str, UrdfJoint]) -> None:
    """Every ``<mimic>`` names a one-DOF joint (revolute, continuous, prismatic) other than its own.

    A mimic naming no joint, one that does not exist or a fixed one passed silently:
    each reader then did what it liked with it (ignored it, or refused the file).
    """
    for el in doc.root.findall("joint"):
        name = el.get("name")
        for mimic in el.findall("mimic"):
            leader = mimic.get("joint")
            where = f"{at_line(doc, mimic)}joint {name!r}: <mimic joint>"
            if not leader:
                raise UrdfError(path, f"{where} names no joint; it must name the joint it follows")
            if leader not in joints:
                raise UrdfError(
                    path,
                    f"{where} is {leader!r}, which is not a joint; joints are: {listed(joints)}",
                )
            if leader == name:
                raise UrdfError(path, f"{where} is the joint itself")
            if joints[leader].type not in _ONE_DOF:
                raise UrdfError(
                    path,
                    f"{where} is {leader!r}, a {joints[leader].type} joint; a mimic follows "
                    f"a {', '.join(_ONE_DOF[:-1])} or {_ONE_DOF[-1]} joint",
                )
