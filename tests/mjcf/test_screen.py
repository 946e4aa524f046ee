"""Hostile MJCFs: each refused with one MjcfError naming the file and what is wrong.

And what is kept: includes inlined and held to the folder, geometry stripped so no
mesh is ever opened, the compiler's directories ignored.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from fkcheck.errors import FkcheckError, MjcfError
from fkcheck.mjcf import mujoco_poses, read_mjcf, screen_mjcf
from fkcheck.mjcf.screen import MAX_INCLUDES, MAX_MJCF_BYTES, MAX_XML_DEPTH, MAX_XML_ELEMENTS

ARM = """<mujoco model="arm">
  {top}
  <worldbody>
    <body name="b1" pos="0 0 0.3">
      <joint name="j1" axis="0 0 1"/>
      {inside}
      <site name="tip" pos="0.25 0 0"/>
    </body>
  </worldbody>
</mujoco>
"""


def write(folder: Path, top: str = "", inside: str = "", name: str = "arm.xml") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(ARM.format(top=top, inside=inside))
    return path


def include(tmp_path: Path, spec: str) -> Path:
    return write(tmp_path / "model", top=f'<include file="{spec}"/>')


def test_is_a_fkcheck_error() -> None:
    assert issubclass(MjcfError, FkcheckError)


def test_include_escaping_the_folder(tmp_path: Path) -> None:
    (tmp_path / "outside.xml").write_text("<mujoco/>")
    with pytest.raises(MjcfError, match=r"arm\.xml.*'\.\.' leads out of the folder"):
        read_mjcf(include(tmp_path, "../outside.xml"))


def test_include_escaping_by_a_detour(tmp_path: Path) -> None:
    (tmp_path / "outside.xml").write_text("<mujoco/>")
    path = include(tmp_path, "sub/../../outside.xml")
    with pytest.raises(MjcfError, match=r"'\.\.' leads out"):
        read_mjcf(path)


def test_absolute_include(tmp_path: Path) -> None:
    with pytest.raises(MjcfError, match="an absolute path"):
        read_mjcf(include(tmp_path, "/etc/passwd"))


@pytest.mark.parametrize("spec", ["C:/secret.xml", "\\\\server\\share\\x.xml"])
def test_windows_absolute_include(tmp_path: Path, spec: str) -> None:
    with pytest.raises(MjcfError, match="an absolute path"):
        read_mjcf(include(tmp_path, spec))


def test_symlink_escaping_the_folder(tmp_path: Path) -> None:
    (tmp_path / "secret.xml").write_text("<mujoco/>")
    path = include(tmp_path, "link.xml")
    os.symlink(tmp_path / "secret.xml", tmp_path / "model" / "link.xml")
    with pytest.raises(MjcfError, match="a symbolic link leads out"):
        read_mjcf(path)


def test_include_held_to_a_given_root(tmp_path: Path) -> None:
    """The lead's root (the model file's folder) may be above the MJCF's: includes stay in it."""
    (tmp_path / "project" / "shared").mkdir(parents=True)
    (tmp_path / "project" / "shared" / "d.xml").write_text("<mujoco/>")
    path = include(tmp_path / "project", "../shared/d.xml")
    assert read_mjcf(path, root=tmp_path / "project").files[-1].name == "d.xml"
    with pytest.raises(MjcfError, match="leads out"):
        read_mjcf(path)  # held to its own folder by default


def test_include_twice_and_cycles(tmp_path: Path) -> None:
    folder = tmp_path / "model"
    folder.mkdir()
    (folder / "a.xml").write_text('<mujoco><include file="b.xml"/></mujoco>')
    (folder / "b.xml").write_text('<mujoco><include file="a.xml"/></mujoco>')
    with pytest.raises(MjcfError, match=r"a\.xml is included twice"):
        read_mjcf(write(folder, top='<include file="a.xml"/>'))


def test_include_of_itself(tmp_path: Path) -> None:
    with pytest.raises(MjcfError, match="included twice"):
        read_mjcf(include(tmp_path, "arm.xml"))


def test_include_missing(tmp_path: Path) -> None:
    with pytest.raises(MjcfError, match=r"gone\.xml: no such file"):
        read_mjcf(include(tmp_path, "gone.xml"))


def test_include_of_a_fifo_never_blocks(tmp_path: Path) -> None:
    path = include(tmp_path, "pipe.xml")
    os.mkfifo(tmp_path / "model" / "pipe.xml")
    with pytest.raises(MjcfError, match="FIFO"):
        read_mjcf(path)


def test_main_file_a_fifo(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "pipe.xml")
    with pytest.raises(MjcfError, match="FIFO"):
        read_mjcf(tmp_path / "pipe.xml")


def test_include_not_mujoco(tmp_path: Path) -> None:
    (tmp_path / "model").mkdir()
    (tmp_path / "model" / "r.xml").write_text("<robot/>")
    with pytest.raises(MjcfError, match=r"r\.xml: its root element is <robot>"):
        read_mjcf(include(tmp_path, "r.xml"))


def test_too_many_includes(tmp_path: Path) -> None:
    folder = tmp_path / "model"
    folder.mkdir()
    for i in range(MAX_INCLUDES + 1):
        (folder / f"i{i}.xml").write_text("<mujoco/>")
    top = "".join(f'<include file="i{i}.xml"/>' for i in range(MAX_INCLUDES + 1))
    with pytest.raises(MjcfError, match=f"more than {MAX_INCLUDES} included files"):
        read_mjcf(write(folder, top=top))


def test_huge_file_refused_unread(tmp_path: Path) -> None:
    path = tmp_path / "huge.xml"
    with path.open("wb") as f:
        f.truncate(MAX_MJCF_BYTES + 1)  # sparse: refused by its size, never read
    with pytest.raises(MjcfError, match="file too large"):
        read_mjcf(path)


def test_includes_share_one_byte_budget(tmp_path: Path) -> None:
    folder = tmp_path / "model"
    folder.mkdir()
    with (folder / "big.xml").open("wb") as f:
        f.truncate(MAX_MJCF_BYTES - 100)  # alone under the limit, with the main file over it
    with pytest.raises(MjcfError, match="all files of one MJCF together"):
        read_mjcf(write(folder, top='<include file="big.xml"/>'))


def test_deep_nesting(tmp_path: Path) -> None:
    depth = MAX_XML_DEPTH + 1
    inside = "".join(f'<body name="n{i}">' for i in range(depth)) + "</body>" * depth
    with pytest.raises(MjcfError, match=f"deeper than {MAX_XML_DEPTH} levels"):
        read_mjcf(write(tmp_path, inside=inside))


def test_deep_nesting_across_includes(tmp_path: Path) -> None:
    half = MAX_XML_DEPTH // 2 + 2
    folder = tmp_path / "model"
    folder.mkdir()
    nested = "".join(f'<body name="m{i}">' for i in range(half)) + "</body>" * half
    (folder / "deep.xml").write_text(f"<mujoco><worldbody>{nested}</worldbody></mujoco>")
    inside = "".join(f'<body name="n{i}">' for i in range(half))
    inside += '<include file="deep.xml"/>' + "</body>" * half
    with pytest.raises(MjcfError, match="deeper than"):
        read_mjcf(write(folder, inside=inside))


def test_too_many_elements(tmp_path: Path) -> None:
    inside = '<site size="0.01"/>' * (MAX_XML_ELEMENTS + 1)
    with pytest.raises(MjcfError, match=f"more than {MAX_XML_ELEMENTS} elements"):
        read_mjcf(write(tmp_path, inside=inside))


def test_entity_expansion_refused(tmp_path: Path) -> None:
    path = tmp_path / "lol.xml"
    path.write_text('<?xml version="1.0"?><!DOCTYPE m [<!ENTITY a "aaaa">]><mujoco>&a;</mujoco>')
    with pytest.raises(MjcfError, match=r"lol\.xml: line 1: has a DTD"):
        read_mjcf(path)


def test_external_entity_refused(tmp_path: Path) -> None:
    path = tmp_path / "xxe.xml"
    path.write_text('<!DOCTYPE m [<!ENTITY x SYSTEM "file:///etc/passwd">]><mujoco>&x;</mujoco>')
    with pytest.raises(MjcfError, match="DTD"):
        read_mjcf(path)


def test_not_xml(tmp_path: Path) -> None:
    path = tmp_path / "bad.xml"
    path.write_text("<mujoco><worldbody></mujoco>")
    with pytest.raises(MjcfError, match="not valid XML"):
        read_mjcf(path)


def test_urdf_refused(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text('<robot name="r"><link name="a"/></robot>')
    with pytest.raises(MjcfError, match=r"not an MJCF \(a URDF is read as one, through \[urdf\]\)"):
        read_mjcf(path)


def test_namespaced_element_refused(tmp_path: Path) -> None:
    inside = '<x:body xmlns:x="http://www.w3.org/2001/XInclude"/>'
    with pytest.raises(MjcfError, match="XML namespace"):
        read_mjcf(write(tmp_path, inside=inside))


@pytest.mark.parametrize(
    ("inside", "why"),
    [
        ('<attach model="other" body="b"/>', "attaches a model asset"),
        ('<replicate count="1000000"><body/></replicate>', "repeats bodies"),
        ('<composite type="grid" count="9 9 1"/>', "builds bodies by rule"),
        ('<flexcomp type="mesh" file="/etc/passwd"/>', "deformable body"),
        ("<bogus/>", "not an MJCF body element fkcheck knows"),
    ],
)
def test_bodies_from_elsewhere_refused(tmp_path: Path, inside: str, why: str) -> None:
    with pytest.raises(MjcfError, match=why):
        read_mjcf(write(tmp_path, inside=inside))


def test_unknown_section_refused(tmp_path: Path) -> None:
    with pytest.raises(MjcfError, match="<worldbdy> is not a section of an MJCF; sections are: "):
        read_mjcf(write(tmp_path, top="<worldbdy/>"))


MESHES = """
  <compiler meshdir="/etc" assetdir="/root" texturedir="/proc/self"/>
  <asset>
    <mesh name="gone" file="does_not_exist.stl"/>
    <mesh name="shadow" file="/etc/shadow"/>
    <mesh name="up" file="../../../../etc/passwd"/>
    <texture name="t" type="2d" file="/dev/zero"/>
    <hfield name="h" file="/dev/random"/>
    <material name="m" texture="t"/>
    <model name="other" file="/etc/hostname"/>
  </asset>
  <extension><plugin plugin="mujoco.sdf.torus"/></extension>
  <default><geom type="mesh" mesh="gone"/><site material="m"/></default>
"""
GEOMS = """
      <geom type="mesh" mesh="shadow"/><geom type="hfield" hfield="h"/>
      <inertial mass="1" pos="0 0 0" diaginertia="1 1 1"/>
      <site name="painted" material="m"/>
      <camera name="c"/><light name="l"/>
      <plugin plugin="mujoco.pid"/>
"""


def test_meshes_textures_and_plugins_never_opened(tmp_path: Path) -> None:
    """Nonexistent and sensitive files, devices: MuJoCo would fail or block on any of them.

    It compiles, so it opened none; the text every reader gets names none of them.
    """
    desc = read_mjcf(write(tmp_path, top=MESHES, inside=GEOMS))
    for absent in (
        "mesh",
        "texture",
        "hfield",
        "file=",
        "/etc",
        "/dev",
        "plugin",
        "material",
        "geom",
        "inertial",
        "camera",
        "light",
        "meshdir",
    ):
        assert absent not in desc.text, absent
    assert desc.files == ((tmp_path / "arm.xml").resolve(),)
    assert desc.frames == ("world", "b1", "painted", "tip")
    assert mujoco_poses(desc, ["tip"], [[0.5]]).shape == (1, 1, 4, 4)


def test_screened_text_is_all_a_reader_gets(tmp_path: Path) -> None:
    screened = screen_mjcf(
        write(
            tmp_path,
            top='<option timestep="1"/><compiler angle="radian" '
            'eulerseq="zyx" autolimits="true" meshdir="x"/>',
        )
    )
    assert '<compiler angle="radian" eulerseq="zyx" autolimits="true" />' in screened.text
    assert "option" not in screened.text


def test_mujoco_refusal_is_one_line(tmp_path: Path) -> None:
    path = write(tmp_path, inside='<body name="b2"><joint name="j2" axis="0 0 0"/></body>')
    with pytest.raises(
        MjcfError,
        match=r"arm\.xml: MuJoCo [\d.]+ cannot compile it: Error: axis "
        r"too small",
    ) as info:
        read_mjcf(path)
    assert "\n" not in str(info.value)


def test_a_name_two_frames_share(tmp_path: Path) -> None:
    with pytest.raises(MjcfError, match="'b1' names two frames"):
        read_mjcf(write(tmp_path, inside='<site name="b1"/>'))


def test_symlink_loop_in_an_include(tmp_path: Path) -> None:
    path = include(tmp_path, "loop.xml")
    os.symlink("loop.xml", tmp_path / "model" / "loop.xml")
    with pytest.raises(MjcfError, match="loop"):
        read_mjcf(path)


def test_include_in_worldbody_brings_bodies(tmp_path: Path) -> None:
    folder = tmp_path / "model"
    folder.mkdir()
    (folder / "hand.xml").write_text(
        '<mujoco><body name="hand" pos="0 0 0.1"><geom type="mesh" mesh="x"/>'
        '<site name="grip"/></body></mujoco>'
    )
    desc = read_mjcf(write(folder, inside='<include file="hand.xml"/>'))
    assert desc.frames == ("world", "b1", "hand", "tip", "grip")
    assert desc.kinematics.joints["hand:fixed"].parent == "b1"
    assert "geom" not in desc.text
