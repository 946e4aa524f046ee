"""fkcheck: cross-validation of robot-arm forward kinematics.

An in-house Denavit–Hartenberg core (NumPy only) compared pose by pose against
reference libraries. This package imports no reference library at import time.

Example:
    >>> import fkcheck
    >>> model = fkcheck.load_model("ur5")
    >>> model.fk([0.0] * model.dof).shape
    (4, 4)
"""

from fkcheck.errors import (
    BackendNotFoundError,
    FkcheckError,
    FrameError,
    JointInputError,
    ModelError,
    UrdfError,
)
from fkcheck.model.read import bundled_model_paths, load_model
from fkcheck.model.types import Joint, Model

__version__ = "0.1.0"

__all__ = [
    "BackendNotFoundError",
    "FkcheckError",
    "FrameError",
    "Joint",
    "JointInputError",
    "Model",
    "ModelError",
    "UrdfError",
    "__version__",
    "bundled_model_paths",
    "load_model",
]
