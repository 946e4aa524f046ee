"""Memory stays proportional to what is kept: big inputs under an address-space limit.

A 1,000,000-line ``--q-file`` with ``--json`` peaked at 3.3-4.1 GB when every
record and the whole JSON text were built at once; it now streams. Here it runs
under ``RLIMIT_AS`` (what ``ulimit -v`` sets) of 1 GiB — virtual memory, so
numpy's, numba's and the libraries' mappings all count — and must finish with
the same first and last records as a small run. ``nox -s bounded`` runs the
hostile-input suites under a 2 GiB limit too.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fkcheck.core.tolerances import FAST_CORE

LIMIT_BYTES = 1 << 30  # 1 GiB of address space
LINES = 1_000_000


def _tail(path: Path, size: int = 1 << 16) -> bytes:
    with path.open("rb") as handle:
        handle.seek(-size, 2)
        return handle.read()


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (LIMIT_BYTES, LIMIT_BYTES))


@pytest.mark.slow  # a million-line input: `nox -s slow` and `nox -s bounded` run it
def test_a_million_line_q_file_as_json_runs_in_1_gib_of_address_space(tmp_path: Path):
    q = np.random.default_rng(7).uniform(-3.0, 3.0, size=(LINES, 6))
    q_file = tmp_path / "q.csv"
    np.savetxt(q_file, q, fmt="%.6f", delimiter=",")
    out = tmp_path / "fk.json"
    with out.open("wb") as handle:
        done = subprocess.run(
            [sys.executable, "-m", "fkcheck", "fk", "ur5", "--q-file", str(q_file), "--json"],
            stdout=handle, stderr=subprocess.PIPE, preexec_fn=_limited, timeout=600,
        )  # fmt: skip
    assert done.returncode == 0, done.stderr.decode()[-2000:]
    # Read back a record at a time: loading a million records whole would need
    # more memory than this test process may have under `nox -s bounded`.
    marker, count = b'{"model": ', 0
    with out.open("rb") as handle:
        assert handle.read(1) == b"["
        carry = b""
        while chunk := handle.read(1 << 24):
            data = carry + chunk
            count += data.count(marker)
            carry = data[-(len(marker) - 1) :]
            count -= carry.count(marker)
        count += carry.count(marker)
    assert count == LINES
    tail = _tail(out)  # the file is hundreds of MB; its last record is in the last 64 KiB
    last = json.loads(tail[tail.rindex(marker) :].rstrip().removesuffix(b"]"))
    small = subprocess.run(
        [sys.executable, "-m", "fkcheck", "fk", "ur5", "--q", ",".join(f"{v:.6f}" for v in q[-1]),
         "--json"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert small.returncode == 0, small.stderr
    # The batch takes the JIT kernels, one pose the scalar path: equal to FAST_CORE.
    np.testing.assert_allclose(
        json.loads(small.stdout)["matrix"], last["matrix"], rtol=0, atol=FAST_CORE
    )
