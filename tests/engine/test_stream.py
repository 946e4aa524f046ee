"""Long recordings are compared as they stream (issue 35, items 2 and 3).

The recordings are written by :mod:`tests.rtde_cases` from a table by the tests' own
composition (not fkcheck's core). :data:`~fkcheck.backends.recording.KEEP_ROWS` and
:data:`~fkcheck.backends.recording.CHUNK_ROWS` are made small here, so that a
recording of a few hundred rows streams over many chunks and the check runs on a
sample of it: what is asserted is what a recording of millions of rows gets.
"""

from __future__ import annotations

import json
import re
from dataclasses import replace

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends import measured, recording
from fkcheck.backends.measured import MeasuredPoses, PosesFileError, read_poses_file
from fkcheck.cli.main import main
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.engine import compare
from fkcheck.engine.compare import Job
from fkcheck.engine.stream import HISTOGRAM_RATIO, StreamSummary
from tests.rtde_cases import RTDE_HEADER, poses_of, rtde_rows, write_rtde_csv

#: Rows of the recordings here, and the most the check keeps of them.
ROWS = 600
KEEP = 50
#: Rows per chunk: 600 rows are 26 chunks, the last one short.
CHUNK = 23


@pytest.fixture(scope="module")
def ur5():
    return load_model("ur5")


@pytest.fixture
def small(monkeypatch):
    monkeypatch.setattr(recording, "KEEP_ROWS", KEEP)
    monkeypatch.setattr(recording, "CHUNK_ROWS", CHUNK)
    monkeypatch.setattr(measured, "CHUNK_ROWS", CHUNK)


@pytest.fixture(scope="module")
def motion():
    """A smooth motion, each joint at its own frequency (seeded phases)."""
    rng = np.random.default_rng(35)
    t = np.arange(ROWS)[:, None] * 0.01
    return 2.0 * np.sin(rng.uniform(0.1, 1.0, 6) * t + rng.uniform(0, 2 * np.pi, 6))


def _one_row_off(ur5, q, tmp_path, row: int, by_m: float):
    """The recording with ``row``'s x written ``by_m`` off."""
    rows = rtde_rows(ur5, q)
    x = RTDE_HEADER.index("actual_TCP_pose_0")
    rows[row][x] += by_m
    lines = [" ".join(RTDE_HEADER), *(" ".join(map(repr, r)) for r in rows)]
    path = tmp_path / "rec.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_a_recording_that_agrees_streams_every_row_and_passes(ur5, motion, tmp_path, small, capsys):
    path = write_rtde_csv(tmp_path / "rec.csv", ur5, motion)
    report = tmp_path / "r.json"
    code = main(["check", "ur5", "--against", f"poses:{path}", "--json", str(report)])
    out = " ".join(capsys.readouterr().out.split())
    assert code == 0, out
    doc = json.loads(report.read_text())
    # Every 16th row (600 rows thinned until at most 50 are kept: 38) and the worst rows.
    kept = doc["configurations"]
    assert 38 <= kept <= 38 + 6
    assert (
        f"streamed 600 rows (lines 2–601), each compared with fkcheck-dh as read; the check's "
        f"{kept} configurations are one row in 16 and the {kept - 38} worst rows besides them"
    ) in out
    (backend,) = doc["backends"]
    assert backend["status"] == "pass"
    assert backend["max_position_error_m"] < 1e-12


@pytest.mark.parametrize("row", [5, 301, 598])  # in the first chunk, the middle, the last
def test_one_row_off_between_the_sampled_rows_fails_with_its_line_and_size(
    ur5, motion, tmp_path, small, capsys, row
):
    # Row 301 is not in the sample (every 16th row): were only the sample compared,
    # the check would pass. It is kept as a worst row, so the verdict, the maximum and
    # the worst configuration are the recording's own.
    path = _one_row_off(ur5, motion, tmp_path, row, 2e-3)
    report = tmp_path / "r.json"
    code = main(["check", "ur5", "--against", f"poses:{path}", "--json", str(report)])
    out = " ".join(capsys.readouterr().out.split())
    assert code == 1, out
    assert "1 of 600 rows differ: max position error 2.00 mm" in out
    (backend,) = json.loads(report.read_text())["backends"]
    assert backend["max_position_error_m"] == pytest.approx(2e-3, rel=1e-9)
    np.testing.assert_allclose(backend["worst_q"], motion[row], rtol=0, atol=1e-15)


def test_a_table_off_everywhere_counts_every_row_and_its_spread_over_all_of_them(
    motion, tmp_path, small, capsys
):
    ur5 = load_model("ur5")
    path = write_rtde_csv(tmp_path / "rec.csv", ur5, motion)
    text = tmp_path / "m.toml"
    source = load_model("ur5").path
    assert source is not None
    body = source.read_text(encoding="utf-8")
    assert body.count("a = -0.425\n") == 1
    text.write_text(body.replace("a = -0.425\n", "a = -0.4265\n"), encoding="utf-8")
    code = main(["check", str(text), "--against", f"poses:{path}"])
    out = " ".join(capsys.readouterr().out.split())
    assert code == 1, out
    # The count is over every row (a second pass); the spread from the histograms.
    poses = poses_of(ur5, motion)
    changed = load_model(text)
    theirs = poses_of(changed, motion)
    pos_mm = position_error_m(poses, theirs) * 1e3
    assert pos_mm.min() > 1e-3  # every row differs beyond the 1 µm tolerance
    assert "600 of 600 rows differ" in out
    found = re.search(
        r"over the 600 rows: position max ([0-9.]+) mm, median ([0-9.]+) mm, 95th "
        r"percentile ([0-9.]+) mm",
        out,
    )
    assert found, out
    got = [float(v) for v in found.groups()]
    want = [pos_mm.max(), np.median(pos_mm), np.percentile(pos_mm, 95)]
    # Printed to 1 µm; the histogram's bins are 0.1 % apart (a 1.5 mm error: 1.5 µm).
    np.testing.assert_allclose(got, want, rtol=HISTOGRAM_RATIO - 1, atol=6e-4)


def test_the_chunks_read_the_same_rows_as_one_read_of_a_short_file(ur5, motion, tmp_path):
    path = write_rtde_csv(tmp_path / "rec.csv", ur5, motion[:KEEP])
    whole_q, whole_poses, _ = read_poses_file(path, ur5)
    import fkcheck.backends.measured as measured

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(measured, "CHUNK_ROWS", 7)
        q, poses, _ = read_poses_file(path, ur5)
    np.testing.assert_array_equal(q, whole_q)
    np.testing.assert_array_equal(poses, whole_poses)
    np.testing.assert_array_equal(q, motion[:KEEP])


def test_the_summary_keeps_the_worst_rows_of_either_error_whatever_the_tolerance(
    ur5, motion, small
):
    q = motion
    poses = poses_of(ur5, q).copy()
    poses[100, 0, 3] += 1e-3  # row 100: 1 mm, no rotation
    rot = np.array([[1, 0, 0], [0, np.cos(1e-3), -np.sin(1e-3)], [0, np.sin(1e-3), np.cos(1e-3)]])
    poses[333, :3, :3] = poses[333, :3, :3] @ rot  # row 333: 1 mrad, no position
    summary = StreamSummary(ur5, ("base", "tool0"), (1e-6, 1e-6))
    for first in range(0, ROWS, CHUNK):
        stop = min(ROWS, first + CHUNK)
        summary.add(
            recording.PoseChunk(q[first:stop], poses[first:stop], None, np.arange(first, stop) + 2)
        )
    _kept_q, _kept_poses, lines = summary.kept()
    assert summary.rows == ROWS
    assert summary.stride == 16
    assert {102, 335} <= set(lines.tolist())  # lines of rows 100 and 333, not sampled
    assert (np.diff(lines) > 0).all()  # in the recording's order, each row once
    assert summary.max_position_m == pytest.approx(1e-3, rel=1e-9)
    assert summary.max_rotation_rad == pytest.approx(1e-3, rel=1e-6)
    # The quantiles of the histograms, against NumPy's over every row.
    ref = poses_of(ur5, q)
    for which, errors in (
        ("position", position_error_m(ref, poses)),
        ("rotation", rotation_error_rad(ref, poses)),
    ):
        for share in (0.5, 0.95, 1.0):
            exact = np.quantile(errors, share, method="inverted_cdf")
            got = summary.percentile(which, share)
            if exact > 1e-15:
                assert got == pytest.approx(exact, rel=HISTOGRAM_RATIO - 1)
            else:  # round-off rows
                assert got < 1e-14


def test_a_pair_comment_after_the_rows_is_refused_in_one_line(ur5, tmp_path):
    path = write_rtde_csv(tmp_path / "rec.csv", ur5, np.zeros((3, 6)))
    with path.open("a", encoding="utf-8") as f:
        f.write("# fkcheck poses: from=base to=tool0\n")
    with pytest.raises(PosesFileError, match=r"line 5: '# fkcheck poses: from=… to=…' comes after"):
        read_poses_file(path, ur5)


@pytest.mark.parametrize(
    ("field", "problem"),
    [
        ("1_0", r"not a number: '1_0' \(no '_' in numbers\)"),
        ("1e999", r"number too large: '1e999'"),
        ("1e", r"not a number: '1e'"),
        ("-", r"not a number: '-'"),
        ("x" * 101, r"number too long: 101 characters"),
    ],
)
def test_the_quick_read_of_a_chunk_refuses_as_a_line_by_line_read(ur5, tmp_path, field, problem):
    rows = rtde_rows(ur5, np.zeros((30, 6)))
    lines = [" ".join(map(repr, r)) for r in rows]
    k = RTDE_HEADER.index("actual_q_2")
    bad = lines[17].split(" ")
    bad[k] = field
    lines[17] = " ".join(bad)
    path = tmp_path / "rec.csv"
    path.write_text(" ".join(RTDE_HEADER) + "\n" + "\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(PosesFileError, match=rf"line 19, field {k + 1} \(actual_q_2\): {problem}"):
        read_poses_file(path, ur5)


def test_a_check_through_the_api_streams_too(ur5, motion, tmp_path, small):
    from fkcheck import check

    path = _one_row_off(ur5, motion, tmp_path, 301, 2e-3)
    result = check(ur5, [MeasuredPoses(str(path))], tol_pos_m=1e-6)
    (backend,) = result.backends
    assert backend.status == "fail"
    assert "1 of 600 rows differ" in backend.message
    assert backend.max_position_error_m == pytest.approx(2e-3, rel=1e-9)


def _off_by_known_amounts(ur5, q, seed):
    """``poses_of(ur5, q)``, each row moved by a drawn translation and turned about its own z.

    Row ``k`` is moved by ``shift[k]`` (in the tool frame) and turned by ``turn[k]`` about
    its tool z axis: its position error is ``|shift[k]|`` and its rotation error
    ``|turn[k]|``, known without fkcheck's metrics. About a third of the rows are beyond
    the 1 µm / 1 µrad tolerances in position, a third in rotation, some in both.
    """
    rng = np.random.default_rng(seed)
    m = q.shape[0]
    size = rng.choice([0.0, 0.5e-6, 2e-6], m)  # none, within, beyond the 1 µm tolerance
    direction = rng.normal(size=(m, 3))
    shift = direction / np.linalg.norm(direction, axis=1)[:, None] * size[:, None]
    turn = rng.choice([0.0, -0.4e-6, 3e-6], m)
    poses = poses_of(ur5, q).copy()
    c, s = np.cos(turn), np.sin(turn)
    rz = np.zeros((m, 3, 3))
    rz[:, 0, 0], rz[:, 0, 1], rz[:, 1, 0], rz[:, 1, 1], rz[:, 2, 2] = c, -s, s, c, 1.0
    poses[:, :3, 3] += np.einsum("kij,kj->ki", poses[:, :3, :3], shift)
    poses[:, :3, :3] = poses[:, :3, :3] @ rz
    return poses, size, np.abs(turn)


def _beyond(size, turn, tol=(1e-6, 1e-6)):
    """Rows moved or turned by more than ``tol``: NumPy's count of the drawn amounts."""
    return int(((size > tol[0]) | (turn > tol[1])).sum())


@pytest.mark.parametrize("seed", [1, 2])
def test_the_summary_counts_the_rows_beyond_tolerance_as_numpy_does_over_every_row(
    ur5, motion, small, seed
):
    poses, size, turn = _off_by_known_amounts(ur5, motion, seed)
    beyond = _beyond(size, turn)
    assert 0 < beyond < ROWS  # some rows within, some beyond
    summary = StreamSummary(ur5, ("base", "tool0"), (1e-6, 1e-6))
    for first in range(0, ROWS, CHUNK):
        stop = min(ROWS, first + CHUNK)
        summary.add(
            recording.PoseChunk(
                motion[first:stop], poses[first:stop], None, np.arange(first, stop) + 2
            )
        )
    assert summary.stride > 1  # a sample is kept, not every row
    assert summary.beyond == beyond
    # Another tolerance is another summary, counted as it streams, as NumPy does.
    looser = (2.5e-6, 1e-6)
    want = _beyond(size, turn, looser)
    assert 0 < want < beyond
    other = StreamSummary(ur5, ("base", "tool0"), looser)
    for first in range(0, ROWS, CHUNK):
        stop = min(ROWS, first + CHUNK)
        other.add(recording.PoseChunk(motion[first:stop], poses[first:stop], None,
                                      np.arange(first, stop) + 2))  # fmt: skip
    assert other.beyond == want


def test_a_summary_of_other_tolerances_or_pair_is_an_error_never_a_second_read(ur5, motion):
    # The check's comparison takes the count its one read made (under the read's
    # clock); a summary that counted against anything else is a broken contract.
    poses, size, turn = _off_by_known_amounts(ur5, motion, 1)
    rec = _ChunkedRecording(motion, poses)
    summary = StreamSummary(ur5, ("base", "tool0"), (1e-6, 1e-6))
    for chunk in rec.chunks():
        summary.add(chunk)
    assert rec.reads == 1
    backend = MeasuredPoses("rec.csv")
    job = Job(backend, ur5, motion, ("base", "tool0"), (1e-6, 1e-6))
    assert compare._rows_beyond((rec, summary), job) == _beyond(size, turn)
    for other in (replace(job, tol=(2.5e-6, 1e-6)), replace(job, pair=("base_link", "tool0"))):
        with pytest.raises(RuntimeError, match=r"counted against tolerances .* not read again"):
            compare._rows_beyond((rec, summary), other)
    assert rec.reads == 1  # never read again


def test_a_check_at_other_tolerances_counts_against_them_in_its_one_read(
    ur5, motion, tmp_path, small, capsys, monkeypatch
):
    poses, size, turn = _off_by_known_amounts(ur5, motion, 3)
    want = _beyond(size, turn, (2.5e-6, 1e-6))
    assert 0 < want < _beyond(size, turn)  # fewer than at the model's own tolerance
    path = _recording_of(ur5, motion, poses, tmp_path)
    reads = _count_reads(monkeypatch)
    code = main(["check", "ur5", "--against", f"poses:{path}", "--tol-pos", "2.5e-6",
                 "--no-diagnose"])  # fmt: skip
    out = " ".join(capsys.readouterr().out.split())
    assert code == 1, out
    assert f"{want} of 600 rows differ" in out
    assert reads == [path]


class _ChunkedRecording:
    """A recording held in memory, read :data:`CHUNK` rows at a time; counts its reads."""

    method = "in memory"
    pair = None
    where = "row"

    def __init__(self, q, poses):
        self.q, self.poses, self.reads = q, poses, 0

    def chunks(self):
        self.reads += 1
        for first in range(0, self.q.shape[0], CHUNK):
            stop = min(self.q.shape[0], first + CHUNK)
            yield recording.PoseChunk(
                self.q[first:stop], self.poses[first:stop], None, np.arange(first, stop) + 1
            )


def _count_reads(monkeypatch) -> list:
    """The paths of the CSV recordings read from here on, once per read (appended to)."""
    reads = []
    chunks = measured._CsvRecording.chunks

    def counted(self):
        reads.append(self.path)
        return chunks(self)

    monkeypatch.setattr(measured._CsvRecording, "chunks", counted)
    return reads


def _recording_of(ur5, q, poses, tmp_path):
    """An RTDE recording of ``q`` whose TCP poses are ``poses``."""
    from scipy.spatial.transform import Rotation

    rows = rtde_rows(ur5, q)
    lines = [" ".join(RTDE_HEADER)]
    x = RTDE_HEADER.index("actual_TCP_pose_0")
    rotvec = Rotation.from_matrix(poses[:, :3, :3]).as_rotvec()
    for row, pose in zip(rows, np.hstack([poses[:, :3, 3], rotvec]), strict=True):
        row[x : x + 6] = pose.tolist()
        lines.append(" ".join(map(repr, row)))
    path = tmp_path / "rec.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_a_failing_check_reads_the_recording_once_and_counts_every_row(
    ur5, motion, tmp_path, small, capsys, monkeypatch
):
    poses, size, turn = _off_by_known_amounts(ur5, motion, 3)
    beyond = _beyond(size, turn)
    path = _recording_of(ur5, motion, poses, tmp_path)
    reads = _count_reads(monkeypatch)
    code = main(["check", "ur5", "--against", f"poses:{path}"])
    out = " ".join(capsys.readouterr().out.split())
    assert code == 1, out
    assert f"{beyond} of 600 rows differ" in out
    # Once: the check's count, its diagnosis (every explanation it verifies) included.
    assert reads == [path]


def test_the_diagnosis_of_a_streamed_recording_explains_it_without_reading_it_again(
    motion, tmp_path, small, capsys, monkeypatch
):
    # A UR10e recording checked with the UR10's table: the diagnosis names the UR10e,
    # verified against the recording's own rows (the ones the check kept).
    ur10e = load_model("ur10e")
    path = write_rtde_csv(tmp_path / "rec.csv", ur10e, motion)
    reads = _count_reads(monkeypatch)
    code = main(["check", "ur10", "--against", f"poses:{path}"])
    out = " ".join(capsys.readouterr().out.split())
    assert code == 1, out
    assert "600 of 600 rows differ" in out
    assert "the reference matches the published table ur10e" in out
    assert "could not run" not in out
    assert reads == [path]


def test_reading_a_recording_past_the_checks_time_limit_is_one_line_exit_2(
    ur5, motion, tmp_path, small, capsys, monkeypatch
):
    from fkcheck.engine import stream

    path = write_rtde_csv(tmp_path / "rec.csv", ur5, motion)
    monkeypatch.setattr(stream, "READ_MIN_S", 0.0)  # the time limit is --timeout alone
    code = main(["check", "ur5", "--against", f"poses:{path}", "--timeout", "1e-9"])
    _assert_timed_out(code, capsys, path, "1e-09", r"\d+")


def _assert_timed_out(code: int, capsys, path, limit: str, rows: str) -> None:
    """Exit 2 and one line: the read of ``path`` ran past ``limit`` s, ``rows`` (a pattern) read."""
    captured = capsys.readouterr()
    assert code == 2, captured.out
    assert captured.err.count("\n") == 1, captured.err
    assert re.search(
        rf"reading {re.escape(str(path))} did not finish within its time limit of {limit} s "
        rf"\({rows} rows read\); give it more with --timeout",
        captured.err,
    ), captured.err
    assert "Traceback" not in captured.err


#: Blank lines before the header of the recording whose rows come late: 10 MB on
#: disk. Before the fix (the time limit started at the first chunk of rows) its
#: check with ``--timeout 1`` read through them and passed, 8.4 s; now 1.3 s, exit 2.
_BLANK_LINES = 10_000_000
#: The time limit of that read (``READ_MIN_S`` set to 0), and how much longer the
#: run may take: the model's loading and one reader's step, on a busy 2-core machine.
_LIMIT_S = 1.0
_SLACK_S = 3.0


def _late_rows(ur5, q, path, blank_lines: int):
    """An RTDE recording of ``q`` whose header comes after ``blank_lines`` blank lines."""
    rows = rtde_rows(ur5, q)
    body = [" ".join(RTDE_HEADER), *(" ".join(map(repr, r)) for r in rows)]
    with path.open("wb") as f:
        f.write(b"\n" * blank_lines)
        f.write(("\n".join(body) + "\n").encode())
    return path


@pytest.mark.parametrize("command", ["check", "diagnose"])
def test_a_recording_whose_first_rows_come_late_ends_at_the_time_limit_in_one_line(
    command, ur5, motion, tmp_path, capsys, monkeypatch
):
    # Before the fix the clock started at the first chunk of rows: 10 million blank
    # lines (or a bag of joint states without a pose) were read with no limit at all,
    # and fkcheck diagnose read the whole recording with no limit at all.
    import time

    from fkcheck.engine import stream

    path = _late_rows(ur5, motion[:20], tmp_path / "late.csv", _BLANK_LINES)
    monkeypatch.setattr(stream, "READ_MIN_S", 0.0)  # the time limit is --timeout alone
    start = time.monotonic()
    code = main([command, "ur5", "--against", f"poses:{path}", "--timeout", f"{_LIMIT_S:g}"])
    took = time.monotonic() - start
    _assert_timed_out(code, capsys, path, "1", "0")
    assert took < _LIMIT_S + _SLACK_S, took


def test_diagnose_reads_a_recording_whole_within_the_default_timeout(
    ur5, motion, tmp_path, capsys, monkeypatch
):
    from fkcheck.backends.measured import MeasuredPoses
    from fkcheck.model.options import DEFAULT_TIMEOUT_S

    limits = []
    keep_with = MeasuredPoses.keep_with

    def spy(self, keeper):
        limits.append(keeper.read_limit_s)
        keep_with(self, keeper)

    monkeypatch.setattr(MeasuredPoses, "keep_with", spy)
    path = _late_rows(ur5, motion[:20], tmp_path / "late.csv", 3)
    assert main(["diagnose", "ur5", "--against", f"poses:{path}"]) == 0
    assert "20 configurations" in capsys.readouterr().out
    assert limits == [DEFAULT_TIMEOUT_S]


@pytest.mark.parametrize(
    ("value", "problem"),
    [("0", r"must be > 0 and at most 86400 s"), ("nan", r"must be > 0 and at most 86400 s"),
     ("1e9", r"must be > 0 and at most 86400 s")],
)  # fmt: skip
def test_a_bad_diagnose_timeout_is_one_line_exit_2(ur5, motion, tmp_path, capsys, value, problem):
    path = _late_rows(ur5, motion[:20], tmp_path / "rec.csv", 0)
    assert main(["diagnose", "ur5", "--against", f"poses:{path}", "--timeout", value]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert re.search(rf"--timeout: {problem}", err), err


def test_a_reader_yields_empty_chunks_while_it_finds_no_rows(ur5, motion, tmp_path, small):
    # What lets the caller look at its clock: every CHUNK lines without a row.
    path = _late_rows(ur5, motion[:30], tmp_path / "late.csv", 100)
    chunks = list(measured.open_recording(path, ur5).chunks())
    assert [c.q.shape[0] for c in chunks] == [0, 0, 0, 0, CHUNK, 30 - CHUNK]
    np.testing.assert_array_equal(np.concatenate([c.q for c in chunks]), motion[:30])
    assert np.concatenate([c.lines for c in chunks]).tolist() == list(range(102, 132))


def test_the_time_limit_of_a_recordings_read_is_never_below_read_min_s(ur5, motion, small):
    from fkcheck.engine.stream import READ_MIN_S, StreamKeeper

    assert StreamKeeper((1e-6, 1e-6), 1e-9).read_limit_s == READ_MIN_S
    assert StreamKeeper((1e-6, 1e-6), 2 * READ_MIN_S).read_limit_s == 2 * READ_MIN_S
    assert StreamKeeper((1e-6, 1e-6)).read_limit_s is None
    summary = StreamKeeper((1e-6, 1e-6), 1e-9)(ur5, ("base", "tool0"))
    poses = poses_of(ur5, motion)
    summary.add(recording.PoseChunk(motion, poses, None, np.arange(ROWS) + 2))
    assert summary.rows == ROWS
    # Equal keepers read a recording once, whatever their time limits.
    assert StreamKeeper((1e-6, 1e-6), 5.0) == StreamKeeper((1e-6, 1e-6))
    assert StreamKeeper((1e-6, 1e-6)) != StreamKeeper((1e-6, 2e-6))
