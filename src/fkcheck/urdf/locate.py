"""Where a URDF is: a ``[urdf].path`` spec to a file, and a file back to a spec (stdlib only).

A spec is either ``example-robot-data:<subpath>``, found under the installed
example-robot-data package's ``robots/`` directory without importing its loaders
(they import Pinocchio), ``fkcheck:<subpath>``, a file or directory bundled with
fkcheck's models (:func:`fkcheck.model.read.bundled_models_dir`, e.g. UR's ROS 2
description ``fkcheck:ur_description``), or a file path, relative to the model
file (or, on the command line, to the current directory). :func:`urdf_spec_for`
goes the other way, for a generated model file; :func:`display_path` is how every
output (terminal, HTML, Markdown, messages) names a file to a person.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

from fkcheck.errors import INSTALL_REFERENCE, BackendUnavailable, ModelError, UrdfError
from fkcheck.urdf.screen import check_urdf_path

__all__ = [
    "ERD_PREFIX",
    "FKCHECK_PREFIX",
    "bundled_location",
    "display_path",
    "example_robot_data_dir",
    "locate",
    "locate_urdf",
    "path_for",
    "urdf_spec_for",
]

#: A ``[urdf].path`` starting with this names a file of example-robot-data.
ERD_PREFIX = "example-robot-data:"
#: A ``[urdf].path`` or package directory starting with this names a file bundled with fkcheck.
FKCHECK_PREFIX = "fkcheck:"


def bundled_location(spec: str) -> Path:
    """The file or directory ``fkcheck:<subpath>`` names, inside fkcheck's bundled models.

    Raises:
        UrdfError: The subpath is empty, absolute or climbs out with ``..`` (or
            through a symbolic link): one line naming the spec.
    """
    from fkcheck.model.read import bundled_models_dir

    sub = spec[len(FKCHECK_PREFIX) :]
    parts = Path(sub).parts
    if not sub.strip() or Path(sub).is_absolute() or ".." in parts or "\\" in sub:
        raise UrdfError(
            repr(spec),
            f"a {FKCHECK_PREFIX} path names a file bundled with fkcheck by a relative "
            f"path without '..' (e.g. {FKCHECK_PREFIX}ur_description/urdf/ur.urdf.xacro)",
        )
    root = bundled_models_dir().resolve()
    path = root / sub
    if not path.resolve().is_relative_to(root):
        raise UrdfError(repr(spec), "leads outside fkcheck's bundled models (a symbolic link)")
    return path


def locate(spec: str, relative_to: Path | None = None) -> Path:
    """The file or directory ``spec`` names: ``fkcheck:<subpath>`` or a path.

    A relative path is taken from ``relative_to`` (default: the current directory).

    Raises:
        UrdfError: A ``fkcheck:`` spec that leaves the bundled models.
    """
    if spec.startswith(FKCHECK_PREFIX):
        return bundled_location(spec)
    path = Path(spec)
    if not path.is_absolute() and relative_to is not None:
        path = relative_to / path
    return path


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
    raise BackendUnavailable(f"example-robot-data is not installed ({INSTALL_REFERENCE})")


def locate_urdf(spec: str, relative_to: Path | None = None) -> tuple[Path, tuple[Path, ...]]:
    """The file a URDF spec names, and the directories that may hold its packages.

    Args:
        spec: ``example-robot-data:<subpath>``, ``fkcheck:<subpath>`` or a file path.
        relative_to: The directory a relative path is taken from (default: the
            current directory).

    Returns:
        ``(path, package_dirs)``: the file (checked to be an existing regular
        file of bounded size, not yet opened) and where ``package://`` names in
        it are looked up (example-robot-data's ``robots/``, or the file's
        grandparent and great-grandparent directories).

    Raises:
        UrdfError: The file does not exist, is not a regular file or is too large.
        BackendUnavailable: The spec names example-robot-data, which is not installed.
    """
    if not spec.strip() or spec.strip() in (ERD_PREFIX, FKCHECK_PREFIX):
        raise UrdfError(
            repr(spec),
            f"names no file: give a URDF file's path, {ERD_PREFIX}<subpath> "
            f"or {FKCHECK_PREFIX}<subpath>",
        )
    if spec.startswith(ERD_PREFIX):
        robots = example_robot_data_dir()
        path = robots / spec[len(ERD_PREFIX) :]
        package_dirs: tuple[Path, ...] = (robots,)
    else:
        path = locate(spec, relative_to)
        package_dirs = (path.parent.parent, path.parent.parent.parent)
    check_urdf_path(path, spec)
    return path, package_dirs


def urdf_spec_for(path: Path, output: Path | None) -> str:
    """How a generated model file should name ``path``: by a prefix or relative to the file.

    ``example-robot-data:…`` for a file of that package, else as :func:`path_for`.

    Args:
        path: The URDF file.
        output: The model file to be written (``None``: printed, so the path is absolute).
    """
    resolved = path.resolve()
    try:
        robots = example_robot_data_dir().resolve()
    except BackendUnavailable:
        robots = None
    if robots is not None and resolved.is_relative_to(robots):
        return ERD_PREFIX + resolved.relative_to(robots).as_posix()
    return path_for(path, output)


def path_for(path: Path, output: Path | None) -> str:
    """How a generated model file should name ``path``: ``fkcheck:…``, relative, or absolute.

    ``fkcheck:<subpath>`` for a file or directory bundled with fkcheck (UR's ROS 2
    description), wherever the model file goes.

    Args:
        path: A file or directory.
        output: The model file to be written (``None``: printed, so the path is absolute).
    """
    from fkcheck.model.read import bundled_models_dir

    resolved = path.resolve()
    bundled = bundled_models_dir().resolve()
    if resolved.is_relative_to(bundled) and resolved != bundled:
        return FKCHECK_PREFIX + resolved.relative_to(bundled).as_posix()
    if output is None:
        return str(resolved)
    return Path(os.path.relpath(resolved, output.resolve().parent)).as_posix()


def display_path(path: Path | str) -> str:
    """How an output names a file to a person: ``fkcheck:…``, relative, or as given.

    A file bundled with fkcheck reads ``fkcheck:<subpath>`` (``fkcheck:ur5.toml``,
    the spec :func:`bundled_location` reads back), never its place in
    site-packages or a source checkout; a file under the current directory reads
    relative to it (``robots/arm.toml``); anything else as given. Every
    human-readable output names model and configuration files through this one
    function (JSON keeps its machine fields as they are).
    """
    from fkcheck.model.read import bundled_models_dir

    given = Path(path)
    try:
        resolved = given.resolve()
        here = Path.cwd().resolve()
    except (OSError, RuntimeError):  # a symbolic-link loop, a removed current directory
        return str(path)
    try:
        bundled: Path | None = bundled_models_dir().resolve()
    except ModelError:  # an incomplete installation: nothing is bundled
        bundled = None
    if bundled is not None and resolved.is_relative_to(bundled) and resolved != bundled:
        return FKCHECK_PREFIX + resolved.relative_to(bundled).as_posix()
    if given.is_absolute() and resolved.is_relative_to(here) and resolved != here:
        return resolved.relative_to(here).as_posix()
    return str(path)
