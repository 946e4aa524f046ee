"""Benchmarks of the in-house core against the reference libraries, like for like.

May import: :mod:`fkcheck.backends` (to build each peer the way the check does),
:mod:`fkcheck.model`, :mod:`fkcheck.core`, :mod:`fkcheck.urdf`.
"""

__all__: list[str] = []
