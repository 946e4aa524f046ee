"""Timing the in-house DH core against its peers, on the same configurations.

Each *contender* computes ``world_T_tcp`` (or, for a URDF, the model's check
frame pair) for the first ``n`` of one seeded set of configurations; slow
contenders get a smaller ``n`` (:data:`PEER_POSES` caps it) and say so. Every
time is the median of ``repeat`` runs after one warm-up run
(:func:`~fkcheck.bench.timing.median_seconds`), and every peer's result is
compared with the in-house core's on the same poses (largest position
difference).

The in-house contenders are timed here; the peers (Robotics Toolbox,
Pinocchio, yourdfpy, each built by its backend's own builder) are in
:mod:`fkcheck.bench.peers`. A peer whose library is not installed is reported
as skipped, with the reason; a peer that is installed but fails is an error,
and the bench fails (exit 1): a crash must not read as "not measured".

Ratios are like for like. The headline compares the in-house batch with
Robotics Toolbox's ``ETS.eval`` under the same conditions: one thread (RTB's C
loop is single-threaded), a new result array each call (as RTB allocates one),
the same N. Faster modes — numba's threads, writing into a reused ``out=``
buffer, a larger N — are extra rows, labelled as such in their ``mode``.

This module imports no peer library at import time.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from fkcheck.backends.base import BackendUnavailable
from fkcheck.bench import peers
from fkcheck.bench.machine import library_versions, machine_info
from fkcheck.bench.recordings import run_recording_bench
from fkcheck.bench.timing import (
    LIKE_FOR_LIKE,
    BenchResult,
    Timing,
    bench_configurations,
    max_pos_err,
    median_seconds,
    numba_threads,
    one_thread,
)
from fkcheck.core import dh
from fkcheck.core.typing import Float
from fkcheck.model.types import Model

__all__ = ["OUTPUT_BYTES_PER_POSE", "PEER_POSES", "run_bench"]

#: A pose is a 4×4 float64 matrix: the least a batched FK writes per pose.
OUTPUT_BYTES_PER_POSE = 128

#: Largest n per contender (the first n of the N configurations): enough for a
#: steady per-pose time, small enough that the slow ones take under a second.
PEER_POSES = {
    "numpy": 200_000,
    "reference": 20_000,
    "one-pose": 20_000,
    "one-pose-python": 5_000,
    "rtb-eval": 200_000,  # at least dh.JIT_MIN_POSES: the like-for-like row is the kernel
    "rtb-fkine": 2_000,
    "pinocchio": 20_000,
    "yourdfpy": 200,
}


def run_bench(
    model: Model,
    n: int,
    repeat: int,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> BenchResult:
    """Time every contender on the first poses of ``n`` seeded configurations.

    Args:
        model: The robot.
        n: Configurations for the in-house batched core (peers: up to :data:`PEER_POSES`).
        repeat: Timed runs per contender (median reported).
        seed: Seed of the configurations (uniform within the joint limits).
        progress: Called with each contender's name before it runs.

    Returns:
        The timings, in-house first, then the peers, then the memory bound; and
        reading a recording, fkcheck against pandas (:mod:`fkcheck.bench.recordings`).
    """
    say = progress or (lambda _name: None)
    q = bench_configurations(model, n, seed)
    chain = model.chain
    timings: list[Timing] = []

    def part(key: str) -> int:
        return min(n, PEER_POSES[key])

    # One pose on the scalar Python path: only measurable before the JIT is loaded.
    k = part("one-pose-python")
    say("in-house, one pose, Python")
    python_one, python_poses = _python_one_pose(model, q[:k], repeat)
    timings.append(python_one)

    say("in-house, batched")
    jit = dh.load_jit() and n >= dh.JIT_MIN_POSES
    path = "JIT" if jit else "NumPy path"
    out = np.empty((n, 4, 4))
    threads = numba_threads() if jit else 1
    extra = f"extra: {threads} thread{'s' if threads > 1 else ''}"
    seconds = median_seconds(lambda: dh.fk(chain, q, out=out), repeat)
    timings.append(
        Timing(f"in-house batch, {path}, out=", "in-house", n, seconds,
               note="fk(chain, Q, out=buffer)", mode=f"{extra}, out=")
    )  # fmt: skip
    seconds = median_seconds(lambda: dh.fk(chain, q), repeat)
    timings.append(
        Timing(
            f"in-house batch, {path}, new array",
            "in-house",
            n,
            seconds,
            note="fk(chain, Q): a new (N, 4, 4) result each call",
            mode=extra if threads > 1 or n != part("rtb-eval") else LIKE_FOR_LIKE,
        )
    )
    ours = dh.fk(chain, q, out=out)
    if python_poses is not None:
        python_one.max_pos_err_m = max_pos_err(python_poses, ours[:k])
    k = part("rtb-eval")
    if jit and k >= dh.JIT_MIN_POSES:
        say("in-house, like for like")
        timings.append(_like_for_like(chain, q[:k], repeat))

    k = part("one-pose")
    say("in-house, one pose")
    rows = list(q[:k])
    seconds = median_seconds(lambda: [model.fk(r) for r in rows], repeat)
    path = "JIT" if dh.jit_status().startswith("loaded") else "Python"
    err = max_pos_err(np.array([model.fk(r) for r in rows]), ours[:k])
    timings.append(
        Timing(f"in-house one pose, {path}", "in-house", k, seconds, err, "model.fk(q) in a loop")
    )

    for key, label, name, batch, note in (
        ("numpy", "NumPy path", "in-house batch, NumPy path", dh.fk_numpy,
         "fk_numpy(chain, Q): the fallback without numba"),
        ("reference", "fk_reference", "fk_reference (4×4 @ chain)", dh.fk_reference,
         "fk_reference(chain, Q): what the core is tested against"),
    ):  # fmt: skip
        say(f"in-house, {label}")
        timings.append(_batch_row(name, batch, chain, q[: part(key)], ours, repeat, note))

    for name, key, measure in peers.PEERS:
        say(name)
        k = part(key)
        timings.append(_peer_row(name, measure, model, q[:k], ours[:k], repeat))

    say("memory bound")
    timings.append(_memory_bound(n, repeat))
    recordings = run_recording_bench(model, repeat, seed, say)
    return BenchResult(
        model=model.name,
        n=n,
        repeat=repeat,
        seed=seed,
        timings=timings,
        jit=dh.jit_status(),
        threads=numba_threads(),
        machine=machine_info(),
        versions=library_versions(),
        recordings=recordings,
    )


def _python_one_pose(model: Model, q: Float, repeat: int) -> tuple[Timing, Float | None]:
    """One pose at a time on the scalar Python path, and its poses (``None`` when skipped).

    Only measurable before the JIT is loaded: afterwards the row says it was skipped.
    """
    k = q.shape[0]
    python_one = Timing("in-house one pose, Python", "in-house", k)
    if dh.jit_status() != "not loaded":
        python_one.skipped = "the JIT was already loaded in this process"
        return python_one, None
    rows = list(q)
    python_one.seconds = median_seconds(lambda: [model.fk(r) for r in rows], repeat)
    python_one.note = "model.fk(q) in a loop, JIT not loaded (math module)"
    return python_one, np.array([model.fk(r) for r in rows])


def _peer_row(
    name: str,
    measure: peers.Measure,
    model: Model,
    q: Float,
    ours: Float,
    repeat: int,
) -> Timing:
    """One peer's row: timed, skipped (not installed, or the model lacks what it needs), failed."""
    k = q.shape[0]
    try:
        return measure(model, q, ours, repeat)
    except (ImportError, BackendUnavailable) as exc:
        return Timing(name, "peer", k, skipped=f"not installed: {exc}")
    except LookupError as exc:  # the model lacks what the peer needs (no URDF)
        return Timing(name, "peer", k, skipped=str(exc))
    except Exception as exc:  # installed but failed: an error, and the bench fails
        return Timing(name, "peer", k, error=f"{type(exc).__name__}: {exc}")


def _batch_row(
    name: str,
    batch: Callable[[dh.DHChain, Float], Float],
    chain: dh.DHChain,
    q: Float,
    ours: Float,
    repeat: int,
    note: str,
) -> Timing:
    """Time one in-house batched path on ``q`` and compare it with ``ours`` (the batch's poses)."""
    seconds = median_seconds(lambda: batch(chain, q), repeat)
    k = q.shape[0]
    return Timing(name, "in-house", k, seconds, max_pos_err(batch(chain, q), ours[:k]), note=note)


def _like_for_like(chain: dh.DHChain, q: Float, repeat: int) -> Timing:
    """The JIT batch as the peers run: one thread, a new result array, the peer's N."""
    with one_thread():
        seconds = median_seconds(lambda: dh.fk(chain, q), repeat)
    return Timing(
        "in-house batch, JIT, like for like",
        "in-house",
        q.shape[0],
        seconds,
        note="fk(chain, Q) with numba.set_num_threads(1): same N, threads and allocation "
        "as RTB ETS.eval",
        mode=LIKE_FOR_LIKE,
    )


def _memory_bound(n: int, repeat: int) -> Timing:
    """``np.copyto`` of ``n`` poses' worth of bytes: what memory alone costs per pose."""
    src = np.ones((n, 4, 4))
    dst = np.zeros_like(src)
    seconds = median_seconds(lambda: np.copyto(dst, src), repeat)
    return Timing(
        "memory bound: np.copyto",
        "bound",
        n,
        seconds,
        note=f"copy of N × {OUTPUT_BYTES_PER_POSE} B: a batch writes that much, so "
        "it cannot be much faster",
    )
