"""The in-house kinematics: fkcheck's own maths, independent of every reference library.

Owns the batched DH forward kinematics (:mod:`~fkcheck.core.dh`, JIT kernels in
:mod:`~fkcheck.core._kernels`), the one rotation vocabulary with its gimbal-lock
rule (:mod:`~fkcheck.core.geometry`), pose formats, error metrics and the named
tolerances. May import: NumPy, SciPy, numba, :mod:`fkcheck.io` (text and
numbers at the boundary), :mod:`fkcheck.errors`. Nothing else of fkcheck, so no
reference library's maths can leak in.
"""

__all__: list[str] = []
