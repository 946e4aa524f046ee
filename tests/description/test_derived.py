"""A table derived from one description, the other declared to be read by its own readers."""

from __future__ import annotations

import pytest

from fkcheck.description.derived import ChainEnds, default_ends, derived_model
from fkcheck.description.registry import read_description_file
from fkcheck.errors import FkcheckError, FrameError
from tests.description.conversion_arm import MJCF, URDF, seeded, write_pair

NAMES = ("arm.urdf", "arm.xml")


def pair(tmp_path, mjcf=None):
    urdf, xml = write_pair(tmp_path) if mjcf is None else write_pair(tmp_path, mjcf)
    return read_description_file(urdf), read_description_file(xml)


def test_urdf_to_mjcf_the_table_is_the_urdfs_and_the_mjcf_is_declared(tmp_path):
    urdf, xml = pair(tmp_path)
    model = derived_model(urdf, xml, ChainEnds(), ChainEnds(), names=NAMES)
    assert model.joint_names == ("j1", "j2", "j3")
    assert model.urdf is None  # the source is not read again as a reference
    assert model.mjcf is not None
    assert model.mjcf.joints == ("j1", "j2", "j3")
    assert model.mjcf.path == str(xml.path.resolve())
    # Each chain from the link its first moving joint hangs from to the one its last moves.
    assert (model.check.frame_from, model.check.frame_to) == ("base_link", "link3")
    assert model.frames["base_link"].mjcf == "base_link"
    assert model.frames["link3"].mjcf == "link3"
    assert model.derived is not None
    assert (model.derived.source, model.derived.checked) == NAMES
    assert "not whether either holds the vendor's numbers" in model.derived.line


def test_mjcf_to_urdf_declares_the_urdf(tmp_path):
    urdf, xml = pair(tmp_path)
    model = derived_model(xml, urdf, ChainEnds(), ChainEnds(), names=NAMES[::-1])
    assert model.mjcf is None
    assert model.urdf is not None
    assert model.urdf.joints == ("j1", "j2", "j3")
    assert model.frames["link3"].urdf == "link3"


def test_the_table_comes_from_the_source_alone(tmp_path):
    """A faulty checked file leaves the table as it is: else the check could not see it."""
    right = derived_model(*pair(tmp_path), ChainEnds(), ChainEnds(), names=NAMES)
    other = tmp_path / "faulty"
    other.mkdir()
    faulty = derived_model(
        *pair(other, seeded("body 1 mm off")), ChainEnds(), ChainEnds(), names=NAMES
    )
    assert faulty.joints == right.joints
    assert (faulty.base, faulty.tool) == (right.base, right.tool)


def test_given_ends_map_a_link_onto_a_site(tmp_path):
    urdf, xml = pair(tmp_path)
    model = derived_model(urdf, xml, ChainEnds(tip="tool0"), ChainEnds(), names=NAMES)
    assert model.check.frame_to == "tool0"
    assert model.frames["tool0"].mjcf == "tool0"  # the checked tip defaults to --tip's name
    model = derived_model(
        urdf, xml, ChainEnds(tip="tool0"), ChainEnds(base="world", tip="link3"), names=NAMES
    )
    assert (model.frames["base_link"].mjcf, model.frames["tool0"].mjcf) == ("world", "link3")


def test_joints_are_matched_by_name_and_a_difference_lists_both(tmp_path):
    urdf, _ = pair(tmp_path)
    renamed = tmp_path / "renamed.xml"
    renamed.write_text(MJCF.replace('name="j3"', 'name="joint3"'), encoding="utf-8")
    with pytest.raises(FkcheckError, match=r"has j1, j2, j3; arm.xml \(base_link → link3\) "
                       r"has j1, j2, joint3 \(not there: j3\)$"):  # fmt: skip
        derived_model(urdf, read_description_file(renamed), ChainEnds(), ChainEnds(), names=NAMES)


def test_a_tip_that_is_not_there_lists_the_links(tmp_path):
    urdf, xml = pair(tmp_path)
    with pytest.raises(FrameError, match="flange"):
        derived_model(urdf, xml, ChainEnds(tip="flange"), ChainEnds(), names=NAMES)


def test_moving_joints_that_are_not_one_chain_ask_for_the_ends(tmp_path):
    finger = """  <link name="finger"/>
  <joint name="f1" type="prismatic">
    <parent link="link1"/><child link="finger"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.1" effort="1" velocity="1"/>
  </joint>
</robot>"""
    path = tmp_path / "branched.urdf"
    path.write_text(URDF.replace("</robot>", finger), encoding="utf-8")
    tree = read_description_file(path).tree
    with pytest.raises(FkcheckError, match=r"\(j1, j2, j3, f1\) are not one chain; give --base "
                       "and --tip"):  # fmt: skip
        default_ends(tree, ChainEnds())
    assert default_ends(tree, ChainEnds("base_link", "link3")) == ("base_link", "link3")
