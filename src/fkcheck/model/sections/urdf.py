"""``[urdf]``: the reference URDF, its joints in DH order, and how a xacro file is expanded."""

from __future__ import annotations

from typing import Any

from fkcheck.io.numbers import show_text
from fkcheck.model.sections.reader import Reader, is_text_list, shown_key
from fkcheck.model.types import PACKAGE_NAME, UrdfSpec

__all__ = ["URDF_KEYS", "read_urdf"]

URDF_KEYS = {"path", "joints", "xacro", "xacro_args", "packages", "xacro_files"}


def read_urdf(r: Reader, raw: Any, n: int) -> UrdfSpec:
    """The ``[urdf]`` table of a model with ``n`` joints."""
    u = r.table(raw, "urdf", URDF_KEYS)
    path = _path(r, u)
    joints = _joints(r, u.get("joints"), n)
    xacro = r.flag(u.get("xacro", False), "urdf.xacro")
    xacro_args = r.text_table(u.get("xacro_args", {}), "urdf.xacro_args", "a value")
    packages = r.text_table(u.get("packages", {}), "urdf.packages", "a directory")
    xacro_files = r.text_table(u.get("xacro_files", {}), "urdf.xacro_files", "a file")
    for name in xacro_files:
        if name in xacro_args:
            raise r.fail(
                f"urdf.xacro_files.{shown_key(name)}",
                "also in urdf.xacro_args: an argument is a value or a file, give it in one of them",
            )
        if not xacro_files[name].strip():
            raise r.fail(f"urdf.xacro_files.{shown_key(name)}", "names no file")
    for pname in packages:
        if not PACKAGE_NAME.fullmatch(pname):
            raise r.fail(
                f"urdf.packages.{shown_key(pname)}",
                "not a package name (letters, digits, '_', '.', '-')",
            )
    return UrdfSpec(path, joints, xacro, xacro_args, packages, xacro_files)


def _path(r: Reader, u: dict[str, Any]) -> str:
    """``path``: required, and naming a file."""
    if "path" not in u:
        raise r.fail("urdf.path", "missing (required in [urdf])")
    path = r.string(u["path"], "urdf.path")
    if not path.strip() or path.strip() in ("example-robot-data:", "fkcheck:"):
        raise r.fail(
            "urdf.path",
            f"{show_text(path)} names no file: give the URDF's path (relative to this file), "
            "example-robot-data:<subpath> or fkcheck:<subpath>",
        )
    return path


def _joints(r: Reader, raw: Any, n: int) -> tuple[str, ...]:
    """``joints``: one distinct URDF joint name per DH joint."""
    if not is_text_list(raw):
        raise r.fail("urdf.joints", "expected a list of URDF joint names in DH order")
    if len(raw) != n:
        raise r.fail("urdf.joints", f"names {len(raw)} URDF joints but the DH table has {n}")
    if len(set(raw)) != len(raw):
        raise r.fail("urdf.joints", "names a URDF joint twice")
    return tuple(raw)
