"""A recording's peak memory does not grow with its length (issue 35, item 2).

Two RTDE recordings of one motion, one ten times as long as the other, are read as
the check reads them (:class:`~fkcheck.engine.stream.StreamSummary` comparing every
row with the core) in processes of their own; each reports its own peak (VmHWM: a
child's ``ru_maxrss`` starts at its parent's). Both are longer than
:data:`~fkcheck.backends.recording.KEEP_ROWS`, so both keep the same number of rows.
Read whole, as before, the longer one took about 270 MB more (300 bytes a row).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends.recording import KEEP_ROWS
from tests.rtde_cases import RTDE_HEADER, rtde_rows

#: Rows of the shorter recording; the longer one has ten times as many. The peak is
#: reached within the first few chunks after :data:`KEEP_ROWS` rows (the sample
#: thinned, the allocator's arenas in use): about 80,000 rows.
SHORT_ROWS = 100_000
#: How much more the longer recording's reading may peak at, bytes: the rows kept
#: differ (a sample of ≤ KEEP_ROWS, 184 bytes each, is at 1/2 to 1/1 of it), the
#: allocator's arenas by a few pages. Read whole it was ~270 MB more.
SAME_PEAK_BYTES = 8 << 20

_READ = """
import sys
from fkcheck import load_model
from fkcheck.backends.measured import MeasuredPoses
from fkcheck.engine.stream import StreamKeeper
model = load_model("ur5")
backend = MeasuredPoses(sys.argv[1])
backend.keep_with(StreamKeeper((1e-6, 1e-6)))
q = backend.configurations(model)
_, summary = backend.streamed(model)
status = open("/proc/self/status").read().split("VmHWM:", 1)[1]
print(summary.rows, q.shape[0], summary.max_position_m, int(status.split()[0]))
"""


def _read(path):
    done = subprocess.run(
        [sys.executable, "-c", _READ, str(path)], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-2000:]
    rows, kept, worst, peak_kib = done.stdout.split()
    return int(rows), int(kept), float(worst), int(peak_kib) * 1024


@pytest.mark.slow  # 1.1 million rows read: about 12 s of one core
def test_ten_times_the_rows_peak_within_a_few_megabytes(tmp_path):
    ur5 = load_model("ur5")
    rng = np.random.default_rng(3510)
    t = np.arange(SHORT_ROWS)[:, None] * 0.002
    q = 2.5 * np.sin(rng.uniform(0.05, 0.5, 6) * t + rng.uniform(0, 2 * np.pi, 6))
    block = "".join(" ".join(map(repr, row)) + "\n" for row in rtde_rows(ur5, q))
    short, long = tmp_path / "short.csv", tmp_path / "long.csv"
    short.write_text(" ".join(RTDE_HEADER) + "\n" + block, encoding="utf-8")
    with long.open("w", encoding="utf-8") as f:
        f.write(" ".join(RTDE_HEADER) + "\n")
        for _ in range(10):  # the motion ten times over
            f.write(block)
    assert SHORT_ROWS > KEEP_ROWS
    rows_s, kept_s, worst_s, peak_s = _read(short)
    rows_l, kept_l, worst_l, peak_l = _read(long)
    assert (rows_s, rows_l) == (SHORT_ROWS, 10 * SHORT_ROWS)  # every row read and compared
    assert worst_s < 1e-12
    assert worst_l < 1e-12
    assert KEEP_ROWS // 2 <= kept_s <= KEEP_ROWS + 6
    assert KEEP_ROWS // 2 <= kept_l <= KEEP_ROWS + 6
    assert peak_l - peak_s < SAME_PEAK_BYTES, (peak_s, peak_l)
