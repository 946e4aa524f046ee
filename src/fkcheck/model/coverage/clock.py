"""The analysis' time limit.

Part of :mod:`fkcheck.model.coverage`.
"""

from __future__ import annotations

import math
import time

from fkcheck.errors import TimeLimitError

__all__: list[str] = []


class _Clock:
    """The analysis' time limit, looked at between its steps.

    A step is at most one decomposition of the model's columns (about a second at
    :data:`~fkcheck.model.types.MAX_JOINTS` joints), or one number's nudge.
    """

    def __init__(self, limit_s: float | None, what: str) -> None:
        self.limit_s, self.what = limit_s, what
        self.deadline = math.inf if limit_s is None else time.monotonic() + limit_s

    def check(self) -> None:
        """Raise :class:`TimeLimitError` once the limit has passed."""
        if time.monotonic() > self.deadline:
            raise TimeLimitError(
                f"per-number evidence of {self.what} did not finish within the check's "
                f"time limit of {self.limit_s:g} s; give it more with --timeout"
            )


_NO_LIMIT = _Clock(None, "")
