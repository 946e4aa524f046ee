"""fkcheck diagnose: each typical mistake is named, with its evidence and a fix that passes."""

from __future__ import annotations

import json
import math
import re
import tomllib
from dataclasses import replace

import numpy as np
import pytest

import fkcheck.backends.registry as registry
from fkcheck import load_model
from fkcheck.backends.base import BackendDefaults, BackendUnavailable
from fkcheck.backends.blackbox import frame_poses_from_tcp
from fkcheck.backends.measured import MeasuredPoses, PosesFileError
from fkcheck.cli.main import main
from fkcheck.core.geometry import matrix_from_xyz_rpy, translation
from fkcheck.core.pose_formats import pose_from_matrix
from fkcheck.core.tolerances import ROUNDED_URDF
from fkcheck.diagnose import diagnose, format_text, to_dict
from fkcheck.diagnose.offsets import fit_offsets
from fkcheck.engine.axes import line_distance
from fkcheck.engine.runner import run_check
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.types import Offset
from fkcheck.model.write import model_to_toml, offset_toml
from tests.backend_cases import URDF_BACKENDS


@pytest.fixture(scope="module")
def reference():
    return registry.make_backend("pinocchio-urdf")


def with_joint(model, index, **changes):
    joints = list(model.joints)
    joints[index] = replace(joints[index], **changes)
    return replace(model, joints=tuple(joints))


def with_frame(model, name, **changes):
    frames = dict(model.frames)
    frames[name] = replace(frames[name], **changes)
    return replace(model, frames=frames)


def run_diagnose(model, backend, **kwargs):
    return diagnose(model, backend, samples=100, **kwargs)


@pytest.mark.parametrize(("d1", "delta_mm"), [(0.08946, -0.301), (0.089459, -0.300)])
def test_ur5_older_d1_is_named_with_its_size(d1, delta_mm, reference):
    result = run_diagnose(with_joint(load_model("ur5"), 0, d=d1), reference)
    assert not result.agrees
    assert result.before.position_m == pytest.approx(abs(delta_mm) * 1e-3, abs=1e-6)
    best = result.best
    assert best is not None
    assert best.kind == "parameter"
    [change] = best.changes
    assert change.field == "joint[0].d"
    assert change.symbol == "d1 (shoulder_pan)"
    assert change.new == pytest.approx(0.089159, abs=1e-9)
    assert change.delta * 1e3 == pytest.approx(delta_mm, abs=1e-6)
    text = format_text(result)
    assert f"d1 (shoulder_pan) = {d1:g} here, 0.089159 would match, Δ = {delta_mm:+.3f} mm" in text
    # The honest ambiguity: the same 0.3 mm is a constant z shift of the base frame.
    offset = next(e for e in result.explanations if e.kind == "offset")
    assert offset.explains
    assert any("exactly what d1" in line for line in offset.details)


def test_rtb_d1_is_traced_to_robotics_toolbox(reference):
    result = run_diagnose(with_joint(load_model("ur5"), 0, d=0.089459), reference)
    [change] = result.best.changes
    assert "published table ur5" in change.note
    assert "Robotics Toolbox for Python's packaged UR5" in change.note


def test_rtb_model_reference_names_its_d1(capsys):
    assert main(["diagnose", "ur5", "--against", "rtb-model:UR5", "--samples", "50"]) == 0
    out = capsys.readouterr().out
    assert "1. [parameter] one number differs: d1 (shoulder_pan)" in out
    assert "d1 (shoulder_pan) = 0.089159 here, 0.089459 would match, Δ = +0.300 mm" in out
    # A base-frame shift cannot be the fix against a black box that reuses our base.
    assert "[frames.base]" not in out


def test_base_link_vs_base_is_named_and_the_printed_fix_passes(tmp_path, reference):
    good = load_model("ur5")
    bad = with_frame(good, "base_link", offset=Offset())  # no Rz(π)
    result = run_diagnose(bad, reference, frame_from="base_link", frame_to="tool0")
    best = result.best
    assert best.kind == "frames"
    assert "base_link vs base" in best.title
    assert "Rz(π)" in best.title
    fix = tomllib.loads(best.fix_toml)["frames"]["base_link"]
    assert fix.pop("source").startswith("Universal_Robots_ROS2_Description")  # kept
    assert fix == {"dh": 0, "rpy": [0.0, 0.0, 180.0], "urdf": "base_link"}  # ur5.toml is in deg
    # Apply the printed TOML to the broken model file and run the real check.
    text = model_to_toml(bad)
    start = text.index('[frames.base_link]\ndh = 0\nurdf = "base_link"\nsource = ')
    broken = text[start : text.index("\n\n", start) + 1]
    path = tmp_path / "fixed.toml"
    path.write_text(text.replace(broken, best.fix_toml), encoding="utf-8")
    fixed = load_model(path)
    backends = [registry.make_backend(name) for name in URDF_BACKENDS]
    check = run_check(fixed, backends, samples=64, frame_from="base_link", frame_to="tool0")
    assert check.verdict == "pass", [b.message for b in check.backends]
    # Before the fix the same check fails, by about 2 m and π rad.
    failing = run_check(bad, backends[:1], samples=16, frame_from="base_link", frame_to="tool0")
    assert failing.verdict == "fail"


def test_a_base_or_tool_fix_is_written_as_the_model_file_writes_it():
    """One writer for [base]/[tool]: a fix in degrees reads back to the fitted angle."""
    from fkcheck.diagnose.offsets import _fix_side

    model = load_model("ur5")  # angles in degrees
    odd = math.radians(12.3456789012345)  # not a 9-digit number of degrees
    X = matrix_from_xyz_rpy((0.0, 0.0, 0.01), (0.0, 0.0, odd))
    for frame, base_side, label in (("world", True, "base"), ("tcp", False, "tool")):
        fixed, text = _fix_side(model, frame, X, base_side=base_side)
        offset = getattr(fixed, label)
        assert text == offset_toml(label, offset, "deg")
        [yaw] = [v for v in tomllib.loads(text)[label]["rpy"] if abs(v) > 1]
        assert math.radians(yaw) == pytest.approx(offset.rpy[2], abs=1e-15)
        assert abs(abs(yaw) - 12.3456789012345) < 1e-12


def test_flange_vs_tool0_is_a_tip_rotation_with_its_fix(reference):
    bad = with_frame(load_model("ur5"), "flange", offset=Offset())  # flange mapped as tool0
    result = run_diagnose(bad, reference, frame_from="base", frame_to="flange")
    best = result.best
    assert best.kind == "frames"
    assert "flange/ee_link vs tool0" in best.title
    fix = tomllib.loads(best.fix_toml)["frames"]["flange"]
    assert fix["rpy"] == [-90.0, -90.0, 0.0]  # ur5.toml's documented flange mapping
    check = run_check(best.model, [reference], samples=32, frame_from="base", frame_to="flange")
    assert check.verdict == "pass"


def test_panda_table_run_as_standard_dh_says_modified(reference):
    result = run_diagnose(replace(load_model("panda"), convention="standard"), reference)
    best = result.best
    assert best.kind == "convention"
    assert "modified (Craig) DH, run as standard DH" in best.title
    assert 'convention = "modified"' in best.title


def test_ur5_in_degrees_declared_radians_says_so(reference):
    good = load_model("ur5")
    deg = [
        replace(j, alpha=math.degrees(j.alpha), theta=math.degrees(j.theta)) for j in good.joints
    ]
    bad = replace(good, joints=tuple(deg), angle_unit="rad")
    result = run_diagnose(bad, reference)
    assert result.best.kind == "degrees"
    assert result.best.title == (
        'the table\'s angles are in degrees but were read as radians: set angle_unit = "deg"'
    )


@pytest.mark.parametrize(
    ("name", "joint"), [("ur5", 0), ("ur5", 3), ("ur5", 4), ("panda", 2), ("panda", 5)]
)
def test_one_flipped_alpha_names_that_joint(name, joint, reference):
    good = load_model(name)
    bad = with_joint(good, joint, alpha=-good.joints[joint].alpha)
    best = run_diagnose(bad, reference).best
    assert best.kind == "sign"
    assert [c.field for c in best.changes] == [f"joint[{joint}].alpha"]
    assert f"α{joint if good.convention == 'modified' else joint + 1} " in best.title


def test_flipped_alpha_without_a_urdf_against_a_packaged_table():
    bad = with_joint(load_model("puma560"), 2, alpha=math.pi / 2)  # α3 is -90° in the table
    result = run_diagnose(
        bad, registry.make_backend("rtb-model:Puma560"), frame_from="world", frame_to="tcp"
    )
    assert result.best.kind == "sign"
    assert [c.field for c in result.best.changes] == ["joint[2].alpha"]


def test_reversed_joint_is_named_and_its_axis_is_reversed(reference):
    bad = with_joint(load_model("ur5"), 2, flip=True)
    result = run_diagnose(bad, reference)
    assert result.best.kind == "flip"
    assert "joint 3 (elbow) turns the other way: set flip = false" in result.best.title
    rows = {a.joint: a for a in result.axes}
    assert rows[2].reversed
    assert all(rows[k].agrees for k in (0, 1))


def test_missing_theta_offset_is_named(reference):
    bad = with_joint(load_model("ur5"), 1, theta=-math.pi / 2)  # an extra -90° on θ2
    result = run_diagnose(bad, reference)
    assert result.best.kind == "theta-offset"
    assert [c.field for c in result.best.changes] == ["joint[1].theta"]
    assert result.best.changes[0].new == pytest.approx(0.0, abs=1e-15)


def test_several_wrong_numbers_match_the_published_table(reference):
    bad = with_joint(with_joint(load_model("ur5"), 1, a=-0.4262), 3, d=0.1113)
    best = run_diagnose(bad, reference).best
    assert best.kind == "parameter"
    assert "published table ur5" in best.title
    assert {c.field: round(c.delta, 9) for c in best.changes} == {
        "joint[1].a": 0.0012,
        "joint[3].d": -0.00215,
    }


def test_full_fit_recovers_several_numbers_and_says_what_it_cannot_tell_apart(reference):
    from fkcheck.diagnose.paramfit import explain_parameter_fit
    from fkcheck.diagnose.problem import Problem, diagnosis_configurations

    good = load_model("ur5")
    bad = with_joint(with_joint(with_joint(good, 1, a=-0.4262), 3, d=0.1113), 2, alpha=0.003)
    q = diagnosis_configurations(bad, 100, 0)
    problem = Problem.build(bad, reference, q, ("base", "tool0"), (1e-6, 1e-6))
    [fit] = explain_parameter_fit(problem)
    assert fit.kind == "fit"
    assert fit.explains
    moved = {c.field: c for c in fit.changes}
    assert moved["joint[1].a"].new == pytest.approx(-0.425, abs=1e-9)
    assert moved["joint[2].alpha"].new == pytest.approx(0.0, abs=1e-9)
    # d2, d3, d4 slide along the parallel axes 2–4: only their sum is determined.
    total = sum(moved[f"joint[{i}].d"].delta for i in (1, 2, 3) if f"joint[{i}].d" in moved)
    assert total == pytest.approx(-0.00215, abs=1e-9)
    assert any("parallel axes" in line and "-2.150 mm in total" in line for line in fit.details)


def test_nothing_to_explain(reference, capsys):
    result = run_diagnose(load_model("ur5"), reference)
    assert result.agrees
    assert result.explanations == ()
    assert "nothing to explain" in format_text(result)


def test_joint_axes_name_the_first_wrong_row(reference):
    bad = with_joint(load_model("ur5"), 3, a=0.01)  # a4 = 10 mm: z4 (joint 5's axis) moves
    result = run_diagnose(bad, reference)
    first = next(a for a in result.axes if not a.agrees)
    assert first.joint == 4
    assert first.distance_m == pytest.approx(0.01, abs=1e-9)
    assert "look at row 4" in result.axes_note


def test_offset_fit_recovers_known_offsets(rng):
    model = load_model("panda")
    q = rng.uniform(-1, 1, size=(60, 7))
    T = model.fk(q)
    X = matrix_from_xyz_rpy([0.1, -0.2, 0.05], [0.3, -0.2, 1.0])
    Y = matrix_from_xyz_rpy([0.0, 0.01, 0.1], [0.0, 0.4, -0.7])
    fit = fit_offsets(T, X @ T @ Y)
    np.testing.assert_allclose(fit.X, X, atol=1e-9)
    np.testing.assert_allclose(fit.Y, Y, atol=1e-9)
    assert fit.residual.position_m < 1e-10


def test_line_distance():
    p, d = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 2.0])
    assert line_distance(p, d / 2, np.array([0.0, 3.0, 5.0]), np.array([1.0, 0, 0])) == 3.0
    assert line_distance(p, d / 2, np.array([0.0, 0.0, 0.0]), d / 2) == 1.0  # parallel


def test_cli_json_and_exit_codes(tmp_path, capsys):
    bad = with_joint(load_model("ur5"), 0, d=0.08946)
    model_path = tmp_path / "ur5_old.toml"
    model_path.write_text(model_to_toml(bad), encoding="utf-8")
    out = tmp_path / "diag.json"
    assert main(["diagnose", str(model_path), "--samples", "50", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["reference"] == "pinocchio-urdf"
    assert data["explained"] is True
    first = data["explanations"][0]
    assert first["kind"] == "parameter"
    assert first["changes"][0]["symbol"] == "d1 (shoulder_pan)"
    assert first["changes"][0]["delta"] == pytest.approx(-0.000301, abs=1e-9)
    assert data == json.loads(json.dumps(data))  # plain JSON types only
    assert set(data) >= {"before", "axes", "tried", "duration_s", "tolerance"}
    capsys.readouterr()
    assert main(["diagnose", "planar2"]) == 2  # no URDF and no --against
    err = capsys.readouterr().err
    assert err.startswith(
        "fkcheck: error: model planar2 has no [urdf] to diagnose against: give --against a "
        "backend independent of its table (rtb-model:…, poses:…)"
    ), err
    assert "unknown backend" not in err
    assert err.count("\n") == 1
    assert main(["diagnose", "ur5", "--against", "nope"]) == 2


def test_swapped_urdf_joints_are_named(reference):
    good = load_model("ur5")
    names = list(good.urdf.joints)
    names[1], names[2] = names[2], names[1]
    bad = replace(good, urdf=replace(good.urdf, joints=tuple(names)))
    best = run_diagnose(bad, reference).best
    assert best.kind == "mapping"
    assert "'elbow_joint' and 'shoulder_lift_joint' swapped (DH joints 2 and 3)" in best.title


def test_cli_unexplained_is_exit_1(tmp_path, capsys):
    # tool0 mapped onto the forearm: its pose ignores joints 4-6, so no table, offset,
    # mistake or fit can match it.
    bad = with_frame(load_model("ur5"), "tool0", urdf="forearm_link")
    path = tmp_path / "odd.toml"
    path.write_text(model_to_toml(bad), encoding="utf-8")
    code = main(["diagnose", str(path), "--samples", "30"])
    out = capsys.readouterr().out
    assert code == 1, out
    assert "explains it:" not in out
    assert "no hypothesis explains the disagreement" in out


def write_pendant_csv(path, model, q_deg):
    """Poses as a UR pendant shows them: mm and a rotation vector, joints in degrees."""
    q = np.radians(q_deg)
    T = relative_pose(*reference_poses(model, q, ("base", "tool0")))
    rows = np.hstack([q_deg, pose_from_matrix(T, "rotvec") * [1e3, 1e3, 1e3, 1, 1, 1]])
    header = ",".join(
        [f"q{i + 1}_deg" for i in range(6)] + ["x_mm", "y_mm", "z_mm", "rx", "ry", "rz"]
    )
    lines = ["# fkcheck poses: from=base to=tool0", header]
    lines += [",".join(repr(float(v)) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def test_measured_pendant_poses_as_a_reference(tmp_path, rng, capsys):
    robot = with_joint(load_model("ur5"), 0, d=0.089459)  # the "real" robot differs in d1
    csv = tmp_path / "pendant.csv"
    q_deg = np.round(rng.uniform(-170, 170, size=(40, 6)), 2)
    write_pendant_csv(csv, robot, q_deg)
    backend = MeasuredPoses(str(csv))
    model = load_model("ur5")
    q = backend.configurations(model)
    np.testing.assert_allclose(np.degrees(q), q_deg, atol=1e-12)
    poses = backend.frame_poses(model, q, ("base", "tool0"))
    expected = relative_pose(*reference_poses(robot, q, ("base", "tool0")))
    np.testing.assert_allclose(poses[1], expected, atol=1e-12)
    assert main(["diagnose", "ur5", "--against", f"poses:{csv}"]) == 0
    out = capsys.readouterr().out
    assert "40 configurations" in out
    assert "d1 (shoulder_pan) = 0.089159 here, 0.089459 would match, Δ = +0.300 mm" in out


def test_measured_poses_drive_the_check_and_skip_other_configurations_and_pairs(tmp_path, rng):
    csv = tmp_path / "pendant.csv"
    write_pendant_csv(csv, load_model("ur5"), np.round(rng.uniform(-90, 90, size=(5, 6)), 1))
    backend = registry.make_backend(f"poses:{csv}")
    assert backend.name == f"poses:{csv}"
    # The check runs on the file's configurations, whatever the sample count.
    result = run_check(load_model("ur5"), [backend], samples=4)
    assert result.q.shape == (5, 6)
    assert result.backends[0].status == "pass"
    # Anywhere else the file has no pose.
    some_q = np.zeros((2, 6))
    with pytest.raises(BackendUnavailable, match="only at the file's configurations"):
        backend.frame_poses(load_model("ur5"), some_q, ("base", "tool0"))
    other = run_check(
        load_model("ur5"), [backend], samples=4, frame_from="base_link", frame_to="tool0"
    )
    assert "not base_link → tool0" in other.backends[0].message


def test_measured_poses_file_errors(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("q1,q2,q3,q4,q5,q6,x,y,z\n0,0,0,0,0,0,1,2,3\n")
    with pytest.raises(PosesFileError, match="header needs a rotation"):
        MeasuredPoses(str(bad)).configurations(load_model("ur5"))
    bad.write_text("q1,q2,q3,q4,q5,q6,x,y,z,rx,ry,rz\n0,0,0,0,0,zero,1,2,3,0,0,0\n")
    with pytest.raises(PosesFileError, match=r"line 2, column 11 \(q6\): not a number: .zero."):
        MeasuredPoses(str(bad)).configurations(load_model("ur5"))
    assert MeasuredPoses(str(tmp_path / "none.csv")).unavailable_reason(load_model("ur5")) == (
        f"no such file: {tmp_path / 'none.csv'}"
    )


def test_diagnose_run_time_on_ur5(reference):
    bad = with_joint(load_model("ur5"), 0, d=0.08946)
    result = diagnose(bad, reference)  # the CLI's defaults: 200 samples
    assert result.configurations == 205
    assert result.duration_s < 30.0  # measured ~1 s; generous for slow CI machines
    assert re.search(r"took (\d+ ms|\d+\.\d\d s)$", format_text(result))
    assert to_dict(result)["duration_s"] == result.duration_s


def test_fixed_models_are_within_rounded_urdf_accuracy(reference):
    bad = with_joint(load_model("ur5"), 0, d=0.08946)
    best = run_diagnose(bad, reference).best
    assert best.residual.position_m < ROUNDED_URDF


class OwnTableBlackBox(BackendDefaults):
    """A plugin-like black box: its own copy of a table, the TCP moved by ``tip_T`` after
    the tool; frames at DH 0 and n placed with the *checked* model's base and tool."""

    name = "own-table-black-box"
    method = "its own table's fk"
    evidence = "implementation"
    reads = "program"

    def __init__(self, table, tip_T):
        self.table = table
        self.tip_T = tip_T

    def unavailable_reason(self, model):
        return None

    def frame_poses(self, model, q, frames):
        return frame_poses_from_tcp(model, self.table.fk(q) @ self.tip_T, frames)


def test_fit_is_tried_when_the_black_box_rules_out_the_frame_offset():
    # The tip is 0.2 mm along x6 and 0.3 mm along z6 further out: a constant tool0 offset
    # matches the poses computed once, but the black box applies any [frames.tool0] offset
    # too, so re-run on the changed model it is still 0.36 mm off. Only a6 and d6 together
    # (not one of them alone) explain it, which the full fit must then find.
    ur5 = load_model("ur5")
    result = run_diagnose(ur5, OwnTableBlackBox(ur5, translation(0.0002, 0.0, 0.0003)))
    assert result.before.position_m == pytest.approx(math.hypot(0.2e-3, 0.3e-3), abs=1e-12)
    assert "all DH parameters + base + tool fitted together" in result.tried
    assert not any(e.explains for e in result.explanations if e.kind in ("frames", "offset"))
    best = result.best
    assert best is not None
    assert best.kind == "fit"
    assert {c.field: c.delta for c in best.changes} == pytest.approx(
        {"joint[5].a": 0.0002, "joint[5].d": 0.0003}, abs=1e-9
    )
