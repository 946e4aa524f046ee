"""The one screening every MJCF goes through before MuJoCo, Pinocchio or fkcheck reads it.

An MJCF (MuJoCo's XML) is read from anywhere, so it is hostile until proven
otherwise, as a URDF is (:mod:`fkcheck.urdf.screen`, whose expat handlers,
limits and file readers this module reuses). :func:`screen_mjcf` reads the file
and every file it includes itself and parses each once, with expat, refusing
with one :class:`~fkcheck.errors.MjcfError` naming the file (and the line):

* a path that is not a regular file, or files together over
  :data:`MAX_MJCF_BYTES` (:func:`fkcheck.io.files.read_bytes`: looked at
  before it is opened, opened non-blocking, so a FIFO never blocks);
* any DTD or entity (``<!DOCTYPE``: entity expansion, external entities);
* more than :data:`MAX_XML_ELEMENTS` elements or nesting deeper than
  :data:`MAX_XML_DEPTH`, counted over the main file and its includes together,
  and more than :data:`MAX_INCLUDES` included files;
* an element or attribute in an XML namespace (MJCF has none);
* a root element other than ``<mujoco>`` (a URDF is read through ``[urdf]``);
* ``<include file>`` naming an absolute path, a path whose ``..`` leaves the
  folder includes are held to (``root``, by default the MJCF's own folder), a
  symbolic link leading out of it, or a file included twice (MuJoCo includes
  each file once; this also ends cycles). The name is relative to the main
  file's folder, as MuJoCo resolves it. fkcheck inlines each included file's
  ``<mujoco>`` children in place of its ``<include>``, as MuJoCo does, so no
  reader ever resolves an include itself;
* elements that build bodies from other files or by rule — ``<attach>``
  (a model asset), ``<replicate>``, ``<composite>``, ``<flexcomp>`` — and any
  element in ``<worldbody>`` that is not a body, joint, site or frame and not
  one of the non-kinematic ones dropped below: fkcheck reads explicit bodies only.

What is kept is the kinematics, and nothing that names a file: the
``<mujoco model>`` name; ``<compiler>``'s ``angle``, ``eulerseq`` and
``autolimits`` (so ``meshdir``, ``assetdir``, ``texturedir`` and the rest are
ignored); ``<default>`` classes with their ``<joint>`` and ``<site>`` defaults;
and ``<worldbody>`` with its ``<body>``, ``<joint>``, ``<freejoint>``, ``<site>``
and ``<frame>`` elements, every attribute kept but a site's ``material``.
Dropped: ``<asset>`` (meshes, textures, height fields, skins, materials, models),
``<geom>``, ``<inertial>``, ``<camera>``, ``<light>``, ``<plugin>`` and every
other top-level section (``option``, ``size``, ``visual``, ``statistic``,
``custom``, ``extension``, ``contact``, ``deformable``, ``equality``, ``tendon``,
``actuator``, ``sensor``, ``keyframe``). Element text (MJCF reads none),
comments and processing instructions are dropped too. So no mesh or texture is
ever opened, by fkcheck or by a reader: :attr:`ScreenedMjcf.text`, the screened
tree re-serialised, is what every reader is given — never the file's path or bytes.
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
import xml.parsers.expat as expat
from dataclasses import dataclass, field
from pathlib import Path

from fkcheck.errors import MjcfError
from fkcheck.io.files import InputFileError, read_bytes
from fkcheck.urdf.screen import (
    MAX_URDF_BYTES,
    MAX_XML_DEPTH,
    MAX_XML_ELEMENTS,
    _clark,
    _Refused,
    _Screen,
)

__all__ = [
    "DROPPED_BODY_ELEMENTS",
    "DROPPED_SECTIONS",
    "MAX_INCLUDES",
    "MAX_MJCF_BYTES",
    "MAX_XML_DEPTH",
    "MAX_XML_ELEMENTS",
    "READ_BODY_ELEMENTS",
    "ScreenedMjcf",
    "screen_mjcf",
]

#: All the files of one MJCF together (the main file and its includes), bytes: as a URDF.
MAX_MJCF_BYTES = MAX_URDF_BYTES
#: Included files in one MJCF. Menagerie's largest scenes include a handful.
MAX_INCLUDES = 256

#: What ``<worldbody>`` and ``<body>`` keep: the kinematic tree.
READ_BODY_ELEMENTS = ("body", "joint", "freejoint", "site", "frame")
#: What they may hold that is dropped: geometry, inertia, sensors of light and sight.
DROPPED_BODY_ELEMENTS = ("geom", "inertial", "camera", "light", "plugin")
#: Top-level sections dropped whole (``compiler``, ``default`` and ``worldbody`` are read).
DROPPED_SECTIONS = (
    "option", "size", "visual", "statistic", "custom", "extension", "asset", "contact",
    "deformable", "equality", "tendon", "actuator", "sensor", "keyframe",
)  # fmt: skip
#: The ``<compiler>`` attributes that change what the kinematics mean.
_COMPILER_KEPT = ("angle", "eulerseq", "autolimits")
#: What a ``<default>`` class keeps.
_DEFAULT_KEPT = ("default", "joint", "site")
#: Elements that build bodies out of other files or by rule: refused, with why.
_REFUSED_BODY_ELEMENTS = {
    "attach": "it attaches a model asset, another file",
    "replicate": "it repeats bodies by rule; write them out",
    "composite": "it builds bodies by rule; write them out",
    "flexcomp": "it builds a deformable body, from a file or by rule",
}
#: A Windows drive (``C:``) or UNC start: absolute on some system, refused everywhere.
_DRIVE = re.compile(r"^(?:[A-Za-z]:|[\\/]{2})")


@dataclass(frozen=True, eq=False)
class ScreenedMjcf:
    """An MJCF that passed the screen, its includes inlined and its geometry stripped.

    Attributes:
        path: The main file, resolved.
        root: The folder includes were held to, resolved.
        text: The screened tree re-serialised: what every reader is given.
        files: Every file read, resolved: the main file first, then its includes
            in the order they were read.
    """

    path: Path
    root: Path
    text: str
    files: tuple[Path, ...]


@dataclass
class _Budget:
    """What the main file and its includes may spend together."""

    elements: int = 0
    bytes_left: int = MAX_MJCF_BYTES
    files: list[Path] = field(default_factory=list)


class _MjcfScreen(_Screen):
    """The URDF screen's expat set-up, with MJCF's rules: includes allowed, text dropped."""

    def __init__(self, budget: _Budget, depth: int) -> None:
        super().__init__()
        self.budget = budget
        self.depth = depth

    def _doctype(self, *_: object) -> None:
        raise _Refused(
            "has a DTD (<!DOCTYPE …>): entity declarations are not allowed in an MJCF "
            "(they are how entity expansion and external files get in)"
        )

    def _entity(self, *_: object) -> None:
        raise _Refused("declares or references an entity: not allowed in an MJCF")

    def _external(self, *_: str | None) -> int:
        raise _Refused("references an external entity: not allowed in an MJCF")

    def _data(self, text: str) -> None:
        """Element text: MJCF reads none, so none is kept (and none can hide anything)."""

    def _start(self, name: str, attrs: dict[str, str]) -> None:
        self.budget.elements += 1
        self.depth += 1
        if self.budget.elements > MAX_XML_ELEMENTS:
            raise _Refused(
                f"has more than {MAX_XML_ELEMENTS} elements with its includes (the limit)"
            )
        if self.depth > MAX_XML_DEPTH:
            raise _Refused(
                f"nests elements deeper than {MAX_XML_DEPTH} levels with its includes (the limit)"
            )
        tag = _clark(name)
        if tag.startswith("{"):
            raise _Refused(f"has an element in an XML namespace ({tag}): MJCF has none")
        attrib = {}
        for key, value in attrs.items():
            attr = _clark(key)
            if attr.startswith("{"):
                raise _Refused(f"has an attribute in an XML namespace ({attr}) on <{tag}>")
            attrib[attr] = value
        element = self.builder.start(tag, attrib)
        self.lines[id(element)] = self.parser.CurrentLineNumber

    def _end(self, name: str) -> None:
        self.depth -= 1
        self.builder.end(_clark(name))


def _parse(path: Path, budget: _Budget, depth: int) -> tuple[ET.Element, dict[int, int]]:
    """Read and parse one file of the MJCF (the main one or an include), screened."""
    try:
        data = read_bytes(path, budget.bytes_left)
    except InputFileError as exc:
        too_big = "too large" in exc.problem
        extra = f"; all files of one MJCF together: at most {MAX_MJCF_BYTES} bytes"
        raise MjcfError(path, exc.problem + (extra if too_big else "")) from None
    budget.bytes_left -= len(data)
    budget.files.append(path)
    screen = _MjcfScreen(budget, depth)
    try:
        screen.parser.Parse(data, True)
    except _Refused as exc:
        raise MjcfError(
            path, f"line {exc.line or screen.parser.CurrentLineNumber}: {exc}"
        ) from None
    except (expat.ExpatError, ValueError, LookupError) as exc:
        raise MjcfError(path, f"not valid XML: {exc}") from None
    root = screen.builder.close()
    if root.tag != "mujoco":
        raise MjcfError(
            path, f"its root element is <{root.tag}>, not <mujoco>: not an MJCF (a URDF "
            "is read as one, through [urdf])"
        )  # fmt: skip
    return root, screen.lines


def _include_target(spec: str, where: Path, base: Path, root: Path) -> Path:
    """The file ``<include file=spec>`` names, held to ``root``.

    Args:
        spec: The ``file`` attribute as written.
        where: The file the include is in (for messages).
        base: The folder names are relative to (the main file's, as MuJoCo).
        root: The folder every included file must lie in.
    """
    what = f"<include file={spec!r}>"
    if not spec:
        raise MjcfError(where, f"{what}: names no file")
    if os.path.isabs(spec) or spec.startswith(("/", "\\")) or _DRIVE.match(spec):
        raise MjcfError(
            where, f"{what}: an absolute path; an include names a file relative to the "
            f"MJCF's folder, inside {root}"
        )  # fmt: skip
    lexical = Path(os.path.normpath(base / spec))
    if not lexical.is_relative_to(root):
        raise MjcfError(
            where, f"{what}: '..' leads out of the folder includes are held to ({root})"
        )
    try:
        target = lexical.resolve()
    except (OSError, RuntimeError) as exc:  # a symbolic link loop
        raise MjcfError(where, f"{what}: cannot be resolved: {exc}") from None
    if not target.is_relative_to(root):
        raise MjcfError(
            where, f"{what}: a symbolic link leads out of the folder includes are held to "
            f"({root}), to {target}"
        )  # fmt: skip
    return target


def _inline(
    element: ET.Element,
    where: Path,
    lines: dict[int, int],
    depth: int,
    budget: _Budget,
    base: Path,
    root: Path,
) -> None:
    """Replace every ``<include>`` below ``element`` by the included file's children."""
    out: list[ET.Element] = []
    for child in list(element):
        if child.tag != "include":
            _inline(child, where, lines, depth + 1, budget, base, root)
            out.append(child)
            continue
        line = lines.get(id(child))
        shown = f"{where} (line {line})" if line else where
        target = _include_target(child.get("file", ""), Path(shown), base, root)
        if target in budget.files:
            raise MjcfError(
                shown, f"<include file={child.get('file')!r}>: {target.name} is included "
                "twice (MuJoCo includes each file once)"
            )  # fmt: skip
        if len(budget.files) > MAX_INCLUDES:  # the main file and MAX_INCLUDES includes
            raise MjcfError(shown, f"more than {MAX_INCLUDES} included files (the limit)")
        included, included_lines = _parse(target, budget, depth)
        _inline(included, target, included_lines, depth, budget, base, root)
        out.extend(included)
    element[:] = out


def _strip_default(element: ET.Element) -> None:
    kept = [child for child in element if child.tag in _DEFAULT_KEPT]
    for child in kept:
        if child.tag == "default":
            _strip_default(child)
        elif child.tag == "site":
            child.attrib.pop("material", None)
    element[:] = kept


def _strip_body(element: ET.Element, path: Path) -> None:
    kept = []
    for child in element:
        if child.tag in _REFUSED_BODY_ELEMENTS:
            raise MjcfError(
                path, f"<{child.tag}> in <{element.tag}>: not read, "
                f"{_REFUSED_BODY_ELEMENTS[child.tag]}"
            )  # fmt: skip
        if child.tag in DROPPED_BODY_ELEMENTS:
            continue
        if child.tag not in READ_BODY_ELEMENTS:
            raise MjcfError(
                path, f"<{child.tag}> in <{element.tag}> is not an MJCF body element fkcheck "
                f"knows; it reads {', '.join(READ_BODY_ELEMENTS)} and drops "
                f"{', '.join(DROPPED_BODY_ELEMENTS)}"
            )  # fmt: skip
        if child.tag == "site":
            child.attrib.pop("material", None)
        if child.tag in ("body", "frame"):
            _strip_body(child, path)
        else:
            child[:] = []  # joints and sites have no children MuJoCo reads
        kept.append(child)
    element[:] = kept


def _strip(root: ET.Element, path: Path) -> None:
    """Keep the kinematics (module docstring), in place."""
    root.attrib = {k: v for k, v in root.attrib.items() if k == "model"}
    kept = []
    for section in root:
        if section.tag in DROPPED_SECTIONS:
            continue
        if section.tag == "compiler":
            section.attrib = {k: v for k, v in section.attrib.items() if k in _COMPILER_KEPT}
            section[:] = []
        elif section.tag == "default":
            _strip_default(section)
        elif section.tag == "worldbody":
            _strip_body(section, path)
        else:
            known = ("compiler", "default", "worldbody", "include", *DROPPED_SECTIONS)
            raise MjcfError(
                path, f"<{section.tag}> is not a section of an MJCF; sections are: "
                f"{', '.join(known)}"
            )  # fmt: skip
        kept.append(section)
    root[:] = kept


def screen_mjcf(path: Path | str, *, root: Path | str | None = None) -> ScreenedMjcf:
    """Read, screen, inline and strip an MJCF (see the module docstring for the rules).

    Args:
        path: The main MJCF file.
        root: The folder every ``<include>`` must stay in (default: the main
            file's folder), e.g. the folder of the model file that names the MJCF.

    Returns:
        The screened MJCF: its text, what every reader is given, and its files.

    Raises:
        MjcfError: Anything the screen refuses, naming the file and what is wrong.
    """
    main = Path(path)
    try:
        resolved = main.resolve()
    except (OSError, RuntimeError) as exc:  # a symlink loop
        raise MjcfError(main, f"cannot be resolved: {exc}") from None
    base = resolved.parent
    held = base if root is None else Path(root).resolve()
    budget = _Budget()
    tree, lines = _parse(resolved, budget, 0)
    _inline(tree, resolved, lines, 1, budget, base, held)
    _strip(tree, resolved)
    return ScreenedMjcf(resolved, held, ET.tostring(tree, encoding="unicode"), tuple(budget.files))
