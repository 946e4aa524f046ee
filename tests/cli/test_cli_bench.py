"""`fkcheck bench` as a user runs it: the table, the JSON, agreement, skipped peers.

No timing is asserted (times depend on the machine); what is asserted is what was
timed, on how many poses, whether the results agree, and how the numbers are written.
"""

from __future__ import annotations

import json
import stat
import sys

import pytest

from fkcheck import load_model
from fkcheck.bench import harness, peers, timing
from fkcheck.bench import jacobian as bench_jacobian
from fkcheck.cli.bench import write_json
from fkcheck.cli.main import main
from fkcheck.core import dh
from fkcheck.model.read import model_from_dict


def bench(capsys, tmp_path, *argv):
    path = tmp_path / "out" / "bench.json"
    code = main(["bench", *argv, "--repeat", "1", "--json", str(path)])
    out, err = capsys.readouterr()
    return code, out, err, json.loads(path.read_text()) if path.exists() else None


def test_bench_times_every_contender_on_the_same_poses(capsys, tmp_path):
    code, out, err, data = bench(capsys, tmp_path, "panda", "--n", "600")
    assert code == 0, err
    assert (data["model"], data["n"], data["repeat"]) == ("panda", 600, 1)
    rows = {t["name"]: t for t in data["timings"]}
    for name in ("in-house batch, NumPy path", "fk_reference (4×4 @ chain)",
                 "RTB ETS.eval (C batch)", "RTB DHRobot.fkine", "Pinocchio FK loop",
                 "yourdfpy loop (URDF)", "memory bound: np.copyto"):  # fmt: skip
        assert name in rows, sorted(rows)
        assert rows[name]["skipped"] == "", rows[name]["skipped"]
        assert rows[name]["seconds"] > 0
        assert rows[name]["us_per_pose"] > 0
        assert rows[name]["n"] == min(600, harness.PEER_POSES.get(_key(name), 600))
    peers = [t for t in data["timings"] if t["kind"] == "peer"]
    assert all(t["max_pos_err_m"] <= data["tol_pos_m"] for t in peers)
    assert data["disagree"] == []
    fastest = min(peers, key=lambda t: t["us_per_pose"])
    assert data["fastest_peer"] == fastest["name"]
    assert rows[fastest["name"]]["speedup_vs_fastest_peer"] == pytest.approx(1.0)
    # The table names every contender and the facts needed to read it.
    for name in rows:
        assert name in out
    assert "load average" in out
    assert "seed 0" in out


def _key(name: str) -> str:
    return {
        "in-house batch, NumPy path": "numpy",
        "fk_reference (4×4 @ chain)": "reference",
        "RTB ETS.eval (C batch)": "rtb-eval",
        "RTB DHRobot.fkine": "rtb-fkine",
        "Pinocchio FK loop": "pinocchio",
        "yourdfpy loop (URDF)": "yourdfpy",
    }.get(name, "")


def test_bench_reports_a_missing_peer_as_skipped(capsys, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pinocchio", None)  # as if not installed
    code, out, err, data = bench(capsys, tmp_path, "planar2", "--n", "50")
    assert code == 0, err
    rows = {t["name"]: t for t in data["timings"]}
    assert rows["Pinocchio FK loop"]["skipped"].startswith("not installed")
    assert rows["Pinocchio FK loop"]["seconds"] is None
    # planar2 has no URDF: yourdfpy is skipped, saying so.
    assert "no [urdf]" in rows["yourdfpy loop (URDF)"]["skipped"]
    assert "skipped, not installed" in out


def test_bench_exits_1_when_a_peer_disagrees(capsys, tmp_path, monkeypatch):
    model = load_model("planar2")
    wrong = model_from_dict(
        {"name": "planar2", "convention": "standard",
         "joint": [{"a": 1.0, "alpha": 0, "d": 0}, {"a": 0.8001, "alpha": 0, "d": 0}]}
    )  # fmt: skip
    assert model.joints[1].a == 0.8
    monkeypatch.setattr(peers, "rtb_robot", lambda _model: _real_rtb_robot(wrong))
    code, _, err, data = bench(capsys, tmp_path, "planar2", "--n", "50")
    assert code == 1
    assert set(data["disagree"]) == {"RTB ETS.eval (C batch)", "RTB DHRobot.fkine"}
    assert "RTB ETS.eval (C batch)" in err


_real_rtb_robot = peers.rtb_robot


@pytest.mark.parametrize("bad", ["0", "-3", "many"])
def test_bench_refuses_a_bad_n(capsys, bad):
    assert main(["bench", "ur5", "--n", bad]) == 2
    assert "--n" in capsys.readouterr().err


def test_json_is_written_atomically_and_readable(tmp_path):
    path = tmp_path / "bench.json"
    path.write_text("old")
    write_json(path, {"a": 1})
    assert json.loads(path.read_text()) == {"a": 1}
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bench.json"]  # no temp file left
    with pytest.raises(TypeError, match="not JSON serializable"):
        write_json(path, {"a": object()})  # not JSON: the old file stays, no temp file
    assert json.loads(path.read_text()) == {"a": 1}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bench.json"]


def test_the_headline_ratio_is_like_for_like(capsys, tmp_path, monkeypatch):
    """Same N, one thread, a new array each call: the in-house row and RTB's ETS.eval."""
    monkeypatch.setattr(dh, "JIT_MIN_POSES", 10_000)  # the kernel's rows, at a test's size
    code, out, err, data = bench(capsys, tmp_path, "ur5", "--n", "20000")
    assert code == 0, err
    rows = {t["name"]: t for t in data["timings"]}
    ours, peer = rows["in-house batch, JIT, like for like"], rows["RTB ETS.eval (C batch)"]
    assert ours["mode"] == peer["mode"] == timing.LIKE_FOR_LIKE
    assert ours["n"] == peer["n"] == 20000
    headline = data["headline"]
    assert (headline["in_house"], headline["peer"], headline["n"]) == (
        "in-house batch, JIT, like for like", "RTB ETS.eval (C batch)", 20000
    )  # fmt: skip
    assert headline["speedup"] == pytest.approx(peer["us_per_pose"] / ours["us_per_pose"])
    # Faster modes are extra rows, labelled as such.
    assert rows["in-house batch, JIT, out="]["mode"].startswith(("extra:", "1 thread"))
    assert "Headline, like for like (1 thread, new array, N = 20,000)" in " ".join(out.split())


def test_a_peer_that_crashes_fails_the_bench(capsys, tmp_path, monkeypatch):
    def crash(model, q, ours, repeat):
        raise RuntimeError("segfault-like failure inside the peer")

    crashing = [(name, key, crash if key == "pinocchio" else fn)
                for name, key, fn in peers.PEERS]  # fmt: skip
    monkeypatch.setattr(peers, "PEERS", crashing)
    code, _, err, data = bench(capsys, tmp_path, "planar2", "--n", "200")
    assert code == 1
    rows = {t["name"]: t for t in data["timings"]}
    assert (
        rows["Pinocchio FK loop"]["error"] == "RuntimeError: segfault-like failure inside the peer"
    )
    assert rows["Pinocchio FK loop"]["skipped"] == ""
    assert data["failed"] == [
        "Pinocchio FK loop (RuntimeError: segfault-like failure inside the peer)"
    ]
    assert "peers failed: Pinocchio FK loop" in err


# --------------------------------------------------------------------------- --jacobian

JACOBIAN_PEERS = ("RTB ETS.jacob0 loop", "Pinocchio computeFrameJacobian loop")


def test_bench_jacobian_times_the_core_and_both_peers_on_the_same_configurations(capsys, tmp_path):
    code, out, err, data = bench(capsys, tmp_path, "stanford", "--jacobian", "--n", "300")
    assert code == 0, err
    assert (data["quantity"], data["reference"], data["model"], data["n"]) == (
        "jacobian", "world-aligned", "stanford", 300
    )  # fmt: skip
    rows = {t["name"]: t for t in data["timings"]}
    # Below JIT_MIN_POSES the core takes its NumPy path, and the rows say so.
    # At n = the peers' n the all-N 1-thread run is the like-for-like row itself: no twin.
    assert "in-house Jacobian, NumPy path, 1 thread" not in rows
    for name in ("in-house Jacobian, NumPy path, like for like",
                 "in-house FK (TCP pose), NumPy path, 1 thread",
                 "in-house Jacobian, NumPy path", *JACOBIAN_PEERS):  # fmt: skip
        assert name in rows, sorted(rows)
        assert (rows[name]["skipped"], rows[name]["error"]) == ("", "")
        assert rows[name]["seconds"] > 0
        assert rows[name]["ns_per_config"] == pytest.approx(rows[name]["us_per_pose"] * 1e3)
    for name in JACOBIAN_PEERS:  # checked against the core, timed like for like
        peer = rows[name]
        assert peer["n"] == 300
        assert peer["mode"] == timing.JACOBIAN_LIKE_FOR_LIKE
        assert 0 <= peer["max_jac_err"] <= data["tol_jacobian"]
        assert peer["max_jac_err"] < 1e-12  # same chain: round-off only
    ours = rows["in-house Jacobian, NumPy path, like for like"]
    assert ours["mode"] == timing.JACOBIAN_LIKE_FOR_LIKE
    assert ours["n"] == 300
    assert sorted(ours["speedup_vs_peers"]) == sorted(JACOBIAN_PEERS)
    for peer, ratio in ours["speedup_vs_peers"].items():
        assert ratio == pytest.approx(rows[peer]["us_per_pose"] / ours["us_per_pose"])
        assert ratio > 0
    assert data["headline"]["peer"] == "Pinocchio computeFrameJacobian loop"
    assert data["headline"]["in_house"] == ours["name"]
    assert data["headline"]["mode"] == timing.JACOBIAN_LIKE_FOR_LIKE
    assert (data["disagree"], data["failed"]) == ([], [])
    assert "tol_pos_m" not in data
    text = " ".join(out.split())
    for name in rows:
        assert name in text
    assert "Headline, like for like (1 thread, out=, n = 300)" in text
    assert "× PEER: that peer's time per configuration divided by this row's" in text


def test_bench_jacobian_headline_at_the_jit_threshold(capsys, tmp_path, monkeypatch):
    """Above the JIT's threshold the like-for-like row is the kernel on one thread."""
    monkeypatch.setattr(dh, "JIT_MIN_POSES", 10_000)  # the kernel's rows, at a test's size
    code, out, err, data = bench(capsys, tmp_path, "ur5", "--jacobian", "--n", "20000")
    assert code == 0, err
    rows = {t["name"]: t for t in data["timings"]}
    ours = rows["in-house Jacobian, JIT, like for like"]
    assert ours["n"] == rows["Pinocchio computeFrameJacobian loop"]["n"] == 20000
    assert data["headline"]["in_house"] == ours["name"]
    assert data["headline"]["speedup"] == pytest.approx(
        rows["Pinocchio computeFrameJacobian loop"]["us_per_pose"] / ours["us_per_pose"]
    )
    assert rows["in-house Jacobian, NumPy path"]["max_jac_err"] < 1e-12  # vs the kernel
    assert "Jacobian vs pose: the batched Jacobian takes" in " ".join(out.split())
    assert set(data["jacobian_over_fk"]) >= {"1 thread"}
    for label, ratio in data["jacobian_over_fk"].items():
        fk = rows[f"in-house FK (TCP pose), JIT, {label}"]
        assert fk["n"] == 20000
        assert ratio > 0


def test_bench_jacobian_refuses_to_time_a_peer_that_disagrees(capsys, tmp_path, monkeypatch):
    wrong = model_from_dict(
        {"name": "planar2", "convention": "standard",
         "joint": [{"a": 1.0, "alpha": 0, "d": 0}, {"a": 0.8001, "alpha": 0, "d": 0}]}
    )  # fmt: skip
    monkeypatch.setattr(bench_jacobian, "rtb_robot", lambda _model: _real_rtb_robot(wrong))
    code, out, err, data = bench(capsys, tmp_path, "planar2", "--jacobian", "--n", "100")
    assert code == 1
    rows = {t["name"]: t for t in data["timings"]}
    rtb = rows["RTB ETS.jacob0 loop"]
    assert rtb["seconds"] is None  # not timed
    assert rtb["max_jac_err"] == pytest.approx(1e-4, rel=0.5)  # a₂ off by 0.1 mm
    assert rtb["note"].startswith("not timed: its Jacobians differ from the core's by")
    assert data["disagree"] == ["RTB ETS.jacob0 loop"]
    assert rows["Pinocchio computeFrameJacobian loop"]["seconds"] > 0
    assert "disagree with the in-house core by more than 1e-06" in err
    assert "not timed" in out


def test_bench_jacobian_reports_a_missing_peer_as_skipped(capsys, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pinocchio", None)  # as if not installed
    code, out, err, data = bench(capsys, tmp_path, "planar2", "--jacobian", "--n", "50")
    assert code == 0, err
    rows = {t["name"]: t for t in data["timings"]}
    pin = rows["Pinocchio computeFrameJacobian loop"]
    assert pin["skipped"].startswith("not installed")
    assert pin["seconds"] is None
    assert rows["RTB ETS.jacob0 loop"]["seconds"] > 0
    assert data["headline"] is None  # its peer did not run
    assert "no like-for-like pair ran" in out


def test_bench_times_reading_a_recording_against_pandas(capsys, tmp_path, monkeypatch):
    from fkcheck.bench import recordings

    monkeypatch.setattr(recordings, "RECORDING_ROWS", 2_000)
    code, out, err, data = bench(capsys, tmp_path, "ur5", "--n", "200")
    assert code == 0, err
    rows = {r["name"]: r for r in data["recordings"]}
    assert list(rows) == [
        "fkcheck read (poses:)",
        "fkcheck read + compare (check)",
        "pandas.read_csv (C)",
    ]
    size = rows["pandas.read_csv (C)"]["bytes"]
    assert 2_000 * 200 < size < 2_000 * 300  # about 240 bytes a row, as UR's recorder writes
    for row in rows.values():
        assert (row["rows"], row["bytes"], row["skipped"], row["error"]) == (2_000, size, "", "")
        assert row["rows_per_s"] == pytest.approx(2_000 / row["seconds"])
        assert row["mb_per_s"] == pytest.approx(size / row["seconds"] / 1e6)
    assert rows["fkcheck read (poses:)"]["max_diff"] == 0.0  # repr's digits read back exactly
    # pandas' default float parser is not Python's correctly rounded one: a last bit, at most.
    assert rows["pandas.read_csv (C)"]["max_diff"] < 1e-14
    assert "reading an RTDE recording: 2,000 rows" in out
    assert "× pandas" in out


def test_the_recording_row_without_pandas_or_six_joints_is_skipped(capsys, tmp_path, monkeypatch):
    from fkcheck.bench import recordings

    monkeypatch.setattr(recordings, "RECORDING_ROWS", 500)
    monkeypatch.setitem(sys.modules, "pandas", None)  # as if not installed
    code, out, err, data = bench(capsys, tmp_path, "ur5", "--n", "50")
    assert code == 0, err
    pandas_row = data["recordings"][-1]
    assert pandas_row["skipped"].startswith("not installed")
    assert pandas_row["seconds"] is None
    assert data["recordings"][0]["seconds"] > 0  # fkcheck's own read still timed
    assert "pandas.read_csv (C): skipped, not installed" in out
    code, _, err, data = bench(capsys, tmp_path, "panda", "--n", "50")
    assert code == 0, err
    assert {r["skipped"] for r in data["recordings"]} == {
        "an RTDE recording holds 6 joints; model panda has 7"
    }
