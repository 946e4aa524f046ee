"""What one bench run measured, and how each time is taken.

A :class:`Timing` is one contender's row; a :class:`BenchResult` holds every row
of a run with the facts needed to read them (machine, versions, JIT, threads) and
derives the headline ratio and the speed-ups. Every time is
:func:`median_seconds` (the median of ``repeat`` runs after one warm-up run);
every result is compared with the in-house core's by :func:`max_pos_err`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any, Literal

import numpy as np

from fkcheck.core.typing import Float

__all__ = [
    "HEADLINE_PEER",
    "LIKE_FOR_LIKE",
    "BenchResult",
    "Kind",
    "Timing",
    "max_pos_err",
    "median_seconds",
]

Kind = Literal["in-house", "peer", "bound"]

#: The peers' conditions: one thread, a new result array per call.
LIKE_FOR_LIKE = "1 thread, new array"
#: The peer the headline ratio is taken against (the fastest batched peer).
HEADLINE_PEER = "RTB ETS.eval (C batch)"


@dataclass
class Timing:
    """One contender's result.

    Attributes:
        name: What was timed.
        kind: ``in-house``, ``peer`` (another library) or ``bound`` (memory copy).
        n: Poses per run.
        seconds: Median seconds per run (``None`` if skipped or failed).
        max_pos_err_m: Largest position difference from the in-house core on the
            same poses (``None`` where not compared).
        note: How it was called, and why ``n`` is smaller than asked.
        skipped: Why it did not run (library missing, no URDF).
        mode: Threads and allocation, e.g. ``"1 thread, new array"``; in-house rows
            that differ from the peers' conditions say ``"extra: …"``.
        error: The peer is installed but failed (the bench then fails).
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

    @property
    def headline(self) -> tuple[Timing, Timing, float] | None:
        """``(in-house like-for-like row, RTB ETS.eval row, speedup)``, if both ran."""
        peer = next((t for t in self.timings if t.name == HEADLINE_PEER and t.seconds), None)
        if peer is None:
            return None
        ours = next((t for t in self.timings if t.mode == LIKE_FOR_LIKE and t.kind == "in-house"
                     and t.seconds is not None and t.n == peer.n), None)  # fmt: skip
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

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON: every timing with its derived numbers."""
        best = self.fastest_peer
        return {
            "model": self.model,
            "n": self.n,
            "repeat": self.repeat,
            "seed": self.seed,
            "jit": self.jit,
            "threads": self.threads,
            "machine": self.machine,
            "versions": self.versions,
            "fastest_peer": None if best is None else best.name,
            "headline": None
            if self.headline is None
            else {
                "in_house": self.headline[0].name,
                "peer": self.headline[1].name,
                "n": self.headline[0].n,
                "mode": LIKE_FOR_LIKE,
                "speedup": self.headline[2],
            },
            "timings": [
                {
                    **asdict(t),
                    "us_per_pose": t.us_per_pose,
                    "poses_per_s": t.poses_per_s,
                    "speedup_vs_fastest_peer": self.speedup(t),
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


def max_pos_err(poses: Float, reference: Float) -> float:
    """Largest distance between the translations of two ``(n, 4, 4)`` stacks (m)."""
    return float(np.linalg.norm(poses[:, :3, 3] - reference[:, :3, 3], axis=-1).max())
