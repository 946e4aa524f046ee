"""A description is one concept: read in one place, kept by its files' bytes, asked by format."""

from __future__ import annotations

import copy
import os
from dataclasses import replace

import pytest

from fkcheck.backends import registry
from fkcheck.backends.base import contract_problems, reads_format, reads_model_description
from fkcheck.backends.registry import make_backend
from fkcheck.description.registry import (
    FORMATS,
    clear_descriptions,
    format_named,
    load_description,
    model_format,
    read_description_file,
)
from fkcheck.errors import FkcheckError, UrdfError, XacroRefused
from fkcheck.model.read import load_model
from tests.xacro_cases import twin_urdf, write_description, write_model

PACKAGES = 'packages = { arm_description = "../arm_description" }'


def plain_model(tmp_path):
    """The xacro cases' arm as a plain URDF (``robot/arm.urdf``), reach 0.4."""
    write_description(tmp_path)
    path = write_model(tmp_path, "0.4", "")
    (path.parent / "arm.urdf").write_text(twin_urdf("0.4"))
    path.write_text(path.read_text().replace('"arm.urdf.xacro"', '"arm.urdf"'))
    return load_model(path)


def test_a_plain_urdf_is_a_urdf_description_with_its_tree_and_frames(tmp_path):
    model = plain_model(tmp_path)
    described = load_description(model)
    assert described.format == "urdf"
    assert described.language == "urdf"
    assert described.path == (tmp_path / "robot" / "arm.urdf").resolve()
    assert described.files == (described.path,)
    assert "<robot" in described.text
    assert described.frames == described.tree.links
    assert {"base", "tip"} <= set(described.frames)
    assert [j.name for j in described.tree.movable(described.tree.chain("base", "tip"))] == [
        "j1",
        "j2",
        "j3",
    ]
    assert model_format(model) is format_named("urdf")
    assert format_named("urdf").mapped_joints(model) == ("j1", "j2", "j3")


def test_a_kept_description_is_read_again_when_a_file_changes_its_bytes_not_its_date(tmp_path):
    """Same size, same modification time, other bytes: a date-and-size key would keep it."""
    clear_descriptions()
    model = plain_model(tmp_path)
    first = load_description(model)
    assert load_description(model) is first  # kept
    urdf = tmp_path / "robot" / "arm.urdf"
    stat = urdf.stat()
    text = urdf.read_text()
    assert 'xyz="0.4 0 0"' in text
    urdf.write_text(text.replace('xyz="0.4 0 0"', 'xyz="0.5 0 0"'))
    os.utime(urdf, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    assert urdf.stat().st_size == stat.st_size
    again = load_description(model)
    assert again is not first
    assert 'xyz="0.5 0 0"' in again.text


def test_the_mapping_is_checked_on_every_load_even_of_a_kept_description(tmp_path):
    model = plain_model(tmp_path)
    load_description(model)  # kept, right mapping
    assert model.urdf is not None
    wrong = replace(model, urdf=replace(model.urdf, joints=("j1", "j2", "nope")))
    with pytest.raises(UrdfError, match=r"joint 'nope' \(for DH joint j3\) not in URDF"):
        load_description(wrong)
    assert load_description(wrong, mapping=False).format == "urdf"  # map proposes a mapping


def test_a_xacro_model_reads_as_xacro_and_its_expansion_travels_with_it(tmp_path):
    write_description(tmp_path)
    model = load_model(write_model(tmp_path, "0.4", f"xacro = true\n{PACKAGES}"))
    fmt = model_format(model)
    assert fmt is not None
    assert fmt.name == "xacro"
    assert fmt.executes
    described = load_description(model)
    assert described.format == "xacro"
    assert described.language == "urdf"
    assert len(described.files) > 1  # the include is one of its files
    carried = fmt.carry(model, described)
    assert carried.urdf is not None
    assert carried.urdf.expanded == described.text


def test_a_xacro_allowed_model_naming_a_plain_urdf_reads_as_urdf(tmp_path):
    model = plain_model(tmp_path)
    assert model.urdf is not None
    allowed = replace(model, urdf=replace(model.urdf, xacro=True))
    assert model_format(allowed) is format_named("xacro")
    described = load_description(allowed)
    assert described.format == "urdf"  # xacro never ran on it
    assert format_named("xacro").carry(allowed, described) is allowed


def test_a_file_on_the_command_line_is_read_by_its_format(tmp_path):
    model = plain_model(tmp_path)
    plain = read_description_file(tmp_path / "robot" / "arm.urdf")
    assert plain.format == "urdf"
    assert plain.frames == load_description(model).frames
    xacro = tmp_path / "robot" / "arm.urdf.xacro"
    with pytest.raises(XacroRefused):
        read_description_file(xacro)  # no arguments given: no code runs
    packages = {"arm_description": tmp_path / "arm_description"}
    expanded = read_description_file(xacro, args={}, packages=packages)
    assert expanded.format == "xacro"


def test_an_unknown_format_lists_the_formats():
    wanted = r"unknown description format 'sdf'; formats are: xacro, urdf, mjcf$"
    with pytest.raises(FkcheckError, match=wanted):
        format_named("sdf")
    assert [f.name for f in FORMATS] == ["xacro", "urdf", "mjcf"]


def test_a_model_without_a_description_has_no_format():
    model = load_model("planar2")
    assert model.urdf is None
    assert model_format(model) is None
    with pytest.raises(UrdfError, match="has no \\[urdf\\] table"):
        load_description(model)
    assert not reads_model_description(make_backend("pinocchio-urdf"), model)


def test_backends_declare_the_formats_they_read(tmp_path):
    model = plain_model(tmp_path)
    urdf_readers = registry.names(reads="urdf")
    assert urdf_readers
    assert registry.names(format="urdf") == urdf_readers
    assert registry.names(format="xacro") == urdf_readers
    assert "rtb-dh" not in registry.names(format="urdf")
    assert registry.names(format="sdf") == ()
    pin, dh = make_backend("pinocchio-urdf"), make_backend("rtb-dh")
    assert reads_format(pin, "urdf")
    assert reads_format(pin, "xacro")
    assert not reads_format(dh, "urdf")
    assert reads_model_description(pin, model)
    assert not reads_model_description(dh, model)


def test_the_contract_holds_formats_to_the_language_a_backend_reads():
    pin, dh = copy.copy(make_backend("pinocchio-urdf")), copy.copy(make_backend("rtb-dh"))
    assert contract_problems(pin) == []
    pin.formats = ("urdf", "sdf")
    assert contract_problems(pin) == ["formats names 'sdf', not one of xacro, urdf, mjcf"]
    dh.formats = ("urdf",)
    assert contract_problems(dh) == ["reads 'dh' but reads format 'urdf', which is in 'urdf'"]
    dh.formats = ["urdf"]
    assert contract_problems(dh) == ["'formats' is not a tuple of format names"]
