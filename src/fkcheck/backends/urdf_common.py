"""What the URDF backends share: their cheap availability test, inputs and the frame → link mapping.

Every URDF backend compares the poses of the URDF *links* that named frames
name as their twin (``[frames.NAME] urdf = "…"``); a frame without a twin
cannot be computed from a URDF. Native parsers that print their complaints on
the process's standard error (urdfdom's ``Error:`` lines) run inside
:func:`captured_stderr`, so that a bad URDF still ends in one line.
"""

from __future__ import annotations

import contextlib
import importlib.util
import os
import sys
import tempfile
import threading
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from fkcheck.backends.base import BackendDefaults, Evidence, Reads, validated_q
from fkcheck.core.typing import Float
from fkcheck.description.registry import load_description, model_format
from fkcheck.description.urdf import urdf_info
from fkcheck.errors import (
    INSTALL_REFERENCE,
    BackendUnavailable,
    FrameError,
    UnmappedFrameError,
    UrdfError,
)
from fkcheck.model.types import Model, resolve_frame
from fkcheck.urdf.locate import ERD_PREFIX
from fkcheck.urdf.source import resolve_urdf_path
from fkcheck.urdf.tree import UrdfInfo, listed

__all__ = [
    "CapturedStderr",
    "UrdfReader",
    "captured_stderr",
    "kinematic_text",
    "urdf_inputs",
    "urdf_twins",
    "urdf_unavailable_reason",
]


class UrdfReader(BackendDefaults):
    """What every URDF backend declares alike: it reads the model's URDF, table evidence.

    A backend reading ``[urdf]`` computes any link of it, so the engine may
    compare ``urdf:LINK`` frames no ``[frames]`` entry declares.
    """

    evidence: Evidence = "table"
    reads: Reads = "urdf"
    #: A URDF, or a xacro file's expansion (screened, then read as a URDF).
    formats: tuple[str, ...] = ("urdf", "xacro")

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """The model's URDF (or xacro) file as ``[urdf].path`` names it.

        Empty when the model has none or the path does not resolve (the check
        reports that when poses are asked for).
        """
        if model.urdf is None:
            return ()
        try:
            path, _ = resolve_urdf_path(model)
        except (UrdfError, BackendUnavailable):
            return ()
        return (path,)


def kinematic_text(info: UrdfInfo, *, inertials: bool = True) -> str:
    """The screened URDF reduced to its tree, the one text every geometry-free parser gets.

    ``<robot>``, its ``<link>``s — empty, or with their ``<inertial>`` when
    ``inertials`` — and its ``<joint>``s as written. Every other element
    (``<visual>``, ``<collision>``, ``<material>``, ``<gazebo>``,
    ``<transmission>``, a parser's extension block) goes, so no parser ever
    resolves a mesh; XML comments were dropped by the screen.
    """
    root = ET.fromstring(info.text)
    tree = ET.Element("robot", {"name": root.get("name", "robot")})
    for element in root:
        if element.tag == "link":
            link = ET.SubElement(tree, "link", {"name": element.get("name", "")})
            if inertials:
                link.extend(child for child in element if child.tag == "inertial")
        elif element.tag == "joint":
            tree.append(element)
    return ET.tostring(tree, encoding="unicode")


#: Most of a native library's standard error kept for the message.
_CAPTURE_LIMIT = 64 * 1024
#: One redirection of file descriptor 2 at a time in this process.
_STDERR_LOCK = threading.Lock()


@dataclass
class CapturedStderr:
    """What native code wrote to file descriptor 2 inside :func:`captured_stderr`.

    Attributes:
        text: The first 64 KiB of it, decoded (filled in when the block ends).
    """

    text: str = ""

    def first_error(self) -> str | None:
        """The first ``Error:`` line (urdfdom's first complaint), without that prefix."""
        for line in self.text.splitlines():
            head, sep, rest = line.strip().partition("Error:")
            if sep and not head and rest.strip():
                return rest.strip()
        return None


@contextlib.contextmanager
def captured_stderr() -> Iterator[CapturedStderr]:
    """Send what is written to file descriptor 2 to a temporary file while the block runs.

    For native parsers that print to the process's standard error (urdfdom's
    ``Error: … at line … in joint.cpp``) instead of raising with the message.
    The redirection is process-wide: anything another thread writes to stderr
    in the meantime (a few milliseconds: one parse) lands in the capture too,
    so it is kept to the native call. If file descriptor 2 cannot be
    duplicated (it is closed), the block runs without capture.
    """
    captured = CapturedStderr()
    with _STDERR_LOCK, tempfile.TemporaryFile() as tmp:
        try:
            saved = os.dup(2)
        except OSError:
            saved = -1
        if saved < 0:
            yield captured
            return
        with contextlib.suppress(ValueError, OSError):
            sys.stderr.flush()  # Python's own buffered text goes out first
        os.dup2(tmp.fileno(), 2)
        try:
            yield captured
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            captured.text = tmp.read(_CAPTURE_LIMIT).decode("utf-8", errors="replace")


def urdf_unavailable_reason(model: Model, module: str, install_hint: str) -> str | None:
    """Why a URDF backend cannot check ``model`` here, without importing anything heavy.

    Args:
        model: The model to check.
        module: The backend's library as imported (``"pinocchio"``, ``"yourdfpy"``).
        install_hint: The reason to give when that library is missing.

    Returns:
        ``None`` when the library is importable and the model names a URDF whose
        source package (example-robot-data) is installed; otherwise the reason.
    """
    if importlib.util.find_spec(module) is None:
        return install_hint
    fmt = model_format(model, "urdf")
    if fmt is None:
        return "model has no [urdf]"
    if fmt.name not in UrdfReader.formats:
        return f"its description is {fmt.name}, which URDF readers do not read"
    assert model.urdf is not None
    if model.urdf.path.startswith(ERD_PREFIX) and (
        importlib.util.find_spec("example_robot_data") is None
    ):
        return (
            f"its URDF comes from example-robot-data, which is not installed ({INSTALL_REFERENCE})"
        )
    return None


def urdf_twins(
    model: Model, frames: Sequence[str], backend: str, links: Sequence[str] = ()
) -> list[str]:
    """The URDF link names of named frames, in order.

    Args:
        model: The model.
        frames: Names from ``model.frames``.
        backend: The asking backend's name, for the message.
        links: The URDF's link names, listed in the message when a twin is missing.

    Raises:
        FrameError: A name is not a frame of the model, or its twin is not one of ``links``.
        UnmappedFrameError: A frame has no ``urdf`` twin: the URDF the model
            declares would go unread, which is the backend's error, not a skip.
    """
    twins: list[str] = []
    for name in frames:
        spec = resolve_frame(model, name)
        if spec.urdf is None:
            mapped = [s.name for s in model.frames.values() if s.urdf is not None]
            where = f"DH frame {spec.dh}" if isinstance(spec.dh, int) else f"the {spec.dh}"
            raise UnmappedFrameError(
                f"frame {name!r} (at {where}) has no URDF twin, so {backend} cannot compare the "
                f'model with its URDF: add urdf = "<link>" to [frames.{name}] (or check a pair '
                f"of mapped frames with --from/--to); mapped frames: "
                f"{', '.join(mapped) or '(none)'}; URDF links: {listed(links)}"
            )
        if links and spec.urdf not in links:
            raise FrameError(spec.urdf, f"the URDF (frame {name})", links)
        twins.append(spec.urdf)
    return twins


def urdf_inputs(
    model: Model, q: Float, frames: Sequence[str], backend: str
) -> tuple[UrdfInfo, Float, list[str]]:
    """What every URDF backend's ``frame_poses`` starts from.

    Args:
        model: The model.
        q: Joint values, ``(N, n)``, radians / metres, DH joint order.
        frames: Names from ``model.frames``.
        backend: The asking backend's name, for messages.

    Returns:
        ``(info, q, twins)``: the screened URDF (the model's description,
        :func:`~fkcheck.description.registry.load_description`),
        ``q`` validated as C-contiguous float64 ``(N, n)``, and the frames' URDF links.

    Raises:
        BackendUnavailable: The model has no ``[urdf]``.
        UrdfError: The URDF is missing, unsafe or does not fit the model.
        FrameError: A name is not a frame of the model, or a twin is not a URDF link.
        UnmappedFrameError: A frame has no ``urdf`` twin.
        JointInputError: ``q`` has the wrong shape or non-finite values.
    """
    fmt = model_format(model, "urdf")
    if fmt is None or fmt.name not in UrdfReader.formats:
        raise BackendUnavailable("model has no [urdf]")
    info = urdf_info(load_description(model, language="urdf"))
    return info, validated_q(model, q), urdf_twins(model, frames, backend, info.links)
