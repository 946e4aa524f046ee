"""OPW parameters derived from DH tables (fkcheck.ik.opw_params).

The published sets the bundled OPW arms must reproduce:

* KUKA KR 6 R700 sixx: ROS-Industrial's kuka_experimental
  ``kuka_kr6_support/config/opw_kinematics_kr6r700sixx.yaml`` at commit
  e78bbd15edb2b39c9053ff3b963ef2947e10a531 (the same numbers as opw_kinematics'
  ``makeKukaKR6_R700_sixx``);
* ABB IRB 2400/10: opw_kinematics' ``makeIrb2400_10``
  (``include/opw_kinematics/opw_parameters_examples.h`` at
  8a32bda8197c50bd0d60dfe1d12ecb4c13111b72), which its tests hold against the IRB
  2400's ikfast solver.

Each model's table is written from its URDF's dimensions, not from the set.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from fkcheck.core.geometry import invert
from fkcheck.ik.opw_params import (
    NotOpwShaped,
    OpwParameters,
    derive_opw,
    opw_fk,
    opw_fk_deviation,
)
from fkcheck.model.convert import convert_model
from fkcheck.model.read import load_model
from fkcheck.model.types import Offset

pytest.importorskip("py_opw_kinematics")

#: The published KR 6 R700 sixx set (kuka_experimental, see the module's docstring).
KR6_PUBLISHED = {
    "a1": 0.025, "a2": -0.035, "b": 0.000, "c1": 0.400, "c2": 0.315, "c3": 0.365, "c4": 0.080,
}  # fmt: skip
KR6_OFFSETS = (0.0, -1.57079632679, 0.0, 0.0, 0.0, 0.0)
KR6_SIGNS = (-1, 1, 1, -1, 1, -1)
#: Each bundled OPW arm's published set: lengths, offsets, sign corrections.
PUBLISHED = {
    "kr6r700sixx": (KR6_PUBLISHED, KR6_OFFSETS, KR6_SIGNS),
    "irb2400": (
        {"a1": 0.100, "a2": -0.135, "b": 0.000, "c1": 0.615, "c2": 0.705, "c3": 0.755,
         "c4": 0.085},
        (0.0, 0.0, -math.pi / 2.0, 0.0, 0.0, 0.0),
        (1, 1, 1, 1, 1, 1),
    ),
}  # fmt: skip
#: The lengths come from the table's millimetres through sines and cosines of exact
#: quarter turns: round-off (1e-16) is all that may separate them from the published.
LENGTH_TOL_M = 1e-12
#: The published offset -1.57079632679 is -π/2 to 11 decimals.
PUBLISHED_ANGLE_TOL_RAD = 1e-11
#: The published offset's 5e-12 rad moves a point 0.7 m out by 4e-12 m.
PUBLISHED_POSE_M = 1e-11
#: OPW's FK and the table's compute one geometry in double precision over a reach of
#: about 2 m: they agree to ~1e-15; 1e-12 leaves round-off room and no more.
FK_AGREEMENT_M = 1e-12
FK_AGREEMENT_RAD = 1e-12
#: Smallest disagreement a wrong parameter must show (it is 1e-4 m or 0.01 rad off).
WRONG_SHOWS = 1e-6


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_the_published_parameter_set_comes_out_number_by_number(name):
    lengths, offsets, signs = PUBLISHED[name]
    p = derive_opw(load_model(name))
    for key, value in lengths.items():
        assert p.lengths[key] == pytest.approx(value, abs=LENGTH_TOL_M), key
    assert p.offsets == pytest.approx(offsets, abs=PUBLISHED_ANGLE_TOL_RAD)
    assert p.sign_corrections == signs
    assert p.base_is_world
    assert p.tool_is_tcp


@pytest.mark.parametrize("name", ["kr6r700sixx", "irb2400", "puma560"])
def test_opw_fk_matches_the_table(name):
    model = load_model(name)
    deviation = opw_fk_deviation(model, derive_opw(model), samples=2000, seed=3)
    assert deviation.samples > 2000  # the structured configurations besides
    assert deviation.max_position_m < FK_AGREEMENT_M
    assert deviation.max_angle_rad < FK_AGREEMENT_RAD


def test_puma560_is_opw_shaped_with_its_shoulder_offset_as_b():
    p = derive_opw(load_model("puma560"))
    # Corke's PUMA: d3 = 0.15005 sideways, a3 = 0.0203 elbow offset, d4 = 0.4318 forearm.
    assert (p.a1, p.b, p.c1, p.c2, p.c3, p.c4) == pytest.approx(
        (0.0, 0.15005, 0.67183, 0.4318, 0.4318, 0.0), abs=LENGTH_TOL_M
    )
    assert abs(p.a2) == pytest.approx(0.0203, abs=LENGTH_TOL_M)


IDENTITY = Offset()


def _shifted(model, base=IDENTITY, tool=IDENTITY):
    return replace(model, base=base, tool=tool)


@pytest.mark.parametrize(
    ("base", "tool"),
    [
        (Offset((0.3, -0.2, 0.5), (0.1, -0.2, 0.7)), Offset()),
        (Offset(), Offset((0.01, 0.02, 0.15), (0.3, 0.0, -1.0))),
        (Offset((0.0, 0.0, 1.2), (math.pi, 0.0, 0.0)), Offset((0.0, 0.0, 0.1))),  # hanging
    ],
    ids=["base-moved", "tool-off-axis", "ceiling"],
)
def test_base_and_tool_that_are_not_opws_frames_are_carried(base, tool):
    model = _shifted(load_model("kr6r700sixx"), base, tool)
    p = derive_opw(model)
    deviation = opw_fk_deviation(model, p, samples=500, seed=1)
    assert deviation.max_position_m < FK_AGREEMENT_M
    assert deviation.max_angle_rad < FK_AGREEMENT_RAD
    # The arm itself is the same: its lengths do not change with where it stands (a
    # hanging one, seen with the world's z, is mirrored: a1 and a2 change sign).
    kr6 = derive_opw(load_model("kr6r700sixx"))
    for name in ("a1", "a2", "b", "c2", "c3"):
        assert abs(p.lengths[name]) == pytest.approx(abs(kr6.lengths[name]), abs=LENGTH_TOL_M)


def test_a_tool_along_axis_6_lengthens_c4_instead_of_an_adapter():
    model = _shifted(load_model("kr6r700sixx"), tool=Offset((0.0, 0.0, 0.12)))
    p = derive_opw(model)
    assert p.tool_is_tcp
    assert p.c4 == pytest.approx(0.080 + 0.12, abs=LENGTH_TOL_M)


def test_a_hanging_arm_keeps_the_worlds_z():
    model = _shifted(load_model("kr6r700sixx"), Offset((0.0, 0.0, 2.0), (math.pi, 0.0, 0.0)))
    p = derive_opw(model)
    assert p.base_is_world  # axis 1 is the world's z axis, pointing down: a sign, no adapter
    assert p.sign_corrections[0] == 1  # A1 turns about base_link's -z, which now points up
    assert p.c1 == pytest.approx(2.0 - 0.4, abs=LENGTH_TOL_M)


def test_modified_dh_gives_the_same_parameters():
    standard = load_model("kr6r700sixx")
    modified = convert_model(standard, "modified")
    assert modified.convention == "modified"
    p, m = derive_opw(standard), derive_opw(modified)
    assert m.lengths == pytest.approx(p.lengths, abs=LENGTH_TOL_M)
    assert m.offsets == pytest.approx(p.offsets, abs=LENGTH_TOL_M)
    assert m.sign_corrections == p.sign_corrections
    deviation = opw_fk_deviation(modified, m, samples=500, seed=2)
    assert deviation.max_position_m < FK_AGREEMENT_M


def _wrong(p: OpwParameters, field: str, index: int | None) -> OpwParameters:
    if field == "sign_corrections":
        signs = list(p.sign_corrections)
        signs[index] = -signs[index]
        return replace(p, sign_corrections=tuple(signs))
    if field == "offsets":
        offsets = list(p.offsets)
        offsets[index] += 0.01
        return replace(p, offsets=tuple(offsets))
    return replace(p, **{field: getattr(p, field) + 1e-4})


WRONG = [
    *[(name, None) for name in ("a1", "a2", "b", "c1", "c2", "c3", "c4")],
    *[("offsets", i) for i in range(6)],
    *[("sign_corrections", i) for i in range(6)],
]


@pytest.mark.parametrize(("field", "index"), WRONG, ids=[f"{f}-{i}" for f, i in WRONG])
def test_the_fk_comparison_sees_every_wrong_parameter(field, index):
    """What would have to be wrong for the comparison to stay green: any one number."""
    model = load_model("kr6r700sixx")
    wrong = _wrong(derive_opw(model), field, index)
    deviation = opw_fk_deviation(model, wrong, samples=200, seed=0)
    assert max(deviation.max_position_m, deviation.max_angle_rad) > WRONG_SHOWS


def test_opw_fk_places_base_and_tool():
    model = _shifted(load_model("kr6r700sixx"), Offset((1.0, 2.0, 0.0), (0.0, 0.0, 0.5)))
    p = derive_opw(model)
    q = np.radians([[10.0, -80.0, 70.0, 20.0, 30.0, 40.0]])
    bare = replace(p, world_T_base=np.eye(4), flange_T_tcp=np.eye(4))
    # OPW's own frames: the library's pose is the model's with the adapters taken off.
    expected = invert(p.world_T_base) @ model.fk(q[0]) @ invert(p.flange_T_tcp)
    np.testing.assert_allclose(opw_fk(bare, q)[0], expected, atol=FK_AGREEMENT_M)


def _edited(name: str, index: int, **values):
    model = load_model(name)
    joints = list(model.joints)
    joints[index] = replace(joints[index], **values)
    return replace(model, joints=tuple(joints))


@pytest.mark.parametrize(
    ("model", "match"),
    [
        (load_model("ur5e"), r"axes 4, 5, 6 do not meet in one point.*0\.0997 m.*"
         r"joint\[4\]\.d \(wrist_2\) = 0\.0997 m"),
        (load_model("ur5"), r"axes 4, 5, 6 do not meet in one point.*joint\[4\]\.d \(wrist_2\) = "
         r"0\.09465 m"),
        (convert_model(load_model("ur5e"), "modified"), r"axes 4, 5, 6 do not meet in one "
         r"point.*joint\[4\]\.d \(wrist_2\) = 0\.0997 m"),
        (load_model("panda"), r"OPW arms have 6 joints, this table has 7"),
        (load_model("stanford"), r"joint\[2\] \(j3\) is prismatic"),
        (load_model("planar2"), r"OPW arms have 6 joints, this table has 2"),
        (_edited("kr6r700sixx", 0, alpha=math.radians(-80)), r"axes 1 and 2 are not perpendicular "
         r"\(at 80° to each other\)"),
        (_edited("kr6r700sixx", 1, alpha=math.radians(5)), r"axes 2 and 3 are not parallel "
         r"\(at 5° to each other\)"),
        (_edited("kr6r700sixx", 2, alpha=math.radians(80)), r"axis 4 is not perpendicular to "
         r"axes 2 and 3 \(at 80° to them\)"),
        (_edited("kr6r700sixx", 3, a=0.01), r"axes 4 and 5 do not meet \(0\.01 m apart\)"),
        (_edited("kr6r700sixx", 4, a=0.002), r"axes 5 and 6 do not meet \(0\.002 m apart\)"),
        (_edited("kr6r700sixx", 4, alpha=math.radians(60)), r"axes 5 and 6 of the wrist are not "
         r"perpendicular \(at 60° to each other\)"),
        (_edited("kr6r700sixx", 1, a=0.0), r"axes 2 and 3 are the same line"),
    ],
    ids=["ur5e", "ur5", "ur5e-modified", "panda", "stanford", "planar2", "axes-1-2", "axes-2-3",
         "axis-4", "wrist-4-5", "wrist-5-6", "wrist-angle", "no-upper-arm"],
)  # fmt: skip
def test_a_table_that_is_not_opw_shaped_is_refused_with_the_condition(model, match):
    with pytest.raises(NotOpwShaped, match=match) as info:
        derive_opw(model)
    assert str(info.value).startswith(f"model {model.name}: not OPW-shaped: ")


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_the_table_is_the_published_arm_through_opws_own_fk(name):
    """The published parameters, not derived ones, in py-opw-kinematics: the table's FK.

    This checks the hand-written table against a reference it shares nothing with
    (the published parameter set and the library's closed-form FK).
    """
    model = load_model(name)
    lengths, offsets, signs = PUBLISHED[name]
    # KUKA's YAML writes -π/2 as -1.57079632679, 5e-12 short: the poses agree to that.
    published = OpwParameters(**lengths, offsets=offsets, sign_corrections=signs)
    q = np.radians(np.random.default_rng(4).uniform(-170.0, 170.0, (500, 6)))
    deviation_m = np.abs(opw_fk(published, q)[:, :3, 3] - model.fk(q)[:, :3, 3]).max()
    deviation_r = np.abs(opw_fk(published, q)[:, :3, :3] - model.fk(q)[:, :3, :3]).max()
    assert deviation_m < PUBLISHED_POSE_M
    assert deviation_r < PUBLISHED_ANGLE_TOL_RAD


def _random_table(rng, index):
    """A random six-joint table with a spherical wrist's zeros, maybe OPW-shaped or not."""
    from fkcheck.model.types import Joint, Model

    convention = str(rng.choice(["standard", "modified"]))
    joints = []
    for i in range(6):
        twists = [0, 90, -90, 180] if i < 3 or i == 5 else [90, -90]
        arm = i < 3 if convention == "standard" else i < 4
        joints.append(
            Joint(
                name=f"j{i + 1}",
                a=float(rng.choice([0.0, rng.uniform(-0.5, 0.5)])) if arm else 0.0,
                alpha=math.radians(float(rng.choice(twists))),
                d=float(rng.choice([0.0, rng.uniform(-0.5, 0.5)])) if i != 4 else 0.0,
                theta=float(rng.choice([0.0, math.pi / 2, -math.pi / 2, rng.uniform(-3, 3)])),
                flip=bool(rng.random() < 0.3),
                limits=(-3.0, 3.0),
            )
        )
    base, tool = IDENTITY, IDENTITY
    if rng.random() < 0.3:
        base = Offset(tuple(rng.uniform(-1, 1, 3)), tuple(rng.uniform(-3, 3, 3)))
    if rng.random() < 0.3:
        tool = Offset(tuple(rng.uniform(-0.2, 0.2, 3)), tuple(rng.uniform(-3, 3, 3)))
    return Model(f"random{index}", convention, tuple(joints), base=base, tool=tool)


def test_random_tables_are_derived_right_or_refused():
    """Random tables (standard and modified, flips, θ offsets, base and tool): each one
    is refused with NotOpwShaped, or its parameters give the table's FK."""
    rng = np.random.default_rng(2024)
    derived = 0
    for index in range(600):
        model = _random_table(rng, index)
        try:
            params = derive_opw(model)
        except NotOpwShaped:
            continue
        derived += 1
        deviation = opw_fk_deviation(model, params, samples=32, seed=index)
        assert deviation.max_position_m < FK_AGREEMENT_M, model.joints
        assert deviation.max_angle_rad < FK_AGREEMENT_RAD, model.joints
    assert derived >= 20  # enough OPW arms among them (29 with this seed)
