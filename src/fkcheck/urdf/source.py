"""A model's reference URDF: found, read through the one screening, checked against the model.

:func:`load_urdf` resolves ``[urdf].path`` (:func:`fkcheck.urdf.locate.locate_urdf`:
``example-robot-data:<subpath>`` or a path relative to the model file), reads
it with :func:`fkcheck.urdf.tree.read_urdf` (screened, its tree checked and
bounded) and checks the model's joint mapping against the joints (names, types), so a
mismatch is one clear error before any backend parses the URDF. A frame's
``urdf`` link is checked where the frame is used (a model copied onto a URDF
without one of its links still checks its other frames).
"""

from __future__ import annotations

from pathlib import Path

from fkcheck.errors import UrdfError
from fkcheck.model.types import Model
from fkcheck.urdf.locate import locate_urdf
from fkcheck.urdf.tree import UrdfInfo, read_urdf

__all__ = ["load_urdf", "resolve_urdf_path"]


def resolve_urdf_path(model: Model) -> tuple[Path, tuple[Path, ...]]:
    """Resolve ``[urdf].path`` to a file and the directories holding its packages.

    Raises:
        UrdfError: No ``[urdf]`` table, or the file does not exist, is not a
            regular file or is too large.
        BackendUnavailable: The path names example-robot-data, which is not installed.
    """
    if model.urdf is None:
        raise UrdfError(f"model {model.name}", "has no [urdf] table")
    return locate_urdf(model.urdf.path, None if model.path is None else model.path.parent)


def load_urdf(model: Model) -> UrdfInfo:
    """Resolve, screen and summarise the model's URDF, and check the mapping.

    Raises:
        UrdfError: Missing, not a regular file, too large, not XML, refused by the
            screen (:mod:`fkcheck.urdf.screen`), not a valid tree, or a mapped
            joint is missing or of the wrong type. (A ``[frames.*].urdf`` link
            the URDF lacks is an error only where that frame is used.)
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
    return info
