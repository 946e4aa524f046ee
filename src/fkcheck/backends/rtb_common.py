"""What the three Robotics Toolbox backends share: the availability test and batched ETS evaluation.

Robotics Toolbox's fast forward kinematics is ``ETS.eval`` (its C extension,
``fknm``). Two facts about it, both read in roboticstoolbox-python 1.5.0's
``ets/cpp-extensions/fknm_nb.cpp`` and confirmed by running it:

* A ``q`` array of shape ``(N, 1)`` is taken as *one* configuration (the C code
  treats a single column like a single row), so a one-joint ETS cannot be
  evaluated over a batch as it is: only the first row would be used.
* A batch of one, shape ``(1, n)``, comes back as ``(4, 4)``, not ``(1, 4, 4)``.

:func:`eval_batch` therefore passes the joint values *padded with one extra zero
column*: ``(N, m + 1)`` for a chain whose joints are indexed ``0 … m-1``. Robotics
Toolbox accepts a ``q`` longer than the largest joint index ("global" joint
addressing, trailing entries ignored), so the padding changes no value and
every batch is at least two columns wide.
"""

from __future__ import annotations

import importlib.util
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.typing import Float
from fkcheck.errors import INSTALL_REFERENCE, BackendUnavailable

__all__ = [
    "INSTALL_HINT",
    "RTB_IMPORTS",
    "eval_batch",
    "import_rtb",
    "padded_q",
    "rtb_unavailable_reason",
]


#: What the Robotics Toolbox backends import lazily; the engine imports these once,
#: in the main thread, before backends start (concurrent first imports of
#: ``roboticstoolbox.ets`` from two threads could end in ``_DeadlockError``).
RTB_IMPORTS = (
    "spatialmath",
    "roboticstoolbox",
    "roboticstoolbox.ets.ET",
    "roboticstoolbox.ets.ETS",
    "roboticstoolbox.tools.urdf",
    "roboticstoolbox.models.URDF.URDFRobot",
)

#: The reason given when Robotics Toolbox is not installed.
INSTALL_HINT = (
    f"Robotics Toolbox for Python (roboticstoolbox) is not installed ({INSTALL_REFERENCE})"
)


def rtb_unavailable_reason() -> str | None:
    """``None`` if Robotics Toolbox can be imported, else why not (without importing it)."""
    if importlib.util.find_spec("roboticstoolbox") is None:
        return INSTALL_HINT
    return None


def import_rtb() -> Any:
    """Import and return :mod:`roboticstoolbox` (about 1.5–2 s the first time).

    Raises:
        BackendUnavailable: It is not installed or fails to import.
    """
    try:
        import roboticstoolbox
    except ImportError as exc:
        raise BackendUnavailable(f"{INSTALL_HINT}: {exc}") from None
    return roboticstoolbox


def padded_q(q: Float, width: int, columns: NDArray[np.intp] | None = None) -> Float:
    """Joint values laid out for :func:`eval_batch`: shape ``(N, width + 1)``, zeros elsewhere.

    Args:
        q: ``(N, n)`` joint values.
        width: Number of joints the robot indexes (its ``n``).
        columns: The column (Robotics Toolbox ``jindex``) of each of ``q``'s
            columns; ``0 … n-1`` when omitted.

    Returns:
        A C-contiguous ``(N, width + 1)`` array; the last column is always zero.
    """
    out = np.zeros((q.shape[0], width + 1))
    if columns is None:
        out[:, : q.shape[1]] = q
    else:
        out[:, columns] = q
    return out


def eval_batch(ets: Any, q_padded: Float) -> Float:
    """``ets.eval`` over a batch, always returning ``(N, 4, 4)``.

    Args:
        ets: A Robotics Toolbox ``ETS``.
        q_padded: Joint values from :func:`padded_q` (one spare column).

    Returns:
        ``(N, 4, 4)`` poses, float64.
    """
    T = np.asarray(ets.eval(q_padded), dtype=np.float64)
    return T.reshape(q_padded.shape[0], 4, 4)
