"""fkcheck urdf: the written URDF must pass the check in all three URDF backends."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import replace

import pytest

import fkcheck.backends.registry as registry
from fkcheck import ModelError, load_model
from fkcheck.cli.main import main
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.engine.runner import run_check
from fkcheck.model.types import FrameSpec, Joint
from fkcheck.urdf.export import urdf_from_model
from tests.backend_cases import URDF_BACKENDS
from tests.helpers import BUNDLED


def export(model_name_or_model, tmp_path):
    if isinstance(model_name_or_model, str):
        argv_model = model_name_or_model
    else:  # write the in-memory model first
        from fkcheck.model.write import model_to_toml

        path = tmp_path / "in.toml"
        tmp_path.mkdir(parents=True, exist_ok=True)
        path.write_text(model_to_toml(model_name_or_model), encoding="utf-8")
        argv_model = str(path)
    urdf, toml = tmp_path / "out" / "robot.urdf", tmp_path / "robot.toml"
    assert main(["urdf", argv_model, "-o", str(urdf), "--write-model", str(toml)]) == 0
    return urdf, load_model(toml)


def assert_passes(model, pair=None, samples=64):
    backends = [registry.make_backend(name) for name in URDF_BACKENDS]
    kwargs = {} if pair is None else {"frame_from": pair[0], "frame_to": pair[1]}
    result = run_check(model, backends, samples=samples, **kwargs)
    for r in result.backends:
        assert r.status == "pass", f"{r.name}: {r.message}"
        assert r.max_position_error_m <= SAME_CHAIN
        assert r.max_rotation_error_rad <= SAME_CHAIN
    assert result.verdict == "pass"


@pytest.mark.parametrize("name", BUNDLED)
def test_urdf_of_every_bundled_model_passes_in_all_urdf_backends(name, tmp_path):
    _, model = export(name, tmp_path)
    assert_passes(model)
    last = f"dh_frame_{model.dof}"
    assert_passes(model, ("world", "dh_frame_2"), samples=16)
    assert_passes(model, ("dh_frame_1", last), samples=16)


def test_ur5_named_frames_all_agree(tmp_path):
    _, model = export("ur5", tmp_path)
    assert_passes(model, ("base_link", "ee_link"))
    assert_passes(model, ("base", "tool0"))
    assert model.urdf.path == "out/robot.urdf"  # relative to the model file


def test_flipped_prismatic_and_unlimited_joints(tmp_path):
    base = load_model("stanford")
    joints = list(base.joints)
    joints[0] = replace(joints[0], flip=True, limits=None)  # continuous, axis -z
    joints[2] = replace(joints[2], flip=True, limits=None)  # prismatic, ±1 m, axis -z
    for convention in ("standard", "modified"):
        model = replace(base, joints=tuple(joints), convention=convention)
        urdf, mapped = export(model, tmp_path / convention)
        root = ET.parse(urdf).getroot()
        j1 = root.find("joint[@name='j1']")
        assert j1.get("type") == "continuous"
        assert j1.find("axis").get("xyz") == "0 0 -1"
        j3 = root.find("joint[@name='j3']")
        assert j3.get("type") == "prismatic"
        assert (j3.find("limit").get("lower"), j3.find("limit").get("upper")) == ("-1.0", "1.0")
        assert_passes(mapped)


def test_urdf_from_a_urdf_extracted_table_round_trips(tmp_path):
    spec = "example-robot-data:kinova_description/robots/kinova.urdf"
    extracted = tmp_path / "kinova.toml"
    assert (
        main(
            [
                "table-from",
                spec,
                "--base",
                "base",
                "--tip",
                "j2s6s200_end_effector",
                "--convention",
                "modified",
                "-o",
                str(extracted),
            ]
        )
        == 0
    )
    _, model = export(str(extracted), tmp_path)
    assert_passes(model, ("base", "j2s6s200_link_4"))


def test_frame_named_like_a_generated_link_is_refused():
    model = load_model("ur5")
    frames = dict(model.frames)
    frames["dh_frame_2"] = FrameSpec("dh_frame_2", 3)
    with pytest.raises(ModelError, match=r"frames\.dh_frame_2: collides with a link"):
        urdf_from_model(replace(model, frames=frames))


def test_limits_are_written_in_radians(tmp_path):
    urdf, _ = export("ur5", tmp_path)  # ur5.toml declares ±360° in degrees
    lift = ET.parse(urdf).getroot().find("joint[@name='shoulder_lift']/limit")
    assert float(lift.get("upper")) == pytest.approx(2 * math.pi, abs=1e-15)


def test_single_joint_model(tmp_path):
    model = replace(
        load_model("planar2"),
        joints=(Joint("only", a=0.5, alpha=0.0, d=0.1),),
        poses={},
        frames={"world": FrameSpec("world", "world"), "tcp": FrameSpec("tcp", "tcp")},
    )
    _, mapped = export(model, tmp_path)
    assert_passes(mapped)
