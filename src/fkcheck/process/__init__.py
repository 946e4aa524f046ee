"""Other programs and child processes, time-limited and cleaned up.

Owns running a program under a supervisor that reaps orphans
(:mod:`~fkcheck.process.supervise`, with the supervisor process itself in
:mod:`~fkcheck.process._supervisor`) and running a pickled Python job in a
supervised child (:mod:`~fkcheck.process.isolation`), and how many CPUs it may
use (:mod:`~fkcheck.process.cpus`).
May import: the standard library only.
"""

__all__: list[str] = []
