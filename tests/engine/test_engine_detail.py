"""The engine keeps the evidence of a failure while the check runs; reports only format it."""

from __future__ import annotations

import json
import tomllib
from typing import Any

import numpy as np
import pytest

import fkcheck
import fkcheck.backends.registry
import fkcheck.core.dh
import fkcheck.diagnose.failures
import fkcheck.diagnose.run
import fkcheck.engine.axes
import fkcheck.engine.compare
import fkcheck.engine.evidence
import fkcheck.engine.runner
import fkcheck.model.frames
import fkcheck.urdf.chain
import fkcheck.urdf.source
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.engine.evidence import WorstTracker
from fkcheck.engine.runner import run_check
from fkcheck.errors import BackendUnavailable
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.read import model_from_dict
from fkcheck.model.types import Model
from fkcheck.report.html import write_html, write_index
from fkcheck.report.index import IndexEntry, build_index_page
from fkcheck.report.json_report import write_json
from fkcheck.report.junit import write_junit
from fkcheck.report.markdown import markdown_summary, write_summary
from tests.report_cases import Agrees, Shifted, TwistedDH, golden_model

PAIR = ("base", "tool")


def _scores(check: Any, r: Any) -> np.ndarray:
    score = np.maximum(
        r.position_error_m / check.tol_pos_m, r.rotation_error_rad / check.tol_rot_rad
    )
    score[np.isnan(score)] = np.inf
    return score


def test_a_passing_backend_keeps_nothing_and_a_failing_one_its_worst_cases():
    model = golden_model()
    check = run_check(model, [Agrees(), Shifted(), TwistedDH()], samples=40, seed=3)
    agrees, shifted, twisted = check.backends
    assert agrees.status == "pass"
    assert agrees.detail is None
    for r in (shifted, twisted):
        assert r.status == "fail"
        assert r.detail is not None
        worst = r.detail.worst
        assert worst.indices[0] == r.worst_index
        assert len(set(worst.indices)) == len(worst.indices) == 3
        # The kept matrices are the ones compared: their errors are the recorded errors.
        np.testing.assert_allclose(
            position_error_m(worst.ours, worst.theirs), r.position_error_m[list(worst.indices)]
        )
        np.testing.assert_allclose(
            rotation_error_rad(worst.ours, worst.theirs), r.rotation_error_rad[list(worst.indices)]
        )
        ref = reference_poses(model, check.q[list(worst.indices)], PAIR)
        np.testing.assert_allclose(worst.ours, relative_pose(ref[0], ref[1]), atol=1e-15)
        arm = r.detail.arm
        np.testing.assert_allclose(
            arm.world_T_dh, model.fk(check.q[r.worst_index], all_frames=True)
        )
    assert shifted.detail is not None
    np.testing.assert_allclose(
        np.linalg.norm(
            shifted.detail.worst.theirs[:, :3, 3] - shifted.detail.worst.ours[:, :3, 3], axis=1
        ),
        3e-4,
        rtol=1e-9,
    )
    assert shifted.detail.dh_parting is None  # a black box: no DH frames
    assert twisted.detail is not None
    assert twisted.detail.dh_parting is not None
    assert twisted.detail.dh_parting.first == 2  # α2 flipped: the chains part at frame 2


def test_worst_cases_over_many_chunks_are_the_global_top(monkeypatch):
    monkeypatch.setattr(fkcheck.engine.compare, "CHUNK", 7)
    check = run_check(golden_model(), [TwistedDH()], samples=100, seed=5)
    r = check.backends[0]
    assert r.detail is not None
    score = _scores(check, r)
    expected = [int(i) for i in np.argsort(-score, kind="stable")[:3]]
    assert list(r.detail.worst.indices) == expected
    assert r.worst_index == expected[0]


def test_tracker_breaks_ties_to_the_earlier_index():
    tracker = WorstTracker(k=2)
    eye = np.broadcast_to(np.eye(4), (3, 4, 4))
    tracker.add(0, np.array([1.0, 5.0, 5.0]), eye, eye)
    tracker.add(3, np.array([5.0, 9.0, 0.0]), eye, eye)
    assert tracker.cases(4).indices == (4, 1)


class NotRigid(Agrees):
    """Scales one configuration's rotation: not a rigid transform there, else exact."""

    name = "not-rigid"

    def frame_poses(self, model: Model, q: np.ndarray, frames: Any) -> np.ndarray:
        poses = super().frame_poses(model, q, frames)
        hit = np.flatnonzero(np.isclose(q[:, 0], self.q0))
        poses[1, hit, :3, :3] *= 1.001
        return poses


def test_a_defect_decides_the_worst_case_and_it_is_kept_first():
    model = golden_model()
    probe = run_check(model, [Agrees()], samples=30, seed=1)
    backend = NotRigid()
    backend.q0 = float(probe.q[17, 0])
    check = run_check(model, [backend], samples=30, seed=1)
    r = check.backends[0]
    assert r.status == "fail"
    assert "not a rigid transform" in r.message
    assert r.worst_index == 17
    assert r.detail is not None
    assert r.detail.worst.indices[0] == 17
    np.testing.assert_allclose(
        r.detail.worst.theirs[0][:3, :3] / 1.001, r.detail.worst.ours[0][:3, :3], atol=1e-12
    )


class HalfNaN(Agrees):
    """NaN on every other configuration."""

    name = "half-nan"

    def frame_poses(self, model: Model, q: np.ndarray, frames: Any) -> np.ndarray:
        poses = super().frame_poses(model, q, frames)
        poses[1, ::2] = np.nan
        return poses


def test_nan_rows_are_kept_as_returned_and_the_report_says_so(tmp_path):
    check = run_check(golden_model(), [HalfNaN()], samples=10, seed=2)
    r = check.backends[0]
    assert r.status == "fail"
    assert r.detail is not None
    assert r.worst_index == 0
    assert np.isnan(r.detail.worst.theirs[0]).all()
    page = write_html(check, tmp_path / "r.html", plots=False).read_text(encoding="utf-8")
    assert "not a rotation: NaN or inf entries" in page


def _twisted_ur5() -> Model:
    """UR5 with α4 of the wrong sign: every URDF backend disagrees from joint 5 on."""
    path = fkcheck.bundled_model_paths()["ur5"]
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    data["joint"][3]["alpha"] = -data["joint"][3]["alpha"]
    return model_from_dict(data, path)


def test_urdf_axes_are_gathered_for_a_black_box_that_fails():
    pytest.importorskip("pinocchio")
    model = _twisted_ur5()
    check = run_check(model, [fkcheck.backends.registry.make_backend("pinocchio-urdf")], samples=20)
    r = check.backends[0]
    assert r.status == "fail", r.message
    assert r.detail is not None
    axes = r.detail.urdf_axes
    assert axes is not None
    assert axes.index == r.worst_index
    assert axes.first == 4  # joint 5's axis is the first the flipped α4 moves


class OtherTable(Agrees):
    """A DH backend that runs another table (the bundled UR5's) for the model's frames."""

    name = "other-table"

    def __init__(self) -> None:
        self.other = fkcheck.load_model("ur5")

    def frame_poses(self, model: Model, q: np.ndarray, frames: Any) -> np.ndarray:
        dh, tcp = self.other.fk(q, all_frames=True), self.other.fk(q)
        return fkcheck.model.frames.frame_poses_from_dh(model, dh, tcp, frames)

    def dh_frames(self, model: Model, q: np.ndarray) -> np.ndarray:
        return np.asarray(self.other.fk(q, all_frames=True))

    @classmethod
    def black_box(cls) -> Any:
        """The same poses from a backend without DH frames (so its evidence is the axes)."""

        class BlackBox(Agrees):
            name = "black-box"

            def frame_poses(self, model: Model, q: np.ndarray, frames: Any) -> np.ndarray:
                return cls().frame_poses(model, q, frames)

        return BlackBox()


def test_urdf_evidence_that_cannot_be_read_leaves_the_failure_a_failure(monkeypatch):
    """example-robot-data missing while gathering axes: still ``fail``, just no axes."""

    def unavailable(*args: Any, **kwargs: Any) -> Any:
        raise BackendUnavailable("example-robot-data is not installed")

    monkeypatch.setattr(fkcheck.engine.evidence, "axis_lines", unavailable)
    model = _twisted_ur5()
    check = run_check(model, [OtherTable.black_box()], samples=10)
    r = check.backends[0]
    assert r.status == "fail", r.message
    assert r.detail is not None
    assert r.detail.urdf_axes is None
    assert check.verdict == "fail"


def _forbid(monkeypatch: pytest.MonkeyPatch, target: Any, name: str) -> None:
    def refuse(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError(f"a report called {target.__name__}.{name}")

    monkeypatch.setattr(target, name, refuse)


def test_writing_every_report_runs_no_fk_no_backend_and_no_parser(tmp_path, monkeypatch):
    """After the check: every way to compute or parse raises; every format is still written."""
    pytest.importorskip("pinocchio")
    model = _twisted_ur5()
    backends = [
        fkcheck.backends.registry.make_backend("rtb-dh"),
        fkcheck.backends.registry.make_backend("pinocchio-urdf"),
        OtherTable(),
    ]
    outcome = fkcheck.check(model, backends, samples=20)
    assert outcome.verdict == "fail"
    assert outcome.diagnoses, "the failure was diagnosed before any report"

    for backend in backends:
        _forbid(monkeypatch, backend, "frame_poses")
        if hasattr(backend, "dh_frames"):
            _forbid(monkeypatch, backend, "dh_frames")
    _forbid(monkeypatch, Model, "fk")
    _forbid(monkeypatch, fkcheck.core.dh, "fk")
    _forbid(monkeypatch, fkcheck.core.dh, "fk_reference")
    _forbid(monkeypatch, fkcheck.model.frames, "reference_poses")
    _forbid(monkeypatch, fkcheck.model.frames, "frame_poses_from_dh")
    _forbid(monkeypatch, fkcheck.urdf.source, "load_urdf")
    _forbid(monkeypatch, fkcheck.urdf.chain, "urdf_kinematics")
    _forbid(monkeypatch, fkcheck.engine.axes, "axis_lines")
    _forbid(monkeypatch, fkcheck.engine.axes, "read_urdf_kinematics")
    _forbid(monkeypatch, fkcheck.engine.runner, "run_check")
    _forbid(monkeypatch, fkcheck.diagnose.run, "diagnose")
    _forbid(monkeypatch, fkcheck.diagnose.failures, "diagnose")

    written = fkcheck.write_report(
        outcome,
        html=tmp_path / "r.html",
        json=tmp_path / "r.json",
        junit=tmp_path / "r.xml",
        summary=tmp_path / "r.md",
    )
    assert [p.name for p in written] == ["r.html", "r.json", "r.xml", "r.md"]
    page = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert page.count("data:image/png;base64,") >= 2  # the plots and the arm drawings
    assert "difference (pinocchio-urdf − in-house)" in page
    assert "DH table against the URDF: joint axes in" in page
    assert "other-table: DH frames world_T_i" in page
    assert 'id="diagnosis"' in page
    assert json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))["verdict"] == "fail"
    write_json(outcome.check, tmp_path / "again.json")
    write_junit(outcome.check, tmp_path / "again.xml")
    write_summary(tmp_path / "again.md", markdown_summary([outcome.check]))
    index = build_index_page([IndexEntry(outcome.check, "r.html", "r.json", "r.xml")])
    write_index(index, tmp_path / "index.html")
    assert "r.html" in (tmp_path / "index.html").read_text(encoding="utf-8")
