"""Shared test helpers: the bundled models, configurations within limits, pose
assertions (one place that knows the maths), and a time bound."""

from __future__ import annotations

import contextlib
import signal
from collections.abc import Iterator
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from fkcheck.model.read import bundled_model_paths, load_model
from fkcheck.model.types import Model, UrdfSpec

#: The bundled model names, sorted (for parametrize).
BUNDLED = sorted(bundled_model_paths())


def on_ros1_description(model: Model) -> Model:
    """A bundled UR3/UR5/UR10 on example-robot-data's older ROS 1 URDF (``urX_robot.urdf``).

    The bundled models name UR's ROS 2 description; the ROS 1 one has the same
    joints, ``base``, ``base_link`` and ``tool0``, and ``ee_link`` where ROS 2 has
    ``flange``: ``ee_link`` is mapped, ``flange`` is not.
    """
    assert model.urdf is not None
    urdf = UrdfSpec(f"example-robot-data:ur_description/urdf/{model.name}_robot.urdf",
                    model.urdf.joints)  # fmt: skip
    frames = dict(model.frames)
    frames["ee_link"] = replace(frames["ee_link"], urdf="ee_link")
    frames["flange"] = replace(frames["flange"], urdf=None)
    return replace(model, urdf=urdf, frames=frames)


def ur5_ros1() -> Model:
    """The bundled UR5 on example-robot-data's ROS 1 ``ur5_robot.urdf``."""
    return on_ros1_description(load_model("ur5"))


def rotation_angle(R_a: np.ndarray, R_b: np.ndarray) -> np.ndarray:
    """Angle (rad) of R_aᵀ R_b, stable near 0 and π (atan2 of |axis| and trace)."""
    R = np.swapaxes(R_a, -1, -2) @ R_b
    skew = np.stack(
        [R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]],
        axis=-1,
    )
    trace = R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2]
    return np.arctan2(np.linalg.norm(skew, axis=-1) / 2.0, (trace - 1.0) / 2.0)


def assert_pose_close(actual: ArrayLike, expected: ArrayLike, tol: float, what: str = "") -> None:
    """Assert poses (..., 4, 4) agree in position (m) and rotation angle (rad) within tol."""
    a = np.asarray(actual, dtype=float)
    e = np.asarray(expected, dtype=float)
    assert a.shape == e.shape, f"{what}: shape {a.shape} != {e.shape}"
    assert np.isfinite(a).all(), f"{what}: non-finite values in actual pose"
    pos = np.linalg.norm(a[..., :3, 3] - e[..., :3, 3], axis=-1)
    rot = rotation_angle(a[..., :3, :3], e[..., :3, :3])
    assert pos.max(initial=0.0) <= tol, f"{what}: position error {pos.max():.3g} m > {tol:g}"
    assert rot.max(initial=0.0) <= tol, f"{what}: rotation error {rot.max():.3g} rad > {tol:g}"
    # Entry-wise too: catches a wrong last row, which the two norms above ignore.
    np.testing.assert_allclose(a, e, rtol=0, atol=tol, err_msg=what)


def assert_se3(T: ArrayLike, tol: float) -> None:
    """Assert every (..., 4, 4) is a rigid transform: RᵀR = I, det R = 1, last row 0 0 0 1."""
    T = np.asarray(T, dtype=float)
    R = T[..., :3, :3]
    eye = np.broadcast_to(np.eye(3), R.shape)
    np.testing.assert_allclose(np.swapaxes(R, -1, -2) @ R, eye, rtol=0, atol=tol)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, rtol=0, atol=tol)
    last = np.broadcast_to(np.array([0.0, 0.0, 0.0, 1.0]), T[..., 3, :].shape)
    np.testing.assert_array_equal(T[..., 3, :], last)


@contextlib.contextmanager
def deadline(seconds: float) -> Iterator[None]:
    """Fail (TimeoutError) if the block runs longer than ``seconds``: SIGALRM, main thread only.

    A blocking system call (opening a FIFO, reading a pipe) is interrupted too.
    """

    def expire(signum: int, frame: object) -> None:
        raise TimeoutError(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def random_q(model: Model, rng: np.random.Generator, n: int) -> np.ndarray:
    """n configurations uniformly within limits (±π where a joint has none)."""
    lo = np.where(np.isfinite(model.limits[:, 0]), model.limits[:, 0], -np.pi)
    hi = np.where(np.isfinite(model.limits[:, 1]), model.limits[:, 1], np.pi)
    return rng.uniform(lo, hi, size=(n, model.dof))


def _address_space_bytes() -> int:
    """This process's address space now (``VmSize``), bytes; 0 where /proc is not there."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


@contextlib.contextmanager
def address_space_cap(extra_bytes: int) -> Iterator[None]:
    """Let the block grow this process's address space by at most ``extra_bytes``.

    ``RLIMIT_AS``'s soft limit (what ``ulimit -v`` and ``nox -s bounded`` set)
    is lowered to the address space now plus ``extra_bytes`` (never above the
    hard limit) and put back after: a reader whose memory blows up raises
    ``MemoryError`` in the test instead of taking the machine's memory. Virtual
    memory counts, so ``extra_bytes`` must leave room for the libraries' mappings
    the block may make (a new thread's stack, an import).
    """
    import resource

    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    now = _address_space_bytes()
    if now == 0:  # no /proc: no cap (the bounded session's own limit still holds)
        yield
        return
    cap = now + extra_bytes
    if hard != resource.RLIM_INFINITY:
        cap = min(cap, hard)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
