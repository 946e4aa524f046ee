"""A model's reference URDF: found, read through the one screening, checked against the model.

:func:`load_urdf` resolves ``[urdf].path`` (:func:`fkcheck.urdf.locate.locate_urdf`:
``example-robot-data:<subpath>`` or a path relative to the model file), reads
it with :func:`fkcheck.urdf.tree.read_urdf` (screened, its tree checked and
bounded) — or, when the model opts in with ``xacro = true``, expands it with
:func:`~fkcheck.urdf.xacro.read_xacro` and screens the result the same way —
and checks the model's joint mapping against the joints (names, types), so a
mismatch is one clear error before any backend parses the URDF. A frame's
``urdf`` link is checked where the frame is used (a model copied onto a URDF
without one of its links still checks its other frames).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from fkcheck.errors import UrdfError, XacroRefused
from fkcheck.model.types import Model
from fkcheck.urdf.locate import locate, locate_urdf
from fkcheck.urdf.tree import UrdfInfo, read_urdf
from fkcheck.urdf.xacro import XACRO_TIMEOUT_S, read_xacro, screen_expansion

__all__ = [
    "allow_xacro",
    "check_urdf_mapping",
    "load_urdf",
    "read_model_urdf",
    "read_model_urdf_expanded",
    "resolve_urdf_path",
]


def allow_xacro(model: Model) -> Model:
    """The model with ``xacro = true`` in its ``[urdf]`` (what ``--allow-xacro`` does).

    A model without ``[urdf]`` is returned as it is.
    """
    if model.urdf is None or model.urdf.xacro:
        return model
    return replace(model, urdf=replace(model.urdf, xacro=True))


def read_model_urdf(model: Model, xacro_timeout_s: float = XACRO_TIMEOUT_S) -> UrdfInfo:
    """Resolve and read the model's URDF: screened, or expanded from xacro then screened.

    With ``xacro = true`` a file the screen finds xacro in is expanded
    (:func:`~fkcheck.urdf.xacro.read_xacro`) with the model's ``xacro_args``,
    ``$(find …)`` resolving only its ``packages`` (directories relative to the
    model file, or ``fkcheck:<subpath>``), its ``xacro_files`` passed as files
    — or its ``expanded`` text, which the engine keeps, is screened again; a
    plain URDF is read as one, xacro never runs on it. Without the opt-in a
    xacro file is refused by the screen, naming the opt-in.
    ``xacro_timeout_s`` is the expansion's time limit.

    Raises:
        UrdfError: As :func:`resolve_urdf_path`, refused by the screen, not a
            valid tree, or the xacro expansion failed.
        BackendUnavailable: The path names example-robot-data, which is not installed.
    """
    return read_model_urdf_expanded(model, xacro_timeout_s)[0]


def read_model_urdf_expanded(
    model: Model, xacro_timeout_s: float = XACRO_TIMEOUT_S
) -> tuple[UrdfInfo, bool]:
    """:func:`read_model_urdf`'s URDF, and whether it is a xacro file's expansion.

    Raises:
        UrdfError: As :func:`read_model_urdf`.
        BackendUnavailable: The path names example-robot-data, which is not installed.
    """
    path, package_dirs = resolve_urdf_path(model)
    assert model.urdf is not None
    if not model.urdf.xacro:
        return read_urdf(path, package_dirs), False
    base = Path.cwd() if model.path is None else model.path.parent
    packages = {name: locate(where, base) for name, where in model.urdf.packages.items()}
    files = {name: locate(where, base) for name, where in model.urdf.xacro_files.items()}
    dirs = package_dirs + tuple(p.parent for p in packages.values())
    if model.urdf.expanded is not None:  # expanded once by this check: screened, not re-run
        return screen_expansion(path, model.urdf.expanded, dirs), True
    try:
        return read_urdf(path, dirs), False  # a plain URDF is read as one: xacro never runs on it
    except XacroRefused:
        info = read_xacro(path, model.urdf.xacro_args, packages, dirs, xacro_timeout_s, files)
        return info, True


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


def load_urdf(model: Model, xacro_timeout_s: float = XACRO_TIMEOUT_S) -> UrdfInfo:
    """Resolve, screen and summarise the model's URDF, and check the mapping.

    ``xacro_timeout_s`` is the time limit of a xacro expansion.

    Raises:
        UrdfError: Missing, not a regular file, too large, not XML, refused by the
            screen (:mod:`fkcheck.urdf.screen`), not a valid tree, its xacro
            expansion failed, or a mapped joint is missing or of the wrong type.
            (A ``[frames.*].urdf`` link the URDF lacks is an error only where
            that frame is used.)
    """
    info = read_model_urdf(model, xacro_timeout_s)
    check_urdf_mapping(model, info)
    return info


def check_urdf_mapping(model: Model, info: UrdfInfo) -> None:
    """Check the model's ``[urdf].joints`` against the URDF's joints (names, types).

    Raises:
        UrdfError: A mapped joint is missing or of the wrong type.
    """
    path = info.path
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
