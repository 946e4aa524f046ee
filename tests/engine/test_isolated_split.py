"""An isolated backend's configurations split over several processes, run at once.

The split is forced here (two cores, a handful of configurations a part) so that
small checks exercise it; the parts' processes are seen through the pids they
write, and none is left running whatever happens to the backend.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends.registry import make_backend
from fkcheck.description.registry import load_description
from fkcheck.engine import runner
from fkcheck.engine.plan import BackendPlan
from fkcheck.engine.runner import run_check
from tests.engine.test_check_engine import ReferenceChain
from tests.processes import LINUX_ONLY, alive, descendants

pytestmark = LINUX_ONLY


class PidChain(ReferenceChain):
    """The table's own poses, from an isolated process that writes its pid down."""

    name = "pid-chain"
    isolated = True

    def frame_poses(self, model, q, frames):
        where = Path(os.environ["FKCHECK_TEST_PIDS"])
        (where / f"{os.getpid()}-{q.shape[0]}").write_text(repr(float(q[0, 0])))
        return super().frame_poses(model, q, frames)


class EnvChain(ReferenceChain):
    """The table's own poses, from an isolated process that writes its thread variables down."""

    name = "env-chain"
    isolated = True

    def frame_poses(self, model, q, frames):
        where = Path(os.environ["FKCHECK_TEST_PIDS"])
        names = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")
        (where / str(os.getpid())).write_text(" ".join(os.environ.get(n, "-") for n in names))
        return super().frame_poses(model, q, frames)


class HangInSecondPart(ReferenceChain):
    """Answers at once for the first part; the second part's process hangs."""

    name = "hang-in-second-part"
    isolated = True

    def frame_poses(self, model, q, frames):
        where = Path(os.environ["FKCHECK_TEST_PIDS"])
        (where / str(os.getpid())).write_text("")
        if float(q[0, 0]) != FIRST_Q0:
            time.sleep(60)
        return super().frame_poses(model, q, frames)


class CrashInSecondPart(ReferenceChain):
    name = "crash-in-second-part"
    isolated = True

    def frame_poses(self, model, q, frames):
        if float(q[0, 0]) != FIRST_Q0:
            os._exit(3)
        return super().frame_poses(model, q, frames)


#: q[0, 0] of the check's first configuration (its zero pose comes first).
FIRST_Q0 = 0.0


@pytest.fixture
def two_parts(monkeypatch, tmp_path):
    """Two cores, and 10 configurations a part at least; pids written to ``tmp_path``."""
    monkeypatch.setattr(runner, "usable_cores", lambda: 2)
    monkeypatch.setattr(runner, "SPLIT_MIN_CONFIGS", 10)
    monkeypatch.setenv("FKCHECK_TEST_PIDS", str(tmp_path))
    return tmp_path


@pytest.fixture(scope="module")
def ur5():
    return load_model("ur5")


def test_split_is_contiguous_in_order_and_only_when_each_part_is_worth_a_process(monkeypatch):
    monkeypatch.setattr(runner, "usable_cores", lambda: 2)
    least = runner.SPLIT_MIN_CONFIGS
    assert runner._split(2 * least - 1) == [(0, 2 * least - 1)]
    assert runner._split(10_081) == [(0, 5_040), (5_040, 10_081)]
    monkeypatch.setattr(runner, "usable_cores", lambda: 8)
    assert runner._split(3 * least) == [(0, least), (least, 2 * least), (2 * least, 3 * least)]
    monkeypatch.setattr(runner, "usable_cores", lambda: 1)
    assert runner._split(100 * least) == [(0, 100 * least)]


def test_the_parts_run_in_two_processes_and_join_to_the_unsplit_answer(ur5, two_parts):
    check = run_check(ur5, [PidChain(), ReferenceChain()], samples=100)
    split, threaded = check.backends
    assert split.status == threaded.status == "pass"
    np.testing.assert_array_equal(split.position_error_m, threaded.position_error_m)
    np.testing.assert_array_equal(split.rotation_error_rad, threaded.rotation_error_rad)
    written = sorted(p.name for p in two_parts.iterdir())
    n = check.q.shape[0]
    assert len(written) == 2
    assert {int(w.split("-")[0]) for w in written} != {os.getpid()}
    assert len({w.split("-")[0] for w in written}) == 2  # two processes
    assert sorted(int(w.split("-")[1]) for w in written) == [n // 2, n - n // 2]
    # The part tests below tell the first part from the second by its first q.
    assert check.q[0, 0] == FIRST_Q0 != check.q[n // 2, 0]
    firsts = sorted(float((two_parts / w).read_text()) for w in written)
    assert FIRST_Q0 in firsts
    assert len(set(firsts)) == 2


def test_processes_caps_the_parts_and_one_keeps_the_backend_in_one_process(
    ur5, two_parts, monkeypatch
):
    least = runner.SPLIT_MIN_CONFIGS
    monkeypatch.setattr(runner, "usable_cores", lambda: 8)
    assert runner._split(3 * least, processes=2) == [
        (0, 3 * least // 2),
        (3 * least // 2, 3 * least),
    ]
    assert runner._split(3 * least, processes=1) == [(0, 3 * least)]
    check = run_check(ur5, [PidChain(), ReferenceChain()], samples=100, processes=1)
    assert check.options.processes == 1
    split, threaded = check.backends
    assert split.status == threaded.status == "pass"
    np.testing.assert_array_equal(split.position_error_m, threaded.position_error_m)
    written = [p.name for p in two_parts.iterdir()]
    assert len(written) == 1  # one process, all configurations
    assert int(written[0].split("-")[1]) == check.q.shape[0]


def test_a_part_that_hangs_times_the_backend_out_and_every_part_is_killed(ur5, two_parts):
    start = time.perf_counter()
    check = run_check(ur5, [HangInSecondPart()], samples=40, timeout_s=3)
    assert time.perf_counter() - start < 20
    assert check.backends[0].status == "error"
    assert check.backends[0].message == "timed out after 3 s"
    pids = [int(p.name) for p in two_parts.iterdir()]
    assert len(pids) == 2
    deadline = time.monotonic() + 10
    while any(alive(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not any(alive(pid) for pid in pids)
    assert descendants(os.getpid()) == []


def test_a_part_that_dies_is_the_backends_error(ur5, two_parts):
    check = run_check(ur5, [CrashInSecondPart(), ReferenceChain()], samples=40)
    crashed, good = check.backends
    assert (crashed.status, crashed.message) == (
        "error",
        "its process exited with code 3 without an answer",
    )
    assert good.status == "pass"


@pytest.mark.parametrize(("processes", "each"), [(None, "1 1 1 1"), (1, "- - - -")])
def test_the_parts_side_by_side_share_the_cores_between_their_thread_pools(
    ur5, two_parts, monkeypatch, processes, each
):
    # Two parts on two cores: each process's BLAS, OpenMP and numba run one thread, not
    # two each (four threads on two cores, waiting on each other). One part inherits.
    from fkcheck.process import threads

    monkeypatch.setattr(threads, "usable_cores", lambda: 2)
    for name in (*threads.THREAD_VARIABLES, "NUMBA_NUM_THREADS"):
        monkeypatch.delenv(name, raising=False)
    check = run_check(ur5, [EnvChain()], samples=100, processes=processes)
    assert check.backends[0].status == "pass"
    written = [p.read_text() for p in two_parts.iterdir()]
    assert written == [each] * (2 if processes is None else 1)


class CostedPidChain(PidChain):
    """:class:`PidChain` with a declared cost, µs a configuration of a 6-joint arm."""

    name = "costed-pid-chain"

    def __init__(self, pose_cost_us: float) -> None:
        self.pose_cost_us = pose_cost_us


def _pids(where: Path) -> set[int]:
    return {int(p.name.split("-")[0]) for p in where.iterdir()}


def _declared_s(backend: CostedPidChain, configurations: int) -> float:
    return backend.pose_cost_us * 1e-6 * configurations  # UR5: six joints, the unit


def test_a_share_under_half_a_second_runs_in_the_engines_process(ur5, two_parts):
    cheap = CostedPidChain(10.0)  # less than a process costs to start
    check = run_check(ur5, [cheap, ReferenceChain()], samples=10)
    assert _declared_s(cheap, check.q.shape[0]) < runner.IN_PROCESS_MAX_S
    assert [r.status for r in check.backends] == ["pass", "pass"]
    assert _pids(two_parts) == {os.getpid()}


def test_a_share_of_half_a_second_or_more_runs_in_processes_of_its_own(ur5, two_parts):
    dear = CostedPidChain(10_000.0)
    check = run_check(ur5, [dear, ReferenceChain()], samples=100)
    assert _declared_s(dear, check.q.shape[0]) >= runner.IN_PROCESS_MAX_S
    assert [r.status for r in check.backends] == ["pass", "pass"]
    assert os.getpid() not in _pids(two_parts)
    assert len(_pids(two_parts)) == 2  # split over the two cores, as before


def test_an_isolated_backend_without_a_declared_cost_always_runs_in_its_own_process(ur5, two_parts):
    run_check(ur5, [PidChain(), ReferenceChain()], samples=2)
    assert os.getpid() not in _pids(two_parts)


@pytest.mark.parametrize(
    ("full_s", "compared", "own"),
    [
        (None, 64, True),  # no declared cost
        (0.49, 64, False),
        (0.5, 64, True),
        (4.0, 8, True),  # 0.5 s of its share
        (4.0, 7, False),  # 0.44 s of its share
    ],
)
def test_in_own_processes_weighs_the_declared_cost_of_the_share(full_s, compared, own):
    plan = BackendPlan("x", compared, 64, 0, full_s, None, 120.0)
    assert runner.in_own_processes(PidChain(), plan) is own
    assert runner.in_own_processes(ReferenceChain(), plan) is False  # not isolated


def test_a_long_description_keeps_a_cheap_share_in_processes_of_its_own():
    # The declared cost counts poses only; a reader's load of a long description does
    # not stop at the time limit in a thread.
    plan = BackendPlan("x", 64, 64, 0, 0.04, None, 120.0)
    limit = runner.IN_PROCESS_MAX_DESCRIPTION_CHARS
    assert runner.in_own_processes(PidChain(), plan, limit) is False
    assert runner.in_own_processes(PidChain(), plan, limit + 1) is True
    assert runner.in_own_processes(ReferenceChain(), plan, limit + 1) is False  # not isolated


def _padded_ur5(tmp_path: Path, links: int) -> Path:
    """ur5.toml on its URDF with ``links`` extra fixed links (no visuals) on ``base_link``."""
    from tests.hostile.test_hostile_urdf import UR5_TEXT, joint, model_with_urdf

    extra = "".join(
        f'<link name="x{i}"/>' + joint(f"xj{i}", "base_link", f"x{i}") for i in range(links)
    )
    return model_with_urdf(tmp_path, UR5_TEXT.replace("</robot>", extra + "</robot>"))


@pytest.mark.parametrize(("links", "own"), [(0, False), (1_000, True)])
def test_yourdfpy_on_a_description_past_the_limit_runs_in_its_own_process(
    tmp_path, monkeypatch, links, own
):
    pytest.importorskip("yourdfpy")
    model = load_model(_padded_ur5(tmp_path, links))
    chars = len(load_description(model, language="urdf").text)
    assert (chars > runner.IN_PROCESS_MAX_DESCRIPTION_CHARS) is own, chars
    started = []
    real = runner.run_isolated
    monkeypatch.setattr(runner, "run_isolated", lambda *a, **k: started.append(1) or real(*a, **k))
    check = run_check(model, [make_backend("yourdfpy-urdf")], samples=64)
    assert check.backends[0].status == "pass", check.backends[0].message
    assert bool(started) is own


def test_every_bundled_urdf_is_short_enough_to_run_in_the_engines_process():
    # 64 poses of a bundled model stay in-process (the reason the split exists).
    from fkcheck.model.read import bundled_model_paths

    longest = 0
    for path in bundled_model_paths().values():
        model = load_model(path)
        if model.urdf is not None:
            longest = max(longest, len(load_description(model, language="urdf").text))
    assert 0 < longest <= runner.IN_PROCESS_MAX_DESCRIPTION_CHARS
