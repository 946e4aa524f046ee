"""Finding, screening and summarising a model's reference URDF (stdlib only).

Every URDF backend parses the file with its own parser (urdfdom, lxml, Robotics
Toolbox's reader); this module runs first, for all of them:

* resolves ``[urdf].path`` (``example-robot-data:<subpath>`` or a path relative
  to the model file) without importing the example-robot-data loaders;
* refuses any DTD (``<!DOCTYPE``/``<!ENTITY``): a URDF never needs one, and it is
  how entity expansion ("billion laughs") and external entities
  (``SYSTEM "file:///etc/passwd"``) get in — no parser ever sees such a file;
* refuses xacro (``${…}``, ``$(…)``): one reader runs xacro, which evaluates
  expressions as Python — a plain URDF never has them;
* parses the joints and links once and checks the model's mapping against them
  (joint names, joint types, frame names), so a mismatch is one clear error.

Mesh files are never opened here or by the backends.
"""

from __future__ import annotations

import importlib.util
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from fkcheck.errors import BackendUnavailable, FrameError, UrdfError
from fkcheck.model import Model

__all__ = [
    "MAX_URDF_BYTES",
    "UrdfInfo",
    "UrdfJoint",
    "example_robot_data_dir",
    "load_urdf",
    "read_urdf",
    "resolve_urdf_path",
]

#: A robot description is kilobytes to a few megabytes; refuse anything larger.
MAX_URDF_BYTES = 32 * 1024 * 1024
ERD_PREFIX = "example-robot-data:"
_DTD = re.compile(rb"<!\s*(DOCTYPE|ENTITY)", re.IGNORECASE)
#: xacro substitutions: Robotics Toolbox's reader runs xacro, which evaluates
#: ``${…}`` as Python and ``$(…)`` as substitution args. A plain URDF has neither
#: outside comments (which are skipped: some published URDFs keep xacro there).
_XACRO = re.compile(rb"\$[{(]")


@dataclass(frozen=True)
class UrdfJoint:
    """One ``<joint>`` of a URDF."""

    name: str
    type: str
    parent: str
    child: str


@dataclass(frozen=True)
class UrdfInfo:
    """A screened URDF: where it is, what it holds, where its packages live.

    Attributes:
        path: The URDF file.
        text: Its content (screened: no DTD).
        package_dirs: Directories that contain the ``package://`` packages it names.
        joints: Joints by name.
        links: Link names.
        root: The root link.
    """

    path: Path
    text: str
    package_dirs: tuple[Path, ...]
    joints: dict[str, UrdfJoint]
    links: tuple[str, ...]
    root: str

    def chain(self, base: str, tip: str) -> list[UrdfJoint]:
        """The joints from link ``base`` down to link ``tip``.

        Raises:
            UrdfError: ``tip`` is not below ``base``.
        """
        by_child = {j.child: j for j in self.joints.values()}
        out: list[UrdfJoint] = []
        link = tip
        while link != base:
            joint = by_child.get(link)
            if joint is None:
                raise UrdfError(self.path, f"no chain connects {base!r} to {tip!r}")
            out.append(joint)
            link = joint.parent
        return out[::-1]


def example_robot_data_dir() -> Path:
    """The ``robots/`` directory installed by the example-robot-data package.

    Found from the installed Python package's location, without importing it
    (its loader imports Pinocchio).

    Raises:
        BackendUnavailable: example-robot-data is not installed (URDF backends
            then report themselves skipped, not failed).
    """
    spec = importlib.util.find_spec("example_robot_data")
    if spec is not None and spec.origin:
        # <prefix>/lib/pythonX.Y/site-packages/example_robot_data/__init__.py
        prefix = Path(spec.origin).resolve().parents[4]
        robots = prefix / "share" / "example-robot-data" / "robots"
        if robots.is_dir():
            return robots
    raise BackendUnavailable("example-robot-data is not installed (pip install example-robot-data)")


def resolve_urdf_path(model: Model) -> tuple[Path, tuple[Path, ...]]:
    """Resolve ``[urdf].path`` to a file and the directories holding its packages.

    Raises:
        UrdfError: No ``[urdf]`` table, or the file does not exist.
        BackendUnavailable: The path names example-robot-data, which is not installed.
    """
    if model.urdf is None:
        raise UrdfError(f"model {model.name}", "has no [urdf] table")
    spec = model.urdf.path
    if spec.startswith(ERD_PREFIX):
        robots = example_robot_data_dir()
        path = robots / spec[len(ERD_PREFIX) :]
        package_dirs: tuple[Path, ...] = (robots,)
    else:
        path = Path(spec)
        if not path.is_absolute() and model.path is not None:
            path = model.path.parent / path
        package_dirs = (path.parent.parent, path.parent.parent.parent)
    if not path.is_file():
        raise UrdfError(spec, f"URDF file not found ({path})")
    return path, package_dirs


def load_urdf(model: Model) -> UrdfInfo:
    """Resolve, screen and summarise the model's URDF, and check the mapping.

    Raises:
        UrdfError: Missing, too large, not XML, has a DTD, or a mapped joint is
            missing or of the wrong type.
        FrameError: A ``[frames.*].urdf`` name is not a link of the URDF.
    """
    path, package_dirs = resolve_urdf_path(model)
    info = read_urdf(path, package_dirs)
    assert model.urdf is not None
    for name, joint in zip(model.urdf.joints, model.joints, strict=True):
        found = info.joints.get(name)
        if found is None:
            movable = [j.name for j in info.joints.values() if j.type != "fixed"]
            raise UrdfError(
                path,
                f"joint {name!r} (for DH joint {joint.name}) not in URDF; "
                f"movable joints are: {', '.join(movable)}",
            )
        expected = ("revolute", "continuous") if joint.type == "revolute" else ("prismatic",)
        if found.type not in expected:
            raise UrdfError(
                path, f"joint {name!r} is {found.type} in the URDF but {joint.type} in the model"
            )
    for spec in model.frames.values():
        if spec.urdf is not None and spec.urdf not in info.links:
            raise FrameError(spec.urdf, f"URDF {path.name} (frame {spec.name})", info.links)
    return info


def read_urdf(path: Path, package_dirs: tuple[Path, ...] = ()) -> UrdfInfo:
    """Screen and summarise a URDF file (no model mapping checks).

    Raises:
        UrdfError: Missing, too large, not XML, or has a DTD.
    """
    if not path.is_file():
        raise UrdfError(path, "URDF file not found")
    stat = path.stat()  # part of the cache key: a file edited in place is read again
    return _read(path, package_dirs, stat.st_mtime_ns, stat.st_size)


@lru_cache(maxsize=32)
def _read(path: Path, package_dirs: tuple[Path, ...], mtime_ns: int, size: int) -> UrdfInfo:
    if size > MAX_URDF_BYTES:
        raise UrdfError(path, f"{size} bytes is larger than the {MAX_URDF_BYTES} byte limit")
    raw = path.read_bytes()
    if _DTD.search(raw):
        raise UrdfError(
            path, "has a DTD (<!DOCTYPE or <!ENTITY): entity declarations are not allowed in URDF"
        )
    try:
        root = ET.fromstring(raw)
    except ET.ParseError as exc:
        raise UrdfError(path, f"not valid XML: {exc}") from None
    if any(
        _XACRO.search(text.encode())
        for el in root.iter()
        for text in (el.text or "", *el.attrib.values())
    ):
        raise UrdfError(
            path,
            "contains xacro substitutions (${...} or $(...)): expand it to a plain URDF first",
        )
    if root.tag != "robot":
        raise UrdfError(path, f"root element is <{root.tag}>, expected <robot>")
    links = tuple(str(link.get("name")) for link in root.iter("link") if link.get("name"))
    joints: dict[str, UrdfJoint] = {}
    for el in root.iter("joint"):
        parent, child = el.find("parent"), el.find("child")
        if el.get("name") is None or parent is None or child is None:
            continue  # <joint> inside <transmission> has no parent/child
        joints[str(el.get("name"))] = UrdfJoint(
            name=str(el.get("name")),
            type=str(el.get("type", "")),
            parent=str(parent.get("link")),
            child=str(child.get("link")),
        )
    children = {j.child for j in joints.values()}
    roots = [link for link in links if link not in children]
    if len(roots) != 1:
        raise UrdfError(path, f"expected one root link, found {len(roots)}: {', '.join(roots)}")
    return UrdfInfo(
        path=path,
        text=raw.decode("utf-8", errors="replace"),
        package_dirs=package_dirs,
        joints=joints,
        links=links,
        root=roots[0],
    )
