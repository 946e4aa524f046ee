"""What every description format declared in one model-file section reads the same way.

A format is declared in a table of the model file (``[urdf]``, ``[mjcf]``) holding
``path`` and ``joints``, and maps a frame by one key of ``[frames.X]`` (``urdf =
…``, ``mjcf = …``). :class:`SectionFormat` answers the
:class:`~fkcheck.description.types.DescriptionFormat` questions that depend on
those two names alone, so a third format gives its names (``section``,
``frame_key``) and writes only what is its own: how its file is found, read and
checked.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Protocol

from fkcheck.model.types import FrameSpec, Model

__all__ = ["SectionFormat", "SectionSpec"]


class SectionSpec(Protocol):
    """A model file's description section, as :class:`~fkcheck.model.types.UrdfSpec` is."""

    @property
    def path(self) -> str: ...  # noqa: D102 (as written in the model file)
    @property
    def joints(self) -> tuple[str, ...]: ...  # noqa: D102 (the description's joint per DH joint)


class SectionFormat:
    """The half of a format that reads its section and frame key by their names.

    Attributes:
        section: The :class:`~fkcheck.model.types.Model` field (and model-file table)
            the format is declared in.
        frame_key: The :class:`~fkcheck.model.types.FrameSpec` field (and ``[frames.X]``
            key) that maps a frame onto one of the description's.
    """

    section: str
    frame_key: str

    def section_of(self, model: Model) -> SectionSpec | None:
        """``model``'s section of this format (``model.urdf``), or ``None``."""
        found: SectionSpec | None = getattr(model, self.section)
        return found

    def declared_by(self, model: Model) -> bool:
        """Whether ``model`` has the section."""
        return self.section_of(model) is not None

    def mapped_joints(self, model: Model) -> tuple[str, ...]:
        """The section's ``joints``: the description's joint per DH joint (``()`` without it)."""
        spec = self.section_of(model)
        return () if spec is None else tuple(spec.joints)

    def written(self, model: Model) -> str:
        """The section's ``path`` as written."""
        spec = self.section_of(model)
        assert spec is not None
        return spec.path

    def frame(self, spec: FrameSpec) -> str | None:
        """The frame's twin in a description of this format (its ``frame_key``), or ``None``."""
        twin: str | None = getattr(spec, self.frame_key)
        return twin

    def with_frame(self, spec: FrameSpec, twin: str | None) -> FrameSpec:
        """``spec`` with its ``frame_key`` set to ``twin``."""
        changes: dict[str, Any] = {self.frame_key: twin}
        return replace(spec, **changes)

    def remapped(self, model: Model, joints: tuple[str, ...]) -> Model:
        """``model`` with the section's ``joints`` replaced."""
        spec: Any = self.section_of(model)  # a dataclass (UrdfSpec, MjcfSpec)
        assert spec is not None
        changes: dict[str, Any] = {self.section: replace(spec, joints=tuple(joints))}
        return replace(model, **changes)
