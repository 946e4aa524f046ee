"""The cross-check: sample, run every backend, compare pose by pose, keep the evidence.

Owns the run (:mod:`~fkcheck.engine.runner`: threads, time limits, isolated
backends), the results (:mod:`~fkcheck.engine.results`), the verdict and what it
proved (:mod:`~fkcheck.engine.verdict`) and the evidence a report shows
(:mod:`~fkcheck.engine.evidence`: worst configurations with every backend's
pose, where two chains part, joint axes against the URDF — gathered once,
during the check). May import: everything below it (:mod:`fkcheck.backends`,
:mod:`fkcheck.urdf`, :mod:`fkcheck.model`, :mod:`fkcheck.core`,
:mod:`fkcheck.io`, :mod:`fkcheck.process`); never the diagnosis, the reports
or the command line.
"""

__all__: list[str] = []
