"""Benchmarks of the in-house core against the reference libraries, like for like.

Owns the runs (:mod:`~fkcheck.bench.harness`: the in-house contenders, the
memory bound, :func:`~fkcheck.bench.harness.run_bench`; :mod:`~fkcheck.bench.jacobian`:
``fkcheck bench --jacobian``), the peers built by the
backends' own builders (:mod:`~fkcheck.bench.peers`), the rows and how each
time is taken (:mod:`~fkcheck.bench.timing`) and the machine facts recorded
beside them (:mod:`~fkcheck.bench.machine`).
May import: :mod:`fkcheck.backends` (to build each peer the way the check does),
:mod:`fkcheck.model`, :mod:`fkcheck.core`, :mod:`fkcheck.urdf`.
"""

__all__: list[str] = []
