"""MuJoCo's compiler run on a screened MJCF text: the ``mjModel`` the tree and ``mujoco-mjcf`` read.

MuJoCo resolves MJCF's semantics — ``<default>`` classes and ``childclass``,
``<compiler angle>`` (degrees unless ``angle="radian"``), ``eulerseq``,
``quat`` (w x y z), ``axisangle``, ``xyaxes``, ``zaxis``, ``euler``, ``<frame>``,
joint ``ref``, ``autolimits`` — and fkcheck reads the compiled numbers
(``body_pos``, ``body_quat``, ``jnt_pos``, ``jnt_axis``, ``qpos0``, ``site_pos``,
``site_quat`` …) instead of implementing them again. Only the screened text
(:mod:`fkcheck.mjcf.screen`) is compiled, through ``MjSpec.from_string``: it
names no file, so MuJoCo opens none.

The screen drops ``<inertial>`` and ``<geom>``, so moving bodies would be
massless, which MuJoCo refuses; ``compiler.boundmass`` and
``compiler.boundinertia`` give every body the same small mass and inertia, as
the ``mujoco-urdf`` backend does. Kinematics reads neither.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from fkcheck.errors import MjcfError, missing_extra

__all__ = ["BODY_INERTIA", "BODY_MASS", "compile_mjcf", "mujoco_module", "mujoco_names"]

#: The mass [kg] every body gets (the MJCF's are dropped): any value above mjMINVAL would do.
BODY_MASS = 1.0
#: The principal inertia [kg·m²] every body gets.
BODY_INERTIA = 1.0


def mujoco_module() -> Any:
    """The ``mujoco`` module.

    Raises:
        MissingExtraError: MuJoCo is not installed (it comes with the reference extra).
    """
    try:
        import mujoco
    except ImportError as exc:
        missing = missing_extra(exc)
        if missing is None:
            raise
        raise missing from None
    return mujoco


def compile_mjcf(text: str, path: Path | str) -> Any:
    """The ``mjModel`` MuJoCo compiles from a screened MJCF text.

    Args:
        text: :attr:`fkcheck.mjcf.screen.ScreenedMjcf.text` (never a raw file).
        path: The MJCF file, for messages.

    Raises:
        MjcfError: MuJoCo refuses the model (its message, one line; its line
            numbers are the screened text's, not the file's).
        MissingExtraError: MuJoCo is not installed.
    """
    mujoco = mujoco_module()
    try:
        spec = mujoco.MjSpec.from_string(text)
        spec.compiler.boundmass = BODY_MASS
        spec.compiler.boundinertia = BODY_INERTIA
        return spec.compile()
    except ValueError as exc:
        message = " ".join(str(exc).split())
        raise MjcfError(path, f"MuJoCo {mujoco.__version__} cannot compile it: {message}") from None


def mujoco_names(mjmodel: Any, kind: str, count: int) -> list[str]:
    """The names of ``count`` objects of one kind (``"body"``, ``"joint"``, ``"site"``), by id.

    An unnamed object's name is ``""``.
    """
    mujoco = mujoco_module()
    obj = getattr(mujoco.mjtObj, f"mjOBJ_{kind.upper()}")
    return [mujoco.mj_id2name(mjmodel, obj, i) or "" for i in range(count)]
