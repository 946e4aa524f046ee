"""The per-number evidence on a slow machine: the clock ends it, it never changes it.

The analysis looks at its time limit between steps (``_Clock``). Whatever the
clock says, :func:`~fkcheck.model.coverage.coverage` either returns the very
analysis it returns on an idle machine or raises :class:`TimeLimitError` (exit 2):
a busy machine can never make a number read ``verified`` that is not. The clock
is simulated (``time.monotonic`` jumps), so these tests do not depend on the load.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.core.tolerances import DEFAULT_TOL_POS_M, DEFAULT_TOL_ROT_RAD
from fkcheck.errors import TimeLimitError
from fkcheck.model.coverage import Coverage, coverage
from fkcheck.model.coverage import clock as coverage_clock  # where the analysis reads the time

#: A time limit no simulated jump below reaches, seconds.
LIMIT_S = 60.0


class _Clock:
    """``time.monotonic`` of a machine that stalls: ``jump`` seconds at the ``at``-th look."""

    def __init__(self, at: float = float("inf"), jump: float = 0.0, step: float = 0.0) -> None:
        self.at, self.jump, self.step = at, jump, step
        self.looks = 0
        self.now = 1000.0

    def monotonic(self) -> float:
        self.looks += 1
        self.now += self.step
        if self.looks == self.at:
            self.now += self.jump
        return self.now


def _held_ur5():
    """UR5 with its elbow held at ``[0.3, 0.3]``: numbers the limits hide, numbers verified."""
    from dataclasses import replace

    model = load_model("ur5")
    joints = list(model.joints)
    joints[2] = replace(joints[2], limits=(0.3, 0.3))
    return replace(model, joints=tuple(joints))


def _run(model, clock: _Clock, monkeypatch: pytest.MonkeyPatch) -> Coverage:
    monkeypatch.setattr(coverage_clock, "time", SimpleNamespace(monotonic=clock.monotonic))
    q = np.random.default_rng(7).uniform(-1.0, 1.0, (40, model.dof))
    return coverage(
        model, "world", "tcp", DEFAULT_TOL_POS_M, DEFAULT_TOL_ROT_RAD, q=q, time_limit_s=LIMIT_S
    )


def _statuses(c: Coverage) -> list[tuple[str, str, str, tuple[str, ...]]]:
    return [(n.name, n.status, n.reason, n.trades_with) for n in c.numbers]


@pytest.fixture(scope="module")
def idle() -> tuple[list[tuple[str, str, str, tuple[str, ...]]], int]:
    """The held UR5's analysis on a clock that never moves, and how often it looked."""
    with pytest.MonkeyPatch.context() as mp:
        clock = _Clock()
        result = _run(_held_ur5(), clock, mp)
    return _statuses(result), clock.looks


def test_the_idle_analysis_has_numbers_of_every_kind(idle):
    """The analysis under test is worth testing: some numbers verified, some held by the limits."""
    statuses, looks = idle
    assert {s for _, s, _, _ in statuses} == {"verified", "not-identifiable"}
    assert "limits" in {r for _, _, r, _ in statuses}
    assert looks > 20  # the clock is looked at between steps: every jump below lands in one


def test_a_clock_that_creeps_within_the_limit_changes_nothing(idle, monkeypatch):
    """A slow machine that stays within the limit gets the idle machine's analysis, exactly."""
    statuses, looks = idle
    slow = _Clock(step=LIMIT_S / (2 * looks))  # half the limit spent, spread over every step
    assert _statuses(_run(_held_ur5(), slow, monkeypatch)) == statuses


@pytest.mark.parametrize("fraction", [0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0])
def test_a_stall_past_the_limit_at_any_step_ends_the_analysis_in_one_line(
    idle, monkeypatch, fraction
):
    """The limit passed at any step is TimeLimitError: never a smaller or different analysis."""
    _, looks = idle
    at = 2 + round(fraction * (looks - 2))  # the 1st look sets the deadline; the last one ends it
    with pytest.raises(TimeLimitError, match=r"did not finish within the check's time limit of "
                       r"60 s; give it more with --timeout$"):  # fmt: skip
        _run(_held_ur5(), _Clock(at=at, jump=LIMIT_S + 1.0), monkeypatch)


def test_any_clock_gives_the_idle_analysis_or_the_time_limit(idle, monkeypatch):
    """Seeded random clocks (steps and stalls): each outcome is the idle one or TimeLimitError."""
    statuses, looks = idle
    rng = np.random.default_rng(20261128)
    outcomes = []
    for _ in range(12):
        clock = _Clock(
            at=int(rng.integers(2, looks + 1)),
            jump=float(rng.uniform(0.0, 2.0 * LIMIT_S)),
            step=float(rng.uniform(0.0, LIMIT_S / looks)),
        )
        try:
            outcomes.append(_statuses(_run(_held_ur5(), clock, monkeypatch)) == statuses)
        except TimeLimitError:
            outcomes.append("time limit")
    assert set(outcomes) <= {True, "time limit"}
    assert set(outcomes) == {True, "time limit"}, outcomes  # both outcomes were exercised


def test_the_analysis_reads_no_other_clock(monkeypatch):
    """Only the time limit reads the time: perf_counter and wall time are never consulted."""
    import time

    def forbidden() -> float:
        raise AssertionError("the per-number evidence read a clock")

    for name in ("perf_counter", "time", "process_time"):
        monkeypatch.setattr(time, name, forbidden)
    creep = _Clock(step=0.001)
    assert _statuses(_run(_held_ur5(), creep, monkeypatch))  # ran with its own clock only
    assert creep.looks > 20
