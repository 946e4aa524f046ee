"""The bundled UR models against both of UR's descriptions.

The models name UR's own ROS 2 description (bundled, expanded through the
opt-in xacro path); example-robot-data ships the older ROS 1 description of
UR3/UR5/UR10 (``urX_robot.urdf``), which names the same joints and ``base``,
``base_link``, ``tool0``, and ``ee_link`` where ROS 2 has ``flange``. Both must
agree with the published tables.
"""

from __future__ import annotations

import pytest

from fkcheck.backends.registry import make_backend
from fkcheck.engine.runner import run_check
from fkcheck.model.read import load_model
from fkcheck.urdf.locate import FKCHECK_PREFIX
from tests.helpers import on_ros1_description

URDF_READERS = ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "mujoco-urdf", "idyntree-urdf")
UR_TYPES = ("ur3", "ur3e", "ur5", "ur5e", "ur10", "ur10e", "ur16e", "ur20", "ur30")

pytest.importorskip("example_robot_data")


@pytest.mark.parametrize("name", UR_TYPES)
def test_every_bundled_ur_model_names_urs_ros2_description(name):
    model = load_model(name)
    assert model.urdf is not None
    assert model.urdf.path == f"{FKCHECK_PREFIX}ur_description/urdf/ur.urdf.xacro"
    assert model.urdf.xacro
    assert model.urdf.xacro_args == {"ur_type": name, "name": name}
    assert model.urdf.packages == {"ur_description": f"{FKCHECK_PREFIX}ur_description"}
    mapped = {f.name: f.urdf for f in model.frames.values() if f.urdf is not None}
    assert mapped == {"base": "base", "base_link": "base_link", "tool0": "tool0",
                      "flange": "flange"}  # fmt: skip
    assert (model.check.frame_from, model.check.frame_to) == ("base", "tool0")


@pytest.mark.parametrize(("frame_from", "frame_to"), [("base", "tool0"), ("base_link", "flange")])
@pytest.mark.parametrize("name", ["ur5e", "ur20"])
def test_urs_ros2_description_verifies_the_table(name, frame_from, frame_to):
    check = run_check(load_model(name), [make_backend(n) for n in URDF_READERS], samples=20,
                      frame_from=frame_from, frame_to=frame_to)  # fmt: skip
    assert check.verdict == "pass"
    assert check.evidence.table.status == "verified"


@pytest.mark.parametrize(("frame_from", "frame_to"), [("base", "tool0"), ("base_link", "ee_link")])
@pytest.mark.parametrize("name", ["ur3", "ur5", "ur10"])
def test_the_older_ros1_description_still_agrees(name, frame_from, frame_to):
    model = on_ros1_description(load_model(name))
    check = run_check(model, [make_backend(n) for n in URDF_READERS], samples=20,
                      frame_from=frame_from, frame_to=frame_to)  # fmt: skip
    assert check.verdict == "pass"
    assert check.evidence.table.status == "verified"
    assert [b.status for b in check.backends] == ["pass"] * len(URDF_READERS)


def test_the_bundled_description_names_meshes_that_are_not_there():
    """No mesh is bundled: the checks above pass without one (no reader opens a mesh)."""
    from fkcheck.model.read import bundled_models_dir
    from fkcheck.urdf.source import load_urdf

    root = bundled_models_dir() / "ur_description"
    assert not (root / "meshes").exists()
    assert (root / "LICENSE").is_file()
    assert "2221ec0f720fb1af99339eb891639b499b62f1da" in (root / "SOURCE.md").read_text()
    info = load_urdf(load_model("ur5e"))
    assert "package://ur_description/meshes/ur5e/visual/base.dae" in info.text
