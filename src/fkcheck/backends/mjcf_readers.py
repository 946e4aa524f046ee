"""The MJCF readers as backends: ``mujoco-mjcf`` (MuJoCo's compiler) and ``pinocchio-mjcf``.

Each reads the model's ``[mjcf]`` description through
:func:`fkcheck.description.registry.load_description` (screened first, kept once
per process) and computes the mapped frames' poses with
:func:`fkcheck.mjcf.readers.mujoco_poses` or
:func:`fkcheck.mjcf.readers.pinocchio_poses`, which read the screened text with
their own library and nothing of fkcheck's tree. A frame is a body, a site or
``world`` (``[frames.NAME] mjcf = "…"``); ``q`` is given to ``[mjcf].joints``
in DH order, every other hinge or slide joint held at its ``ref``. A reader that
fails is the backend's error, naming the library and its version
(:class:`fkcheck.mjcf.readers.ReaderError`): a finding about the reader, never
a skip and never a pass.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable, Sequence
from pathlib import Path

from fkcheck.backends.base import BackendDefaults, Evidence, Reads, validated_q
from fkcheck.backends.registry import BackendOptions
from fkcheck.core.typing import Float
from fkcheck.description.mjcf import MJCF, mjcf_native
from fkcheck.description.registry import load_description
from fkcheck.errors import (
    INSTALL_REFERENCE,
    BackendUnavailable,
    FrameError,
    MjcfError,
    UnmappedFrameError,
)
from fkcheck.mjcf.readers import mujoco_poses, pinocchio_poses
from fkcheck.model.types import Model, resolve_frame

__all__ = ["MjcfReader", "MujocoMjcf", "PinocchioMjcf"]


class MjcfReader(BackendDefaults):
    """What both MJCF readers declare alike: the model's ``[mjcf]``, table evidence."""

    evidence: Evidence = "table"
    reads: Reads = "mjcf"
    formats: tuple[str, ...] = ("mjcf",)
    name = ""
    method = ""
    #: The importable module of its library.
    module = ""
    #: ``(description, frames, q, joints=…) -> poses``: :mod:`fkcheck.mjcf.readers`.
    compute: Callable[..., Float]

    def __init__(self, arg: str = "", options: BackendOptions | None = None) -> None:
        """Build the backend; ``arg`` is unused (built-in backends take none)."""
        self.options = options or BackendOptions()

    def unavailable_reason(self, model: Model) -> str | None:
        """Why it cannot run: its library is missing, or the model has no ``[mjcf]``."""
        if importlib.util.find_spec(self.module) is None:
            return f"{self.module} is not installed ({INSTALL_REFERENCE})"
        if model.mjcf is None:
            return "model has no [mjcf]"
        return None

    def inputs(self, model: Model) -> tuple[Path, ...]:
        """The model's MJCF file as ``[mjcf].path`` names it (none without one)."""
        if model.mjcf is None:
            return ()
        try:
            return (MJCF.locate(model),)
        except (MjcfError, BackendUnavailable):
            return ()

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``world_T_frame`` of each frame's MJCF twin, ``(len(frames), N, 4, 4)``.

        Raises:
            BackendUnavailable: The model has no ``[mjcf]``, or the library is missing.
            MjcfError: The MJCF is missing, unsafe, or does not fit the mapping.
            FrameError: A frame's twin is not a body or site of it.
            UnmappedFrameError: A frame has no ``mjcf`` twin (the backend's error).
            ReaderError: The library failed on it (the backend's error, with its version).
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        if model.mjcf is None:
            raise BackendUnavailable("model has no [mjcf]")
        native = mjcf_native(load_description(model, language="mjcf"))
        q2 = validated_q(model, q)
        twins = []
        for name in frames:
            spec = resolve_frame(model, name)
            if spec.mjcf is None:
                mapped = [s.name for s in model.frames.values() if s.mjcf is not None]
                raise UnmappedFrameError(
                    f"frame {name!r} has no MJCF twin, so {self.name} cannot compare the model "
                    f'with its MJCF: add mjcf = "<body or site>" to [frames.{name}]; mapped '
                    f"frames: {', '.join(mapped) or '(none)'}"
                )
            if spec.mjcf not in native.frames:
                raise FrameError(spec.mjcf, f"the MJCF (frame {name})", native.frames)
            twins.append(spec.mjcf)
        return type(self).compute(native, twins, q2, joints=model.mjcf.joints)


class MujocoMjcf(MjcfReader):
    """Reference FK from the model's MJCF, compiled and computed by MuJoCo."""

    name = "mujoco-mjcf"
    method = "MjSpec.from_string + compile + mj_kinematics (loop over qpos)"
    module = "mujoco"
    distributions = ("mujoco-core",)
    imports = ("mujoco",)
    pose_cost_us = 10.0
    compute = staticmethod(mujoco_poses)


class PinocchioMjcf(MjcfReader):
    """Reference FK from the model's MJCF read by Pinocchio's MJCF parser."""

    name = "pinocchio-mjcf"
    method = "buildModelFromMJCF + framesForwardKinematics (loop)"
    module = "pinocchio"
    distributions = ("pin",)
    imports = ("pinocchio",)
    pose_cost_us = 10.0
    compute = staticmethod(pinocchio_poses)
