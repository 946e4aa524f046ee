"""The machine and library versions a bench ran on, recorded beside its numbers."""

from __future__ import annotations

import os
import platform
from typing import Any

__all__ = ["library_versions", "machine_info"]


def machine_info() -> dict[str, Any]:
    """CPU model, CPU count, load average, Python version and platform."""
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


def library_versions() -> dict[str, str]:
    """The installed versions of the core's and the backends' distributions (the registry's)."""
    from fkcheck.backends.registry import library_versions as registered

    return registered()
