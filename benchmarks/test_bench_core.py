"""pytest-benchmark timings of the DH core and its peers (not part of the test session).

Run with ``python -m pytest benchmarks`` (add ``--benchmark-json PATH`` to keep the
numbers). Each benchmark also checks its result against the plain reference chain,
so a fast wrong answer cannot pass; nothing here asserts a time.
"""

from __future__ import annotations

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.bench import peers
from fkcheck.core import dh
from fkcheck.core.tolerances import FAST_CORE
from fkcheck.model.sampling import sampling_box

N_BATCH = 1_000_000


@pytest.fixture(scope="module")
def ur5():
    return load_model("ur5")


@pytest.fixture(scope="module")
def q(ur5):
    lo, hi = sampling_box(ur5)
    return np.random.default_rng(0).uniform(lo, hi, size=(N_BATCH, ur5.dof))


@pytest.fixture(scope="module")
def jit():
    assert dh.load_jit(), dh.jit_status()


def check(poses, model, q):
    """Entries within FAST_CORE of fk_reference on a sample of the poses."""
    idx = np.linspace(0, q.shape[0] - 1, min(q.shape[0], 2000)).astype(int)
    expected = dh.fk_reference(model.chain, q[idx])
    assert np.abs(np.asarray(poses)[idx] - expected).max() <= FAST_CORE


@pytest.mark.benchmark(group="batch, 1e6 UR5 poses")
def test_jit_batch_into_buffer(benchmark, jit, ur5, q):
    out = np.empty((q.shape[0], 4, 4))
    benchmark.pedantic(dh.fk, args=(ur5.chain, q), kwargs={"out": out}, rounds=10, warmup_rounds=1)
    check(out, ur5, q)


@pytest.mark.benchmark(group="batch, 1e6 UR5 poses")
def test_jit_batch_allocating(benchmark, jit, ur5, q):
    poses = benchmark.pedantic(dh.fk, args=(ur5.chain, q), rounds=10, warmup_rounds=1)
    check(poses, ur5, q)


@pytest.mark.benchmark(group="batch, 1e5 UR5 poses")
def test_numpy_path(benchmark, ur5, q):
    poses = benchmark.pedantic(dh.fk_numpy, args=(ur5.chain, q[:100_000]), rounds=5)
    check(poses, ur5, q[:100_000])


@pytest.mark.benchmark(group="batch, 1e5 UR5 poses")
def test_rtb_ets_eval(benchmark, ur5, q):
    pytest.importorskip("roboticstoolbox")
    ets = peers.rtb_robot(ur5).ets()
    poses = benchmark.pedantic(ets.eval, args=(q[:100_000],), rounds=5)
    check(poses, ur5, q[:100_000])


@pytest.mark.benchmark(group="batch, 1e4 UR5 poses")
def test_reference_chain(benchmark, ur5, q):
    poses = benchmark.pedantic(dh.fk_reference, args=(ur5.chain, q[:10_000]), rounds=5)
    check(poses, ur5, q[:10_000])


@pytest.mark.benchmark(group="batch, 1e4 UR5 poses")
def test_pinocchio_loop(benchmark, ur5, q):
    pin = pytest.importorskip("pinocchio")
    model = peers.pinocchio_model(ur5)
    data = model.createData()
    tcp = model.getFrameId("tcp")
    rows = list(q[:10_000])
    poses = np.empty((len(rows), 4, 4))

    def loop():
        for k, row in enumerate(rows):
            pin.forwardKinematics(model, data, row)
            pin.updateFramePlacements(model, data)
            poses[k] = data.oMf[tcp].homogeneous

    benchmark.pedantic(loop, rounds=5)
    check(poses, ur5, q[:10_000])


@pytest.mark.benchmark(group="one pose")
def test_one_pose_jit(benchmark, jit, ur5, q):
    T = benchmark(ur5.fk, q[0])
    check(T[None], ur5, q[:1])


@pytest.mark.benchmark(group="one pose")
def test_one_pose_python_path(benchmark, jit, ur5, q, monkeypatch):
    monkeypatch.setattr(dh, "_jit", None)  # the path taken before the JIT is loaded
    T = benchmark(ur5.fk, q[0])
    check(T[None], ur5, q[:1])
