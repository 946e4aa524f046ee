"""The check engine's verdict logic with small in-test backends (no reference library)."""

from __future__ import annotations

import json
import re
import time
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from fkcheck import FkcheckError, FrameError, load_model
from fkcheck.backends.base import Backend, BackendDefaults, BackendUnavailable
from fkcheck.backends.blackbox import frame_poses_from_tcp
from fkcheck.core.dh import fk_reference
from fkcheck.core.geometry import rot_z, translation
from fkcheck.core.metrics import rotation_error_rad
from fkcheck.engine.runner import run_check
from fkcheck.engine.verdict import headline
from fkcheck.model.frames import frame_poses_from_dh
from fkcheck.model.sampling import sample_configurations
from fkcheck.report.json_report import TIME_FIELDS, result_to_dict, write_json
from fkcheck.report.junit import junit_xml


class ReferenceChain(BackendDefaults):
    """Same table, computed with the plain 4x4 product chain (a second implementation)."""

    name = "reference-chain"
    method = "fk_reference"
    evidence = "implementation"
    reads = "dh"

    def unavailable_reason(self, model):
        return None

    def frame_poses(self, model, q, frames):
        return frame_poses_from_dh(
            model,
            fk_reference(model.chain, q, all_frames=True),
            fk_reference(model.chain, q),
            frames,
        )


class Offset(ReferenceChain):
    """Poses moved by a constant transform on the tip side."""

    def __init__(self, name, tip_T):
        self.name = name
        self.tip_T = tip_T

    def frame_poses(self, model, q, frames):
        poses = super().frame_poses(model, q, frames)
        poses[1] = poses[1] @ self.tip_T
        return poses


class Raising(ReferenceChain):
    name = "raising"

    def frame_poses(self, model, q, frames):
        raise ZeroDivisionError("boom")


class Skipping(ReferenceChain):
    name = "skipping"

    def unavailable_reason(self, model):
        return "library not installed here"


class SkipsLate(ReferenceChain):
    name = "skips-late"

    def frame_poses(self, model, q, frames):
        raise BackendUnavailable("discovered at run time")


class MidChain(ReferenceChain):
    name = "tcp-only"

    def frame_poses(self, model, q, frames):
        return frame_poses_from_tcp(model, model.fk(q), frames)


class Returns(ReferenceChain):
    def __init__(self, name, fn):
        self.name = name
        self.fn = fn

    def frame_poses(self, model, q, frames):
        return self.fn(super().frame_poses(model, q, frames))


class Hanging(ReferenceChain):
    name = "hanging"

    def frame_poses(self, model, q, frames):
        time.sleep(30)
        raise AssertionError("not reached")


@pytest.fixture(scope="module")
def ur5():
    return load_model("ur5")


def test_backends_satisfy_the_protocol():
    assert isinstance(ReferenceChain(), Backend)


def test_agreeing_backend_passes(ur5):
    check = run_check(ur5, [ReferenceChain()], samples=200)
    (r,) = check.backends
    assert r.status == "pass"
    assert r.max_position_error_m < 1e-12
    assert check.verdict == "pass"
    assert (check.frame_from, check.frame_to) == ("base", "tool0")
    assert check.q.shape[0] == 200 + len(check.origin) - check.origin.count("random")


def test_constant_offset_fails_with_its_size(ur5):
    check = run_check(
        ur5, [Offset("shifted", translation(0, 0, 3e-4)), ReferenceChain()], samples=100
    )
    shifted, good = check.backends
    assert shifted.status == "fail"
    np.testing.assert_allclose(shifted.position_error_m, 3e-4, rtol=1e-9)
    assert "differ" in shifted.message
    assert good.status == "pass"
    assert check.verdict == "fail"


def test_rotation_error_is_accurate_near_zero_and_pi():
    for angle in (1e-9, 1e-4, 1.0, np.pi - 1e-9, np.pi):
        err = rotation_error_rad(np.eye(4), rot_z(angle))
        assert err == pytest.approx(angle, rel=1e-6)


def test_raise_is_error_skip_is_skipped_and_never_a_pass(ur5):
    check = run_check(ur5, [Raising(), Skipping(), SkipsLate(), ReferenceChain()], samples=10)
    raising, skipping, late, good = check.backends
    assert raising.status == "error"
    assert "ZeroDivisionError: boom" in raising.message
    assert (skipping.status, skipping.message) == ("skipped", "library not installed here")
    assert (late.status, late.message) == ("skipped", "discovered at run time")
    assert good.status == "pass"
    assert check.verdict == "error"


def test_nothing_ran_is_an_error_verdict(ur5):
    check = run_check(ur5, [Skipping()], samples=10)
    assert check.verdict == "error"
    assert check.ran == ()
    doc = ET.fromstring(junit_xml(check))
    assert doc.find("testsuite").get("errors") == "1"
    assert "nothing was cross-checked" in junit_xml(check).decode()


def test_no_backends_at_all_is_an_error_verdict(ur5):
    assert run_check(ur5, [], samples=10).verdict == "error"


def test_output_of_the_wrong_shape_is_an_error_no_answer(ur5):
    check = run_check(ur5, [Returns("bad", lambda p: p[:, :5])], samples=10)
    (r,) = check.backends
    assert r.status == "error"
    assert re.search(r"returned shape \(2, 5, 4, 4\)", r.message), r.message
    assert not r.ran
    assert check.verdict == "error"


@pytest.mark.parametrize(
    ("fn", "match"),
    [
        (lambda p: np.where(p == p[0, 0, 0, 0], np.nan, p), r"returned NaN or inf at \d+ of"),
        (lambda p: p * 1.01, r"not a rigid transform: defect 0\.0\d+ at q = \["),
    ],
)
def test_a_wrong_answer_is_a_failure_with_its_reason_and_errors(ur5, fn, match):
    """It answered, and the answer is wrong: fail (not error), numbers still shown."""
    check = run_check(ur5, [Returns("bad", fn), ReferenceChain()], samples=10)
    bad, good = check.backends
    assert bad.status == "fail"
    assert re.search(match, bad.message), bad.message
    assert bad.ran
    assert bad.max_position_error_m is not None
    assert bad.max_position_error_m > 0
    assert good.status == "pass"
    assert check.verdict == "fail"
    assert headline(check.verdict, check.evidence, len(check.ran)) == (
        "fail — implementation disagrees"
    )


def test_hanging_backend_is_stopped_at_the_time_limit(ur5):
    start = time.perf_counter()
    check = run_check(ur5, [Hanging(), ReferenceChain()], samples=10, timeout_s=0.5)
    assert time.perf_counter() - start < 10
    hanging, good = check.backends
    assert (hanging.status, hanging.message) == ("error", "timed out after 0.5 s")
    assert good.status == "pass"


def test_tcp_only_backend_skips_mid_chain_frames():
    panda = load_model("panda")
    check = run_check(
        panda, [MidChain()], samples=10, frame_from="panda_link0", frame_to="panda_link3"
    )
    (r,) = check.backends
    assert r.status == "skipped"
    assert "mid-chain" in r.message
    check = run_check(
        panda, [MidChain()], samples=10, frame_from="panda_link0", frame_to="panda_hand"
    )
    assert check.backends[0].status == "pass"


def test_unknown_frame_is_bad_input(ur5):
    with pytest.raises(
        FrameError, match=r"frame 'tool' not in model ur5; frames are: world, tcp, base"
    ):
        run_check(ur5, [ReferenceChain()], frame_to="tool")


def test_tolerances_come_from_the_model_or_arguments(ur5):
    offset = Offset("shifted", translation(0, 0, 3e-4))
    assert run_check(ur5, [offset], samples=10).verdict == "fail"
    assert run_check(ur5, [offset], samples=10, tol_pos_m=1e-3).verdict == "pass"


def test_same_seed_same_json_apart_from_times(ur5, tmp_path):
    docs = []
    for k in range(2):
        check = run_check(ur5, [ReferenceChain(), Offset("off", rot_z(1e-3))], samples=50, seed=7)
        path = write_json(check, tmp_path / f"r{k}.json")
        doc = json.loads(path.read_text())
        for field in TIME_FIELDS:
            doc.pop(field)
        for b in doc["backends"]:
            b.pop("duration_s")
        docs.append(doc)
    assert docs[0] == docs[1]
    other = result_to_dict(run_check(ur5, [ReferenceChain()], samples=50, seed=8))
    assert other["seed"] == 8


def test_json_contract_fields(ur5):
    check = run_check(ur5, [Offset("off", translation(1e-3, 0, 0))], samples=20)
    doc = result_to_dict(check)
    assert {"model", "samples", "seed", "from", "to", "tolerance", "backends", "verdict"} <= set(
        doc
    )
    assert doc["tolerance"] == {"position_m": 1e-6, "rotation_rad": 1e-6}
    (b,) = doc["backends"]
    assert {"name", "status", "max_position_error_m", "max_rotation_error_rad", "worst_q",
            "message"} <= set(b)  # fmt: skip
    assert b["status"] == "fail"
    assert b["max_position_error_m"] == pytest.approx(1e-3, rel=1e-9)
    assert len(b["worst_q"]) == 6


def test_samples_cover_poses_zero_corners_and_limits(ur5):
    s = sample_configurations(ur5, 64, seed=3)
    assert s.origin[:3] == ("pose:zero", "pose:home", "pose:worked_example")
    assert s.origin.count("corner") == 64  # 2^6
    assert s.origin.count("random") == 64
    lo, hi = ur5.limits[:, 0], ur5.limits[:, 1]
    assert ((s.q >= lo) & (s.q <= hi)).all()
    again = sample_configurations(ur5, 64, seed=3)
    np.testing.assert_array_equal(s.q, again.q)
    assert not np.array_equal(s.q, sample_configurations(ur5, 64, seed=4).q)
    uniform = sample_configurations(ur5, 10, seed=3, sampler="uniform")
    assert uniform.origin.count("random") == 10


def test_reports_are_written_readable_by_others(ur5, tmp_path):
    import os
    import stat

    path = write_json(run_check(ur5, [ReferenceChain()], samples=5), tmp_path / "r.json")
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o644
    assert [p.name for p in tmp_path.iterdir()] == ["r.json"]  # no temporary file left


def test_measured_poses_become_the_configurations_of_the_check(capsys, tmp_path):
    from fkcheck.cli.main import main

    report = tmp_path / "r.json"
    argv = ["check", "ur5", "--against", "poses:tests/data/ur5_pendant.csv,rtb-dh"]
    code = main([*argv, "--tol-pos", "2e-6", "--tol-rot", "2e-6", "--json", str(report)])
    out = capsys.readouterr().out
    doc = json.loads(report.read_text())
    assert code == 0, out
    assert doc["configurations"] == 2
    assert [b["status"] for b in doc["backends"]] == ["pass", "pass"]
    # Printed to 6 decimals (m: 3 decimals of mm): agreement within half a unit.
    assert doc["backends"][0]["max_position_error_m"] < 1e-6


class IsolatedChain(ReferenceChain):
    name = "isolated-chain"
    isolated = True


class IsolatedCrash(ReferenceChain):
    name = "isolated-crash"
    isolated = True

    def frame_poses(self, model, q, frames):
        import os

        os._exit(3)  # dies like a C extension that segfaults: no exception, no reply


class IsolatedHang(Hanging):
    name = "isolated-hang"
    isolated = True


class IsolatedBadInput(ReferenceChain):
    name = "isolated-bad-input"
    isolated = True

    def frame_poses(self, model, q, frames):
        raise FrameError("nope", "URDF x.urdf", ["a", "b"])


def test_isolated_backend_runs_in_its_own_process_with_the_same_result(ur5):
    check = run_check(ur5, [IsolatedChain(), ReferenceChain()], samples=100)
    isolated, threaded = check.backends
    assert isolated.status == threaded.status == "pass"
    np.testing.assert_array_equal(isolated.position_error_m, threaded.position_error_m)
    np.testing.assert_array_equal(isolated.rotation_error_rad, threaded.rotation_error_rad)


def test_isolated_backend_that_dies_is_an_error_not_a_crash(ur5):
    check = run_check(ur5, [IsolatedCrash(), ReferenceChain()], samples=10)
    crashed, good = check.backends
    assert (crashed.status, crashed.message) == (
        "error",
        "its process exited with code 3 without an answer",
    )
    assert good.status == "pass"
    assert check.verdict == "error"


def test_isolated_backend_that_hangs_is_killed(ur5):
    start = time.perf_counter()
    check = run_check(ur5, [IsolatedHang()], samples=10, timeout_s=3)
    assert time.perf_counter() - start < 20
    assert check.backends[0].message == "timed out after 3 s"


def test_isolated_backend_bad_input_is_still_bad_input(ur5):
    with pytest.raises(FkcheckError, match=r"frame 'nope' not in URDF x\.urdf; frames are: a, b"):
        run_check(ur5, [IsolatedBadInput()], samples=10)


def test_scripts_need_no_main_guard_for_isolated_backends(tmp_path):
    import subprocess
    import sys

    script = tmp_path / "script.py"
    script.write_text(
        "from fkcheck import load_model\n"
        "from fkcheck.backends.registry import make_backend\n"
        "from fkcheck.engine.runner import run_check\n"
        "check = run_check(load_model('ur5'), [make_backend('yourdfpy-urdf')], samples=5)\n"
        "print('VERDICT', check.verdict, check.backends[0].status)\n"
    )
    proc = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "VERDICT pass pass"
