"""fkcheck map's logic: joints by behaviour, links at constant offsets, urdf:LINK placement.

Every bundled model with a ``[urdf]`` is covered (the list is read from
``models/``, so arms added later are too): the map must propose exactly the
joints and frames bundled, and a model rebuilt from the proposal must pass the
check against pinocchio-urdf.
"""

from __future__ import annotations

import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import fkcheck.backends.registry as registry
from fkcheck.engine.runner import run_check
from fkcheck.errors import FkcheckError, FrameError
from fkcheck.model.read import bundled_model_paths, load_model, model_from_dict
from fkcheck.model.types import CheckSpec, FrameSpec, Model
from fkcheck.model.write import model_to_toml
from fkcheck.urdf.chain import UrdfKinematics, urdf_kinematics
from fkcheck.urdf.locate import ERD_PREFIX, FKCHECK_PREFIX
from fkcheck.urdf.mapping import MapResult, link_frame, map_model, proposal_toml
from fkcheck.urdf.source import load_urdf
from tests.helpers import ur5_ros1

#: How far a link may stray from a constant offset: UR's ROS 2 kinematics YAML writes
#: π/2 as 1.570796327, 2e-10 rad short, ~1e-9 m and rad over a metre of arm.
SPREAD = 5e-9

#: Every bundled model that names a URDF, read from models/ (new arms are covered).
MAPPED = [name for name, path in bundled_model_paths().items() if load_model(path).urdf]


def _kin(model: Model) -> UrdfKinematics:
    return urdf_kinematics(load_urdf(model))


def _mapped(name: str) -> tuple[Model, MapResult]:
    model = load_model(name)
    assert model.urdf is not None
    xacro = model.urdf.xacro
    result = map_model(model, _kin(model), model.urdf.path,
                       xacro_args=model.urdf.xacro_args if xacro else None,
                       packages=model.urdf.packages)  # fmt: skip
    return model, result


def _recorded_to_differ(model: Model) -> bool:
    """The model file records that its URDF disagrees with the table (not read off a run)."""
    return any(k.applies_to("pinocchio-urdf", "urdf") for k in model.known_differences)


def _passes_pinocchio_urdf(model: Model) -> bool:
    result = run_check(model, [registry.make_backend("pinocchio-urdf")], samples=32, seed=1)
    return result.backends[0].status == "pass"


def test_the_bundled_models_with_a_urdf_are_found():
    assert {"ur3", "ur5", "ur10", "panda"} <= set(MAPPED)


@pytest.mark.parametrize("name", MAPPED)
def test_map_proposes_the_bundled_joints_and_frames(name):
    """The map agrees with the bundled mapping exactly where the bundled model passes."""
    model, result = _mapped(name)
    assert model.urdf is not None
    assert _passes_pinocchio_urdf(model) != _recorded_to_differ(model)
    if _recorded_to_differ(model):
        # A recorded disagreement between the vendor's table and the URDF: the map
        # must not paper over it, and must say how near the nearest link came, or
        # name the number (Jaco2's d4, 0.05 mm: its d6 is the tip frame's business).
        assert not result.complete
        text = proposal_toml(result)
        assert "NO " in text or (result.edits.values and "differs)" in text)
        return
    assert result.complete
    assert tuple(j.urdf for j in result.joints) == model.urdf.joints
    assert not any(j.flipped for j in result.joints)
    proposed = {p.spec.name: p for p in result.frames}
    kin = _kin(model)
    for spec in model.frames.values():
        if spec.urdf is None or spec.urdf not in kin.links:
            continue
        got = proposed[spec.name]  # declared frames keep their names
        assert got.fit is not None
        assert got.spec.urdf == spec.urdf
        assert got.spec.dh == spec.dh
        np.testing.assert_allclose(got.spec.offset.matrix, spec.offset.matrix, atol=1e-9)
        # UR's ROS 2 YAML writes π/2 as 1.570796327 (2e-10 rad short): ~1e-9 over the arm.
        assert got.fit.spread_m <= SPREAD
        assert got.fit.spread_rad <= SPREAD
    # Both ends have a link (the bundled check's frames included).
    assert any(p.fit is not None and p.spec.dh == 0 for p in result.frames)
    assert any(p.fit is not None and p.spec.dh in (model.dof, "tcp") for p in result.frames)


def _rebuilt(model: Model, result: MapResult, tmp_path: Path) -> Model:
    """The model's table (and poses, tool, check) with the map's block instead of its own."""
    builtin = {k: v for k, v in model.frames.items() if k in ("world", "tcp") and v.urdf is None}
    table = model_to_toml(replace(model, urdf=None, frames=builtin))
    text = table + "\n" + proposal_toml(result)
    path = tmp_path / f"{model.name}_mapped.toml"
    path.write_text(text, encoding="utf-8")
    return model_from_dict(tomllib.loads(text), path)


@pytest.mark.parametrize("name", MAPPED)
def test_check_passes_on_a_model_rebuilt_from_the_map(name, tmp_path):
    model, result = _mapped(name)
    assert result.complete != _recorded_to_differ(model)  # see the test above
    if not result.complete:
        return
    assert model.urdf is not None
    assert model.urdf.path.startswith((ERD_PREFIX, FKCHECK_PREFIX))
    rebuilt = _rebuilt(model, result, tmp_path)
    assert rebuilt.urdf == model.urdf
    assert _passes_pinocchio_urdf(rebuilt)
    for p in result.frames:  # every proposed link, at both ends
        if p.fit is not None:
            checked = run_check(
                rebuilt,
                [registry.make_backend("pinocchio-urdf")],
                samples=16,
                frame_from=rebuilt.check.frame_from,
                frame_to=p.spec.name,
            )
            assert checked.backends[0].status == "pass", p.spec.name


def test_names_are_ranked_by_how_common_they_are():
    model = ur5_ros1()  # ROS 1's ur5_robot.urdf: base, base_link, world; tool0, ee_link
    result = map_model(model, _kin(model), "ur5_robot.urdf")
    at_base = [p.spec.urdf for p in result.frames if p.spec.dh == 0 and p.fit is not None]
    assert at_base == ["base", "base_link", "world"]
    at_tip = [p.spec.urdf for p in result.frames if p.spec.dh == 6 and p.fit is not None]
    assert at_tip[:2] == ["tool0", "ee_link"]
    assert "wrist_3_link" in at_tip
    frames = {p.spec.name: p.spec for p in result.frames}
    # An undeclared link gets a frame of its own name ('world' is taken by fkcheck).
    assert frames["urdf_world"].urdf == "world"
    assert frames["wrist_3_link"].offset.xyz == (0.0, 0.0, -0.0823)  # snapped: exact
    assert frames["flange"].urdf is None  # declared without a link: kept


def test_names_on_urs_ros2_description():
    _model, result = _mapped("ur5")
    at_base = [p.spec.urdf for p in result.frames if p.spec.dh == 0 and p.fit is not None]
    assert at_base[:2] == ["base", "base_link"]
    at_tip = [p.spec.urdf for p in result.frames if p.spec.dh == 6 and p.fit is not None]
    assert at_tip[:2] == ["tool0", "flange"]


def test_the_panda_flange_frames_stay_at_the_tcp():
    _model, result = _mapped("panda")
    frames = {p.spec.name: p.spec for p in result.frames}
    assert frames["panda_link8"] == FrameSpec("panda_link8", "tcp", urdf="panda_link8")
    assert frames["panda_hand_tcp"].urdf == "panda_hand_tcp"
    # The fingers move (their joints take random values): never rigid to the flange.
    assert "panda_leftfinger" not in {p.spec.urdf for p in result.frames}


def _with_row(model: Model, index: int, **change: object) -> Model:
    joints = list(model.joints)
    joints[index] = replace(joints[index], **change)  # type: ignore[arg-type]
    return replace(model, joints=tuple(joints))


def test_a_flipped_alpha_is_named_as_the_edit_that_makes_the_chain_fit(tmp_path):
    """α4 typed -90° for 90°: no chain moves like the table, but it does with α4's sign changed.

    (The same motion as wrist_1's and wrist_2's zeros half a turn away: the map
    says it as the one sign, the likelier slip.)
    """
    model = ur5_ros1()
    wrong = _with_row(model, 3, alpha=-model.joints[3].alpha)  # α4 = -90° instead of 90°
    assert model.urdf is not None
    result = map_model(wrong, _kin(model), model.urdf.path)
    assert not result.complete
    assert result.joints_fit  # once edited
    assert result.edits.negated == (("wrist_1", "alpha"),)
    assert not result.edits.flips
    assert not result.edits.thetas
    assert not result.edits.values
    assert result.edits.apply(wrong).joints == model.joints
    text = proposal_toml(result)
    assert "#   [[joint]] wrist_1: alpha = 90 (was -90: α4's sign)" in text
    assert not result.nearest  # the frames are those of the edited table
    rebuilt = _rebuilt(result.edits.apply(wrong), result, tmp_path)
    assert _passes_pinocchio_urdf(rebuilt)


def test_a_table_of_another_arm_matches_no_link_and_says_how_near():
    model = ur5_ros1()
    wrong = _with_row(model, 1, a=model.joints[1].a * 1.5)  # a2 half as long again
    wrong = _with_row(wrong, 2, a=model.joints[2].a * 0.5)  # and a3 half as long
    result = map_model(wrong, _kin(model), "ur5.urdf")
    assert not result.complete
    assert not result.joints_fit
    assert result.fit_m > 1e-3  # millimetres off, not round-off
    assert {n.anchor for n in result.nearest} == {0, 6}
    text = proposal_toml(result)
    assert "NO chain of the URDF moves like this table" in text
    assert "NO URDF link sits at a constant offset from DH frame 6: the nearest" in text
    assert " mm / " in text


def test_a_joint_turning_the_other_way_is_named_with_the_fix():
    model = ur5_ros1()
    flipped = _with_row(model, 4, flip=True)
    result = map_model(flipped, _kin(model), "ur5.urdf")
    assert result.joints_fit
    assert not result.complete
    assert [j.dh for j in result.joints if j.flipped] == ["wrist_2"]
    assert [j.urdf for j in result.joints] == list(model.urdf.joints)  # type: ignore[union-attr]
    assert "set flip = false on [[joint]] wrist_2" in proposal_toml(result)


def test_an_undeclared_link_is_placed_on_its_dh_frame():
    model = ur5_ros1()
    fit = link_frame(model, _kin(model), "wrist_2_link")
    assert fit.anchor == 5
    assert fit.offset.xyz == (0.0, 0.09465, 0.0)
    assert fit.spread_m < 1e-9
    assert fit.spread_rad < 1e-9


def test_an_unknown_link_lists_the_links():
    model = ur5_ros1()
    with pytest.raises(FrameError, match="wrist_2_link"):
        link_frame(model, _kin(model), "nosuch")


@pytest.mark.parametrize(("link", "anchor"), [("shoulder_link", 1), ("upper_arm_link", 2)])
def test_a_link_next_to_the_base_is_placed_on_its_dh_frame(link, anchor):
    model = ur5_ros1()
    fit = link_frame(model, _kin(model), link)
    assert fit.anchor == anchor
    assert fit.fits(1e-9, 1e-9)


@pytest.mark.parametrize(
    ("joint", "change", "link", "urdf_joint", "anchor"),
    [
        (2, {"a": -0.40225}, "shoulder_link", "shoulder_pan_joint", 1),  # a3 10 mm long
        (2, {"a": -0.40225}, "upper_arm_link", "shoulder_lift_joint", 2),
        (3, {"alpha": "sign"}, "wrist_3_link", "wrist_3_joint", 6),  # α4 the wrong way
    ],
)
def test_a_wrong_table_refuses_every_placement_and_says_where_the_link_hangs(
    joint, change, link, urdf_joint, anchor
):
    """Not "at no constant offset from any DH frame": the link is fixed to DH frame 1, but
    the chain the placement is fitted from does not move as the table does."""
    model = ur5_ros1()
    value = {k: (-getattr(model.joints[joint], k) if v == "sign" else v) for k, v in change.items()}
    wrong = _with_row(model, joint, **value)
    with pytest.raises(FkcheckError) as refused:
        link_frame(wrong, _kin(model), link)
    message = str(refused.value)
    assert message.startswith(
        f"urdf:{link}: URDF link {link!r} moves with URDF joint {urdf_joint!r} (DH joint "
        f"{anchor}: it belongs on DH frame {anchor}), but no placement of it on model ur5's DH "
        "frames can be trusted: the table and the URDF disagree over the chain — its last DH "
        "frame strays up to "
    )
    assert "from URDF link 'wrist_3_link' over the samples" in message
    assert " mm / " in message
    assert "no constant offset" not in message


def test_a_recorded_difference_with_the_urdf_is_named_in_the_refusal():
    model = load_model("xarm7")
    [known] = model.known_differences
    with pytest.raises(
        FkcheckError, match=r"'link1' moves with URDF joint 'joint1' \(DH joint 1"
    ) as refused:
        link_frame(model, _kin(model), "link1")
    assert f"the model file records a difference with its URDF: {known.finding}" in str(
        refused.value
    )


def test_a_link_moved_by_an_unmapped_joint_is_refused_for_that_reason():
    model = load_model("panda")
    with pytest.raises(FkcheckError) as refused:
        link_frame(model, _kin(model), "panda_leftfinger")
    message = str(refused.value)
    assert (
        "URDF link 'panda_leftfinger' moves with URDF joint 'panda_finger_joint1', which model "
        "panda's [urdf] joints do not map" in message
    )
    assert "though the table and the URDF agree over the chain" in message
    assert "nearest: DH frame 7" in message


def test_a_link_below_a_floating_joint_is_refused_for_that_reason(tmp_path):
    from fkcheck.urdf.chain import read_urdf_file
    from fkcheck.urdf.source import resolve_urdf_path

    model = ur5_ros1()
    path, _ = resolve_urdf_path(model)
    text = path.read_text(encoding="utf-8").replace(
        "</robot>",
        '<link name="puck"/><joint name="puck_joint" type="floating"><parent link="tool0"/>'
        '<child link="puck"/></joint></robot>',
    )
    urdf = tmp_path / "ur5_puck.urdf"
    urdf.write_text(text, encoding="utf-8")
    kin = read_urdf_file(str(urdf))[2]
    with pytest.raises(
        FkcheckError,
        match=r"^urdf:puck: URDF link 'puck' hangs below the floating joint 'puck_joint', which "
        "fkcheck cannot follow",
    ):
        link_frame(model, kin, "puck")


def test_names_from_the_urdf_never_become_lines_of_the_proposed_toml(tmp_path):
    """A joint and a link named with a newline (``&#10;``) cannot inject ``xacro = true``."""
    from fkcheck.cli.main import main
    from fkcheck.urdf.source import resolve_urdf_path

    model = ur5_ros1()
    path, _ = resolve_urdf_path(model)
    evil = "&#10;xacro = true&#10;#"
    text = path.read_text(encoding="utf-8")
    text = text.replace('"shoulder_pan_joint"', f'"shoulder_pan_joint{evil}"')
    text = text.replace('"tool0"', f'"tool0{evil}"')
    urdf = tmp_path / "evil.urdf"
    urdf.write_text(text, encoding="utf-8")
    table = tmp_path / "arm.toml"
    bare = replace(model, urdf=None, frames={}, path=None, check=CheckSpec())
    table.write_text(model_to_toml(bare), "utf-8")
    out = tmp_path / "block.toml"
    assert main(["map", str(table), str(urdf), "-o", str(out)]) in (0, 1)
    block = out.read_text(encoding="utf-8")
    data = tomllib.loads(block)
    assert set(data["urdf"]) == {"path", "joints"}  # no xacro key anywhere
    assert "xacro" not in data
    assert data["urdf"]["joints"][0] == "shoulder_pan_joint\nxacro = true\n#"
    for line in block.splitlines():  # the name shows, escaped, only inside comments
        if "xacro = true" in line:
            assert line.startswith("#") or line.startswith("joints = ") or "urdf = " in line


# ----------------------------------------------------------------------------- slides


def _slides(convention: str, **extra: object) -> Model:
    """A cartesian arm: three prismatic joints at right angles, lengths on every row.

    The last row's a (0.07 m) puts the URDF chain's last link away from DH frame 3
    in a standard table (its ``Tx(a)·Rx(α)`` is a fixed joint after the slide).
    """
    data = {
        "name": "gantry",
        "convention": convention,
        "joint": [
            {"name": "x", "type": "prismatic", "a": 0.02, "alpha": -np.pi / 2, "d": 0.1,
             "theta": 0.0, "limits": [0.0, 0.5]},
            {"name": "y", "type": "prismatic", "a": 0.05, "alpha": -np.pi / 2, "d": 0.03,
             "theta": -np.pi / 2, "limits": [0.0, 0.5]},
            {"name": "z", "type": "prismatic", "a": 0.07, "alpha": 0.0, "d": 0.2,
             "theta": 0.0, "limits": [0.0, 0.5]},
        ],
    }  # fmt: skip
    data.update(extra)
    return model_from_dict(data)


def _slide_and_turn() -> Model:
    """A mixed arm: a slide, a turn about a parallel axis, a slide (the turn's axis is free)."""
    return model_from_dict(
        {
            "name": "lift",
            "convention": "standard",
            "joint": [
                {"name": "lift", "type": "prismatic", "a": 0.0, "alpha": 0.0, "d": 0.1,
                 "theta": 0.0, "limits": [0.0, 0.5]},
                {"name": "swing", "type": "revolute", "a": 0.3, "alpha": 0.0, "d": 0.05,
                 "theta": 0.0, "limits": [-2.0, 2.0]},
                {"name": "reach", "type": "prismatic", "a": 0.04, "alpha": np.pi / 2, "d": 0.2,
                 "theta": np.pi / 2, "limits": [0.0, 0.5]},
            ],
        }
    )  # fmt: skip


def _exported(model: Model, tmp_path: Path) -> UrdfKinematics:
    """The URDF written from ``model``, read back."""
    from fkcheck.urdf.chain import read_urdf_file
    from fkcheck.urdf.export import urdf_from_model

    path = tmp_path / f"{model.name}.urdf"
    path.write_text(urdf_from_model(model).text, encoding="utf-8")
    return read_urdf_file(str(path))[2]


def _assert_offsets_are_the_truth(model: Model, kin: UrdfKinematics, result: MapResult) -> None:
    """Each proposed frame sits where the exported URDF puts its link (finite, exact)."""
    from fkcheck.model.frames import reference_poses

    q = np.array([[0.1, 0.2, 0.3], [0.4, -0.1, 0.05], [0.0, 0.0, 0.0]])
    column = {name: k for k, name in enumerate(model.joint_names)}
    linked = [p for p in result.frames if p.fit is not None]
    assert linked
    for p in linked:
        assert np.all(np.isfinite(p.spec.offset.matrix))
        assert np.abs(p.spec.offset.xyz).max() < 1.0, p.spec  # never 1e20 m
        placed = replace(model, frames={**model.frames, "placed": replace(p.spec, name="placed")})
        [got] = reference_poses(placed, q, ["placed"])
        assert p.spec.urdf is not None
        if p.spec.urdf == kin.root:  # the export's world
            want = np.eye(4)
        else:
            chain = kin.chain(kin.root, p.spec.urdf)
            moving = [column[j.name] for j in kin.movable(chain)]
            want = kin.chain_poses(chain, q[:, moving])[:, -1]
        np.testing.assert_allclose(got, np.broadcast_to(want, got.shape), atol=1e-9,
                                   err_msg=p.spec.name)  # fmt: skip


@pytest.mark.parametrize(
    "model",
    [
        _slides("standard"),
        _slides("modified"),
        _slides("standard", base={"xyz": [0.1, 0.2, 0.3], "rpy": [0.3, 0.2, 0.1]},
                tool={"xyz": [0.01, 0.02, 0.03], "rpy": [0.5, 0.0, 0.0]}),
        _slide_and_turn(),
    ],
    ids=["slides-standard", "slides-modified", "slides-base-tool", "slide-turn-slide"],
)  # fmt: skip
def test_slides_map_with_no_flip_and_the_true_offsets_over_seeds(model, tmp_path):
    kin = _exported(model, tmp_path)
    for seed in range(5):
        result = map_model(model, kin, "robot.urdf", samples=32, seed=seed)
        assert result.complete, (seed, result.nearest)
        assert [j.urdf for j in result.joints] == list(model.joint_names)
        assert not any(j.flipped for j in result.joints), seed
        assert result.fit_m < 1e-9
        _assert_offsets_are_the_truth(model, kin, result)
        # Both ends are found, at the frames the URDF was written with.
        links = {p.spec.urdf: p.spec for p in result.frames if p.fit is not None}
        assert links["dh_frame_0"].offset.is_identity
        assert links["dh_frame_3"].offset.is_identity


@pytest.mark.parametrize("model", [_slides("standard"), _slide_and_turn()], ids=["slides", "mixed"])
def test_slides_flip_only_the_joint_that_turns_the_other_way(model, tmp_path):
    kin = _exported(model, tmp_path)
    flipped = _with_row(model, 1, flip=True)  # the URDF's joint 2 moves the table's way round
    for seed in range(3):
        result = map_model(flipped, kin, "robot.urdf", samples=32, seed=seed)
        assert result.joints_fit
        assert [j.dh for j in result.joints if j.flipped] == [model.joints[1].name], seed
