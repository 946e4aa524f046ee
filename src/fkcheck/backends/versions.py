"""The versions a run depends on: Python, fkcheck's core and every registered backend's library."""

from __future__ import annotations

import platform
from importlib import metadata

from fkcheck.backends.registration import registrations

__all__ = ["CORE_DISTRIBUTIONS", "library_versions"]


#: Distributions every check relies on, whatever its backends: fkcheck, its core, its plots.
CORE_DISTRIBUTIONS = ("fkcheck", "numpy", "numba", "scipy", "matplotlib")


def library_versions() -> dict[str, str]:
    """Python's version, then each distribution's: the core's and every registered backend's.

    A built-in backend names its distributions (``distributions``); a third-party
    one's own distribution is listed. Nothing is imported; a distribution that is
    absent reads ``"not installed"``.
    """
    wanted: list[str] = list(CORE_DISTRIBUTIONS)
    for r in registrations():
        if r.origin != "fkcheck":  # its own distribution: its code runs only when it is used
            names = [r.origin.rpartition(" ")[0]]
        else:
            names = list(r.declared("distributions") or ())
        wanted += [name for name in names if name and name not in wanted]
    out = {"Python": platform.python_version()}
    for dist in wanted:
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out
