"""MJCF (MuJoCo's XML): screening, MuJoCo's reading of it as a kinematic tree, and two readers.

* :mod:`fkcheck.mjcf.screen`: the one screening every MJCF goes through
  (limits, includes held to a folder and inlined, geometry stripped);
* :mod:`fkcheck.mjcf.compile`: MuJoCo's compiler on the screened text;
* :mod:`fkcheck.mjcf.tree`: :func:`read_mjcf`, the tree as
  :class:`~fkcheck.urdf.chain.UrdfKinematics`, frame names, joint order;
* :mod:`fkcheck.mjcf.readers`: :func:`mujoco_poses` and :func:`pinocchio_poses`;
* :mod:`fkcheck.mjcf.compare`: the two readers on one file, and which disagrees.
"""

from fkcheck.mjcf.compare import ReaderComparison, ReaderResult, compare_readers
from fkcheck.mjcf.readers import READERS, ReaderError, mujoco_poses, pinocchio_poses
from fkcheck.mjcf.screen import ScreenedMjcf, screen_mjcf
from fkcheck.mjcf.tree import WORLD, MjcfDescription, read_mjcf

__all__ = [
    "READERS",
    "WORLD",
    "MjcfDescription",
    "ReaderComparison",
    "ReaderError",
    "ReaderResult",
    "ScreenedMjcf",
    "compare_readers",
    "mujoco_poses",
    "pinocchio_poses",
    "read_mjcf",
    "screen_mjcf",
]
