"""A check on a slow machine: time can only make its claim smaller, never turn it "verified".

Every place a check reads a clock, with the slowness simulated (a clock that
jumps, a backend that never answers), so nothing here depends on the machine's
load:

* the plan (:mod:`fkcheck.engine.plan`) reads no clock at all: the same subset
  whatever the time;
* the per-number evidence, in ``prepare`` and again in ``judge`` (on what the
  table's evidence answered), ends in :class:`TimeLimitError` past its limit:
  no result, exit 2, never a smaller analysis;
* a backend past its time limit is an ``error`` that answered nothing: the table
  it would have vouched for is not checked, and the verdict is ``error``.
"""

from __future__ import annotations

import threading
import time
from types import SimpleNamespace

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends.base import BackendDefaults
from fkcheck.core.dh import fk_reference
from fkcheck.core.geometry import translation
from fkcheck.engine.plan import plan_check
from fkcheck.engine.runner import run_check
from fkcheck.errors import TimeLimitError
from fkcheck.model.coverage import clock as coverage_clock  # where the analysis reads the time
from fkcheck.model.frames import frame_poses_from_dh

#: The per-number evidence's limit in these checks (EVIDENCE_MIN_S is the floor), seconds.
TIMEOUT_S = 30.0
#: A backend's time limit short enough for a test, long enough for 20 UR5 poses on a busy machine.
SHORT_TIMEOUT_S = 2.0
#: A declared cost no budget fits: the backend is planned the structured configurations.
PRICELESS_US = 1e9


class TableEvidence(BackendDefaults):
    """Table evidence that agrees: the table's own chain (a stand-in for a URDF reader)."""

    name = "table-evidence"
    method = "fk_reference"
    evidence = "table"
    reads = "dh"

    def __init__(self, name: str = "table-evidence", tip_T: np.ndarray | None = None) -> None:
        self.name = name
        self.tip_T = tip_T

    def unavailable_reason(self, model):
        return None

    def frame_poses(self, model, q, frames):
        poses = frame_poses_from_dh(
            model, fk_reference(model.chain, q, all_frames=True), fk_reference(model.chain, q),
            frames,
        )  # fmt: skip
        if self.tip_T is not None:
            poses[1] = poses[1] @ self.tip_T
        return poses


class Stalled(TableEvidence):
    """Table evidence on a machine so busy it never answers within its time limit."""

    def __init__(self, name: str, release: threading.Event, tip_T=None) -> None:
        super().__init__(name, tip_T)
        self.release = release

    def frame_poses(self, model, q, frames):
        self.release.wait(60.0)  # released when the test ends: the thread does not linger
        return super().frame_poses(model, q, frames)


class _Jumping:
    """``time.monotonic`` for the per-number evidence: still until ``stall()``, then +1 h a look."""

    def __init__(self) -> None:
        self.now, self.stalled = 1000.0, False

    def monotonic(self) -> float:
        if self.stalled:
            self.now += 3600.0
        return self.now

    def stall(self) -> None:
        self.stalled = True


@pytest.fixture(scope="module")
def ur5():
    return load_model("ur5")


@pytest.fixture
def release():
    event = threading.Event()
    yield event
    event.set()


def test_the_plan_reads_no_clock(ur5, monkeypatch):
    """The subset a backend is given is decided without a clock: the same on any machine."""
    backend = TableEvidence()
    backend.pose_cost_us = PRICELESS_US  # type: ignore[attr-defined]
    origin = ["named"] * 5 + ["random"] * 995
    idle = plan_check([backend], origin, dof=ur5.dof, timeout_s=TIMEOUT_S)

    def forbidden() -> float:
        raise AssertionError("the plan read a clock")

    for name in ("monotonic", "perf_counter", "time", "process_time"):
        monkeypatch.setattr(time, name, forbidden)
    busy = plan_check([backend], origin, dof=ur5.dof, timeout_s=TIMEOUT_S)
    assert busy == idle
    assert (busy.backends[0].compared, busy.backends[0].total) == (5, 1000)


def test_per_number_evidence_past_its_limit_ends_the_check_before_any_backend(ur5, monkeypatch):
    """A stall in ``prepare``'s analysis: TimeLimitError, no result, no backend run."""
    clock = _Jumping()
    clock.stall()
    monkeypatch.setattr(coverage_clock, "time", SimpleNamespace(monotonic=clock.monotonic))
    ran = []

    class Watched(TableEvidence):
        def frame_poses(self, model, q, frames):
            ran.append(len(q))
            return super().frame_poses(model, q, frames)

    with pytest.raises(TimeLimitError, match=r"did not finish within the check's time limit of "
                       r"30 s; give it more with --timeout$"):  # fmt: skip
        run_check(ur5, [Watched()], samples=20, timeout_s=TIMEOUT_S)
    assert ran == []


def test_per_number_evidence_past_its_limit_in_judge_is_no_result(ur5, monkeypatch):
    """A subset's numbers are analysed again in ``judge``: a stall there is TimeLimitError too.

    The machine stalls while the backend runs, after ``prepare``'s analysis
    finished: the check on a subset then ends without a result rather than with
    the full set's analysis (which would cover more than the subset tested).
    """
    clock = _Jumping()
    monkeypatch.setattr(coverage_clock, "time", SimpleNamespace(monotonic=clock.monotonic))

    class StallsWhileRunning(TableEvidence):
        pose_cost_us = PRICELESS_US

        def frame_poses(self, model, q, frames):
            clock.stall()
            return super().frame_poses(model, q, frames)

    class OnSubset(TableEvidence):
        pose_cost_us = PRICELESS_US

    idle = run_check(ur5, [OnSubset()], samples=20, timeout_s=TIMEOUT_S)
    assert idle.backends[0].status == "pass"
    assert idle.backends[0].subset is not None  # judge analyses the subset again: the stall's step
    assert not clock.stalled
    with pytest.raises(TimeLimitError, match=r"time limit of 30 s") as info:
        run_check(ur5, [StallsWhileRunning()], samples=20, timeout_s=TIMEOUT_S)
    assert any(entry.name == "judge" for entry in info.traceback)  # after the backend ran


def test_table_evidence_that_never_answers_checks_no_table(ur5, release):
    """The only table evidence past its time limit: table not checked, verdict error."""
    check = run_check(ur5, [Stalled("stalled", release)], samples=20, timeout_s=SHORT_TIMEOUT_S)
    (stalled,) = check.backends
    assert (stalled.status, stalled.message) == ("error", "timed out after 2 s")
    assert stalled.subset is None
    assert check.evidence.table.status == "not-checked"
    assert check.evidence.table.unanswered == ("stalled",)
    assert check.verdict == "error"


def test_a_disagreeing_backend_that_times_out_never_makes_the_check_pass(ur5, release):
    """Idle, a wrong reader fails the check; stalled, the check is an error, never a pass.

    The agreeing reader still vouches for what it compared (``table`` verified by
    it, the stalled one named as unanswered): that claim is no larger than what
    answered, and the verdict says the check did not finish.
    """
    shift = translation(0.0, 0.0, 1e-3)
    idle = run_check(
        ur5, [TableEvidence("agrees"), TableEvidence("wrong", shift)], samples=20,
        timeout_s=SHORT_TIMEOUT_S,
    )  # fmt: skip
    assert (idle.verdict, idle.evidence.table.status) == ("fail", "failed")
    busy = run_check(
        ur5, [TableEvidence("agrees"), Stalled("wrong", release, shift)], samples=20,
        timeout_s=SHORT_TIMEOUT_S,
    )  # fmt: skip
    assert busy.verdict == "error"
    assert busy.evidence.table.agreed == ("agrees",)
    assert busy.evidence.table.unanswered == ("wrong",)
