"""Versions of fkcheck and the libraries it checks against, read from package metadata.

The list comes from the backend registry
(:func:`fkcheck.backends.registry.library_versions`): the core's distributions
and those providing every registered backend's libraries, read without
importing them.
"""

from __future__ import annotations

from fkcheck.backends.registry import library_versions

__all__ = ["library_versions"]
