"""Timing the in-house DH core against its peers, on the same configurations.

Each *contender* computes ``world_T_tcp`` (or, for a URDF, the model's check
frame pair) for the first ``n`` of one seeded set of configurations; slow
contenders get a smaller ``n`` (:data:`PEER_POSES` caps it) and say so. Every
time is the median of ``repeat`` runs after one warm-up run, and every peer's
result is compared with the in-house core's on the same poses (largest
position difference).

What is timed is the library call and nothing else: Robotics Toolbox
(``DHRobot.fkine`` and the C path ``ETS.eval`` behind it, on the ``DHRobot`` the
``rtb-dh`` backend builds), Pinocchio (``forwardKinematics`` +
``updateFramePlacements`` per pose on the model the ``pinocchio-dh`` backend
builds, with only a ``tcp`` frame so no other frame is updated)
and yourdfpy (``update_cfg`` + ``get_transform`` per pose, on the model's URDF
loaded as the ``yourdfpy-urdf`` backend loads it). A peer whose library is not
installed is reported as skipped, with the reason; a peer that is installed but
fails is an error, and the bench fails (exit 1): a crash must not read as
"not measured".

Ratios are like for like. The headline compares the in-house batch with
Robotics Toolbox's ``ETS.eval`` under the same conditions: one thread (RTB's C
loop is single-threaded), a new result array each call (as RTB allocates one),
the same N. Faster modes — numba's threads, writing into a reused ``out=``
buffer, a larger N — are extra rows, labelled as such in their ``mode``.

This module imports no peer library at import time.
"""

from __future__ import annotations

import os
import platform
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any, Literal

import numpy as np

from fkcheck.backends.base import BackendUnavailable
from fkcheck.core import dh
from fkcheck.core.typing import Float
from fkcheck.model.frames import frame_poses_from_dh, relative_pose
from fkcheck.model.sampling import sampling_box
from fkcheck.model.types import Model

__all__ = [
    "OUTPUT_BYTES_PER_POSE",
    "PEER_POSES",
    "BenchResult",
    "Timing",
    "pinocchio_model",
    "rtb_robot",
    "run_bench",
]

Kind = Literal["in-house", "peer", "bound"]

#: The peers' conditions: one thread, a new result array per call.
LIKE_FOR_LIKE = "1 thread, new array"
#: The peer the headline ratio is taken against (the fastest batched peer).
HEADLINE_PEER = "RTB ETS.eval (C batch)"

#: A pose is a 4×4 float64 matrix: the least a batched FK writes per pose.
OUTPUT_BYTES_PER_POSE = 128

#: Largest n per contender (the first n of the N configurations): enough for a
#: steady per-pose time, small enough that the slow ones take under a second.
PEER_POSES = {
    "numpy": 200_000,
    "reference": 20_000,
    "one-pose": 20_000,
    "one-pose-python": 5_000,
    "rtb-eval": 100_000,
    "rtb-fkine": 2_000,
    "pinocchio": 20_000,
    "yourdfpy": 200,
}


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


def _median_seconds(run: Callable[[], object], repeat: int) -> float:
    """Median wall time of ``repeat`` calls, after one untimed warm-up call."""
    run()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _max_pos_err(poses: Float, reference: Float) -> float:
    """Largest distance between the translations of two ``(n, 4, 4)`` stacks (m)."""
    return float(np.linalg.norm(poses[:, :3, 3] - reference[:, :3, 3], axis=-1).max())


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
        The timings, in-house first, then the peers, then the memory bound.
    """
    say = progress or (lambda _name: None)
    rng = np.random.default_rng(seed)
    lo, hi = sampling_box(model)
    q = rng.uniform(lo, hi, size=(n, model.dof))
    chain = model.chain
    timings: list[Timing] = []

    def part(key: str) -> int:
        return min(n, PEER_POSES[key])

    # One pose on the scalar Python path: only measurable before the JIT is loaded.
    k = part("one-pose-python")
    say("in-house, one pose, Python")
    python_one = Timing("in-house one pose, Python", "in-house", k)
    if dh.jit_status() == "not loaded":
        rows = list(q[:k])
        python_one.seconds = _median_seconds(lambda: [model.fk(r) for r in rows], repeat)
        python_one.note = "model.fk(q) in a loop, JIT not loaded (math module)"
        python_poses = np.array([model.fk(r) for r in rows])
    else:
        python_one.skipped = "the JIT was already loaded in this process"
    timings.append(python_one)

    say("in-house, batched")
    jit = dh.load_jit() and n >= dh.JIT_MIN_POSES
    path = "JIT" if jit else "NumPy path"
    out = np.empty((n, 4, 4))
    threads = _numba_threads() if jit else 1
    extra = f"extra: {threads} thread{'s' if threads > 1 else ''}"
    seconds = _median_seconds(lambda: dh.fk(chain, q, out=out), repeat)
    timings.append(
        Timing(f"in-house batch, {path}, out=", "in-house", n, seconds,
               note="fk(chain, Q, out=buffer)", mode=f"{extra}, out=")
    )  # fmt: skip
    seconds = _median_seconds(lambda: dh.fk(chain, q), repeat)
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
    if python_one.seconds is not None:
        python_one.max_pos_err_m = _max_pos_err(python_poses, ours[:k])
    k = part("rtb-eval")
    if jit and k >= dh.JIT_MIN_POSES:
        say("in-house, like for like")
        timings.append(_like_for_like(chain, q[:k], repeat))

    k = part("one-pose")
    say("in-house, one pose")
    rows = list(q[:k])
    seconds = _median_seconds(lambda: [model.fk(r) for r in rows], repeat)
    path = "JIT" if dh.jit_status().startswith("loaded") else "Python"
    err = _max_pos_err(np.array([model.fk(r) for r in rows]), ours[:k])
    timings.append(
        Timing(f"in-house one pose, {path}", "in-house", k, seconds, err, "model.fk(q) in a loop")
    )

    k = part("numpy")
    say("in-house, NumPy path")
    seconds = _median_seconds(lambda: dh.fk_numpy(chain, q[:k]), repeat)
    timings.append(
        Timing(
            "in-house batch, NumPy path",
            "in-house",
            k,
            seconds,
            _max_pos_err(dh.fk_numpy(chain, q[:k]), ours[:k]),
            note="fk_numpy(chain, Q): the fallback without numba",
        )
    )

    k = part("reference")
    say("in-house, fk_reference")
    seconds = _median_seconds(lambda: dh.fk_reference(chain, q[:k]), repeat)
    timings.append(
        Timing(
            "fk_reference (4×4 @ chain)",
            "in-house",
            k,
            seconds,
            _max_pos_err(dh.fk_reference(chain, q[:k]), ours[:k]),
            note="fk_reference(chain, Q): what the core is tested against",
        )
    )

    for name, key, measure in _PEERS:
        say(name)
        k = part(key)
        try:
            timings.append(measure(model, q[:k], ours[:k], repeat))
        except (ImportError, BackendUnavailable) as exc:
            timings.append(Timing(name, "peer", k, skipped=f"not installed: {exc}"))
        except LookupError as exc:  # the model lacks what the peer needs (no URDF)
            timings.append(Timing(name, "peer", k, skipped=str(exc)))
        except Exception as exc:  # installed but failed: an error, and the bench fails
            timings.append(Timing(name, "peer", k, error=f"{type(exc).__name__}: {exc}"))

    say("memory bound")
    timings.append(_memory_bound(n, repeat))
    return BenchResult(
        model=model.name,
        n=n,
        repeat=repeat,
        seed=seed,
        timings=timings,
        jit=dh.jit_status(),
        threads=_numba_threads(),
        machine=_machine(),
        versions=_versions(),
    )


def _like_for_like(chain: dh.DHChain, q: Float, repeat: int) -> Timing:
    """The JIT batch as the peers run: one thread, a new result array, the peer's N."""
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        seconds = _median_seconds(lambda: dh.fk(chain, q), repeat)
    finally:
        numba.set_num_threads(before)
    return Timing(
        "in-house batch, JIT, like for like",
        "in-house",
        q.shape[0],
        seconds,
        note="fk(chain, Q) with numba.set_num_threads(1): same N, threads and allocation "
        "as RTB ETS.eval",
        mode=LIKE_FOR_LIKE,
    )


def _numba_threads() -> int:
    if dh.jit_status().startswith("loaded"):
        import numba

        return int(numba.get_num_threads())
    return 1


def _memory_bound(n: int, repeat: int) -> Timing:
    """``np.copyto`` of ``n`` poses' worth of bytes: what memory alone costs per pose."""
    src = np.ones((n, 4, 4))
    dst = np.zeros_like(src)
    seconds = _median_seconds(lambda: np.copyto(dst, src), repeat)
    return Timing(
        "memory bound: np.copyto",
        "bound",
        n,
        seconds,
        note=f"copy of N × {OUTPUT_BYTES_PER_POSE} B: a batch writes that much, so "
        "it cannot be much faster",
    )


# --------------------------------------------------------------------------- peers


def rtb_robot(model: Model) -> Any:
    """A Robotics Toolbox ``DHRobot`` from the model's table, base and tool (``rtb-dh``'s).

    Raises:
        BackendUnavailable: Robotics Toolbox is not installed.
    """
    from fkcheck.backends.rtb_dh import dh_robot

    return dh_robot(model)


def pinocchio_model(model: Model) -> Any:
    """The ``pinocchio-dh`` backend's Pinocchio model of the DH chain with only a ``tcp`` frame.

    Raises:
        BackendUnavailable: Pinocchio is not installed.
    """
    from fkcheck.backends.pinocchio_dh import PinocchioChain

    return PinocchioChain(model, tcp_only=True).pmodel


def _rtb_eval(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    ets = rtb_robot(model).ets()
    poses = np.asarray(ets.eval(q))
    seconds = _median_seconds(lambda: ets.eval(q), repeat)
    return Timing(
        "RTB ETS.eval (C batch)",
        "peer",
        q.shape[0],
        seconds,
        _max_pos_err(poses, ours),
        note="robot.ets().eval(Q): the fastest RTB path (its C fknm)",
        mode=LIKE_FOR_LIKE,
    )


def _rtb_fkine(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    robot = rtb_robot(model)
    poses = np.asarray(robot.fkine(q).A)
    seconds = _median_seconds(lambda: robot.fkine(q), repeat)
    return Timing(
        "RTB DHRobot.fkine",
        "peer",
        q.shape[0],
        seconds,
        _max_pos_err(poses.reshape(-1, 4, 4), ours),
        note="robot.fkine(Q): an SE3 of N poses",
        mode=LIKE_FOR_LIKE,
    )


def _pinocchio(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    import pinocchio as pin

    pm = pinocchio_model(model)
    data = pm.createData()
    tcp = pm.getFrameId("tcp")
    rows = list(np.ascontiguousarray(q))
    poses = np.empty((len(rows), 4, 4))

    def loop() -> None:
        for k, row in enumerate(rows):
            pin.forwardKinematics(pm, data, row)
            pin.updateFramePlacements(pm, data)
            poses[k] = data.oMf[tcp].homogeneous

    seconds = _median_seconds(loop, repeat)
    return Timing(
        "Pinocchio FK loop",
        "peer",
        len(rows),
        seconds,
        _max_pos_err(poses, ours),
        note="forwardKinematics + updateFramePlacements per pose",
        mode="1 thread, loop",
    )


def _yourdfpy(model: Model, q: Float, ours: Float, repeat: int) -> Timing:
    from fkcheck.backends.yourdfpy_urdf import _load  # the backend's loader: no meshes
    from fkcheck.urdf.source import load_urdf

    if model.urdf is None:
        raise LookupError("the model has no [urdf]")
    robot = _load(load_urdf(model))
    frames = (model.check.frame_from, model.check.frame_to)
    twin_from, twin_to = (model.frames[f].urdf for f in frames)
    if twin_from is None or twin_to is None:
        raise LookupError(f"check frames {frames} have no URDF twins")
    names = list(model.urdf.joints)
    rows = q.tolist()
    poses = np.empty((len(rows), 4, 4))

    def loop() -> None:
        for k, row in enumerate(rows):
            robot.update_cfg(dict(zip(names, row, strict=True)))
            poses[k] = robot.get_transform(frame_to=twin_to, frame_from=twin_from)

    seconds = _median_seconds(loop, repeat)
    world_T = frame_poses_from_dh(model, dh.fk(model.chain, q, all_frames=True), ours, frames)
    expected = relative_pose(world_T[0], world_T[1])
    return Timing(
        "yourdfpy loop (URDF)",
        "peer",
        len(rows),
        seconds,
        _max_pos_err(poses, expected),
        note=f"update_cfg + get_transform({twin_to}, {twin_from}) per pose",
        mode="1 thread, loop",
    )


_PEERS: list[tuple[str, str, Callable[[Model, Float, Float, int], Timing]]] = [
    ("RTB ETS.eval (C batch)", "rtb-eval", _rtb_eval),
    ("RTB DHRobot.fkine", "rtb-fkine", _rtb_fkine),
    ("Pinocchio FK loop", "pinocchio", _pinocchio),
    ("yourdfpy loop (URDF)", "yourdfpy", _yourdfpy),
]


# --------------------------------------------------------------------------- context


def _machine() -> dict[str, Any]:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {
        "cpu": cpu,
        "cpus": os.cpu_count(),
        "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        "python": platform.python_version(),
        "platform": platform.platform(),
    }


def _versions() -> dict[str, str]:
    from importlib.metadata import PackageNotFoundError, version

    found = {}
    for dist in ("numpy", "numba", "roboticstoolbox-python", "pin", "yourdfpy"):
        try:
            found[dist] = version(dist)
        except PackageNotFoundError:
            found[dist] = "not installed"
    return found
