"""URDF and xacro as description formats: :mod:`fkcheck.urdf`'s reading behind the format contract.

Both are declared in a model's ``[urdf]`` table and both give URDF text to their
readers: ``xacro`` is the format of a model with ``xacro = true`` (its file is
expanded in a sandbox, :mod:`fkcheck.urdf.xacro`, then screened as a URDF), ``urdf``
of one without. A xacro-allowed model whose file is a plain URDF reads as ``urdf``:
xacro never runs on it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

from fkcheck.description.section import SectionFormat
from fkcheck.description.types import Description
from fkcheck.errors import XacroRefused
from fkcheck.model.types import Model, UrdfSpec
from fkcheck.urdf.chain import KinematicTree, read_urdf_source, urdf_kinematics
from fkcheck.urdf.source import (
    check_urdf_mapping,
    read_model_urdf_expanded,
    resolve_urdf_path,
)
from fkcheck.urdf.tree import UrdfInfo

__all__ = ["URDF", "XACRO", "UrdfFormat", "urdf_description", "urdf_info"]


def urdf_description(info: UrdfInfo, *, expanded: bool) -> Description:
    """The :class:`Description` of a screened URDF (``expanded``: a xacro file's expansion)."""
    return Description.of(info, "xacro" if expanded else "urdf", "urdf")


def urdf_info(description: Description) -> UrdfInfo:
    """The screened URDF behind a description in the URDF language (URDF or xacro).

    Raises:
        TypeError: The description is in another language (a caller's bug: ask
            :attr:`Description.language` first).
    """
    return description.native_as(UrdfInfo, "URDF")


@dataclass(frozen=True)
class UrdfFormat(SectionFormat):
    """URDF (``xacro = False``) or xacro (``xacro = True``), declared in ``[urdf]``.

    Attributes: as :class:`~fkcheck.description.types.DescriptionFormat`; ``[urdf]``
    and ``urdf =`` frames are read by :class:`~fkcheck.description.section.SectionFormat`.
    """

    name: str
    suffixes: tuple[str, ...]
    executes: bool
    language: str = "urdf"
    section: str = "urdf"
    frame_key: str = "urdf"

    def declared_by(self, model: Model) -> bool:
        """Whether ``model`` has ``[urdf]``: with ``xacro = true`` for xacro, without for URDF."""
        return model.urdf is not None and model.urdf.xacro == self.executes

    def key(self, model: Model) -> tuple[object, ...]:
        """``[urdf]``'s path and xacro keys, the model file's folder and the kept expansion."""
        assert model.urdf is not None
        u = model.urdf
        folder = None if model.path is None else str(model.path.parent.resolve())
        return (
            u.path,
            folder,
            u.xacro,
            tuple(sorted(u.xacro_args.items())),
            tuple(sorted(u.packages.items())),
            tuple(sorted(u.xacro_files.items())),
            u.expanded,
        )

    def locate(self, model: Model) -> Path:
        """``[urdf].path`` resolved (:func:`~fkcheck.urdf.source.resolve_urdf_path`)."""
        return resolve_urdf_path(model)[0]

    def read_model(self, model: Model, timeout_s: float) -> Description:
        """The model's URDF, screened; a xacro file expanded first.

        (:func:`~fkcheck.urdf.source.read_model_urdf`.)
        """
        info, expanded = read_model_urdf_expanded(model, timeout_s)
        return urdf_description(info, expanded=expanded)

    def check_mapping(self, model: Model, description: Description) -> None:
        """``[urdf].joints`` against the URDF (:func:`~fkcheck.urdf.source.check_urdf_mapping`)."""
        check_urdf_mapping(model, urdf_info(description))

    def read_file(
        self,
        spec: str | Path,
        *,
        args: Mapping[str, str] | None = None,
        packages: Mapping[str, Path] | None = None,
    ) -> Description:
        """A URDF named on the command line; a xacro file expanded only when ``args`` is given."""
        try:
            return urdf_description(read_urdf_source(spec), expanded=False)
        except XacroRefused:
            if args is None:
                raise
        info = read_urdf_source(spec, xacro_args=args, packages=packages)
        return urdf_description(info, expanded=True)

    def tree(self, description: Description) -> KinematicTree:
        """The URDF's kinematic tree (:func:`~fkcheck.urdf.chain.urdf_kinematics`)."""
        return urdf_kinematics(urdf_info(description))

    def declared(self, model: Model, path: str, joints: tuple[str, ...]) -> Model:
        """``model`` with a new ``[urdf]`` naming ``path`` (``xacro`` as this format)."""
        return replace(model, urdf=UrdfSpec(path=path, joints=tuple(joints), xacro=self.executes))

    def carry(self, model: Model, description: Description) -> Model:
        """``model`` with ``[urdf].expanded`` set to a xacro file's expansion.

        (Screened again where it is read.)
        """
        if description.format != "xacro" or model.urdf is None:
            return model
        return replace(model, urdf=replace(model.urdf, expanded=description.text))


#: A plain URDF.
URDF = UrdfFormat("urdf", (".urdf",), executes=False)
#: A xacro file, expanded by fkcheck in a sandbox, then screened as a URDF.
XACRO = UrdfFormat("xacro", (".xacro", ".urdf.xacro"), executes=True)
