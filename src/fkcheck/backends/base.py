"""The one small interface every reference backend implements.

A backend turns a :class:`~fkcheck.model.Model` and a batch of joint
configurations into poses of the model's *named frames* (``[frames.NAME]``),
all expressed in one root frame of the backend's choosing. The engine compares
``from_T_to = (root_T_from)⁻¹ · root_T_to`` across backends, so the root never
has to agree between them.

Backends live one per module under :mod:`fkcheck.backends`, import their library
inside their methods (never at module import), and are registered in
:mod:`fkcheck.backends.registry`. Adding one touches no other backend.

Every backend declares which question its agreement answers (:data:`Evidence`):

* ``"implementation"`` — *is the in-house core right, given the table?* The
  backend computes FK from the model's own DH table (``rtb-dh``,
  ``pinocchio-dh``), or is the user's code running that table (plugins,
  ``cmd:`` programs). Agreement proves the arithmetic, not the numbers: a wrong
  d1 is wrong in both.
* ``"table"`` — *is the table right, for the robot?* The backend's poses do not
  come from the table: the robot's URDF read by its parsers, measured or
  pendant poses, a table published elsewhere (``rtb-model:``). A URDF that
  ``fkcheck urdf`` wrote from the checked table does come from it: the engine
  then counts the URDF backends' results as implementation evidence
  (:mod:`fkcheck.engine.provenance`).

Independence is a rule: no backend uses fkcheck's own kinematics (the DH core,
its rotation helpers, its frame offsets, its URDF export) for anything it is
compared on. Base, tool and named-frame offsets are built with each library's
own constructs from the model's ``xyz``/``rpy`` numbers. The import contract in
``pyproject.toml`` (``[tool.importlinter]``) and ``tests/test_independence.py``
enforce it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal, Protocol, runtime_checkable

from fkcheck.core.joint_array import joint_array, require_finite
from fkcheck.core.typing import Float, JacobianReference
from fkcheck.errors import BackendUnavailable, FrameUnavailable
from fkcheck.model.types import Model

__all__ = [
    "Backend",
    "BackendUnavailable",
    "Evidence",
    "FixedConfigurations",
    "FrameUnavailable",
    "ProvidesJacobian",
    "SharesDHFrames",
    "validated_q",
]


#: Which question a backend's agreement answers (see the module docstring).
Evidence = Literal["implementation", "table"]


@runtime_checkable
class Backend(Protocol):
    """A reference FK implementation.

    Attributes:
        name: The backend's name as shown in results (``"rtb-dh"``, ``"cmd:./fk"``).
        method: The library call used, for the report (``"DHRobot.fkine_all"``).
        evidence: ``"implementation"`` or ``"table"``: what its agreement proves.

    A backend may also set class attributes ``isolated = True`` (the engine then
    calls its :meth:`frame_poses` in a process of its own, for slow pure-Python
    backends that hold the GIL; the reference and the comparison stay in the
    engine's process; the object, the model and ``q`` must pickle) and
    ``imports`` (a tuple of module names the engine imports once, in the main
    thread, before backends start: two threads importing one heavy library
    lazily at the same time can hit Python's import-deadlock detection),
    ``reads_urdf = True`` (it computes a link of the model's URDF from the URDF
    itself, so it may compare ``urdf:LINK`` for a link no frame declares; see
    :func:`fkcheck.urdf.mapping.with_link_frames`) and, for a
    :class:`ProvidesJacobian` backend, ``jacobian_method`` (the library call its
    Jacobians come from, for the reports).
    """

    name: str
    method: str
    evidence: Evidence

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
class ProvidesJacobian(Protocol):
    """A backend whose library computes geometric Jacobians itself.

    Rows are linear then angular, one column per DH joint (``(N, 6, n)``), in
    the backend's own root frame (the DH world for backends built from the
    table, the URDF's root for URDF backends). ``reference`` is one of
    :data:`fkcheck.core.typing.JACOBIAN_REFERENCES`: ``"world-aligned"`` (the
    frame origin's velocity and the angular velocity in root axes), ``"local"``
    (both in the frame's own axes) or ``"world"`` (the spatial twist at the
    root's origin, in root axes) — Pinocchio's ``LOCAL_WORLD_ALIGNED``,
    ``LOCAL`` and ``WORLD``.
    """

    def frame_jacobian(
        self, model: Model, q: Float, frame: str, reference: JacobianReference
    ) -> Float | None:
        """The Jacobian of a named frame at each configuration, ``(N, 6, n)``.

        ``None`` when this backend has no Jacobian of that frame in that
        reference (a plugin without one): the engine then differentiates its poses.
        """
        ...


@runtime_checkable
class FixedConfigurations(Protocol):
    """A backend that only knows poses at given configurations (e.g. measured poses).

    When one takes part, the check runs on its configurations instead of sampling.
    """

    def configurations(self, model: Model) -> Float:
        """The configurations it has poses for, ``(N, n)``, radians / metres."""
        ...


def validated_q(model: Model, q: Float) -> Float:
    """``q`` as a C-contiguous float64 ``(N, n)`` array, checked but not computed on.

    Raises:
        JointInputError: Wrong shape, not numeric, or not finite.
    """
    q_arr = joint_array(q, model.dof)
    require_finite(q_arr)
    return q_arr
