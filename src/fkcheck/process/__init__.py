"""Other programs and child processes, time-limited and cleaned up.

Owns running a job in a supervised child (:mod:`~fkcheck.process.isolation`,
with the supervisor :mod:`~fkcheck.process._supervisor` that reaps orphans).
May import: the standard library only.
"""

__all__: list[str] = []
