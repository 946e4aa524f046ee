"""Robot models: the DH table and everything a check needs to know about the robot.

Owns the frozen model types (:mod:`~fkcheck.model.types`), reading and writing
model files (:mod:`~fkcheck.model.read`, :mod:`~fkcheck.model.write`), named
frames and their poses from the core (:mod:`~fkcheck.model.frames`), sampling
configurations within limits (:mod:`~fkcheck.model.sampling`), joint-value
input, DH parameter names, published tables, lint and convention conversion.
May import: :mod:`fkcheck.core`, :mod:`fkcheck.io`, :mod:`fkcheck.errors`.

``from fkcheck.model import Model, load_model`` keeps working: the public names
are re-exported here.
"""

from fkcheck.model.read import bundled_model_paths, load_model, model_from_dict
from fkcheck.model.table import model_from_table
from fkcheck.model.types import (
    MAX_JOINT_RAD,
    MAX_JOINTS,
    MAX_LENGTH_M,
    URDF_FRAME_PREFIX,
    CheckSpec,
    FrameSpec,
    Joint,
    Model,
    Offset,
    UrdfSpec,
    resolve_frame,
)

__all__ = [
    "MAX_JOINTS",
    "MAX_JOINT_RAD",
    "MAX_LENGTH_M",
    "URDF_FRAME_PREFIX",
    "CheckSpec",
    "FrameSpec",
    "Joint",
    "Model",
    "Offset",
    "UrdfSpec",
    "bundled_model_paths",
    "load_model",
    "model_from_dict",
    "model_from_table",
    "resolve_frame",
]
