"""How many CPUs this process may use: its affinity, capped by its cgroup's CPU quota.

A container limited to 2 CPUs of a 64-core host has all 64 in its affinity; one
process per "core" there would be 64 interpreters sharing 2 CPUs' time.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

__all__ = ["cpu_quota", "usable_cores"]


def usable_cores() -> int:
    """The cores this process may run on, no more than its cgroup's CPU quota allows."""
    if hasattr(os, "sched_getaffinity"):
        cores = len(os.sched_getaffinity(0))
    else:  # pragma: no cover - not Linux
        cores = os.cpu_count() or 1
    quota = cpu_quota()
    return cores if quota is None else max(1, min(cores, quota))


def cpu_quota(
    root: Path = Path("/sys/fs/cgroup"), own: Path = Path("/proc/self/cgroup")
) -> int | None:
    """Whole CPUs this process's cgroups allow it (their tightest quota, rounded up).

    ``None``: no quota, or none readable. Read from cgroup v2's ``cpu.max`` and
    v1's ``cpu.cfs_quota_us``/``cpu.cfs_period_us``, in this process's cgroup (of
    the ``cpu`` controller, for v1) and its parents, as mounted under ``root``. A
    cgroup outside this process's cgroup namespace (``/../..``) is not followed
    above ``root``: only ``root`` itself is read for it.
    """
    v2, v1 = {""}, {""}  # a container's own cgroup is often mounted at the root
    with contextlib.suppress(OSError):
        for line in own.read_text().splitlines():
            _, controllers, path = [*line.split(":", 2), "", ""][:3]
            if controllers == "":
                v2.add(path.strip("/"))
            elif "cpu" in controllers.split(","):
                v1.add(path.strip("/"))

    def v2_quota(where: Path) -> int | None:
        limit, period = (where / "cpu.max").read_text().split()
        return None if limit == "max" else -(-int(limit) // int(period))

    def v1_quota(where: Path) -> int | None:
        limit = int((where / "cpu.cfs_quota_us").read_text())
        return None if limit <= 0 else -(-limit // int((where / "cpu.cfs_period_us").read_text()))

    found: list[int] = []
    for bases, paths, read in (
        ((root, root / "unified"), v2, v2_quota),
        ((root / "cpu", root / "cpu,cpuacct"), v1, v1_quota),
    ):
        for base in bases:
            for path in paths:
                parts = Path(path).parts
                if ".." in parts:  # above the namespace's root: not under this mount
                    parts = ()
                for k in range(len(parts) + 1):
                    with contextlib.suppress(OSError, ValueError, ZeroDivisionError):
                        quota = read(base.joinpath(*parts[:k]))
                        if quota is not None:
                            found.append(quota)
    return min(found) if found else None
