"""MJCF (MuJoCo's format) as a description format: :mod:`fkcheck.mjcf` behind the contract.

Declared in a model's ``[mjcf]`` (``path`` relative to the model file, whose
folder its ``<include>`` files are held to; ``joints`` in DH order); a frame is
mapped onto a body, a site or ``world`` by ``[frames.NAME] mjcf = "…"``. The
file is screened (:func:`fkcheck.mjcf.screen.screen_mjcf`) before MuJoCo's
compiler reads it (:func:`fkcheck.mjcf.tree.read_mjcf`), and its readers are
given the screened text alone.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path

from fkcheck.description.section import SectionFormat
from fkcheck.description.types import Description
from fkcheck.errors import MjcfError
from fkcheck.mjcf.tree import MjcfDescription, read_mjcf
from fkcheck.model.types import MjcfSpec, Model
from fkcheck.urdf.chain import KinematicTree
from fkcheck.urdf.locate import FKCHECK_PREFIX, locate

__all__ = ["MJCF", "MjcfFormat", "mjcf_description", "mjcf_native"]


def mjcf_description(native: MjcfDescription) -> Description:
    """The :class:`Description` of an MJCF read by :func:`fkcheck.mjcf.tree.read_mjcf`."""
    return Description.of(native, "mjcf", "mjcf")


def mjcf_native(description: Description) -> MjcfDescription:
    """The MJCF reading behind a description in the MJCF language.

    Raises:
        TypeError: The description is in another language (a caller's bug).
    """
    return description.native_as(MjcfDescription, "MJCF")


@dataclass(frozen=True)
class MjcfFormat(SectionFormat):
    """MJCF, declared in ``[mjcf]``.

    Attributes: as :class:`~fkcheck.description.types.DescriptionFormat`; ``[mjcf]``
    and ``mjcf =`` frames are read by :class:`~fkcheck.description.section.SectionFormat`.
    """

    name: str = "mjcf"
    language: str = "mjcf"
    suffixes: tuple[str, ...] = (".xml", ".mjcf")
    section: str = "mjcf"
    frame_key: str = "mjcf"
    executes: bool = False

    def key(self, model: Model) -> tuple[object, ...]:
        """``[mjcf].path`` and the model file's folder."""
        assert model.mjcf is not None
        folder = None if model.path is None else str(model.path.parent.resolve())
        return (model.mjcf.path, folder)

    def locate(self, model: Model) -> Path:
        """``[mjcf].path`` resolved against the model file's folder (or ``fkcheck:<subpath>``)."""
        assert model.mjcf is not None
        base = Path.cwd() if model.path is None else model.path.parent
        return locate(model.mjcf.path, base)

    def read_model(self, model: Model, timeout_s: float) -> Description:
        """The model's MJCF: screened, its includes held to the model file's folder, compiled."""
        assert model.mjcf is not None
        path = self.locate(model)
        bundled = model.mjcf.path.startswith(FKCHECK_PREFIX)
        root = None if bundled or model.path is None else model.path.parent
        return mjcf_description(read_mjcf(path, root=root))

    def check_mapping(self, model: Model, description: Description) -> None:
        """``[mjcf].joints`` against the MJCF: each a hinge (revolute) or slide (prismatic)."""
        assert model.mjcf is not None
        native = mjcf_native(description)
        for name, joint in zip(model.mjcf.joints, model.joints, strict=True):
            if name not in native.joints:
                raise MjcfError(
                    native.path,
                    f"joint {name!r} (for DH joint {joint.name}) is not a hinge or slide joint "
                    f"of it; its joints are: {', '.join(native.joints) or '(none)'}",
                )
            found = native.kinematics.joints[name].type
            if (found == "prismatic") != (joint.type == "prismatic"):
                raise MjcfError(
                    native.path,
                    f"joint {name!r} is {found} in the MJCF but {joint.type} in the model",
                )

    def read_file(
        self,
        spec: str | Path,
        *,
        args: Mapping[str, str] | None = None,
        packages: Mapping[str, Path] | None = None,
    ) -> Description:
        """An MJCF named on the command line (its includes held to its folder); no code runs."""
        return mjcf_description(read_mjcf(Path(spec)))

    def tree(self, description: Description) -> KinematicTree:
        """The tree MuJoCo's compiler read (``MjcfDescription.kinematics``)."""
        return mjcf_native(description).kinematics

    def declared(self, model: Model, path: str, joints: tuple[str, ...]) -> Model:
        """``model`` with a new ``[mjcf]`` naming ``path``."""
        return replace(model, mjcf=MjcfSpec(path=path, joints=tuple(joints)))

    def carry(self, model: Model, description: Description) -> Model:
        """``model`` as it is: reading an MJCF runs no code."""
        return model


#: MJCF.
MJCF = MjcfFormat()
