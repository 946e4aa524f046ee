"""The ``rtb-urdf`` backend: the model's reference URDF read by Robotics Toolbox's own reader.

A third URDF parser, independent of urdfdom (Pinocchio) and yourdfpy: the
screened URDF text from :func:`fkcheck.description.registry.load_description` goes through
Robotics Toolbox's URDF classes (``URDF.loadstr``, the standard library's XML
parser) and its URDF-to-links conversion (``_links_from_urdf``, the second half
of ``URDF_file``), and becomes an ETS robot (``roboticstoolbox.Robot``).

``URDF_file`` itself is never called: it runs every input through xacro
(xacrodoc) first, and xacro evaluates ``${…}`` as Python and ``$(…)`` as
substitutions that read files and the environment — code execution from a
downloaded URDF. Only text, never a path, reaches RTB, and no xacro processing
happens at all (the screen refuses xacro anyway). ``_links_from_urdf`` is a
private function of roboticstoolbox-python 1.5.0, pinned by a test.

Geometry is left out: every ``<visual>`` and ``<collision>`` (and the
top-level ``<material>`` list) is removed from the in-memory text before RTB
sees it, and the file on disk is not touched. RTB's reader would otherwise
resolve each ``<mesh filename>`` (``rtb_path_to_datafile``, which looks in the
current directory, the home directory and its data package) and refuse the
whole URDF unless every mesh is an existing regular file (``os.path.isfile`` in
``spatialgeometry.Mesh``; roboticstoolbox-python 1.5.0). Forward kinematics
needs none of it; this way no mesh path is resolved, looked at or opened, and a
URDF whose meshes are absent (or are named pipes) is checked like any other.
Links, joints, origins, axes and limits reach RTB as written.

RTB's reader gets a joint axis that is not along x, y or z wrong (a known
upstream limitation, see ``_refuse_crooked_axes``); links below such a joint
are reported as unavailable.

Each DH joint's value goes to the RTB joint of the URDF joint named in
``[urdf].joints`` (found through that joint's child link), unchanged; every
other URDF joint (e.g. the Panda's fingers) stays at 0. Poses are those of each
named frame's URDF twin (``urdf = …``) in the URDF's root link, from
``Robot.ets(start=root, end=link).eval`` (RTB's C forward kinematics, batched).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.registry import BackendOptions
from fkcheck.backends.rtb_common import INSTALL_HINT, RTB_IMPORTS, eval_batch, import_rtb, padded_q
from fkcheck.backends.urdf_common import (
    UrdfReader,
    kinematic_text,
    urdf_inputs,
    urdf_unavailable_reason,
)
from fkcheck.core.typing import Float
from fkcheck.errors import BackendUnavailable, FrameError
from fkcheck.model.types import Model
from fkcheck.urdf.tree import UrdfInfo

__all__ = ["RtbUrdf"]


class _UrdfRobotCache:
    """A model's URDF read by RTB, with the joint columns and per-link ETS cached."""

    def __init__(self, model: Model, info: UrdfInfo, robot: Any, columns: NDArray[np.intp]):
        self.model = model
        self.info = info
        self.robot = robot
        self.columns = columns
        self.ets: dict[str, Any] = {}
        self.crooked = _crooked_axes(info)


class RtbUrdf(UrdfReader):
    """Reference FK from the model's URDF parsed by Robotics Toolbox.

    Attributes:
        name: ``"rtb-urdf"``.
        method: The Robotics Toolbox calls used.
        options: The options the backend was built with.
    """

    name = "rtb-urdf"
    #: Declared cost, µs per configuration of a 6-joint arm (the plan: fkcheck.engine.plan).
    pose_cost_us = 15.0
    distributions = ("roboticstoolbox-python", "spatialmath-python")
    method = "URDF.loadstr + Robot.ets(start=root, end=link).eval (C fknm, batched)"
    imports = RTB_IMPORTS

    def __init__(self, arg: str = "", options: BackendOptions | None = None) -> None:
        """Build the backend; ``arg`` is unused (built-in backends take none)."""
        self.options = options or BackendOptions()
        self._built: _UrdfRobotCache | None = None

    def unavailable_reason(self, model: Model) -> str | None:
        """Why this backend cannot run: no ``[urdf]`` in the model, or a library missing."""
        return urdf_unavailable_reason(model, "roboticstoolbox", INSTALL_HINT)

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``root_T_link`` of each frame's URDF twin, ``(len(frames), N, 4, 4)``.

        Raises:
            BackendUnavailable: Robotics Toolbox is missing, the model has no
                ``[urdf]``, or a joint on the way to a twin has an axis RTB's
                reader gets wrong (not along x, y or z).
            FrameError: A name is not a frame of the model.
            UnmappedFrameError: A frame has no ``urdf`` twin (the backend's error).
            UrdfError: The URDF is missing, unsafe or does not fit the model
                (from :func:`~fkcheck.description.registry.load_description`), or RTB rejects it.
            JointInputError: ``q`` has the wrong shape or non-finite values.
        """
        info, q2, twins = urdf_inputs(model, q, frames, self.name)
        built = self._build(model, info)
        qp = padded_q(q2, int(built.robot.n), built.columns)
        out = np.empty((len(twins), q2.shape[0], 4, 4))
        for link in twins:
            _refuse_crooked_axes(built, link)
        for k, link in enumerate(twins):
            if link == built.robot.base_link.name:
                out[k] = np.eye(4)
                continue
            ets = built.ets.get(link)
            if ets is None:
                ets = built.ets[link] = built.robot.ets(start=built.robot.base_link, end=link)
            out[k] = eval_batch(ets, qp)
        return out

    def _build(self, model: Model, info: UrdfInfo) -> _UrdfRobotCache:
        built = self._built
        if built is None or built.model is not model or built.info is not info:
            robot = _read_robot(info)
            built = self._built = _UrdfRobotCache(model, info, robot, _columns(model, info, robot))
        return built


def _read_robot(info: UrdfInfo) -> Any:
    """Parse the screened, geometry-free URDF text with RTB's reader into a ``Robot``.

    No xacro, no file: ``URDF.loadstr`` parses the text and ``_links_from_urdf``
    turns it into links (``URDF_file`` without its xacro step and its saved
    copies of failing text).

    Raises:
        BackendUnavailable: RTB's reader rejects a URDF fkcheck's screen accepted
            (an axis of ``0 0 1e-300``): its limit, not the input's.
    """
    rtb = import_rtb()
    from roboticstoolbox.models.URDF.URDFRobot import _links_from_urdf
    from roboticstoolbox.tools.urdf import URDF, URDFError

    try:
        elinks, name = _links_from_urdf(URDF.loadstr(kinematic_text(info), None))
        robot = rtb.Robot(elinks, name=name)
    except (URDFError, ValueError, ArithmeticError) as exc:
        lines = str(exc).strip().splitlines()
        first_line = lines[0] if lines else type(exc).__name__
        raise BackendUnavailable(
            f"Robotics Toolbox's URDF reader rejects {info.path.name}: {first_line}"
        ) from None
    if robot.base_link.name != info.root:
        raise BackendUnavailable(
            f"Robotics Toolbox's reader makes {robot.base_link.name!r} the root of "
            f"{info.path.name}, not {info.root!r}"
        )
    return robot


def _crooked_axes(info: UrdfInfo) -> dict[str, str]:
    """Joints whose ``<axis xyz>`` has two or more non-zero components, as RTB counts them."""
    return {
        joint.name: joint.axis
        for joint in info.joints.values()
        if joint.axis is not None and sum(float(v) != 0.0 for v in joint.axis.split()) >= 2
    }


def _refuse_crooked_axes(built: _UrdfRobotCache, link: str) -> None:
    """Skip links below a joint whose axis is not along x, y or z.

    RTB's URDF reader (roboticstoolbox-python 1.5.0, ``_links_from_urdf``) turns
    such an axis ``v`` into a fixed rotation by ``|v|`` radians *about* ``v``
    (``angvec2r(norm, unit)``) followed by a z-axis joint, which is not the
    joint the URDF describes: poses below it are wrong even at ``q = 0``. A
    known upstream limitation ("crooked" axes), so it is reported as
    unavailable rather than as a disagreement.

    Raises:
        BackendUnavailable: A joint between the root and ``link`` has such an axis.
    """
    if not built.crooked:
        return
    for joint in built.info.chain(built.info.root, link):
        if joint.name in built.crooked:
            raise BackendUnavailable(
                f"Robotics Toolbox's URDF reader mishandles joint axes that are not along "
                f"x, y or z: joint {joint.name!r} has axis ({built.crooked[joint.name]}), "
                f"so it cannot compute link {link!r}"
            )


def _columns(model: Model, info: UrdfInfo, robot: Any) -> NDArray[np.intp]:
    """RTB's joint index (``jindex``) for each DH joint, through the URDF joint's child link.

    Raises:
        BackendUnavailable: A mapped joint did not become a moving joint in RTB's robot
            (its reader drops an axis as short as ``0 0 1e-300``).
        FrameError: RTB's robot lacks the joint's child link.
    """
    assert model.urdf is not None
    columns = []
    for urdf_name in model.urdf.joints:
        child = info.joints[urdf_name].child
        link = robot.link_dict.get(child)
        if link is None:
            raise FrameError(
                child, f"Robotics Toolbox's robot of {info.path.name}", robot.link_dict
            )
        if not link.isjoint or link.jindex is None:
            raise BackendUnavailable(  # RTB's reading, not the URDF (an axis of 0 0 1e-300)
                f"joint {urdf_name!r} of {info.path.name} is not a moving joint in Robotics "
                "Toolbox's robot"
            )
        columns.append(int(link.jindex))
    return np.array(columns, dtype=np.intp)
