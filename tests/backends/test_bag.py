"""``poses:BAG`` reads ROS 2 bags as UR's ROS 2 driver records them (issue 35, item 1).

The bags are written by :mod:`tests.bag_cases` with rosbags' writer, in both storages,
from a "calibrated" UR5 table (the nominal one with three numbers changed), its
poses by the tests' own composition (:func:`tests.rtde_cases.poses_of`): joints in
another order than the model's, a joint the model does not have, poses stamped
1 ms after their joint states, other frames changing on ``/tf``. The calibrated
model must pass, the nominal one fail by exactly what the calibration changes,
and another robot's bag fail; every bag that cannot be read is one line, exit 2.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
from pathlib import Path

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends import bag as bag_module
from fkcheck.backends.bag import BagError, BagPairs, read_bag
from fkcheck.backends.registry import BackendOptions
from fkcheck.cli.main import main
from tests.bag_cases import UR_JOINTS, BagSpec, trajectory, write_bag, write_long_bag
from tests.paths import REPO_ROOT
from tests.rtde_cases import poses_of

#: The driver's frame, declared as the model's tool0 (the TCP offset is zero).
_CONTROLLER_FRAME = "\n[frames.tool0_controller]\ndh = 6\n"
#: What the made-up calibration changes in models/ur5.toml: d1 +0.4 mm, a2 -1.2 mm, a3 +0.7 mm.
_CALIBRATION = (("d = 0.089159\n", "d = 0.089559\n"), ("a = -0.425\n", "a = -0.4262\n"),
                ("a = -0.39225\n", "a = -0.39155\n"))  # fmt: skip
#: Poses go through quaternions (SciPy's, then the reader's matrix): a few round-offs.
_ROUND_OFF = 1e-12
_COUNT = 300
#: The driver's bag: shuffled joints, an extra one, poses 1 ms after their joint states.
_DRIVER = BagSpec(order=(3, 1, 0, 5, 2, 4), extra=("gripper_finger_joint",), offset_ns=1_000_000,
                  noise=True)  # fmt: skip


def _model_file(tmp_path: Path, name: str, calibrated: bool, base: str = "ur5") -> Path:
    text = (REPO_ROOT / "models" / f"{base}.toml").read_text(encoding="utf-8")
    if calibrated:
        for old, new in _CALIBRATION:
            assert text.count(old) == 1, old
            text = text.replace(old, new)
    path = tmp_path / f"{name}.toml"
    path.write_text(text + _CONTROLLER_FRAME, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    """``(calibrated, nominal)`` model files, each declaring ``tool0_controller``."""
    tmp = tmp_path_factory.mktemp("models")
    return _model_file(tmp, "ur5_cal", True), _model_file(tmp, "ur5_nom", False)


@pytest.fixture(scope="module")
def motion():
    return trajectory(np.random.default_rng(20261128), _COUNT)


def _bag(tmp_path: Path, model: Path, q: np.ndarray, storage: str = "mcap", **spec) -> Path:
    poses = poses_of(load_model(str(model)), q)
    return write_bag(tmp_path / f"bag_{storage}", q, poses, storage=storage,
                     spec=BagSpec(**spec) if spec else _DRIVER)  # fmt: skip


def _check(model: Path, bag: Path, report: Path | None = None, *extra: str) -> int:
    argv = ["check", str(model), "--against", f"poses:{bag}", "--to", "tool0_controller", "-q"]
    return main(argv + (["--json", str(report)] if report else []) + list(extra))


def _one_line_error(capsys) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "Traceback" not in err
    return err


def _in_project(tmp_path: Path, monkeypatch, table: str) -> Path:
    """A project directory whose pyproject.toml holds ``[tool.fkcheck]`` ``table``; made cwd."""
    project = tmp_path / "project"
    project.mkdir()
    (project / "pyproject.toml").write_text(f"[tool.fkcheck]\n{table}", encoding="utf-8")
    monkeypatch.chdir(project)
    return project


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
def test_the_calibrated_model_passes_and_the_report_names_the_bag(
    models, motion, tmp_path, capsys, storage
):
    bag = _bag(tmp_path, models[0], motion, storage)
    report = tmp_path / "r.json"
    assert _check(models[0], bag, report) == 0, capsys.readouterr().out
    doc = json.loads(report.read_text())
    assert doc["configurations"] == _COUNT
    (backend,) = doc["backends"]
    assert backend["status"] == "pass"
    assert backend["max_position_error_m"] < _ROUND_OFF
    assert backend["max_rotation_error_rad"] < _ROUND_OFF
    assert backend["method"] == (
        f"ROS 2 bag ({storage}): base → tool0_controller from /tf and /tf_static, joints from "
        f"/joint_states; {_COUNT} pairs over 0.598 s (stamps 1700000000.001 … "
        "1700000000.599 s), each pose with the joint state at or before it within 1 ms; "
        "joints not in the model ignored: gripper_finger_joint"
    )


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
def test_the_nominal_model_fails_by_what_the_calibration_changes(
    models, motion, tmp_path, capsys, storage
):
    bag = _bag(tmp_path, models[0], motion, storage)
    calibrated, nominal = (poses_of(load_model(str(m)), motion) for m in models)
    expected = np.linalg.norm(calibrated[:, :3, 3] - nominal[:, :3, 3], axis=1).max()
    assert 1e-3 < expected < 3e-3  # millimetres, as the three numbers make it
    report = tmp_path / "r.json"
    assert _check(models[1], bag, report) == 1, capsys.readouterr().out
    (backend,) = json.loads(report.read_text())["backends"]
    assert backend["status"] == "fail"
    assert backend["max_position_error_m"] == pytest.approx(expected, rel=1e-9)


def test_a_bag_of_another_robot_fails(models, motion, tmp_path, capsys):
    ur10 = _model_file(tmp_path, "ur10", False, base="ur10")
    bag = _bag(tmp_path, ur10, motion)
    report = tmp_path / "r.json"
    assert _check(models[0], bag, report) == 1, capsys.readouterr().out
    (backend,) = json.loads(report.read_text())["backends"]
    assert backend["status"] == "fail"
    assert backend["max_position_error_m"] > 0.1  # a UR10's arm is 0.4 m longer


def test_static_transforms_are_composed_with_the_changing_ones(models, motion, tmp_path, capsys):
    # base_link → base is on /tf_static only (a half turn about z): without it, or with
    # it the wrong way round, base_link → tool0_controller would be off by metres.
    bag = _bag(tmp_path, models[0], motion)
    report = tmp_path / "r.json"
    code = _check(models[0], bag, report, "--from", "base_link")
    assert code == 0, capsys.readouterr().out
    (backend,) = json.loads(report.read_text())["backends"]
    assert backend["max_position_error_m"] < _ROUND_OFF
    assert backend["method"].startswith("ROS 2 bag (mcap): base_link → tool0_controller from ")


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
def test_the_models_own_joint_names_and_a_single_storage_file_are_read(
    models, motion, tmp_path, capsys, storage
):
    names = [j.name for j in load_model(str(models[0])).joints]
    directory = _bag(
        tmp_path, models[0], motion[:20], storage, names=names, order=(5, 4, 3, 2, 1, 0)
    )
    (single,) = (p for p in directory.iterdir() if p.suffix in (".mcap", ".db3"))
    assert _check(models[0], single) == 0, capsys.readouterr().out


def test_a_missing_joint_is_refused_in_one_line(models, motion, tmp_path, capsys):
    bag = _bag(tmp_path, models[0], motion[:5], order=(0, 1, 2, 3, 4), extra=("gripper",))
    assert _check(models[0], bag) == 2
    err = _one_line_error(capsys)
    assert err == (
        f"fkcheck: error: {bag}: a joint state lacks the model's joint wrist_3 or "
        "wrist_3_joint; it names shoulder_pan_joint, shoulder_lift_joint, elbow_joint, "
        "wrist_1_joint, wrist_2_joint, gripper\n"
    )


def test_a_pose_further_from_its_joint_state_than_the_tolerance_is_refused_or_set(
    models, motion, tmp_path, capsys
):
    # 1.5 ms after its joint state, 0.5 ms before the next: beyond the default 1 ms.
    bag = _bag(tmp_path, models[0], motion[:50], offset_ns=1_500_000)
    assert _check(models[0], bag) == 2
    err = _one_line_error(capsys)
    assert (
        "none of the 50 poses of tool0_controller in base has a joint state stamped at or "
        "before it within 1 ms (the nearest joint state before one was 1.5 ms earlier); set "
        "--bag-stamp-tolerance SECONDS" in err
    )
    assert _check(models[0], bag, None, "--bag-stamp-tolerance", "0.0015") == 0


def test_topics_named_otherwise_are_chosen_with_flags(models, motion, tmp_path, capsys):
    topics = ("/ur/joint_states", "/ur/tf", "/ur/tf_static")
    bag = _bag(tmp_path, models[0], motion[:20], topics=topics)
    assert _check(models[0], bag) == 2
    err = _one_line_error(capsys)
    assert "no topic /joint_states in the bag; it has: /chatter, /ur/joint_states, /ur/tf, " in err
    flags = ("--bag-joint-states", topics[0], "--bag-tf", topics[1], "--bag-tf-static", topics[2])
    report = tmp_path / "r.json"
    assert _check(models[0], bag, report, *flags) == 0, capsys.readouterr().out
    (backend,) = json.loads(report.read_text())["backends"]
    assert (
        "from /ur/tf and /ur/tf_static, joints from /ur/joint_states; 20 pairs"
        in (backend["method"])
    )


def test_the_bag_settings_may_be_set_in_the_project_and_a_flag_wins(
    models, motion, tmp_path, capsys, monkeypatch
):
    topics = ("/ur/joint_states", "/ur/tf", "/ur/tf_static")
    bag = _bag(tmp_path, models[0], motion[:20], topics=topics, offset_ns=1_500_000)
    _in_project(
        tmp_path,
        monkeypatch,
        f'bag_joint_states = "{topics[0]}"\nbag_tf = "{topics[1]}"\n'
        f'bag_tf_static = "{topics[2]}"\nbag_stamp_tolerance = 0.0015\n',
    )
    report = tmp_path / "r.json"
    assert _check(models[0], bag, report) == 0, capsys.readouterr()
    (backend,) = json.loads(report.read_text())["backends"]
    assert (
        "from /ur/tf and /ur/tf_static, joints from /ur/joint_states; 20 pairs" in backend["method"]
    )
    assert "within 1.5 ms" in backend["method"]
    capsys.readouterr()
    # Flags win over the file: a tolerance below the bag's lag, another topic.
    assert _check(models[0], bag, None, "--bag-stamp-tolerance", "0.001") == 2
    assert "within 1 ms (the nearest joint state before one was 1.5 ms earlier)" in (
        _one_line_error(capsys)
    )
    assert _check(models[0], bag, None, "--bag-tf", "/other/tf") == 2
    assert "no topic /other/tf in the bag" in _one_line_error(capsys)
    # --isolated ignores the file: the default topics are not in the bag.
    assert _check(models[0], bag, None, "--isolated") == 2
    assert "no topic /joint_states in the bag" in _one_line_error(capsys)


def test_a_bad_bag_setting_in_the_project_is_one_line_exit_2(
    models, motion, tmp_path, capsys, monkeypatch
):
    bag = _bag(tmp_path, models[0], motion[:5])
    project = _in_project(tmp_path, monkeypatch, "bag_stamp_tolerance = 5\n")
    assert _check(models[0], bag) == 2
    assert _one_line_error(capsys) == (
        f"fkcheck: error: {project / 'pyproject.toml'}: tool.fkcheck.bag_stamp_tolerance: must "
        "be seconds from 0 to 1 (a larger lag pairs poses with other cycles' readings), got 5\n"
    )


@pytest.mark.parametrize(
    ("flag", "value", "problem"),
    [
        ("--bag-stamp-tolerance", "2", r"must be seconds from 0 to 1 \(.*\), got 2"),
        ("--bag-stamp-tolerance", "abc", r"'abc' is not a number of seconds"),
        ("--bag-tf", "/tf static", r"must be a topic name \(.*\), got '/tf static'"),
        ("--bag-joint-states", "", r"must be a topic name \(.*\), got ''"),
    ],
)
def test_a_bad_bag_flag_is_one_line_exit_2_by_the_keys_rule(
    models, motion, tmp_path, capsys, flag, value, problem
):
    bag = _bag(tmp_path, models[0], motion[:5])
    assert _check(models[0], bag, None, f"{flag}={value}") == 2
    assert re.search(rf"argument {flag}: {problem}", _one_line_error(capsys))


def test_a_frame_the_bags_tree_does_not_connect_is_refused_with_its_frames(
    models, motion, tmp_path, capsys
):
    bag = _bag(tmp_path, models[0], motion[:5])
    assert main(["check", str(models[0]), "--against", f"poses:{bag}", "--to", "tool0"]) == 2
    err = _one_line_error(capsys)
    assert "no transform of tool0 in base changes on /tf" in err
    assert "its frames: base, base_link, camera, fixture, map, odom, shoulder_link, tool0, " in err


def test_another_type_on_a_topic_read_is_refused(models, motion, tmp_path, capsys):
    bag = _bag(tmp_path, models[0], motion[:5], joint_type="std_msgs/msg/String")
    assert _check(models[0], bag) == 2
    assert "topic /joint_states holds std_msgs/msg/String, not sensor_msgs/msg/JointState" in (
        _one_line_error(capsys)
    )


def _truncated(bag: Path) -> Path:
    (data,) = bag.glob("*.mcap")
    data.write_bytes(data.read_bytes()[: data.stat().st_size // 2])
    return bag


def _garbage_file(bag: Path) -> Path:
    out = bag.parent / "garbage.db3"
    out.write_bytes(os.urandom(4096))
    return out


def _bad_metadata(bag: Path) -> Path:
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: [1, 2\n")
    return bag


def _compressed(bag: Path) -> Path:
    meta = bag / "metadata.yaml"
    meta.write_text(meta.read_text().replace("compression_mode: ''", "compression_mode: FILE"))
    return bag


def _link_out(bag: Path) -> Path:
    (data,) = bag.glob("*.mcap")
    outside = bag.parent / "outside.mcap"
    data.rename(outside)
    data.symlink_to(outside)
    return bag


def _alias_bomb(bag: Path) -> Path:
    lines = ["a: &a [x, x, x, x, x, x, x, x, x]"]
    lines += [
        f"{chr(98 + k)}: &{chr(98 + k)} [{', '.join([f'*{chr(97 + k)}'] * 9)}]" for k in range(8)
    ]
    (bag / "metadata.yaml").write_text("\n".join(lines) + "\nrosbag2_bagfile_information: *i\n")
    return bag


def _no_metadata(bag: Path) -> Path:
    (bag / "metadata.yaml").unlink()
    return bag


@pytest.mark.parametrize(
    ("spoil", "problem"),
    [
        (_truncated, r"not readable as a ROS 2 bag \(mcap\): "),
        (_garbage_file, r"not readable as a ROS 2 bag \(sqlite3\): "),
        (_bad_metadata, r"metadata\.yaml is not a ROS 2 bag's"),
        (_compressed, r"the bag is compressed \(compression_mode 'file'\)"),
        (_link_out, r"its file bag_mcap\.mcap is a symbolic link; a bag's files must be in it"),
        (
            _no_metadata,
            r"is a directory, not a regular file, and not a ROS 2 bag either \(no metadata\.yaml\)",
        ),
        (_alias_bomb, r"metadata\.yaml has an anchor or alias \(&name, \*name\); ROS writes none"),
    ],
    ids=["truncated", "garbage", "metadata", "compressed", "symlink", "no-metadata", "aliases"],
)
def test_a_bag_that_cannot_be_read_is_one_line_exit_2(
    models, motion, tmp_path, capsys, spoil, problem
):
    bag = spoil(_bag(tmp_path, models[0], motion[:20]))
    assert _check(models[0], bag) == 2

    assert re.search(problem, _one_line_error(capsys))


def test_compressed_chunks_are_read_but_not_beyond_the_chunk_limit(
    models, motion, tmp_path, monkeypatch
):
    model = load_model(str(models[0]))
    bag = _bag(tmp_path, models[0], motion[:50], compress=True)
    options = BackendOptions(frame_to="tool0_controller")
    assert read_bag(bag, model, options)[0].shape == (50, 6)
    monkeypatch.setattr(bag_module, "MAX_CHUNK_BYTES", 1000)  # a "bomb": more than declared
    with pytest.raises(BagError, match=r"a chunk declares [\d,]+ bytes \(at most 1,000 are read\)"):
        read_bag(bag, model, options)


def test_the_bags_message_definitions_are_never_compiled(models, motion, tmp_path, monkeypatch):
    # Typestore.register generates Python from definitions and runs it: a bag's own
    # definitions must never reach it.
    from rosbags.typesys.store import Typestore

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("a type was registered from the bag")

    bag = _bag(tmp_path, models[0], motion[:10])
    monkeypatch.setattr(Typestore, "register", refuse)
    q, _, pair, _ = read_bag(
        bag, load_model(str(models[0])), BackendOptions(frame_to="tool0_controller")
    )
    assert q.shape == (10, 6)
    assert pair == ("base", "tool0_controller")


def test_pairs_stream_in_chunks_of_bounded_rows(models, motion, tmp_path):
    bag = _bag(tmp_path, models[0], motion[:50])
    pairs = BagPairs(
        bag, joint_names=[(n,) for n in UR_JOINTS], joint_bounds=[7.0] * 6,
        frames=("base", "tool0_controller"),
    )  # fmt: skip
    chunks = list(pairs.chunks(rows=7))
    assert [c[0].shape[0] for c in chunks] == [7] * 7 + [1]
    q = np.concatenate([c[0] for c in chunks])
    t = np.concatenate([c[2] for c in chunks])
    np.testing.assert_array_equal(q, motion[:50])
    np.testing.assert_allclose(t - t[0], np.arange(50) * 0.002, atol=1e-6)  # stamps as floats
    np.testing.assert_allclose(
        np.concatenate([c[1] for c in chunks]),
        poses_of(load_model(str(models[0])), motion[:50]),
        atol=_ROUND_OFF,
    )
    seen = pairs.provenance
    assert (seen.pairs, seen.unpaired, seen.repeated, seen.ignored_joints) == (
        50,
        0,
        0,
        ("gripper_finger_joint",),
    )


def test_a_bag_without_pairs_for_a_while_yields_empty_chunks_for_the_callers_clock(
    models, motion, tmp_path, monkeypatch
):
    # A bag whose pose is never found (here: a frame no transform leads to) read its
    # every message before its first chunk, outside any time limit; now the reader
    # yields every QUIET_MESSAGES messages, rows or not.
    bag = _bag(tmp_path, models[0], motion[:50])
    monkeypatch.setattr(bag_module, "QUIET_MESSAGES", 10)
    pairs = BagPairs(
        bag, joint_names=[(n,) for n in UR_JOINTS], joint_bounds=[7.0] * 6,
        frames=("base", "camera"),
    )  # fmt: skip
    sizes = []

    def read() -> None:
        for q, T, t in pairs.chunks(rows=7):
            sizes.append((q.shape, T.shape, t.shape))

    with pytest.raises(BagError, match=r"no transform of camera in base changes on /tf"):
        read()
    # 50 joint states and at least 50 tf messages: 10 or more quiet stretches of 10.
    assert len(sizes) >= 10
    assert set(sizes) == {((0, 6), (0, 4, 4), (0,))}


def test_an_unread_bag_has_no_provenance_yet(tmp_path):
    pairs = BagPairs(tmp_path, joint_names=[], joint_bounds=[], frames=("a", "b"))
    with pytest.raises(RuntimeError, match="not been read to its end"):
        _ = pairs.provenance


def test_a_bag_copied_elsewhere_reads_the_same(models, motion, tmp_path):
    # The bag's files are found by name in its directory, not by the paths it recorded.
    bag = _bag(tmp_path, models[0], motion[:10])
    moved = shutil.copytree(bag, tmp_path / "elsewhere" / "renamed")
    model = load_model(str(models[0]))
    options = BackendOptions(frame_to="tool0_controller")
    np.testing.assert_array_equal(
        read_bag(bag, model, options)[0], read_bag(moved, model, options)[0]
    )


def test_diagnose_reads_the_bag_for_the_frames_it_is_given(models, motion, tmp_path, capsys):
    # fkcheck diagnose builds its own backend: the bag's transform is the --to frame's.
    bag = _bag(tmp_path, models[0], motion[:60])
    argv = ["diagnose", str(models[1]), "--against", f"poses:{bag}", "--to", "tool0_controller"]
    assert main(argv) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert (
        f"fkcheck diagnose ur5: base → tool0_controller against poses:{bag}, 60 configurations"
        in out
    )


#: A bag recorded under a namespace: none of the default topics is in it.
_NAMESPACED = ("/ur/joint_states", "/ur/tf", "/ur/tf_static")
_NAMESPACED_FLAGS = ("--bag-joint-states", _NAMESPACED[0], "--bag-tf", _NAMESPACED[1],
                     "--bag-tf-static", _NAMESPACED[2])  # fmt: skip


def _diagnose(model: Path, bag: Path, *extra: str) -> int:
    return main(["diagnose", str(model), "--against", f"poses:{bag}", "--to", "tool0_controller",
                 *extra])  # fmt: skip


def test_diagnose_reads_a_namespaced_bag_by_the_flags_or_the_projects_keys(
    models, motion, tmp_path, capsys, monkeypatch
):
    bag = _bag(tmp_path, models[0], motion[:60], topics=_NAMESPACED)
    monkeypatch.chdir(tmp_path)  # no pyproject.toml above tmp_path: the defaults
    assert _diagnose(models[1], bag) == 2
    assert "no topic /joint_states in the bag; it has: /chatter, /ur/joint_states" in (
        _one_line_error(capsys)
    )
    header = f"fkcheck diagnose ur5: base → tool0_controller against poses:{bag}, 60 configurations"
    assert _diagnose(models[1], bag, *_NAMESPACED_FLAGS) == 0
    assert header in " ".join(capsys.readouterr().out.split())
    # The same settings as [tool.fkcheck] keys, as fkcheck check reads them.
    keys = ("bag_joint_states", "bag_tf", "bag_tf_static")
    project = _in_project(
        tmp_path,
        monkeypatch,
        "".join(f'{key} = "{topic}"\n' for key, topic in zip(keys, _NAMESPACED, strict=True)),
    )
    assert _diagnose(models[1], bag) == 0
    assert header in " ".join(capsys.readouterr().out.split())
    # A flag wins over the key; --isolated ignores the file.
    assert _diagnose(models[1], bag, "--bag-tf", "/other/tf") == 2
    assert "no topic /other/tf in the bag" in _one_line_error(capsys)
    assert _diagnose(models[1], bag, "--isolated") == 2
    assert "no topic /joint_states in the bag" in _one_line_error(capsys)
    # The file read is an input: no output of the diagnosis replaces it.
    before = (project / "pyproject.toml").read_bytes()
    assert _diagnose(models[1], bag, "--json", "pyproject.toml") == 2
    assert _one_line_error(capsys) == (
        "fkcheck: error: --json pyproject.toml: is the configuration file, an input of this "
        "run: write elsewhere\n"
    )
    assert (project / "pyproject.toml").read_bytes() == before


def test_a_bad_bag_setting_is_one_line_exit_2_for_diagnose_too(
    models, motion, tmp_path, capsys, monkeypatch
):
    bag = _bag(tmp_path, models[0], motion[:5])
    project = _in_project(tmp_path, monkeypatch, 'bag_tf = "/tf static"\n')
    assert _diagnose(models[1], bag) == 2
    assert _one_line_error(capsys) == (
        f"fkcheck: error: {project / 'pyproject.toml'}: tool.fkcheck.bag_tf: must be a topic "
        "name (at most 256 characters of text, no spaces), got '/tf static'\n"
    )
    assert _diagnose(models[1], bag, "--isolated", "--bag-stamp-tolerance", "2") == 2
    assert re.search(
        r"argument --bag-stamp-tolerance: must be seconds from 0 to 1 \(.*\), got 2",
        _one_line_error(capsys),
    )


def test_the_checks_diagnose_lines_carry_the_bag_settings_and_reproduce_it(
    models, motion, tmp_path, capsys, monkeypatch
):
    bag = _bag(tmp_path, models[0], motion[:60], topics=_NAMESPACED, offset_ns=1_500_000)
    monkeypatch.chdir(tmp_path)
    html = tmp_path / "r.html"
    flags = (*_NAMESPACED_FLAGS, "--bag-stamp-tolerance", "0.0015")
    assert _check(models[1], bag, None, "--html", str(html), *flags) == 1
    out = capsys.readouterr().out
    wanted = shlex.join(flags)
    # The report's Reproduce line (fkcheck.diagnose.failures.diagnose_command) ...
    (reproduce,) = re.findall(r"Reproduce: <code>(fkcheck diagnose [^<]*)</code>", html.read_text())
    assert reproduce.endswith(" " + wanted), reproduce
    # ... and the hint printed under the results, which runs as printed.
    (hint,) = (line for line in out.splitlines() if line.startswith("hint: explain it: "))
    assert hint.endswith(" " + wanted), hint
    assert main(shlex.split(hint.removeprefix("hint: explain it: fkcheck "))) == 0
    assert "60 configurations" in capsys.readouterr().out
    # Settings left at their defaults add nothing: the line stays as short as before.
    plain = _bag(tmp_path / "plain", models[0], motion[:20])
    assert _check(models[1], plain, None, "--html", str(html)) == 1
    (hint,) = (line for line in capsys.readouterr().out.splitlines() if "explain it" in line)
    assert hint.endswith("--to tool0_controller"), hint
    assert "--bag" not in html.read_text()


def test_the_python_api_reads_the_bag_for_its_frames(models, motion, tmp_path):
    from fkcheck.api import check

    bag = _bag(tmp_path, models[0], motion[:20])
    outcome = check(str(models[1]), against=[f"poses:{bag}"], frame_to="tool0_controller")
    (backend,) = outcome.check.backends
    assert backend.status == "fail"
    assert backend.max_position_error_m > 1e-3  # the calibration's millimetres


@pytest.mark.parametrize("codec", ["zstd", "lz4"])
def test_a_chunk_inflating_beyond_its_declared_size_stops_there(codec):
    # rosbags decompressed a chunk whole, then compared sizes: 100 MB of zeros compress
    # to a few kilobytes. The bounded decompressors stop one byte past the declared size.
    import tracemalloc

    import lz4.frame
    from rosbags.rosbag2 import storage_mcap

    try:
        from compression import zstd
    except ImportError:
        from backports import zstd

    bomb = (zstd.compress if codec == "zstd" else lz4.frame.compress)(bytes(100_000_000))
    assert len(bomb) < 500_000  # zstd: kilobytes; lz4: 0.4 MB
    tracemalloc.start()
    with (
        bag_module._BOUNDED,
        pytest.raises(bag_module._Bad, match="decompresses to more than its declared 1,000 bytes"),
    ):
        storage_mcap.DECOMPRESSORS[codec](bomb, 1000)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 1_000_000  # not the 100 MB


def _rosbags_decompressors() -> dict:
    from rosbags.rosbag2 import storage_mcap

    return dict(storage_mcap.DECOMPRESSORS)


def _same(table: dict) -> bool:
    """Whether rosbags' decompressors are the very objects of ``table`` (none of ours)."""
    assert not any(f.__module__ == bag_module.__name__ for f in table.values())  # rosbags'
    now = _rosbags_decompressors()
    return now.keys() == table.keys() and all(now[k] is table[k] for k in table)


def test_rosbags_decompressors_are_its_own_after_a_read_and_while_the_caller_holds_a_chunk(
    models, motion, tmp_path
):
    # Bounded only while rosbags' reader runs: another user of rosbags in the same
    # process (a user's code, the pytest plugin) never meets them after a read.
    before = _rosbags_decompressors()
    bag = _bag(tmp_path, models[0], motion[:50], compress=True)
    pairs = BagPairs(
        bag, joint_names=[(n,) for n in UR_JOINTS], joint_bounds=[7.0] * 6,
        frames=("base", "tool0_controller"),
    )  # fmt: skip
    held = []
    for chunk in pairs.chunks(rows=7):
        held.append(_same(before))
        assert chunk[0].shape[1] == 6
    assert held == [True] * 8  # 50 rows, 7 at a time
    assert _same(before)
    dropped = pairs.chunks(rows=7)
    next(dropped)
    dropped.close()  # a caller that stops early
    assert _same(before)


def test_rosbags_decompressors_are_its_own_after_a_read_that_fails(
    models, motion, tmp_path, monkeypatch
):
    before = _rosbags_decompressors()
    bag = _bag(tmp_path, models[0], motion[:50], compress=True)
    monkeypatch.setattr(bag_module, "MAX_CHUNK_BYTES", 1000)  # refused by the bounded one
    with pytest.raises(BagError, match=r"a chunk declares [\d,]+ bytes \(at most 1,000 are read\)"):
        read_bag(bag, load_model(str(models[0])), BackendOptions(frame_to="tool0_controller"))
    assert _same(before)


def test_two_reads_at_once_share_the_bounded_decompressors_until_the_last_one_ends():
    import threading

    from rosbags.rosbag2 import storage_mcap

    before = _rosbags_decompressors()
    entered, leave = threading.Barrier(3), threading.Event()
    seen: list[bool] = []

    def read() -> None:
        with bag_module._BOUNDED:
            entered.wait()
            leave.wait()
            seen.append(storage_mcap.DECOMPRESSORS["zstd"] is not before["zstd"])

    threads = [threading.Thread(target=read) for _ in range(2)]
    for t in threads:
        t.start()
    entered.wait()  # both inside
    assert storage_mcap.DECOMPRESSORS["zstd"] is not before["zstd"]
    assert storage_mcap.DECOMPRESSORS["lz4"] is not before["lz4"]
    leave.set()
    for t in threads:
        t.join()
    assert seen == [True, True]  # the first to leave did not take them from the second
    assert _same(before)


def test_a_decompressor_replaced_during_a_read_is_left_as_its_owner_set_it(monkeypatch):
    from rosbags.rosbag2 import storage_mcap

    before = _rosbags_decompressors()

    def theirs(data: bytes, size: int) -> bytes:
        return data

    monkeypatch.setitem(storage_mcap.DECOMPRESSORS, "lz4", before["lz4"])  # undone at the end
    with bag_module._BOUNDED:
        storage_mcap.DECOMPRESSORS["lz4"] = theirs
    assert storage_mcap.DECOMPRESSORS["lz4"] is theirs
    assert storage_mcap.DECOMPRESSORS["zstd"] is before["zstd"]


@pytest.mark.slow
def test_reading_a_bag_ten_times_as_long_takes_no_more_memory(models, motion, tmp_path):
    # The reader keeps one MCAP chunk's messages (about 1 MiB), the joint states of the
    # last REORDER_WINDOW_S of stamps and one chunk of rows: nothing grows with the bag.
    import tracemalloc

    pose = poses_of(load_model(str(models[0])), motion[:1])[0]
    peaks = []
    for count in (2_000, 20_000):  # 2 and 12 MCAP chunks
        bag = write_long_bag(tmp_path / f"long{count}", motion[0], pose, count)
        pairs = BagPairs(
            bag, joint_names=[(n,) for n in UR_JOINTS], joint_bounds=[7.0] * 6,
            frames=("base", "tool0_controller"),
        )  # fmt: skip
        tracemalloc.start()
        rows = sum(chunk[0].shape[0] for chunk in pairs.chunks(rows=1000))
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
        assert rows == count
    assert peaks[1] < peaks[0] + 1_000_000, peaks  # within 1 MB for 10x the pairs


def test_no_report_replaces_a_file_of_the_bag(models, motion, tmp_path, capsys):
    bag = _bag(tmp_path, models[0], motion[:5])
    before = (bag / "metadata.yaml").read_bytes()
    assert _check(models[0], bag, bag / "metadata.yaml") == 2
    assert "is a file of backend poses:" in _one_line_error(capsys)
    assert (bag / "metadata.yaml").read_bytes() == before
