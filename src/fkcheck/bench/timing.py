"""What one bench run measured, and how each time is taken.

A :class:`Timing` is one contender's row; a :class:`BenchResult` holds every row
of a run with the facts needed to read them (machine, versions, JIT, threads) and
derives the headline ratio and the speed-ups. Every time is
:func:`median_seconds` (the median of ``repeat`` runs after one warm-up run);
every result is compared with the in-house core's by :func:`max_pos_err` (poses)
or :func:`max_jacobian_err` (Jacobians, ``fkcheck bench --jacobian``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from typing import Any, Literal

import numpy as np

from fkcheck.core.metrics import jacobian_column_errors
from fkcheck.core.typing import Float
from fkcheck.model.sampling import sampling_box
from fkcheck.model.types import Model

__all__ = [
    "HEADLINE_PEER",
    "JACOBIAN_HEADLINE_PEER",
    "JACOBIAN_LIKE_FOR_LIKE",
    "LIKE_FOR_LIKE",
    "BenchResult",
    "Kind",
    "Quantity",
    "Timing",
    "bench_configurations",
    "max_jacobian_err",
    "max_pos_err",
    "median_seconds",
    "numba_threads",
    "one_thread",
]

Kind = Literal["in-house", "peer", "bound"]
#: What a bench times: poses (``fkcheck bench``) or Jacobians (``--jacobian``).
Quantity = Literal["pose", "jacobian"]

#: The peers' conditions: one thread, a new result array per call.
LIKE_FOR_LIKE = "1 thread, new array"
#: The peer the headline ratio is taken against (the fastest batched peer).
HEADLINE_PEER = "RTB ETS.eval (C batch)"
#: The Jacobian bench's conditions: one thread, every result written into one
#: preallocated ``(N, 6, n)`` array (the peers' per-call result copied into it).
JACOBIAN_LIKE_FOR_LIKE = "1 thread, out="
#: The peer the Jacobian bench's headline ratio is taken against (the fastest).
JACOBIAN_HEADLINE_PEER = "Pinocchio computeFrameJacobian loop"


@dataclass
class Timing:
    """One contender's result.

    Attributes:
        name: What was timed.
        kind: ``in-house``, ``peer`` (another library) or ``bound`` (memory copy).
        n: Configurations per run (poses, or Jacobians with ``--jacobian``).
        seconds: Median seconds per run (``None`` if skipped, failed, or — a
            Jacobian peer — refused because it disagrees).
        max_pos_err_m: Largest position difference from the in-house core on the
            same poses (``None`` where not compared).
        note: How it was called, and why ``n`` is smaller than asked.
        skipped: Why it did not run (library missing, no URDF).
        mode: Threads and allocation, e.g. ``"1 thread, new array"``; in-house rows
            that differ from the peers' conditions say ``"extra: …"``.
        error: The peer is installed but failed (the bench then fails).
        max_jac_err: Jacobian bench: largest difference of a column's linear or
            angular 3-vector from the in-house core's Jacobians of the same
            configurations (m/rad or rad/rad; :func:`max_jacobian_err`).
    """

    name: str
    kind: Kind
    n: int
    seconds: float | None = None
    max_pos_err_m: float | None = None
    note: str = ""
    skipped: str = ""
    mode: str = ""
    error: str = ""
    max_jac_err: float | None = None

    @property
    def us_per_pose(self) -> float | None:
        """Microseconds per pose."""
        return None if self.seconds is None else self.seconds / self.n * 1e6

    @property
    def poses_per_s(self) -> float | None:
        """Poses per second."""
        return None if self.seconds is None else self.n / self.seconds


@dataclass
class BenchResult:
    """All timings of one run, and the facts needed to read them."""

    model: str
    n: int
    repeat: int
    seed: int
    timings: list[Timing]
    jit: str
    threads: int
    machine: dict[str, Any] = field(default_factory=dict)
    versions: dict[str, str] = field(default_factory=dict)
    quantity: Quantity = "pose"
    reference: str = ""
    #: ``fkcheck bench --jacobian``: per thread count (``"1 thread"``, ``"2 threads"``),
    #: the batched Jacobian's time over the FK's on the same N configurations and ``out=``.
    jacobian_over_fk: dict[str, float] = field(default_factory=dict)
    #: ``fkcheck bench``: reading one RTDE recording, fkcheck against pandas
    #: (:mod:`fkcheck.bench.recordings`; its ``RecordingTiming`` rows).
    recordings: list[Any] = field(default_factory=list)

    @property
    def like_for_like(self) -> str:
        """The headline pair's mode: :data:`LIKE_FOR_LIKE` or :data:`JACOBIAN_LIKE_FOR_LIKE`."""
        return JACOBIAN_LIKE_FOR_LIKE if self.quantity == "jacobian" else LIKE_FOR_LIKE

    @property
    def headline(self) -> tuple[Timing, Timing, float] | None:
        """``(in-house like-for-like row, headline peer's row, speedup)``, if both ran.

        The headline peer is RTB's ``ETS.eval`` for poses, Pinocchio's
        ``computeFrameJacobian`` loop for Jacobians.
        """
        name = JACOBIAN_HEADLINE_PEER if self.quantity == "jacobian" else HEADLINE_PEER
        peer = next((t for t in self.timings if t.name == name and t.seconds), None)
        if peer is None:
            return None
        ours = next((t for t in self.timings if t.mode == self.like_for_like
                     and t.kind == "in-house" and t.seconds is not None and t.n == peer.n),
                    None)  # fmt: skip
        if ours is None or ours.us_per_pose is None or peer.us_per_pose is None:
            return None
        return ours, peer, peer.us_per_pose / ours.us_per_pose

    @property
    def fastest_peer(self) -> Timing | None:
        """The peer (another library) with the lowest time per pose."""
        ran = [t for t in self.timings if t.kind == "peer" and t.us_per_pose is not None]
        return min(ran, key=lambda t: t.us_per_pose or 0.0, default=None)

    def speedup(self, timing: Timing) -> float | None:
        """How many times faster than the fastest peer ``timing`` is (per pose)."""
        best = self.fastest_peer
        if best is None or timing.us_per_pose is None or best.us_per_pose is None:
            return None
        return best.us_per_pose / timing.us_per_pose

    def ratios(self, timing: Timing) -> dict[str, float]:
        """Per-configuration time of each peer that ran divided by ``timing``'s."""
        if timing.us_per_pose is None:
            return {}
        return {
            t.name: t.us_per_pose / timing.us_per_pose
            for t in self.timings
            if t.kind == "peer" and t.us_per_pose is not None
        }

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON: every timing with its derived numbers."""
        best = self.fastest_peer
        return {
            "quantity": self.quantity,
            "reference": self.reference or None,
            "model": self.model,
            "n": self.n,
            "repeat": self.repeat,
            "seed": self.seed,
            "jit": self.jit,
            "threads": self.threads,
            "machine": self.machine,
            "versions": self.versions,
            "fastest_peer": None if best is None else best.name,
            "jacobian_over_fk": self.jacobian_over_fk or None,
            "recordings": [
                {**asdict(r), "rows_per_s": r.rows_per_s, "mb_per_s": r.mb_per_s}
                for r in self.recordings
            ],
            "headline": None
            if self.headline is None
            else {
                "in_house": self.headline[0].name,
                "peer": self.headline[1].name,
                "n": self.headline[0].n,
                "mode": self.like_for_like,
                "speedup": self.headline[2],
            },
            "timings": [
                {
                    **asdict(t),
                    "us_per_pose": t.us_per_pose,
                    "poses_per_s": t.poses_per_s,
                    "speedup_vs_fastest_peer": self.speedup(t),
                    "ns_per_config": None if t.us_per_pose is None else t.us_per_pose * 1e3,
                    "speedup_vs_peers": self.ratios(t),
                }
                for t in self.timings
            ],
        }


def median_seconds(run: Callable[[], object], repeat: int) -> float:
    """Median wall time of ``repeat`` calls, after one untimed warm-up call."""
    run()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def max_jacobian_err(jacobians: Float, reference: Float) -> float:
    """Largest difference between two ``(n, 6, dof)`` stacks of Jacobians (NaN counts).

    Measured as ``check --jacobian`` measures it
    (:func:`fkcheck.core.metrics.jacobian_column_errors`: the length of a
    column's linear or angular 3-vector difference), so the bench's gate and the
    check judge a peer alike.
    """
    if jacobians.shape != reference.shape:
        raise ValueError(f"Jacobians of shape {jacobians.shape}, expected {reference.shape}")
    linear, angular = jacobian_column_errors(reference, jacobians)
    worst = max(float(linear.max(initial=0.0)), float(angular.max(initial=0.0)))
    return float("inf") if np.isnan(worst) else worst


def max_pos_err(poses: Float, reference: Float) -> float:
    """Largest distance between the translations of two ``(n, 4, 4)`` stacks (m)."""
    return float(np.linalg.norm(poses[:, :3, 3] - reference[:, :3, 3], axis=-1).max())


def numba_threads() -> int:
    """Numba's thread count when the core's kernels are loaded, else 1."""
    from fkcheck.core import dh

    if dh.jit_status().startswith("loaded"):
        import numba

        return int(numba.get_num_threads())
    return 1


@contextmanager
def one_thread() -> Iterator[None]:
    """Run the block with numba on one thread (nothing to do without the kernels)."""
    from fkcheck.core import dh

    if not dh.jit_status().startswith("loaded"):
        yield
        return
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        yield
    finally:
        numba.set_num_threads(before)


def bench_configurations(model: Model, n: int, seed: int) -> Float:
    """``n`` seeded configurations, uniform within the joint limits: what every row times."""
    rng = np.random.default_rng(seed)
    lo, hi = sampling_box(model)
    configurations: Float = rng.uniform(lo, hi, size=(n, model.dof))
    return configurations
