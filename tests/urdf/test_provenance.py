"""A URDF written from the model's own table is found: by fkcheck's mark, or by its numbers."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import pytest

from fkcheck.model.read import load_model
from fkcheck.model.types import Model
from fkcheck.urdf.export import model_for_urdf, urdf_from_model
from fkcheck.urdf.marker import MARKER_TAG, read_marker, table_fingerprint
from fkcheck.urdf.provenance import derived_from_table
from fkcheck.urdf.source import load_urdf
from fkcheck.urdf.tree import urdf_info_from_bytes
from tests.helpers import BUNDLED

#: The bundled models that name a real URDF (example-robot-data).
WITH_URDF = [name for name in BUNDLED if load_model(name).urdf is not None]
TOL = (1e-6, 1e-6)


def _without_comments(text: str) -> str:
    return re.sub(r"<!--.*?-->", "", text, flags=re.DOTALL)


def _without_mark(text: str) -> str:
    text = re.sub(r"<fkcheck:written-from[^>]*/>", "", _without_comments(text))
    return text.replace(' xmlns:fkcheck="urn:fkcheck:urdf-provenance"', "")


def _renamed(text: str) -> str:
    """Every generated link and fixed joint renamed, as a hand that hides the export would."""
    return text.replace("dh_frame_", "link_").replace("dh_joint_", "knuckle_")


def _read(text: str):
    return urdf_info_from_bytes(Path("vendor.urdf"), text.encode("utf-8"))


def _exported(name: str) -> tuple[Model, str]:
    """The bundled model mapped onto its own export, and the export's text."""
    model = load_model(name)
    export = urdf_from_model(model)
    return model_for_urdf(model, export, "robot.urdf"), export.text


def _with_d1(model: Model, delta: float) -> Model:
    joints = list(model.joints)
    joints[0] = replace(joints[0], d=joints[0].d + delta)
    return replace(model, joints=tuple(joints))


def test_the_mark_survives_stripped_comments_and_the_screen():
    model, text = _exported("ur5")
    info = _read(_without_comments(text))
    assert "<!--" not in info.text
    mark = read_marker(ET.fromstring(info.text))
    assert mark is not None
    assert (mark.model, mark.convention, mark.table) == (
        "ur5",
        "standard",
        table_fingerprint(model),
    )
    assert mark.by.startswith("fkcheck urdf ")


def test_the_fingerprint_is_of_the_numbers_not_the_names_or_limits():
    model = load_model("ur5")
    renamed = replace(
        model,
        name="other",
        joints=tuple(replace(j, name=f"j{i}", limits=None) for i, j in enumerate(model.joints)),
    )
    assert table_fingerprint(renamed) == table_fingerprint(model)
    assert table_fingerprint(_with_d1(model, 1e-12)) != table_fingerprint(model)
    assert table_fingerprint(replace(model, tool=replace(model.tool, xyz=(0, 0, 0.1)))) != (
        table_fingerprint(model)
    )
    flipped = replace(model, joints=(replace(model.joints[0], flip=True), *model.joints[1:]))
    assert table_fingerprint(flipped) != table_fingerprint(model)


@pytest.mark.parametrize("name", ["ur5", "panda"])  # standard and modified
def test_a_marked_export_is_found_by_its_mark(name):
    model, text = _exported(name)
    found = derived_from_table(model, _read(_without_comments(text)), TOL)
    assert found is not None
    assert found.via == "mark"
    assert f"its fkcheck mark names model {name!r} and table sha256:" in found.message
    assert "written by fkcheck from this table" in found.message
    assert "it cannot verify the table" in found.message


@pytest.mark.parametrize("name", ["ur5", "panda", "stanford", "planar3"])
def test_an_export_without_its_mark_and_renamed_is_found_by_its_numbers(name):
    model, text = _exported(name)
    vendor = _renamed(_without_mark(text))
    assert "fkcheck" not in vendor
    assert "dh_frame" not in vendor
    frames = {
        k: replace(v, urdf=_renamed(v.urdf) if v.urdf else None) for k, v in model.frames.items()
    }
    found = derived_from_table(replace(model, frames=frames), _read(vendor), TOL)
    assert found is not None
    assert found.via == "numbers"
    assert "is what fkcheck urdf writes from this table" in found.message


def test_an_export_of_another_table_is_evidence():
    model, text = _exported("ur5")
    wrong = _with_d1(model, 0.01)  # 10 mm: the URDF of the right table is evidence against it
    assert derived_from_table(wrong, _read(text), TOL) is None
    assert derived_from_table(wrong, _read(_without_mark(text)), TOL) is None


def test_numbers_within_the_checks_tolerance_are_the_exports():
    model, text = _exported("ur5")
    nudged = _with_d1(model, 1e-7)  # a new fingerprint, the same kinematics to 1e-6 m
    assert derived_from_table(nudged, _read(text), TOL).via == "numbers"
    assert derived_from_table(nudged, _read(text), (1e-9, 1e-9)) is None


def _dressed(text: str) -> str:
    """Every link given inertia and geometry, numbers rewritten, whitespace and order changed."""
    root = ET.fromstring(_without_mark(text))
    for link in root.findall("link"):
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "mass", value="2.5")
        ET.SubElement(inertial, "inertia", ixx="0.01", ixy="0", ixz="0", iyy="0.01", iyz="0",
                      izz="0.01")  # fmt: skip
        visual = ET.SubElement(link, "visual")
        ET.SubElement(ET.SubElement(visual, "geometry"), "box", size="0.1 0.1 0.1")
    for origin in root.iter("origin"):  # the same numbers, written otherwise
        for key in ("xyz", "rpy"):
            values = [float(v) for v in origin.get(key, "0 0 0").split()]
            origin.set(key, "   ".join(f"{v:.17e}" for v in values))
    joints = root.findall("joint")
    for joint in joints:
        root.remove(joint)
    for joint in reversed(joints):  # elements in another order
        root.append(joint)
    return ET.tostring(root, encoding="unicode")


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_a_copy_given_inertia_and_geometry_is_still_the_export(name):
    """Issue 30, item 5: the chain is compared, not the text; what the links hold aside."""
    model, text = _exported(name)
    dressed = _renamed(_dressed(text))
    assert "<inertial>" in dressed
    assert "fkcheck" not in dressed
    frames = {
        k: replace(v, urdf=_renamed(v.urdf) if v.urdf else None) for k, v in model.frames.items()
    }
    found = derived_from_table(replace(model, frames=frames), _read(dressed), TOL)
    assert found is not None
    assert found.via == "numbers"
    assert "inertia or geometry" in found.message
    # … and the dressed export of a table 1 mm off stays evidence against this one
    assert derived_from_table(_with_d1(model, 1e-3), _read(_dressed(text)), TOL) is None


@pytest.mark.parametrize("name", WITH_URDF)
def test_no_bundled_model_takes_its_real_urdf_for_a_copy(name):
    """Panda's URDF is its modified-DH table, joint for joint; read from its package, it is
    the vendor's (the same file copied beside the model is not: numbers cannot tell)."""
    pytest.importorskip("example_robot_data")
    model = load_model(name)
    info = load_urdf(model)
    assert next(ET.fromstring(info.text).iter(MARKER_TAG), None) is None
    assert derived_from_table(model, info, TOL) is None


def test_the_panda_urdf_copied_beside_the_model_cannot_be_told_from_a_copy(tmp_path):
    """The documented limit: outside its package, a DH table written out is the export."""
    pytest.importorskip("example_robot_data")
    model = load_model("panda")
    assert model.urdf is not None
    info = load_urdf(model)
    local = tmp_path / "panda.urdf"
    local.write_text(info.text, encoding="utf-8")
    copied = replace(model, urdf=replace(model.urdf, path=str(local)))
    found = derived_from_table(copied, _read(info.text), TOL)
    assert found is not None
    assert found.via == "numbers"


def test_a_marks_model_name_is_shown_short_and_on_one_line():
    model, text = _exported("ur5")
    long_name = "line&#10;break" + "x" * 100_000
    forged = text.replace('model="ur5"', f'model="{long_name}"')
    found = derived_from_table(model, _read(forged), TOL)
    assert found is not None
    assert "\n" not in found.message
    assert len(found.message) < 400
    assert "(100010 characters)" in found.message


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_fixed_joints_added_above_the_root_or_merged_do_not_hide_the_export(name):
    model, text = _exported(name)
    root = ET.fromstring(_without_mark(text))
    # A new root `cell`, fixed to the old one by an identity joint (the red team's case) …
    cell = ET.SubElement(root, "link", name="cell")
    joint = ET.SubElement(root, "joint", name="cell_joint", type="fixed")
    ET.SubElement(joint, "parent", link="cell")
    ET.SubElement(joint, "child", link="world")
    ET.SubElement(joint, "origin", xyz="0 0 0", rpy="0 0 0")
    assert cell is not None
    found = derived_from_table(model, _read(ET.tostring(root, encoding="unicode")), TOL)
    assert found is not None
    assert found.via == "numbers"
    # … and the export of a table one number off stays evidence, re-jointed or not.
    assert (
        derived_from_table(_with_d1(model, 0.01), _read(ET.tostring(root, encoding="unicode")), TOL)
        is None
    )
