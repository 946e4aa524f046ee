"""The ``yourdfpy-urdf`` backend: the model's reference URDF, parsed by yourdfpy.

The URDF is first resolved and screened by :func:`fkcheck.description.registry.load_description`;
yourdfpy then parses the screened text from a file object with
``load_meshes=False`` and ``load_collision_meshes=False`` and no collision scene,
so no ``<mesh>`` file is opened: its only mesh-loading path
(``URDF._geometry2trimeshscene``) runs the filename handler and ``trimesh.load``
only when meshes are to be loaded, and the handler given here raises if it is
ever called. Box, cylinder and sphere visuals still become trimesh primitives
(in memory, no file).

Per configuration: ``update_cfg({urdf joint name: q})`` for the mapped joints,
then ``get_transform(frame_to=link)`` for each frame's URDF twin, which is
``base_T_link`` with ``base`` the URDF's root link (``frame_from`` defaults to
it). Facts about yourdfpy 0.0.60 and trimesh 5.2 this relies on, checked in
their source and in the tests:

* ``update_cfg`` does not clip to the URDF's ``<limit>``: values beyond them are
  used as given.
* ``mimic`` joints follow their leader (``multiplier · q + offset``) on every
  ``update_cfg``, whatever value is given for them, so a DH joint mapped onto a
  mimic joint is refused (:class:`~fkcheck.errors.UrdfError`). Unmapped joints
  (the Panda's fingers) stay at zero.
* ``get_transform(frame_to, frame_from)`` returns the pose of ``frame_to`` in
  ``frame_from``; the matrix is cached and read-only, so it is copied.
* trimesh's ``SceneGraph.get`` skips, on a path of two or more edges, every edge
  transform within 1e-8 (largest entry) of the identity: any joint step that
  small — an identity URDF origin at ``|q| < 1e-8``, or an origin whose own
  angle or offset is below 1e-8 — is read as the identity. That bounds this
  backend's resolution near such steps to about 1e-8 (the property tests leave
  such configurations out of yourdfpy's comparison, and pin the behaviour in
  named regression tests).
* trimesh's ``SceneGraph.update`` keeps an edge's stored matrix when the new one
  is within 1e-8 of it (``np.ptp`` of the difference): a joint that moves by
  less than ~5e-9 from the previous configuration (the first one: from q = 0)
  keeps the previous configuration's value. The same ~1e-8 bound, but a pose can
  depend on the configuration before it (and so, at that level, on where the
  engine split a large check over processes: each part starts from q = 0).

It is slow (a few hundred µs per configuration, all in Python): one
``update_cfg`` and one ``get_transform`` per frame are the least the API allows.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from typing import Any

import numpy as np

from fkcheck.backends.registry import BackendOptions
from fkcheck.backends.urdf_common import UrdfReader, urdf_inputs, urdf_unavailable_reason
from fkcheck.core.typing import Float
from fkcheck.errors import INSTALL_REFERENCE, BackendUnavailable, FrameError, UrdfError
from fkcheck.model.types import Model
from fkcheck.urdf.tree import UrdfInfo

__all__ = ["MeshAccessError", "YourdfpyUrdf"]


_INSTALL_HINT = f"yourdfpy is not installed ({INSTALL_REFERENCE})"


class MeshAccessError(RuntimeError):
    """Raised if yourdfpy ever asks for a mesh file: fkcheck never opens meshes."""


def _refuse_mesh(fname: str) -> str:
    """A yourdfpy filename handler that refuses every mesh path."""
    raise MeshAccessError(f"fkcheck does not load meshes, but yourdfpy asked for {fname!r}")


class YourdfpyUrdf(UrdfReader):
    """Reference FK from the model's URDF loaded by yourdfpy.

    Attributes:
        name: ``"yourdfpy-urdf"``.
        method: The yourdfpy call path used per configuration.
        options: The options the backend was built with.
    """

    name = "yourdfpy-urdf"
    #: Declared cost, µs per configuration of a 6-joint arm (the plan: fkcheck.engine.plan).
    pose_cost_us = 630.0
    distributions = ("yourdfpy", "trimesh")
    method = "URDF.update_cfg + URDF.get_transform (loop)"
    #: ~370 µs per pose of pure Python holding the GIL (trimesh's scene graph):
    #: the engine computes its poses in processes of its own, split over the cores
    #: (a share under half a second, e.g. 64 poses, of a URDF of at most 64,000
    #: characters, in the engine's process: fkcheck.engine.runner.in_own_processes).
    isolated = True
    #: Imported before the backends' threads start when it runs in the engine's process.
    imports = ("yourdfpy",)

    def __init__(self, arg: str = "", options: BackendOptions | None = None) -> None:
        """Build the backend; ``arg`` is unused (built-in backends take none)."""
        self.options = options or BackendOptions()

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot run: yourdfpy missing, or no ``[urdf]`` in the model."""
        return urdf_unavailable_reason(model, "yourdfpy", _INSTALL_HINT)

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``root_T_link`` of each frame's URDF twin, ``(len(frames), N, 4, 4)``.

        Raises:
            BackendUnavailable: yourdfpy is not installed or the model has no ``[urdf]``.
            FrameError: A name is not a frame of the model, or yourdfpy's scene
                lacks the twin link.
            UnmappedFrameError: A frame has no ``urdf`` twin (the backend's error).
            UrdfError: The URDF is missing, unsafe, or does not fit the model (a
                mapped joint is absent or a mimic joint).
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        info, q2, twins = urdf_inputs(model, q, frames, self.name)
        assert model.urdf is not None  # urdf_inputs refuses a model without one
        robot = _load(info)
        nodes = robot.scene.graph.nodes
        for twin in twins:
            if twin not in nodes:
                raise FrameError(twin, f"yourdfpy's scene of {info.path.name}", sorted(nodes))
        joint_names = list(model.urdf.joints)
        for name in joint_names:
            joint = robot.joint_map.get(name)
            if joint is None:
                raise UrdfError(info.path, f"yourdfpy has no joint {name!r}")
            if joint.mimic is not None:
                raise UrdfError(
                    info.path,
                    f"joint {name!r} mimics {joint.mimic.joint!r} in the URDF, so yourdfpy "
                    "ignores the value given for it; map the joint it mimics instead",
                )

        N = q2.shape[0]
        out = np.empty((len(twins), N, 4, 4))
        update, get = robot.update_cfg, robot.get_transform
        for k, row in enumerate(q2.tolist()):
            update(dict(zip(joint_names, row, strict=True)))
            for f, twin in enumerate(twins):
                out[f, k] = get(twin)
        return out


def _load(info: UrdfInfo) -> Any:
    """The yourdfpy model of the screened URDF text: scene graph, no meshes."""
    try:
        import yourdfpy
    except ImportError as exc:
        raise BackendUnavailable(f"{_INSTALL_HINT}: {exc}") from None
    return yourdfpy.URDF.load(
        io.BytesIO(info.text.encode("utf-8")),
        build_scene_graph=True,
        build_collision_scene_graph=False,
        load_meshes=False,
        load_collision_meshes=False,
        filename_handler=_refuse_mesh,
    )
