"""Hostile and broken URDFs: each is one clear line and exit 2, before any parser runs it.

A URDF never needs a DTD; entity expansion ("billion laughs") and external
entities only get in through one, so fkcheck refuses any DTD outright and no
URDF parser (urdfdom, lxml, Robotics Toolbox's) ever sees such a file.
"""

from __future__ import annotations

import os
import re
import time
from pathlib import Path

import pytest

from fkcheck.cli import main
from fkcheck.model import bundled_model_paths
from fkcheck.urdf_source import example_robot_data_dir

UR5_URDF = example_robot_data_dir() / "ur_description" / "urdf" / "ur5_robot.urdf"


def model_with_urdf(tmp_path: Path, urdf_text: str | None, *, edit=lambda s: s) -> Path:
    """ur5.toml, pointed at a URDF written next to it (None: no URDF file)."""
    toml = bundled_model_paths()["ur5"].read_text()
    toml = re.sub(r'path = ".*"', 'path = "robot.urdf"', toml)
    model = tmp_path / "ur5_local.toml"
    model.write_text(edit(toml))
    if urdf_text is not None:
        (tmp_path / "robot.urdf").write_text(urdf_text)
    return model


def check(capsys, model: Path, *extra: str):
    code = main(["check", str(model), "--samples", "20", *extra])
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_exit_2(code, out, err, pattern):
    assert code == 2, (out, err)
    assert len(err.strip().splitlines()) == 1, err
    assert re.search(pattern, err), err


BILLION_LAUGHS = """<?xml version="1.0"?>
<!DOCTYPE robot [
 <!ENTITY lol "lol">
 <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<robot name="&lol9;"><link name="base"/></robot>
"""

EXTERNAL_ENTITY = """<?xml version="1.0"?>
<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>
<robot name="r"><link name="&x;"/></robot>
"""


def test_billion_laughs_is_refused_fast(tmp_path, capsys):
    start = time.perf_counter()
    code, out, err = check(capsys, model_with_urdf(tmp_path, BILLION_LAUGHS))
    assert time.perf_counter() - start < 10
    assert_one_line_exit_2(
        code, out, err, r"robot\.urdf: line 2: has a DTD .* entity declarations are not allowed"
    )


def test_external_entity_is_refused_and_never_read(tmp_path, capsys):
    code, out, err = check(capsys, model_with_urdf(tmp_path, EXTERNAL_ENTITY))
    assert_one_line_exit_2(code, out, err, r"has a DTD")
    assert "root:" not in out + err  # /etc/passwd's first line never shows up


@pytest.mark.parametrize(
    "payload", ["${__import__('os').system('touch PWNED')}", "$(find ur_description)"]
)
def test_xacro_expressions_are_refused_never_evaluated(tmp_path, capsys, monkeypatch, payload):
    monkeypatch.chdir(tmp_path)
    text = UR5_URDF.read_text().replace('name="ur5"', f'name="{payload}"', 1)
    code, out, err = check(capsys, model_with_urdf(tmp_path, text))
    assert_one_line_exit_2(code, out, err, r"contains a xacro expression")
    assert not (tmp_path / "PWNED").exists()


def test_missing_urdf_file(tmp_path, capsys):
    code, out, err = check(capsys, model_with_urdf(tmp_path, None))
    assert_one_line_exit_2(code, out, err, r"robot\.urdf: URDF file not found")


def test_not_xml(tmp_path, capsys):
    code, out, err = check(capsys, model_with_urdf(tmp_path, "this is { not xml"))
    assert_one_line_exit_2(code, out, err, r"not valid XML")


def test_mapped_joint_missing_from_urdf(tmp_path, capsys):
    text = UR5_URDF.read_text().replace('"elbow_joint"', '"elbow"')
    code, out, err = check(capsys, model_with_urdf(tmp_path, text))
    assert_one_line_exit_2(
        code,
        out,
        err,
        r"joint 'elbow_joint' \(for DH joint elbow\) not in URDF; movable joints are: .*elbow",
    )


def test_mapped_joint_of_the_wrong_type(tmp_path, capsys):
    text = UR5_URDF.read_text().replace(
        '<joint name="elbow_joint" type="revolute">', '<joint name="elbow_joint" type="prismatic">'
    )
    code, out, err = check(capsys, model_with_urdf(tmp_path, text))
    assert_one_line_exit_2(
        code, out, err, r"joint 'elbow_joint' is prismatic in the URDF but revolute"
    )


def test_frame_not_in_urdf_lists_the_links(tmp_path, capsys):
    model = model_with_urdf(
        tmp_path, UR5_URDF.read_text(), edit=lambda s: s.replace('urdf = "tool0"', 'urdf = "tool"')
    )
    code, out, err = check(capsys, model)
    assert_one_line_exit_2(
        code, out, err, r"frame 'tool' not in URDF robot\.urdf .*; frames are: .*tool0"
    )


def test_disconnected_chain(tmp_path, capsys):
    # Cut the joint that hangs tool0 off wrist_3_link: two separate trees.
    cut = r'<joint name="wrist_3_link-tool0_fixed_joint".*?</joint>'
    text = re.sub(cut, "", UR5_URDF.read_text(), flags=re.S)
    code, out, err = check(capsys, model_with_urdf(tmp_path, text))
    assert_one_line_exit_2(code, out, err, r"expected one root link, found 2")


def test_unknown_check_frame_lists_model_frames(capsys):
    code, out, err = check(capsys, Path(bundled_model_paths()["ur5"]), "--to", "tool")
    assert_one_line_exit_2(
        code, out, err, r"frame 'tool' not in model ur5; frames are: world, tcp, base, base_link"
    )


def test_unknown_backend_lists_backends(capsys):
    code, out, err = check(capsys, Path(bundled_model_paths()["ur5"]), "--against", "kdl")
    assert_one_line_exit_2(
        code, out, err, r"unknown backend 'kdl'; backends are: rtb-dh, pinocchio-dh"
    )


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs POSIX named pipes")
def test_mesh_paths_are_never_opened(tmp_path, capsys):
    # Every mesh of the URDF points at a FIFO: opening one for reading blocks
    # forever, so a backend that touched a mesh would hit the time limit.
    fifo = tmp_path / "mesh.stl"
    os.mkfifo(fifo)
    text = re.sub(r'filename="[^"]*"', f'filename="{fifo}"', UR5_URDF.read_text())
    assert str(fifo) in text
    model = model_with_urdf(tmp_path, text)
    code, out, err = check(
        capsys, model, "--against", "pinocchio-urdf,yourdfpy-urdf,rtb-urdf", "--timeout", "60"
    )
    assert code == 0, out + err
    assert "timed out" not in out
    assert out.count("pass") >= 3
