"""Thread pools sized to a process's share of the cores, when several checks run at once.

NumPy's and SciPy's OpenBLAS, an OpenMP runtime and fkcheck's numba kernels each
run one thread per core in every process. Several checks at once — pytest-xdist
workers, an isolated backend split over processes — then run ``workers × cores``
threads on the cores, and they wait on each other: 16 robots' checks took as long
on 2 xdist workers as on 1, with 40 % more CPU time (``docs/howto/many-robots.md``).

:func:`share_cores` gives this process its share, ``usable cores // workers``
threads (at least 1): to the libraries already loaded through threadpoolctl, to
those loaded later through their own variables (``OMP_NUM_THREADS``,
``OPENBLAS_NUM_THREADS``, ``MKL_NUM_THREADS``, read when a library loads), and to
fkcheck's numba kernels through :func:`thread_limit`. :func:`child_environment`
sizes the pools of child processes started side by side (numba's
``NUMBA_NUM_THREADS`` too: it cannot change once numba runs in a process).

:func:`one_blas_thread` runs BLAS on one thread, whatever the share: fkcheck's
own linear algebra is small (the evidence's SVDs and least squares, a few
thousand rows by tens of columns; the map's fits), where waking a BLAS thread per
core costs more than it saves — and on a busy machine far more: an 870 × 24 SVD
of a check's evidence took 0.3 s with OpenBLAS's two threads on a loaded 2-core
machine, 1 ms with one. The ``fkcheck`` program takes it when it starts, as do
the pytest plugin (for a project with ``[tool.fkcheck]`` models) and fkcheck's own
test suite; a Python caller's process is left as it is.

:func:`share_xdist_cores` is the share of a pytest-xdist worker, taken by the
pytest plugin (for a project with ``[tool.fkcheck]`` models) and by
:func:`fkcheck.testing.assert_fk_matches`. A user who set any of those variables
chose: their pools are left alone (those a parent fkcheck set, which
:data:`SET_BY_FKCHECK` names, are fkcheck's, not a choice).
"""

from __future__ import annotations

import os
from collections.abc import Mapping

from fkcheck.process.cpus import usable_cores

__all__ = [
    "BLAS_VARIABLES",
    "SET_BY_FKCHECK",
    "THREAD_VARIABLES",
    "XDIST_WORKERS",
    "child_environment",
    "one_blas_thread",
    "share_cores",
    "share_xdist_cores",
    "thread_limit",
]

#: The variables that size the thread pools of a library loaded after they are set.
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
#: Of those, the BLAS libraries' (NumPy's and SciPy's OpenBLAS, MKL).
BLAS_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
#: numba's, read once when numba is imported (a child process's only).
_NUMBA_VARIABLE = "NUMBA_NUM_THREADS"

#: The variable pytest-xdist sets in each of its workers: how many workers it runs.
XDIST_WORKERS = "PYTEST_XDIST_WORKER_COUNT"

#: Which of those variables fkcheck set, and to what (``NAME=VALUE,…``), for the
#: processes it starts: a child (an xdist worker of a controller that took
#: :func:`one_blas_thread`) finds them fkcheck's, not the user's choice.
SET_BY_FKCHECK = "FKCHECK_THREAD_VARIABLES"

_limit: int | None = None
#: Whether :func:`one_blas_thread` set BLAS to one thread in this process.
_one_blas = False


def _ours(environ: Mapping[str, str]) -> dict[str, str]:
    """The variables :data:`SET_BY_FKCHECK` says fkcheck set, with their values."""
    items = (item.partition("=") for item in environ.get(SET_BY_FKCHECK, "").split(","))
    return {name: value for name, eq, value in items if eq}


def _setting(environ: Mapping[str, str], values: Mapping[str, str]) -> dict[str, str]:
    """``values``, and :data:`SET_BY_FKCHECK` naming them and those ``environ``'s named already."""
    ours = {**_ours(environ), **values}
    return {**values, SET_BY_FKCHECK: ",".join(f"{k}={v}" for k, v in sorted(ours.items()))}


def _user_chose() -> bool:
    """Whether the user set a pool's size (not fkcheck, here or in a parent)."""
    if _limit is not None or _one_blas:
        return False
    ours = _ours(os.environ)
    return any(
        name in os.environ and os.environ[name] != ours.get(name)
        for name in (*THREAD_VARIABLES, _NUMBA_VARIABLE)
    )


def _sizes(threads: int) -> dict[str, str]:
    """Each variable of :data:`THREAD_VARIABLES` for pools of ``threads`` (BLAS: one, if so)."""
    return {
        name: "1" if _one_blas and name in BLAS_VARIABLES else str(threads)
        for name in THREAD_VARIABLES
    }


def one_blas_thread() -> bool:
    """Run this process's BLAS on one thread, loaded already or later (see the module).

    Idempotent; the user's variables (any of :data:`THREAD_VARIABLES` or numba's,
    set before) leave every pool alone. Children inherit the variables.

    Returns:
        Whether BLAS runs on one thread now.
    """
    global _one_blas
    if _one_blas:
        return True
    if _user_chose():
        return False
    from threadpoolctl import threadpool_limits  # type: ignore[import-untyped]

    # For the libraries this process loads later, and its children.
    os.environ.update(_setting(os.environ, dict.fromkeys(BLAS_VARIABLES, "1")))
    threadpool_limits(limits=1, user_api="blas")  # for those loaded already
    _one_blas = True
    return True


def share_cores(workers: int) -> int | None:
    """Size this process's thread pools to its share, as one of ``workers`` side by side.

    Idempotent; a share once set is never widened (a second, larger one is ignored).

    Returns:
        The threads each pool may run, or ``None`` when the user's variables decide.
    """
    global _limit
    if _user_chose():
        return None
    threads = max(1, usable_cores() // max(1, workers))
    if _limit is not None and _limit <= threads:
        return _limit
    from threadpoolctl import threadpool_limits

    os.environ.update(_setting(os.environ, _sizes(threads)))  # for libraries loaded later
    threadpool_limits(limits={"blas": 1 if _one_blas else threads, "openmp": threads})
    _limit = threads
    return threads


def share_xdist_cores() -> int | None:
    """In a pytest-xdist worker (one of several), :func:`share_cores` with the workers' count.

    Outside xdist, or in its only worker, nothing changes.

    Returns:
        The threads each pool may run, or ``None`` when nothing changed.
    """
    try:
        workers = int(os.environ.get(XDIST_WORKERS, ""))
    except ValueError:  # not an xdist worker (or a variable set by hand, not a count)
        return None
    return share_cores(workers) if workers > 1 else None


def thread_limit() -> int | None:
    """The threads this process's share allows (:func:`share_cores`), or ``None``: no share."""
    return _limit


def child_environment(workers: int) -> dict[str, str] | None:
    """The environment of one of ``workers`` child processes started side by side.

    This process's, with each pool sized to the child's share of this process's
    cores (its own share, when it has one); ``None`` (inherit this process's
    environment) for one child, or when the user's variables decide.
    """
    if workers <= 1 or _user_chose():
        return None
    threads = max(1, (_limit or usable_cores()) // workers)
    sizes = {**_sizes(threads), _NUMBA_VARIABLE: str(threads)}
    return {**os.environ, **_setting(os.environ, sizes)}
