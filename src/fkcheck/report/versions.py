"""Versions of fkcheck and the libraries it checks against, read from package metadata.

:mod:`importlib.metadata` reads the installed distributions' metadata without
importing them, so asking for Pinocchio's version does not load Pinocchio.
"""

from __future__ import annotations

import platform
from importlib import metadata

__all__ = ["DISTRIBUTIONS", "library_versions"]

#: Shown name → distribution name on PyPI.
DISTRIBUTIONS: dict[str, str] = {
    "fkcheck": "fkcheck",
    "NumPy": "numpy",
    "Robotics Toolbox": "roboticstoolbox-python",
    "Pinocchio": "pin",
    "yourdfpy": "yourdfpy",
    "SciPy": "scipy",
    "Matplotlib": "matplotlib",
}


def library_versions() -> dict[str, str]:
    """Shown name → installed version (``"not installed"`` when absent), plus Python's."""
    out: dict[str, str] = {"Python": platform.python_version()}
    for shown, dist in DISTRIBUTIONS.items():
        try:
            out[shown] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[shown] = "not installed"
    return out
