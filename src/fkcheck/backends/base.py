"""The one small interface every reference backend implements.

A backend turns a :class:`~fkcheck.model.Model` and a batch of joint
configurations into poses of the model's *named frames* (``[frames.NAME]``),
all expressed in one root frame of the backend's choosing. The engine compares
``from_T_to = (root_T_from)⁻¹ · root_T_to`` across backends, so the root never
has to agree between them.

Backends live one per module under :mod:`fkcheck.backends`, import their library
inside their methods (never at module import), and are registered in
:mod:`fkcheck.backends.registry`. Adding one touches no other backend.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from fkcheck.errors import FkcheckError
from fkcheck.model import Model

__all__ = [
    "Backend",
    "BackendUnavailable",
    "FixedConfigurations",
    "FrameUnavailable",
    "SharesDHFrames",
]

Float = NDArray[np.float64]


class BackendUnavailable(FkcheckError):
    """Raised by a backend that cannot run here; the check reports it as *skipped*."""


class FrameUnavailable(FkcheckError):
    """A backend cannot provide a named frame (e.g. a mid-chain frame from a black box)."""


@runtime_checkable
class Backend(Protocol):
    """A reference FK implementation.

    Attributes:
        name: The backend's name as shown in results (``"rtb-dh"``, ``"cmd:./fk"``).
        method: The library call used, for the report (``"DHRobot.fkine_all"``).

    A backend may also set a class attribute ``isolated = True``: the engine then
    runs it in a process of its own (for slow pure-Python backends that hold the
    GIL; the object, the model and ``q`` must pickle).
    """

    name: str
    method: str

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot check ``model`` here, or ``None`` if it can.

        Must be cheap: look for the library and the model's inputs (e.g. a
        ``[urdf]`` table) without importing heavy libraries.
        """
        ...

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """Poses of named frames for a batch of configurations.

        Args:
            model: The model being checked.
            q: Joint values, shape ``(N, n)``, radians / metres, DH joint order.
            frames: Names from ``model.frames``.

        Returns:
            Shape ``(len(frames), N, 4, 4)``: ``root_T_frame`` for each frame, with
            one root shared by all frames of this call.

        Raises:
            BackendUnavailable: The library or an input is missing (→ skipped).
            FrameUnavailable: A frame cannot be computed by this backend (→ skipped).
            FkcheckError: Bad input such as an unreadable URDF (→ exit 2).
            Exception: Anything else is reported as this backend's *error*.
        """
        ...


@runtime_checkable
class SharesDHFrames(Protocol):
    """A backend built from the DH table itself, which can give every DH frame.

    Used to find the first joint at which two chains part ways.
    """

    def dh_frames(self, model: Model, q: Float) -> Float:
        """``world_T_i`` for DH frames ``0…n``: shape ``(N, n+1, 4, 4)``."""
        ...


@runtime_checkable
class FixedConfigurations(Protocol):
    """A backend that only knows poses at given configurations (e.g. measured poses).

    When one takes part, the check runs on its configurations instead of sampling.
    """

    def configurations(self, model: Model) -> Float:
        """The configurations it has poses for, ``(N, n)``, radians / metres."""
        ...
