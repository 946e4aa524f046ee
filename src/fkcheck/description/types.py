"""What a description is (:class:`Description`), what a format provides (``DescriptionFormat``)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Protocol, TypeVar

from fkcheck.model.types import FrameSpec, Model
from fkcheck.urdf.chain import KinematicTree

__all__ = ["Description", "DescriptionFormat", "Read"]


_N = TypeVar("_N")


class Read(Protocol):
    """What a format module's reading holds for every format (a URDF's ``UrdfInfo``)."""

    @property
    def path(self) -> Path: ...  # noqa: D102 (the file named)
    @property
    def files(self) -> tuple[Path, ...]: ...  # noqa: D102 (every file it was made of)
    @property
    def text(self) -> str: ...  # noqa: D102 (the screened text)


@dataclass(frozen=True, eq=False)
class Description:
    """A robot's description, read and screened: the same questions for every format.

    Attributes:
        format: The format it was read as (``"urdf"``, ``"xacro"``): a name in
            :data:`fkcheck.description.registry.FORMATS`. A model that allows
            xacro but names a plain URDF has a ``"urdf"`` description.
        language: The language of :attr:`text`, which its readers parse:
            ``"urdf"`` for a URDF and for a xacro file's expansion.
        path: The file the model (or the command line) names.
        files: Every file it was made of (a xacro file's includes too): no
            output of a run may replace one.
        text: The screened text: the only text any reader is given.
        native: The format module's own reading (a
            :class:`~fkcheck.urdf.tree.UrdfInfo` for URDF and xacro), for the
            readers of its language.
    """

    format: str
    language: str
    path: Path
    files: tuple[Path, ...]
    text: str = field(repr=False)
    native: object = field(repr=False)

    @classmethod
    def of(cls, native: Read, format: str, language: str) -> Description:
        """The description of a format module's reading ``native`` (its path, files and text)."""
        return cls(format, language, native.path, native.files, native.text, native)

    def native_as(self, kind: type[_N], what: str) -> _N:
        """:attr:`native` as the reading ``kind`` of the format module that made it.

        Raises:
            TypeError: It is another format's reading (a caller's bug: ask
                :attr:`language` first); the message names ``what`` it holds no reading of.
        """
        if not isinstance(self.native, kind):
            raise TypeError(f"a {self.format} description holds no {what}")
        return self.native

    @cached_property
    def tree(self) -> KinematicTree:
        """Its kinematic tree: links, joints with origin, axis, type and limits.

        Raises:
            UrdfError: The format cannot express it as one (a moving joint
                without an axis).
        """
        from fkcheck.description.registry import format_named

        return format_named(self.format).tree(self)

    @property
    def frames(self) -> tuple[str, ...]:
        """The names a ``[frames.X]`` entry of its format may map a frame onto."""
        return self.tree.links


class DescriptionFormat(Protocol):
    """A description format: what one must provide to be read, screened and checked.

    Attributes:
        name: Its name (``"urdf"``, ``"xacro"``), as :attr:`Description.format`.
        language: The language its screened text is in (:attr:`Description.language`);
            backends reading that language read it.
        suffixes: The file suffixes it is recognised by (``(".urdf",)``).
        section: The model file's table it is declared in (``"urdf"``: ``[urdf]``).
        frame_key: The ``[frames.X]`` key that maps a frame onto one of its
            frames (``"urdf"``: ``urdf = "tool0"``).
        executes: Whether reading it runs the file's own code (xacro's macros, in
            a sandbox): it is then read only when a backend reads it.
    """

    @property
    def name(self) -> str: ...  # noqa: D102 (the class docstring says each)
    @property
    def language(self) -> str: ...  # noqa: D102
    @property
    def suffixes(self) -> tuple[str, ...]: ...  # noqa: D102
    @property
    def section(self) -> str: ...  # noqa: D102
    @property
    def frame_key(self) -> str: ...  # noqa: D102
    @property
    def executes(self) -> bool: ...  # noqa: D102

    def declared_by(self, model: Model) -> bool:
        """Whether ``model``'s description is to be read as this format."""
        ...

    def mapped_joints(self, model: Model) -> tuple[str, ...]:
        """The description's joint for each DH joint, in DH order (``[urdf].joints``)."""
        ...

    def written(self, model: Model) -> str:
        """The description's file as ``model``'s file names it (``[urdf].path``)."""
        ...

    def frame(self, spec: FrameSpec) -> str | None:
        """The frame of the description ``spec`` is mapped onto (its ``frame_key``), or ``None``."""
        ...

    def with_frame(self, spec: FrameSpec, twin: str | None) -> FrameSpec:
        """``spec`` mapped onto ``twin`` of a description in this format (its ``frame_key``)."""
        ...

    def key(self, model: Model) -> tuple[object, ...]:
        """What identifies ``model``'s description besides its files' bytes (the cache's key)."""
        ...

    def locate(self, model: Model) -> Path:
        """The file ``model`` names, found but not read.

        Raises:
            UrdfError: It does not exist, is not a regular file or is too large.
            BackendUnavailable: It names a package that is not installed.
        """
        ...

    def read_model(self, model: Model, timeout_s: float) -> Description:
        """Find, screen and read ``model``'s description (no cache, no mapping check).

        ``timeout_s`` bounds any code the reading runs.

        Raises:
            UrdfError: Missing, unsafe, not valid.
            BackendUnavailable: It names a package that is not installed.
        """
        ...

    def check_mapping(self, model: Model, description: Description) -> None:
        """Check ``model``'s joint mapping against the description.

        Raises:
            UrdfError: A mapped joint is missing or of the wrong type.
        """
        ...

    def read_file(
        self,
        spec: str | Path,
        *,
        args: Mapping[str, str] | None = None,
        packages: Mapping[str, Path] | None = None,
    ) -> Description:
        """Find, screen and read a description named on the command line.

        Args:
            spec: A path, or a spec the format resolves (``example-robot-data:…``).
            args: Given (even empty): code in the file may run with these
                arguments (xacro); ``None``: a file that would run code is refused.
            packages: Directories the file's package references may resolve.

        Raises:
            UrdfError: Missing, unsafe or not valid.
            BackendUnavailable: It names a package that is not installed.
        """
        ...

    def tree(self, description: Description) -> KinematicTree:
        """The kinematic tree of a description this format read."""
        ...

    def remapped(self, model: Model, joints: tuple[str, ...]) -> Model:
        """``model`` with its joint mapping (:meth:`mapped_joints`) replaced by ``joints``."""
        ...

    def declared(self, model: Model, path: str, joints: tuple[str, ...]) -> Model:
        """``model`` declaring a description of this format at ``path`` (its section, new)."""
        ...

    def carry(self, model: Model, description: Description) -> Model:
        """``model`` carrying what reading its description produced, when that ran code.

        A backend in a process of its own is sent the model: a xacro file's
        expansion travels in it, so the file runs once per check. ``model`` as
        it is when nothing ran.
        """
        ...
