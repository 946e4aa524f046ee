"""Each MJCF trap, held by a pose computed by hand from MuJoCo's documented semantics.

One two-joint arm, ``world → b1 (hinge j1 about z) → b2 (hinge j2 about y) → tip``,
varied one trap at a time. Every test checks MuJoCo's reader, Pinocchio's reader
and fkcheck's tree against the hand pose, and checks that a reader ignoring the
trap would be off by more than :data:`TEETH` — so the test could fail.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio
import pytest

from fkcheck.mjcf import compare_readers, mujoco_poses, pinocchio_poses, read_mjcf
from tests.mjcf.hand import T, deg, quat, rot, rx, ry, rz, tr

#: Both readers and the tree compose ~6 float64 transforms of ~1 m: 1e-12 is round-off.
EXACT = 1e-12
#: How far a reader ignoring a trap lands at least (it lands centimetres to metres off).
TEETH = 0.01
I4 = np.eye(4)

Q = np.array([0.7, -0.4])

ARM = """<mujoco model="arm">
  <compiler {compiler}/>
  {defaults}
  <worldbody>
    <body name="b1" pos="0 0 0.3">
      <joint name="j1" axis="0 0 1"/>
      {open_frame}<body name="b2" pos="0.4 0 0" {b2}>
        <joint name="j2" {j2}/>
        <site name="tip" pos="0.25 0 0" {tip}/>
      </body>{close_frame}
    </body>
  </worldbody>
</mujoco>
"""


def arm(
    tmp_path: Path,
    *,
    compiler: str = "",
    defaults: str = "",
    b2: str = "",
    j2: str = 'axis="0 1 0"',
    tip: str = "",
    frame: str = "",
) -> Path:
    path = tmp_path / "arm.xml"
    path.write_text(
        ARM.format(
            compiler=compiler,
            defaults=defaults,
            b2=b2,
            j2=j2,
            tip=tip,
            open_frame=f"<frame {frame}>" if frame else "",
            close_frame="</frame>" if frame else "",
        )
    )
    return path


def hand_tip(q: np.ndarray, *, b2=I4, j2=ry, tip=I4, frame=I4) -> np.ndarray:
    """world_T_tip: world → b1 → (frame) → b2 → tip, as MuJoCo's reference describes it."""
    return T(tr(0, 0, 0.3), rz(q[0]), frame, tr(0.4, 0, 0), b2, j2(q[1]), tr(0.25, 0, 0), tip)


def assert_all_readers(
    path: Path, expected: np.ndarray, ignoring: np.ndarray, *, pinocchio_bug: str = ""
) -> None:
    """MuJoCo, Pinocchio and the tree give ``expected``; ``ignoring`` is off by more than TEETH.

    ``pinocchio_bug``: Pinocchio 4.1.0 is measured wrong here; the comparison
    must then name it (with its version), and only it.
    """
    assert np.abs(expected - ignoring).max() > TEETH, "the trap would not show"
    desc = read_mjcf(path)
    got = mujoco_poses(desc, ["tip"], Q)[0, 0]
    np.testing.assert_allclose(got, expected, atol=EXACT, err_msg="mujoco-mjcf")
    held = compare_readers(
        desc,
        ["tip"],
        Q,
        reference=("the hand pose", expected[None, None]),
        tol_pos_m=EXACT,
        tol_rot_rad=EXACT,
    )
    if pinocchio_bug and pinocchio.__version__ == "4.1.0":
        assert held.disagreeing == ("pinocchio-mjcf",), held.summary()
        assert "pinocchio-mjcf (Pinocchio 4.1.0)" in held.summary()
    elif pinocchio_bug:  # another Pinocchio may have fixed it; MuJoCo must still be right
        assert "mujoco-mjcf" not in held.disagreeing, held.summary()
    else:
        assert held.disagreeing == (), held.summary()
    chain = desc.kinematics.chain("world", "tip")
    tree = desc.kinematics.chain_poses(chain, Q.reshape(1, -1))[0, -1]
    np.testing.assert_allclose(tree, expected, atol=EXACT, err_msg="fkcheck's tree")


def test_angles_are_degrees_by_default(tmp_path: Path) -> None:
    path = arm(tmp_path, b2='euler="0 0 30"')
    assert_all_readers(path, hand_tip(Q, b2=rz(deg(30))), hand_tip(Q, b2=rz(30.0)))


def test_angle_radian(tmp_path: Path) -> None:
    path = arm(tmp_path, compiler='angle="radian"', b2='euler="0 0 0.5"')
    assert_all_readers(path, hand_tip(Q, b2=rz(0.5)), hand_tip(Q, b2=rz(deg(0.5))))


def test_joint_range_in_degrees_by_default(tmp_path: Path) -> None:
    path = arm(tmp_path, j2='axis="0 1 0" range="-90 45"')
    limits = read_mjcf(path).kinematics.joints["j2"].limits
    assert limits == pytest.approx((deg(-90), deg(45)), abs=1e-15)


def test_eulerseq_fixed_axes(tmp_path: Path) -> None:
    # "ZYX": upper case, fixed axes: about Z by 30°, then fixed Y by 20°, then fixed X by 10°.
    path = arm(tmp_path, compiler='eulerseq="ZYX"', b2='euler="30 20 10"')
    expected = hand_tip(Q, b2=T(rx(deg(10)), ry(deg(20)), rz(deg(30))))
    default_xyz = hand_tip(Q, b2=T(rx(deg(30)), ry(deg(20)), rz(deg(10))))  # moving x, y, z
    assert_all_readers(path, expected, default_xyz, pinocchio_bug="fixed-axis eulerseq")


def test_eulerseq_moving_axes(tmp_path: Path) -> None:
    path = arm(tmp_path, compiler='eulerseq="zxy"', b2='euler="30 20 10"')
    expected = hand_tip(Q, b2=T(rz(deg(30)), rx(deg(20)), ry(deg(10))))
    assert_all_readers(path, expected, hand_tip(Q, b2=T(rx(deg(30)), ry(deg(20)), rz(deg(10)))))


def test_quat_is_w_x_y_z_and_normalised(tmp_path: Path) -> None:
    path = arm(tmp_path, b2='quat="0.9 0.1 0.3 0.2"')
    xyzw = quat(0.2, 0.9, 0.1, 0.3)  # the same four numbers read x y z w
    assert_all_readers(path, hand_tip(Q, b2=quat(0.9, 0.1, 0.3, 0.2)), hand_tip(Q, b2=xyzw))


def test_axisangle_degrees_and_unnormalised_axis(tmp_path: Path) -> None:
    path = arm(tmp_path, b2='axisangle="1 1 0 60"')
    expected = hand_tip(Q, b2=rot((1, 1, 0), deg(60)))
    assert_all_readers(
        path, expected, hand_tip(Q, b2=rot((1, 1, 0), 60.0)), pinocchio_bug="unnormalised axis"
    )


def test_xyaxes_orthogonalised(tmp_path: Path) -> None:
    # x = (0, 1, 0); y = (-1, 0.2, 0) loses its part along x: (-1, 0, 0); z = x × y = (0, 0, 1).
    path = arm(tmp_path, b2='xyaxes="0 1 0 -1 0.2 0"')
    assert_all_readers(path, hand_tip(Q, b2=rz(deg(90))), hand_tip(Q))


def test_zaxis_smallest_rotation(tmp_path: Path) -> None:
    # The smallest rotation taking (0, 0, 1) to (1, 0, 1)/√2: 45° about y.
    path = arm(tmp_path, b2='zaxis="1 0 1"')
    assert_all_readers(path, hand_tip(Q, b2=ry(deg(45))), hand_tip(Q))


def test_joint_ref_shifts_the_zero(tmp_path: Path) -> None:
    # At qpos = ref the body is where the MJCF puts it: the hinge turns by qpos − ref.
    path = arm(tmp_path, j2='axis="0 1 0" ref="30"')
    expected = hand_tip(Q, j2=lambda a: ry(a - deg(30)))
    assert_all_readers(path, expected, hand_tip(Q))
    assert read_mjcf(path).qpos0 == pytest.approx((0.0, deg(30)), abs=1e-15)


def test_slide_ref(tmp_path: Path) -> None:
    path = arm(tmp_path, j2='type="slide" axis="1 0 0" ref="0.05"')
    expected = hand_tip(Q, j2=lambda s: tr(s - 0.05, 0, 0))
    assert_all_readers(path, expected, hand_tip(Q, j2=lambda s: tr(s, 0, 0)))


def test_joint_anchor_is_where_it_turns(tmp_path: Path) -> None:
    path = arm(tmp_path, j2='axis="0 1 0" pos="0.1 0 0.05"')
    expected = hand_tip(Q, j2=lambda a: T(tr(0.1, 0, 0.05), ry(a), tr(-0.1, 0, -0.05)))
    assert_all_readers(path, expected, hand_tip(Q))
    kin = read_mjcf(path).kinematics
    assert kin.joints["j2"].child == "b2:j2"  # the intermediate frame at the anchor
    assert kin.joints["j2:body"].parent == "b2:j2"


DEFAULTS = '<default><default class="arm"><joint axis="1 0 0"/></default></default>'


def test_default_class_on_the_joint(tmp_path: Path) -> None:
    path = arm(tmp_path, defaults=DEFAULTS, j2='class="arm"')
    assert_all_readers(path, hand_tip(Q, j2=lambda a: rx(a)), hand_tip(Q, j2=lambda a: rz(a)))


def test_childclass(tmp_path: Path) -> None:
    path = arm(tmp_path, defaults=DEFAULTS, b2='childclass="arm"', j2="")
    assert_all_readers(path, hand_tip(Q, j2=lambda a: rx(a)), hand_tip(Q, j2=lambda a: rz(a)))


def test_include_brings_the_defaults(tmp_path: Path) -> None:
    (tmp_path / "defaults.xml").write_text(f"<mujoco>{DEFAULTS}</mujoco>")
    path = arm(tmp_path, defaults='<include file="defaults.xml"/>', j2='class="arm"')
    assert_all_readers(path, hand_tip(Q, j2=lambda a: rx(a)), hand_tip(Q, j2=lambda a: rz(a)))
    desc = read_mjcf(path)
    assert desc.files == (path.resolve(), (tmp_path / "defaults.xml").resolve())
    assert "include" not in desc.text


def test_include_from_a_subfolder(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "defaults.xml").write_text(f"<mujoco>{DEFAULTS}</mujoco>")
    path = arm(tmp_path, defaults='<include file="parts/defaults.xml"/>', j2='class="arm"')
    assert_all_readers(path, hand_tip(Q, j2=lambda a: rx(a)), hand_tip(Q, j2=lambda a: rz(a)))


def test_frame_places_its_children(tmp_path: Path) -> None:
    path = arm(tmp_path, frame='pos="0.1 0 0" euler="0 0 90"')
    expected = hand_tip(Q, frame=T(tr(0.1, 0, 0), rz(deg(90))))
    assert_all_readers(path, expected, hand_tip(Q), pinocchio_bug="<frame> not read")


def test_site_is_a_tool_frame(tmp_path: Path) -> None:
    path = arm(tmp_path, tip='quat="0 1 0 0"')
    assert_all_readers(path, hand_tip(Q, tip=rx(np.pi)), hand_tip(Q))
    desc = read_mjcf(path)
    assert desc.sites == ("tip",)
    assert desc.frames == ("world", "b1", "b2", "tip")


def test_world_is_the_root_and_identity(tmp_path: Path) -> None:
    desc = read_mjcf(arm(tmp_path))
    for reader in (mujoco_poses, pinocchio_poses):
        np.testing.assert_array_equal(reader(desc, ["world"], Q)[0, 0], np.eye(4))
    assert desc.kinematics.root == "world"
    assert desc.joints == ("j1", "j2")


def test_named_joints_choose_the_columns(tmp_path: Path) -> None:
    desc = read_mjcf(arm(tmp_path, j2='axis="0 1 0" ref="30"'))
    q2 = np.array([[-0.4]])
    for reader in (mujoco_poses, pinocchio_poses):
        got = reader(desc, ["tip"], q2, joints=["j2"])[0, 0]  # j1 stays at its qpos0, 0
        np.testing.assert_allclose(
            got, hand_tip(np.array([0.0, -0.4]), j2=lambda a: ry(a - deg(30))), atol=EXACT
        )


def test_two_joints_in_one_body_each_about_its_anchor(tmp_path: Path) -> None:
    """MuJoCo composes a body's joints in order, each about its own anchor in the body frame."""
    path = tmp_path / "two.xml"
    path.write_text(
        '<mujoco><compiler angle="radian"/><worldbody><body name="b" pos="0 0 0.2">'
        '<joint name="ja" axis="0 0 1" pos="0.1 0 0" ref="0.2"/>'
        '<joint name="jb" axis="1 0 0" pos="0 0.3 0"/>'
        '<site name="tip" pos="0.5 0 0"/></body></worldbody></mujoco>'
    )
    q = np.array([0.9, -0.6])
    expected = T(
        tr(0, 0, 0.2),
        tr(0.1, 0, 0), rz(q[0] - 0.2), tr(-0.1, 0, 0),
        tr(0, 0.3, 0), rx(q[1]), tr(0, -0.3, 0),
        tr(0.5, 0, 0),
    )  # fmt: skip
    desc = read_mjcf(path)
    np.testing.assert_allclose(mujoco_poses(desc, ["tip"], q)[0, 0], expected, atol=EXACT)
    tree = desc.kinematics.chain_poses(desc.kinematics.chain("world", "tip"), q.reshape(1, -1))
    np.testing.assert_allclose(tree[0, -1], expected, atol=EXACT)
    assert [j.name for j in desc.kinematics.chain("world", "tip")] == [
        "ja", "jb", "jb:body", "site:tip",
    ]  # fmt: skip
