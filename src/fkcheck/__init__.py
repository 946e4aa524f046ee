"""fkcheck: cross-validation of robot-arm forward kinematics.

An in-house Denavit–Hartenberg core (NumPy only) compared pose by pose against
reference libraries. This package imports no reference library at import time.

Example:
    >>> import fkcheck
    >>> model = fkcheck.load_model("ur5")
    >>> model.fk([0.0] * model.dof).shape
    (4, 4)
    >>> outcome = fkcheck.check(model, against=["rtb-dh"], samples=100)
    >>> outcome.verdict
    'pass'
    >>> table = fkcheck.model_from_table("2r", [(0.3, 0.0, 0.0, 0.0), (0.2, 0.0, 0.0, 0.0)])
    >>> fkcheck.check(table, against=["rtb-dh"], samples=100).verdict
    'pass'

:func:`check` and :func:`write_report` (with :class:`Outcome`) are the engine's
and the reports' façade, :mod:`fkcheck.api`; they are imported on first use.
"""

from typing import TYPE_CHECKING, Any

from fkcheck.errors import (
    BackendNotFoundError,
    FkcheckError,
    FrameError,
    JointInputError,
    ModelError,
    UrdfError,
)
from fkcheck.model.read import bundled_model_paths, load_model
from fkcheck.model.table import model_from_table
from fkcheck.model.types import Joint, Model

if TYPE_CHECKING:
    from fkcheck.api import Outcome, check, write_report

from fkcheck._version import __version__

_FACADE = ("Outcome", "check", "write_report")


def __getattr__(name: str) -> Any:
    """The façade (:mod:`fkcheck.api`), imported when first used."""
    if name in _FACADE:
        from fkcheck import api

        return getattr(api, name)
    raise AttributeError(f"module 'fkcheck' has no attribute {name!r}")


__all__ = [
    "BackendNotFoundError",
    "FkcheckError",
    "FrameError",
    "Joint",
    "JointInputError",
    "Model",
    "ModelError",
    "Outcome",
    "UrdfError",
    "__version__",
    "bundled_model_paths",
    "check",
    "load_model",
    "model_from_table",
    "write_report",
]
