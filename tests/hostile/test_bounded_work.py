"""Work and memory that grow with what an input is worth, not with its size alone.

Round four of the hostile inputs (issue 31): per-number evidence on a chain at
the model limit took 76–164 s and 1.3 GB for two samples, outside ``--timeout``
(every nudged number recomputed the whole chain; the trade search joined sets
pair by pair). It now costs seconds and stops at the check's time limit in one line.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import time
from pathlib import Path

from fkcheck.model.types import MAX_JOINTS

#: CPU seconds the analysis of a chain at the model limit may take, one BLAS
#: thread: about 5 s measured (it was over 90 s); the margin is for slow runners.
EVIDENCE_CPU_S = 40.0
#: Its peak resident memory, bytes (250 MB measured, the libraries included).
EVIDENCE_RSS_BYTES = 700 << 20


def _long_chain(path: Path, joints: int = MAX_JOINTS) -> Path:
    lines = ['name = "long"', 'convention = "standard"', 'angle_unit = "deg"']
    for i in range(joints):
        lines += [
            "[[joint]]", f'name = "j{i + 1}"', f"a = {0.01 + 0.0001 * (i % 7)}",
            f"alpha = {(0, 90, -90)[i % 3]}", f"d = {0.001 * (i % 5)}", "limits = [-180, 180]",
        ]  # fmt: skip
    path.write_text("\n".join(lines) + "\n")
    return path


_ANALYSE = """
import resource, sys, time
from fkcheck.model.coverage import coverage
from fkcheck.model.read import load_model
from fkcheck.model.sampling import sample_configurations
model = load_model(sys.argv[1])
q = sample_configurations(model, 2, 0, "sobol").q  # 2 samples and every corner: 772
c = coverage(model, "world", "tcp", 1e-6, 1e-6, q=q)
# This process's own peak: VmHWM of its own memory map (ru_maxrss keeps, across exec,
# the peak of the forked test process it started as).
status = open("/proc/self/status").read().split("VmHWM:", 1)[1]
peak_kib = int(status.split()[0])
print(q.shape[0], c.count("verified"), c.count("not-identifiable"), peak_kib)
"""


def test_per_number_evidence_at_the_model_limit_costs_seconds(tmp_path):
    model = _long_chain(tmp_path / "long.toml")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    done = subprocess.run(
        [sys.executable, "-c", _ANALYSE, str(model)],
        capture_output=True, text=True, timeout=600, env=env,
    )  # fmt: skip
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    assert done.returncode == 0, done.stderr[-2000:]
    configurations, verified, hidden, peak_kib = map(int, done.stdout.split())
    assert configurations == 772
    assert verified + hidden == 4 * MAX_JOINTS + MAX_JOINTS  # a, α, d, θ and a direction each
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    assert cpu < EVIDENCE_CPU_S
    # The analysing process's own peak (RUSAGE_CHILDREN's is the largest child the test
    # process ever ran, and a child's ru_maxrss starts at its parent's: under
    # pytest-xdist, another test's).
    assert peak_kib * 1024 < EVIDENCE_RSS_BYTES


def test_the_analysis_obeys_the_check_s_timeout_in_one_line(tmp_path, monkeypatch, capsys):
    # The evidence's limit is --timeout, at least EVIDENCE_MIN_S (10 s: a --timeout for a
    # hanging backend must not end a six-joint check); without that floor, 0.5 s.
    from fkcheck.cli.main import main
    from fkcheck.engine import prepare

    monkeypatch.setattr(prepare, "EVIDENCE_MIN_S", 0.0)
    model = _long_chain(tmp_path / "long.toml")
    start = time.monotonic()
    code = main(["check", str(model), "--samples", "2", "--against", "rtb-dh",
                 "--timeout", "0.5"])  # fmt: skip
    elapsed = time.monotonic() - start
    out, err = capsys.readouterr()
    assert code == 2
    assert err.splitlines() == [
        "fkcheck: error: per-number evidence of long (world → tcp) did not finish within "
        "the check's time limit of 0.5 s; give it more with --timeout"
    ]
    assert "Traceback" not in out + err
    assert elapsed < 120.0  # sampling and one step past the limit; not minutes


def test_a_denormal_tolerance_is_one_line_before_any_work():
    # --tol-pos 5e-324 made every column of the evidence infinite: "SVD did not converge".
    done = subprocess.run(
        [sys.executable, "-m", "fkcheck", "check", "ur5", "--samples", "2", "--against",
         "rtb-dh", "--tol-pos", "5e-324"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 2
    assert done.stdout == ""
    assert done.stderr.splitlines() == [
        "fkcheck: error: --tol-pos: must be at least 1e-12 m (a tighter check judges the "
        "round-off of float arithmetic, not the table), got 4.94066e-324"
    ]


def test_a_recording_of_more_rows_than_the_limit_is_one_line_before_the_rows_are_read(
    tmp_path, monkeypatch, capsys
):
    # 10 million short rows (240 MB) took 236 s and 7.7 GB when read whole; they now
    # stream in bounded memory (tests/backends/test_recording_stream.py), and the row
    # limit bounds the time. One row beyond it (made small here) is one line, exit 2.
    from fkcheck.backends import measured
    from fkcheck.cli.main import main

    monkeypatch.setattr(measured, "MAX_POSES_ROWS", 1000)
    head = " ".join([f"actual_q_{i}" for i in range(6)] + [f"actual_TCP_pose_{i}" for i in
                                                            range(6)])  # fmt: skip
    path = tmp_path / "r.csv"
    with path.open("w", encoding="utf-8") as f:
        f.write(head + "\n" + "0 0 0 0 0 0 1 0 0 0 0 0\n" * 1001)
    code = main(["check", "ur5", "--against", f"poses:{path}"])
    out, err = capsys.readouterr()
    assert code == 2, out
    assert err.splitlines() == [
        f"fkcheck: error: {path}: line 1002: more than 1,000 data rows (at most 1,000); cut "
        "the recording or keep every k-th row"
    ]
