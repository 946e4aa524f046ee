"""``fkcheck bench --jacobian``: the in-house batched Jacobian against its peers, like for like.

Every contender computes the world-aligned geometric Jacobian of the TCP
(Robotics Toolbox's ``jacob0``, Pinocchio's ``LOCAL_WORLD_ALIGNED``; linear rows
first) for the first ``n`` of one seeded set of configurations, and writes it
into one preallocated ``(n, 6, dof)`` array. Like for like means: one thread,
that same preallocated output, the same ``n``. Neither peer has a batched
Jacobian: Robotics Toolbox's ``ETS.jacob0`` (C) takes one configuration (a 2-D
``q`` is not batched), and Pinocchio's parallel algorithms (``rneaInParallel``,
``abaInParallel``) have no Jacobian; so each peer is its library's fastest
per-configuration call in a Python loop, copying the ``(6, dof)`` array it
returns into the output. The in-house rows in other conditions (numba's
threads, a larger ``N``) are labelled ``extra:``; the FK of the same
configurations is timed beside them for scale (the issue's "same order of
time as poses").

Before a peer is timed, its Jacobians of the first :data:`CHECK_CONFIGS`
configurations are compared with the core's: a peer that disagrees by more
than the model's Jacobian tolerance (``[check] tol_jacobian``) is not timed
(its row has no time, its difference and a note saying why, and
``fkcheck bench`` fails); after timing, the whole timed output is compared again.

This module imports no peer library at import time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from fkcheck.backends.base import BackendUnavailable
from fkcheck.bench.machine import library_versions, machine_info
from fkcheck.bench.peers import pinocchio_chain, rtb_robot
from fkcheck.bench.timing import (
    JACOBIAN_LIKE_FOR_LIKE,
    BenchResult,
    Timing,
    bench_configurations,
    max_jacobian_err,
    median_seconds,
    numba_threads,
    one_thread,
)
from fkcheck.core import dh
from fkcheck.core import jacobian as core_jacobian
from fkcheck.core.typing import Float
from fkcheck.core.typing import JacobianReference as Reference
from fkcheck.model.types import Model

__all__ = ["CHECK_CONFIGS", "JACOBIAN_CONFIGS", "REFERENCE", "run_jacobian_bench"]

#: The reference frame every contender computes (both peers have it natively).
REFERENCE: Reference = "world-aligned"

#: Configurations each peer's Jacobians are checked on before it is timed.
CHECK_CONFIGS = 64

#: Largest n per contender (the first n of the N configurations): at least
#: :data:`~fkcheck.core.dh.JIT_MIN_POSES`, so that the like-for-like row is the
#: kernel (the peers' loops take 2–14 µs a configuration: 0.4–2.7 s a run).
JACOBIAN_CONFIGS = {
    "numpy": 200_000,
    "rtb": 200_000,
    "pinocchio": 200_000,
}

#: A peer's Jacobian of one configuration: ``q (dof,) -> (6, dof)`` array.
PeerCall = Callable[[Float], Any]


def run_jacobian_bench(
    model: Model,
    n: int,
    repeat: int,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> BenchResult:
    """Time the in-house batched Jacobian and its peers on the same configurations.

    Args:
        model: The robot.
        n: Configurations for the in-house batched Jacobian (peers: up to
            :data:`JACOBIAN_CONFIGS`).
        repeat: Timed runs per contender (median reported).
        seed: Seed of the configurations (uniform within the joint limits).
        progress: Called with each contender's name before it runs.

    Returns:
        The timings: in-house rows first (like for like, then extra), the FK
        for scale, the NumPy fallback, then the peers.
    """
    say = progress or (lambda _name: None)
    q = bench_configurations(model, n, seed)
    chain = model.chain
    target = chain.flange_T_tool
    k_peer = min(n, JACOBIAN_CONFIGS["rtb"], JACOBIAN_CONFIGS["pinocchio"])
    jit = core_jacobian.load_kernel() and n >= dh.JIT_MIN_POSES
    path = "JIT" if jit else "NumPy path"
    threads = numba_threads() if jit else 1
    timings: list[Timing] = []

    def ours(x: Float, out: Float) -> Float:
        return core_jacobian.jacobian(
            chain, x, moving=model.dof, target=target, reference=REFERENCE, out=out
        )

    out = np.empty((n, 6, model.dof))
    say("in-house Jacobian, like for like")
    with one_thread():
        small = out[:k_peer]
        seconds = median_seconds(lambda: ours(q[:k_peer], small), repeat)
    path_peer = "JIT" if k_peer >= dh.JIT_MIN_POSES and jit else "NumPy path"
    timings.append(
        Timing(f"in-house Jacobian, {path_peer}, like for like", "in-house", k_peer, seconds,
               note="jacobian(chain, Q, out=buffer), 1 thread: the peers' n, threads and "
               "allocation", mode=JACOBIAN_LIKE_FOR_LIKE)
    )  # fmt: skip

    say("in-house Jacobian, batch")
    jacobian_s: dict[str, float] = {}
    with one_thread():
        jacobian_s["1 thread"] = median_seconds(lambda: ours(q, out), repeat)
    if n > k_peer:  # at n = k_peer the like-for-like row is this very run
        timings.append(
            Timing(f"in-house Jacobian, {path}, 1 thread", "in-house", n,
                   jacobian_s["1 thread"], note="jacobian(chain, Q, out=buffer) on all N",
                   mode="extra: N, 1 thread")
        )  # fmt: skip
    if threads > 1:
        label = f"{threads} threads"
        jacobian_s[label] = median_seconds(lambda: ours(q, out), repeat)
        timings.append(
            Timing(f"in-house Jacobian, {path}, {label}", "in-house", n, jacobian_s[label],
                   note="jacobian(chain, Q, out=buffer) on all N", mode=f"extra: N, {label}")
        )  # fmt: skip
    expected = out  # the last timed run's Jacobians: what every other row is compared with

    say("in-house FK, for scale")
    poses = np.empty((n, 4, 4))
    fk_path = "JIT" if jit else "NumPy path"
    over_fk: dict[str, float] = {}
    for label in jacobian_s:
        if label == "1 thread":
            with one_thread():
                seconds = median_seconds(lambda: dh.fk(chain, q, out=poses), repeat)
        else:
            seconds = median_seconds(lambda: dh.fk(chain, q, out=poses), repeat)
        over_fk[label] = jacobian_s[label] / seconds
        timings.append(
            Timing(f"in-house FK (TCP pose), {fk_path}, {label}", "in-house", n, seconds,
                   note="fk(chain, Q, out=buffer): poses of the same configurations, for scale",
                   mode=f"extra: poses, {label}")
        )  # fmt: skip

    say("in-house Jacobian, NumPy path")
    k = min(n, JACOBIAN_CONFIGS["numpy"])
    numpy_out = np.empty((k, 6, model.dof))

    def numpy_path() -> Float:
        return core_jacobian.jacobian_numpy(
            chain, q[:k], moving=model.dof, target=target, reference=REFERENCE, out=numpy_out
        )

    seconds = median_seconds(numpy_path, repeat)
    timings.append(
        Timing("in-house Jacobian, NumPy path", "in-house", k, seconds,
               note="jacobian_numpy(chain, Q, out=buffer): the fallback without numba",
               mode="1 thread, out=", max_jac_err=max_jacobian_err(numpy_out, expected[:k]))
    )  # fmt: skip

    tol = model.check.tol_jacobian
    for name, key, build in _PEERS:
        say(name)
        kp = min(n, JACOBIAN_CONFIGS[key])
        try:
            call, note = build(model)
            timings.append(_peer_row(name, note, call, q[:kp], expected[:kp], tol, repeat))
        except (ImportError, BackendUnavailable) as exc:
            timings.append(Timing(name, "peer", kp, skipped=f"not installed: {exc}"))
        except Exception as exc:  # installed but failed: an error, and the bench fails
            timings.append(Timing(name, "peer", kp, error=f"{type(exc).__name__}: {exc}"))

    return BenchResult(
        model=model.name,
        n=n,
        repeat=repeat,
        seed=seed,
        timings=timings,
        jit=core_jacobian.kernel_status(),
        threads=numba_threads(),
        machine=machine_info(),
        versions=library_versions(),
        quantity="jacobian",
        reference=REFERENCE,
        jacobian_over_fk=over_fk,
    )


def _peer_row(
    name: str, note: str, call: PeerCall, q: Float, expected: Float, tol: float, repeat: int
) -> Timing:
    """Check the peer on the first configurations, then time its loop into one buffer."""
    rows = list(np.ascontiguousarray(q))
    out = np.empty(expected.shape)
    head = min(len(rows), CHECK_CONFIGS)
    for i in range(head):
        out[i] = call(rows[i])
    err = max_jacobian_err(out[:head], expected[:head])
    if not err <= tol:  # refused: a time for wrong numbers would mean nothing
        return Timing(
            name, "peer", len(rows), max_jac_err=err, mode=JACOBIAN_LIKE_FOR_LIKE,
            note=f"not timed: its Jacobians differ from the core's by {err:.3g} (> {tol:g}) "
            f"on the first {head} configurations",
        )  # fmt: skip

    def loop() -> None:
        for i, row in enumerate(rows):
            out[i] = call(row)

    seconds = median_seconds(loop, repeat)
    return Timing(
        name, "peer", len(rows), seconds, note=note, mode=JACOBIAN_LIKE_FOR_LIKE,
        max_jac_err=max_jacobian_err(out, expected),
    )  # fmt: skip


def _rtb(model: Model) -> tuple[PeerCall, str]:
    ets = rtb_robot(model).ets()
    return ets.jacob0, "robot.ets().jacob0(q) per configuration (C; RTB has no batched Jacobian)"


def _pinocchio(model: Model) -> tuple[PeerCall, str]:
    import pinocchio as pin

    chain = pinocchio_chain(model)
    pm, data, tcp = chain.pmodel, chain.data, chain.tcp_frame_id
    frame = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    compute = pin.computeFrameJacobian

    def call(row: Float) -> Any:
        return compute(pm, data, row, tcp, frame)

    return call, (
        "computeFrameJacobian(q, tcp, LOCAL_WORLD_ALIGNED) per configuration "
        "(C++; Pinocchio has no batched or parallel Jacobian)"
    )


#: ``(row name, key in JACOBIAN_CONFIGS, builder)`` of every peer, in the table's order.
_PEERS: list[tuple[str, str, Callable[[Model], tuple[PeerCall, str]]]] = [
    ("RTB ETS.jacob0 loop", "rtb", _rtb),
    ("Pinocchio computeFrameJacobian loop", "pinocchio", _pinocchio),
]
