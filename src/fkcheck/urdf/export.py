"""A URDF from a DH model: one link per DH frame, one joint per DH row, fixed named frames.

Layout (link names are what the companion model maps frames to):

* root link ``world``; a fixed joint places ``dh_frame_0`` at ``[base]``;
* modified DH, row *i*: ``A = Rx(α)·Tx(a)·Rz(θ+q)·Tz(d) = [Rx(α)·Tx(a)·Rz(θ)·Tz(d)]·Rz(q)``
  — one joint from ``dh_frame_{i-1}`` to ``dh_frame_i`` whose origin is the bracket;
* standard DH, row *i*: ``A = Rz(θ+q)·Tz(d)·Tx(a)·Rx(α)``: the motion comes first, so a
  joint with origin ``Tz(d)·Rz(θ)`` moves link ``dh_joint_{i}``, and a fixed joint
  ``Tx(a)·Rx(α)`` carries ``dh_frame_i``;
* a prismatic row slides along the same z (``Tz`` commutes with ``Rz``); a flipped
  joint has axis ``0 0 -1``;
* the TCP is link ``tcp`` (``[tool]`` from the last DH frame) and every other named
  frame is a link fixed to its DH frame (or to ``world``/``tcp``) by its offset;
* ``<robot>`` opens with fkcheck's mark (:mod:`fkcheck.urdf.marker`), an element
  that names the model and its table's fingerprint: the check never counts this
  URDF as evidence for that table (:mod:`fkcheck.urdf.provenance`).

Joints with limits are ``revolute``/``prismatic`` with those limits; a revolute
joint without limits is ``continuous``; a prismatic joint without limits gets
±1 m (the range fkcheck samples it over). ``effort`` and ``velocity`` are
required by URDF readers but unknown to a DH table: they are written as 0.
No inertia, no geometry — this is a kinematic description.

The document is always well-formed XML: a name holding a character XML 1.0
cannot carry (NUL and the other control characters but tab and newline) is
refused with the field that holds it, since renaming it silently would break
the mapping from the model to the URDF.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, replace

from fkcheck.core.geometry import rot_x, rot_z, translation
from fkcheck.errors import ModelError
from fkcheck.io.text import unsafe_xml_character
from fkcheck.model.offsets import offset_from_matrix
from fkcheck.model.sampling import UNLIMITED_PRISMATIC_M
from fkcheck.model.types import FrameSpec, Joint, Model, Offset, UrdfSpec
from fkcheck.model.write import toml_number
from fkcheck.urdf.marker import marker_element

__all__ = ["UrdfExport", "model_for_urdf", "urdf_from_model"]


@dataclass(frozen=True)
class UrdfExport:
    """A URDF written from a DH model.

    Attributes:
        text: The URDF document.
        joint_names: URDF joint names in DH order (the model's joint names).
        frame_links: Model frame name → URDF link name (every named frame, ``world``
            and ``tcp`` included), plus ``dh_frame_<i>`` for each DH frame.
    """

    text: str
    joint_names: tuple[str, ...]
    frame_links: dict[str, str]


def _num(value: float) -> str:
    return toml_number(value)  # shortest round-trip text, no "-0.0"


def _origin(parent: ET.Element, offset: Offset) -> None:
    ET.SubElement(
        parent,
        "origin",
        xyz=" ".join(_num(v) for v in offset.xyz),
        rpy=" ".join(_num(v) for v in offset.rpy),
    )


def _fixed(robot: ET.Element, name: str, parent: str, child: str, offset: Offset) -> None:
    joint = ET.SubElement(robot, "joint", name=name, type="fixed")
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    _origin(joint, offset)


def _check_names(model: Model, robot_name: str | None) -> None:
    """Refuse a name the URDF cannot carry as it is.

    Raises:
        ModelError: A model, joint or frame name (or ``--name``) holds a character
            XML 1.0 cannot carry.
    """
    named = [("--name" if robot_name else "name", robot_name or model.name)]
    named += [(f"joint[{i}].name", joint.name) for i, joint in enumerate(model.joints, start=1)]
    named += [(f"frames.{name}", name) for name in model.frames]
    for field, name in named:
        bad = unsafe_xml_character(name)
        if bad is not None:
            raise ModelError(
                model.path,
                field,
                f"{name!r} holds {bad}, which a URDF (XML) cannot carry; rename it",
            )


def urdf_from_model(model: Model, robot_name: str | None = None) -> UrdfExport:
    """The model as a kinematic URDF.

    Args:
        model: The DH model.
        robot_name: ``<robot name>`` (default: the model's name).

    Raises:
        ModelError: A named frame or joint name collides with a generated link
            (``world``, ``tcp``, ``dh_frame_<i>``, ``dh_joint_<i>``), or a name
            holds a character XML cannot carry.
    """
    _check_names(model, robot_name)
    n = model.dof
    robot = ET.Element("robot", name=robot_name or model.name)
    comment = (
        f" Written by fkcheck urdf from the {model.convention} DH model {model.name!r}. "
        "Kinematics only: no inertia, no geometry; effort and velocity limits are unknown "
        "to a DH table and written as 0. "
    )
    # repr() escaped the name's control characters; "--" may not appear in a comment.
    robot.append(ET.Comment(re.sub(r"-(?=-)", "- ", comment)))
    robot.append(marker_element(model))  # an element: it survives stripped comments
    tcp_default = model.frames.get("tcp") == FrameSpec("tcp", "tcp")
    _refuse_generated_names(model, tcp_default)

    links = ["world"] + [f"dh_frame_{i}" for i in range(n + 1)]
    if model.convention == "standard":
        links += [f"dh_joint_{i}" for i in range(1, n + 1)]
    tool_anchor = "tcp" if tcp_default else "dh_tcp"
    links.append(tool_anchor)
    named = [name for name in model.frames if name not in ("world", tool_anchor)]
    for link in [*links, *named]:
        ET.SubElement(robot, "link", name=link)

    _fixed(robot, "world_to_dh_frame_0", "world", "dh_frame_0", model.base)
    for i, joint in enumerate(model.joints, start=1):
        _joint(robot, model.convention, i, joint)
    _fixed(robot, f"dh_frame_{n}_to_{tool_anchor}", f"dh_frame_{n}", tool_anchor, model.tool)

    frame_links: dict[str, str] = {"world": "world", "tcp": tool_anchor}
    for name in named:
        _frame(robot, name, model.frames[name], tool_anchor)
        frame_links[name] = name
    for i in range(n + 1):
        frame_links.setdefault(f"dh_frame_{i}", f"dh_frame_{i}")
    ET.indent(robot, space="  ")
    text = '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"
    return UrdfExport(text, model.joint_names, frame_links)


def _refuse_generated_names(model: Model, tcp_default: bool) -> None:
    """Refuse a named frame called like a link the export generates (bar the built-in ones).

    Raises:
        ModelError: ``world``, ``tcp``, ``dh_frame_<i>`` or ``dh_joint_<i>`` (standard
            DH) names a frame of the model's own.
    """
    n = model.dof
    generated = {"world", "tcp"} | {f"dh_frame_{i}" for i in range(n + 1)}
    if model.convention == "standard":
        generated |= {f"dh_joint_{i}" for i in range(1, n + 1)}
    world_default = model.frames.get("world") == FrameSpec("world", "world")
    builtin = {"tcp": tcp_default, "world": world_default}
    for name in model.frames:
        if name in generated and not builtin.get(name, False):
            raise ModelError(
                model.path,
                f"frames.{name}",
                "collides with a link fkcheck urdf generates (world, tcp, dh_frame_<i>, "
                "dh_joint_<i>); rename it",
            )


def _joint(robot: ET.Element, convention: str, i: int, joint: Joint) -> None:
    """DH row ``i`` (1-based): its moving joint and, in a standard table, the fixed link after it.

    A modified row's joint carries ``Rx(α)·Tx(a)·Rz(θ)·Tz(d)`` into ``dh_frame_<i>``; a
    standard row's carries ``Tz(d)·Rz(θ)`` into ``dh_joint_<i>``, and a fixed joint
    ``Tx(a)·Rx(α)`` goes on to ``dh_frame_<i>``.
    """
    if convention == "modified":
        placement = (
            rot_x(joint.alpha)
            @ translation(joint.a, 0.0, 0.0)
            @ rot_z(joint.theta)
            @ translation(0.0, 0.0, joint.d)
        )
        child = f"dh_frame_{i}"
    else:
        placement = translation(0.0, 0.0, joint.d) @ rot_z(joint.theta)
        child = f"dh_joint_{i}"
    if joint.type == "revolute":
        jtype = "revolute" if joint.limits is not None else "continuous"
    else:
        jtype = "prismatic"
    el = ET.SubElement(robot, "joint", name=joint.name, type=jtype)
    ET.SubElement(el, "parent", link=f"dh_frame_{i - 1}")
    ET.SubElement(el, "child", link=child)
    _origin(el, offset_from_matrix(placement))
    ET.SubElement(el, "axis", xyz="0 0 -1" if joint.flip else "0 0 1")
    if jtype != "continuous":
        lo, hi = joint.limits or (-UNLIMITED_PRISMATIC_M, UNLIMITED_PRISMATIC_M)
        ET.SubElement(el, "limit", lower=_num(lo), upper=_num(hi), effort="0", velocity="0")
    if convention == "standard":
        link_offset = offset_from_matrix(translation(joint.a, 0.0, 0.0) @ rot_x(joint.alpha))
        _fixed(robot, f"dh_link_{i}", child, f"dh_frame_{i}", link_offset)


def _frame(robot: ET.Element, name: str, spec: FrameSpec, tool_anchor: str) -> None:
    """Named frame ``name``'s fixed joint from its DH frame (or the world, or the TCP)."""
    if spec.dh == "world":
        parent = "world"
    elif spec.dh == "tcp":
        parent = tool_anchor
    else:
        parent = f"dh_frame_{spec.dh}"
    _fixed(robot, f"{parent}_to_{name}", parent, name, spec.offset)


def model_for_urdf(model: Model, export: UrdfExport, urdf_path: str) -> Model:
    """The model with ``[urdf]`` pointing at the exported file and every frame mapped onto it.

    Adds a named frame ``dh_frame_<i>`` for each DH frame (so every DH frame can be
    compared too), and maps ``world`` and ``tcp`` onto their links. The model's
    ``[[known_difference]]`` records are dropped: they were found against its
    old URDF, and the new one is written from the table itself.

    Args:
        model: The model the URDF was written from.
        export: What :func:`urdf_from_model` returned.
        urdf_path: ``[urdf].path`` as it should be written (relative to the model file).
    """
    frames: dict[str, FrameSpec] = {}
    for name, spec in model.frames.items():
        frames[name] = replace(spec, urdf=export.frame_links[name])
    for i in range(model.dof + 1):
        name = f"dh_frame_{i}"
        frames.setdefault(name, FrameSpec(name, i, Offset(), name))
    urdf = UrdfSpec(urdf_path, export.joint_names)
    return replace(model, urdf=urdf, frames=frames, known_differences=())
