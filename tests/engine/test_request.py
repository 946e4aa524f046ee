"""A check as one request through prepare, run and judge (:mod:`fkcheck.engine.request`)."""

from __future__ import annotations

import pytest

from fkcheck import FrameError, load_model
from fkcheck.backends.base import BackendDefaults
from fkcheck.cli.main import main
from fkcheck.core.dh import fk_reference
from fkcheck.engine.judge import judge
from fkcheck.engine.prepare import prepare
from fkcheck.engine.request import CheckRequest
from fkcheck.engine.runner import run_backends, run_request
from fkcheck.model.frames import frame_poses_from_dh
from fkcheck.model.options import CheckOptions


class SameTable(BackendDefaults):
    """The table's own frames (fkcheck's maths: enough for the engine's plumbing)."""

    name = "same-table"
    method = "frame_poses_from_dh"
    evidence = "implementation"
    reads = "dh"

    def __init__(self) -> None:
        self.calls = 0

    def unavailable_reason(self, model):
        return None

    def frame_poses(self, model, q, frames):
        self.calls += 1
        return frame_poses_from_dh(
            model,
            fk_reference(model.chain, q, all_frames=True),
            fk_reference(model.chain, q),
            frames,
        )


def test_the_result_keeps_the_requests_options_object():
    options = CheckOptions(samples=7, seed=11, sampler="uniform", timeout_s=30.0)
    request = CheckRequest(load_model("planar2"), (SameTable(),), options)
    result = run_request(request)
    assert result.options is options  # not copies: the one object, sources and all
    assert result.verdict == "pass"
    assert result.origin.count("random") == 7


def test_the_three_stages_give_what_run_request_gives():
    backend = SameTable()
    request = CheckRequest(load_model("ur5"), (backend,), CheckOptions(samples=20, seed=4))
    prepared = prepare(request)
    assert backend.calls == 0  # prepare runs no backend
    staged = judge(prepared, run_backends(prepared))
    whole = run_request(request)
    assert (staged.frame_from, staged.frame_to) == (whole.frame_from, whole.frame_to)
    assert (staged.q == whole.q).all()
    assert staged.verdict == whole.verdict == "pass"
    assert staged.backends[0].position_error_m.shape == whole.backends[0].position_error_m.shape


def test_bad_input_ends_in_prepare_before_any_backend_runs():
    backend = SameTable()
    options = CheckOptions(frame_to="no_such_frame")
    with pytest.raises(FrameError, match="no_such_frame"):
        prepare(CheckRequest(load_model("ur5"), (backend,), options))
    assert backend.calls == 0


def test_fkcheck_check_reads_the_urdf_once(monkeypatch, tmp_path, capsys):
    pytest.importorskip("example_robot_data", reason="panda's URDF is example-robot-data's")
    # The command line read the URDF before its header, then the engine read it again.
    import fkcheck.description.urdf
    from fkcheck.description.registry import clear_descriptions

    reads: list[str] = []
    real = fkcheck.description.urdf.read_model_urdf_expanded

    def counting(model, *args, **kwargs):
        reads.append(model.name)
        return real(model, *args, **kwargs)

    clear_descriptions()  # another test in this process may have read it already
    monkeypatch.setattr(fkcheck.description.urdf, "read_model_urdf_expanded", counting)
    monkeypatch.chdir(tmp_path)
    assert main(["check", "panda", "--against", "rtb-dh", "--samples", "5", "-q"]) == 0
    assert reads == ["panda"]  # a plain URDF is read even when no backend reads it (screened)
    assert "verdict: pass" in capsys.readouterr().out
