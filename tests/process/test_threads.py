"""Thread pools sized to a process's share of the cores (several checks at once).

Each case runs in a fresh interpreter: a share changes the process's thread pools
and environment for good. The machine's cores are set in it (``usable_cores``), so
the shares asserted do not depend on the machine the tests run on.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from fkcheck.process import threads

pytestmark = pytest.mark.skipif(
    not hasattr(os, "sched_getaffinity"), reason="compares with the process's affinity (Linux)"
)

_SHARE = """
import json, os, sys
import numpy
from fkcheck.process import threads
threads.usable_cores = lambda: int(sys.argv[1])
from threadpoolctl import threadpool_info
before = [p["num_threads"] for p in threadpool_info()]
got = threads.share_xdist_cores()
import scipy.linalg  # its OpenBLAS loads after the share: sized by the variables
after = {p["filepath"].rsplit("/", 1)[-1]: p["num_threads"] for p in threadpool_info()}
from fkcheck.core import dh
assert dh.load_jit()
print(json.dumps({"got": got, "before": before, "after": after, "jit": dh.jit_tasks(),
                  "numba": int(dh._jit.nb.get_num_threads()),
                  "env": {k: os.environ.get(k) for k in threads.THREAD_VARIABLES},
                  "child": threads.child_environment(2) is not None}))
"""


def _run(script: str, cores: int, env: dict[str, str]) -> dict:
    """``script``'s last line, read as JSON, run on ``cores`` cores with ``env`` only set."""
    clean = {
        k: v
        for k, v in os.environ.items()
        if k
        not in (
            *threads.THREAD_VARIABLES,
            "NUMBA_NUM_THREADS",
            threads.XDIST_WORKERS,
            threads.SET_BY_FKCHECK,
        )
    }
    done = subprocess.run(
        [sys.executable, "-c", script, str(cores)],
        env={**clean, **env},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    result: dict = json.loads(done.stdout.splitlines()[-1])
    return result


def _share(cores: int, env: dict[str, str]) -> dict:
    return _run(_SHARE, cores, env)


def test_an_xdist_worker_gets_its_share_of_the_cores_in_every_pool():
    # 4 cores, 4 workers: one thread each — numpy's and SciPy's OpenBLAS (loaded before
    # and after the share) and fkcheck's numba kernels.
    got = _share(4, {threads.XDIST_WORKERS: "4"})
    assert got["got"] == 1
    assert max(got["before"]) > 1 or len(os.sched_getaffinity(0)) == 1  # default: one per core
    assert len(got["after"]) >= 2  # numpy's and SciPy's OpenBLAS
    assert set(got["after"].values()) == {1}
    assert got["jit"] == 1
    assert got["env"] == dict.fromkeys(threads.THREAD_VARIABLES, "1")


def test_two_workers_on_eight_cores_get_four_threads_each():
    got = _share(8, {threads.XDIST_WORKERS: "2"})
    assert got["got"] == 4
    # OpenBLAS loaded before the share runs at most the threads it started with (one per
    # core of this machine); the one loaded after starts with 4.
    least = min(4, len(os.sched_getaffinity(0)))
    assert all(least <= v <= 4 for v in got["after"].values()), got["after"]
    assert got["jit"] == min(4, got["numba"])


@pytest.mark.parametrize(
    "env",
    [
        {},  # not an xdist worker
        {threads.XDIST_WORKERS: "1"},  # its only worker
        {threads.XDIST_WORKERS: "4", "OMP_NUM_THREADS": "3"},  # the user chose
        {threads.XDIST_WORKERS: "4", "NUMBA_NUM_THREADS": "2"},
    ],
)
def test_no_share_outside_xdist_or_when_the_user_sized_the_pools(env):
    got = _share(4, env)
    assert got["got"] is None
    assert got["after"]
    assert set(got["after"].values()) == set(got["before"])
    assert got["jit"] == got["numba"]
    for name in threads.THREAD_VARIABLES:
        assert got["env"][name] == env.get(name)
    # Children inherit this process's environment when the user chose.
    assert got["child"] is not any(k in env for k in ("OMP_NUM_THREADS", "NUMBA_NUM_THREADS"))


def test_children_side_by_side_each_get_their_share(monkeypatch):
    monkeypatch.setattr(threads, "usable_cores", lambda: 8)
    monkeypatch.setattr(threads, "_limit", None)
    monkeypatch.setattr(threads, "_one_blas", False)  # the suite's conftest set it
    for name in (*threads.THREAD_VARIABLES, "NUMBA_NUM_THREADS"):
        monkeypatch.delenv(name, raising=False)
    assert threads.child_environment(1) is None  # one child: this process's environment
    env = threads.child_environment(2)
    assert env is not None
    assert {env[k] for k in (*threads.THREAD_VARIABLES, "NUMBA_NUM_THREADS")} == {"4"}
    assert env["PATH"] == os.environ["PATH"]  # the rest is this process's
    env = threads.child_environment(16)
    assert env is not None
    assert env["OPENBLAS_NUM_THREADS"] == "1"  # at least one
    # A process with a share of its own splits that share, not the machine.
    monkeypatch.setattr(threads, "_limit", 2)
    env = threads.child_environment(2)
    assert env is not None
    assert env["OMP_NUM_THREADS"] == "1"


_ONE_BLAS = """
import json, os, sys
import numpy
from fkcheck.process import threads
threads.usable_cores = lambda: int(sys.argv[1])
from threadpoolctl import threadpool_info
def pools():
    return sorted({(p["user_api"], p["num_threads"]) for p in threadpool_info()})
one = threads.one_blas_thread()
first = pools()
got = threads.share_xdist_cores()
import scipy.linalg  # its OpenBLAS loads after: sized by the variables
print(json.dumps({"one": one, "first": first, "got": got, "after": pools(),
                  "env": {k: os.environ.get(k) for k in threads.THREAD_VARIABLES},
                  "child": threads.child_environment(2)}))
"""


def _one_blas(cores: int, env: dict[str, str]) -> dict:
    return _run(_ONE_BLAS, cores, env)


def test_one_blas_thread_keeps_blas_at_one_thread_through_a_share_and_in_children():
    got = _one_blas(8, {threads.XDIST_WORKERS: "2"})
    assert got["one"] is True
    assert ["blas", 1] in got["first"]
    assert got["got"] == 4  # the workers' share: OpenMP and numba
    assert {n for api, n in got["after"] if api == "blas"} == {1}  # numpy's and SciPy's
    assert got["env"] == {"OMP_NUM_THREADS": "4", "OPENBLAS_NUM_THREADS": "1",
                          "MKL_NUM_THREADS": "1"}  # fmt: skip
    child = got["child"]
    assert (child["OMP_NUM_THREADS"], child["NUMBA_NUM_THREADS"]) == ("2", "2")
    assert (child["OPENBLAS_NUM_THREADS"], child["MKL_NUM_THREADS"]) == ("1", "1")


def test_one_blas_thread_leaves_the_pools_the_user_sized():
    got = _one_blas(8, {"OPENBLAS_NUM_THREADS": "2"})
    assert got["one"] is False
    assert got["got"] is None  # not an xdist worker
    assert got["env"]["OPENBLAS_NUM_THREADS"] == "2"
    assert got["env"]["MKL_NUM_THREADS"] is None


def test_the_fkcheck_program_runs_blas_on_one_thread(tmp_path):
    # The program (argv None), not a Python caller of main([...]): it sets the variable
    # its children and the libraries it loads later read.
    script = (
        "import os, sys; from fkcheck.cli.main import main; "
        "sys.argv = ['fkcheck', '--version']; "
        "import atexit; atexit.register(lambda: print(os.environ.get('OPENBLAS_NUM_THREADS'))); "
        "main()"
    )
    clean = {k: v for k, v in os.environ.items() if k not in threads.THREAD_VARIABLES}
    done = subprocess.run(
        [sys.executable, "-c", script], env=clean, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-1] == "1"


def test_variables_a_parent_fkcheck_set_are_not_the_users_choice(monkeypatch):
    # An xdist worker inherits the variables its controller's plugin set: still fkcheck's.
    monkeypatch.setattr(threads, "_limit", None)
    monkeypatch.setattr(threads, "_one_blas", False)
    for name in (*threads.THREAD_VARIABLES, "NUMBA_NUM_THREADS"):
        monkeypatch.delenv(name, raising=False)
    marker = "MKL_NUM_THREADS=1,OPENBLAS_NUM_THREADS=1"
    monkeypatch.setenv(threads.SET_BY_FKCHECK, marker)
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "1")
    monkeypatch.setenv("MKL_NUM_THREADS", "1")
    assert threads._user_chose() is False
    env = threads.child_environment(2)
    assert env is not None
    assert threads._ours(env) == {
        "MKL_NUM_THREADS": "1",
        "NUMBA_NUM_THREADS": env["NUMBA_NUM_THREADS"],
        "OMP_NUM_THREADS": env["OMP_NUM_THREADS"],
        "OPENBLAS_NUM_THREADS": env["OPENBLAS_NUM_THREADS"],
    }
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "2")  # not what fkcheck set: the user's
    assert threads._user_chose() is True
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "1")
    monkeypatch.setenv("OMP_NUM_THREADS", "3")  # fkcheck set no OMP_NUM_THREADS
    assert threads._user_chose() is True


_CALLER = """
import json, os, sys
import numpy
from fkcheck.process import threads
threads.usable_cores = lambda: int(sys.argv[1])
from threadpoolctl import threadpool_info, threadpool_limits
threadpool_limits(limits=2, user_api="blas")  # the caller's own size, whatever the machine
def pools():
    return sorted({(p["user_api"], p["num_threads"]) for p in threadpool_info()})
names = (*threads.THREAD_VARIABLES, "NUMBA_NUM_THREADS", threads.SET_BY_FKCHECK)
before = (pools(), {k: os.environ.get(k) for k in names})
import fkcheck
checked = [fkcheck.check("ur5", against=["pinocchio-dh"], samples=64).verdict,
           fkcheck.check("ur5", against=["yourdfpy-urdf"], samples=64).verdict]
from fkcheck.core import dh
import numba
print(json.dumps({"before": before, "after": (pools(), {k: os.environ.get(k) for k in names}),
                  "checked": checked, "jit": dh.load_jit(),
                  "numba": [numba.get_num_threads(), numba.config.NUMBA_DEFAULT_NUM_THREADS]}))
"""


def test_a_python_caller_keeps_its_blas_and_variables_through_fkcheck_check():
    # fkcheck.check() is a library call: the caller's pools and environment are its own
    # (one_blas_thread is the program's and the plugin's only).
    got = _run(_CALLER, 8, {})
    assert got["checked"] == ["pass", "pass"]
    assert ["blas", 2] in got["before"][0]
    assert [api for api, n in got["after"][0] if api == "blas" and n != 2] == []
    assert got["after"][1] == got["before"][1] == dict.fromkeys(got["before"][1])


_NUMBA_AFTER_ONE_BLAS = """
import json, sys
import numpy
from fkcheck.process import threads
assert threads.one_blas_thread()
from fkcheck.core import dh
assert dh.load_jit()
import numba
from threadpoolctl import threadpool_info
print(json.dumps({"numba": [numba.get_num_threads(), numba.config.NUMBA_DEFAULT_NUM_THREADS],
                  "pools": sorted({(p["user_api"], p["num_threads"]) for p in threadpool_info()})}))
"""


def test_one_blas_thread_leaves_numba_its_threads():
    # Only BLAS runs on one thread: the core's parallel FK (numba, large checks) keeps one
    # thread per core, and so does the OpenMP pool numba's threading layer may use.
    got = _run(_NUMBA_AFTER_ONE_BLAS, 8, {})
    used, default = got["numba"]
    assert used == default == numba_default_threads()
    assert {n for api, n in got["pools"] if api == "blas"} == {1}
    assert {n for api, n in got["pools"] if api == "openmp"} <= {default}


def numba_default_threads() -> int:
    """numba's default: one thread per CPU it sees (not fkcheck's usable cores)."""
    numba = pytest.importorskip("numba")
    return int(numba.config.NUMBA_DEFAULT_NUM_THREADS)
