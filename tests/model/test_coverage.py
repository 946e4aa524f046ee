"""Per-number evidence (fkcheck.model.coverage): what one frame pair can verify of a model.

The joints a pair spans, each kind of number the issue found counted as verified
while the check never tested it (uncovered base and tool, pairs spanning no
joint, offsets that absorb a table number), and the resolutions.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from fkcheck.errors import FrameError
from fkcheck.model.coverage import RESOLUTION_LIMIT, coverage
from fkcheck.model.frames import reference_poses, relative_pose
from fkcheck.model.read import load_model
from fkcheck.model.types import FrameSpec, Offset

TOL = 1e-6


def joints_spanned(model, frame_from, frame_to):
    return coverage(model, frame_from, frame_to, TOL, TOL).joints_spanned


@pytest.fixture(scope="module")
def ur5():
    model = load_model("ur5")
    frames = dict(model.frames)
    frames["on1"] = FrameSpec("on1", 1, Offset((0.1, 0.0, 0.0)))
    frames["on0"] = FrameSpec("on0", 0, Offset((0.0, 0.0, 0.2), (0.0, 0.0, 1.0)))
    return replace(model, frames=frames)


@pytest.mark.parametrize(
    ("pair", "spanned"),
    [
        (("base", "tool0"), (1, 2, 3, 4, 5, 6)),
        (("tool0", "base"), (1, 2, 3, 4, 5, 6)),
        (("world", "tcp"), (1, 2, 3, 4, 5, 6)),
        (("tcp", "tcp"), ()),
        (("tool0", "flange"), ()),  # both on DH frame 6
        (("world", "base"), ()),  # DH frame 0 never moves
        (("world", "on0"), ()),
        (("world", "on1"), (1,)),
        (("on1", "tcp"), (2, 3, 4, 5, 6)),
        (("urdf:base", "urdf:tool0"), (1, 2, 3, 4, 5, 6)),
    ],
)
def test_the_joints_between_the_anchors(ur5, pair, spanned):
    assert joints_spanned(ur5, *pair) == spanned


@pytest.mark.parametrize(
    "pair",
    [("world", "tcp"), ("on1", "tool0"), ("world", "on1"), ("tcp", "tool0"), ("base", "on0")],
)
def test_a_joint_moves_the_pose_exactly_when_it_is_spanned(ur5, pair):
    rng = np.random.default_rng(7)
    q = rng.uniform(-3.0, 3.0, size=(5, ur5.dof))
    before = relative_pose(*reference_poses(ur5, q, pair))
    spanned = joints_spanned(ur5, *pair)
    for joint in range(1, ur5.dof + 1):
        moved = q.copy()
        moved[:, joint - 1] += 0.3
        after = relative_pose(*reference_poses(ur5, moved, pair))
        changed = bool(np.abs(after - before).max() > 1e-9)
        assert changed == (joint in spanned), joint


def test_an_unknown_frame_is_a_frame_error(ur5):
    with pytest.raises(FrameError, match="nowhere"):
        joints_spanned(ur5, "world", "nowhere")


def statuses(c):
    return {n.name: n.status for n in c.numbers}


def unvouched(model):
    frames = {k: replace(v, source="") for k, v in model.frames.items()}
    return replace(model, frames=frames)


def test_the_bundled_ur5_check_verifies_every_number_and_names_the_parallel_axes(ur5):
    c = coverage(ur5, "base", "tool0", TOL, TOL)
    assert c.complete
    assert c.summary() == "table verified"
    assert len(c.table_numbers) == 30  # a, α, d, θ and the direction of 6 joints
    assert c.count("verified") == 30
    by_name = {n.name: n for n in c.numbers}
    # d2, d3, d4 translate along UR's three parallel axes: only their sum is seen.
    assert set(by_name["d2"].trades_with) == {"d3", "d4"}
    assert by_name["a2"].trades_with == ()
    # Unobstructed, a length shows 1:1 in position and an angle 1:1 in rotation.
    for n in c.table_numbers:
        if not n.name.startswith("flip"):  # a direction has no resolution
            assert n.resolution == pytest.approx(TOL, rel=1e-3), n.name


@pytest.mark.parametrize(
    ("pair", "hidden"),
    [
        (("base_link", "tool0"), {"θ1"}),  # base_link = base · Rz(π): a missing θ offset
        (("base", "ee_link"), {"α6", "θ6"}),  # ee_link = tool0 · rpy(90°, −90°, 0)
        (("base_link", "ee_link"), {"θ1", "α6", "θ6"}),
    ],
)
def test_an_offset_carrying_what_a_table_number_produces_hides_it(ur5, pair, hidden):
    c = coverage(unvouched(ur5), *pair, TOL, TOL)
    assert {n.name for n in c.by_status("not-identifiable")} == hidden
    assert not c.complete
    for n in c.by_status("not-identifiable"):
        assert n.absorbed_by.startswith("[frames.")
    assert "not identifiable" in c.summary()


def test_a_vouched_offset_hides_nothing_and_is_shown(ur5):
    c = coverage(ur5, "base_link", "ee_link", TOL, TOL)  # the bundled UR5 vouches for both
    assert c.complete
    vouched = {n.group for n in c.vouched}
    assert vouched == {"[frames.base_link]", "[frames.ee_link]"}
    assert all(n.source for n in c.vouched)


def test_d1_ten_mm_long_mapped_into_the_base_frame_is_not_identifiable(ur5):
    wrong = replace(ur5, joints=(replace(ur5.joints[0], d=ur5.joints[0].d + 0.01), *ur5.joints[1:]))
    frames = dict(wrong.frames)
    frames["base"] = FrameSpec("base", 0, Offset((0.0, 0.0, 0.01)), "base")
    c = coverage(replace(wrong, frames=frames), "base", "tool0", TOL, TOL)
    assert [n.name for n in c.by_status("not-identifiable")] == ["d1"]
    d1 = next(n for n in c.numbers if n.name == "d1")
    assert d1.absorbed_by == "[frames.base]: translation along z of DH frame 0"
    assert c.summary().startswith("table verified except d1 not identifiable")


def test_a_urdf_link_frame_is_named_whole_as_the_offset_that_could_absorb(ur5):
    """``[frames.urdf:shoulder_link]``, not ``[frames.urdf`` cut at the name's own colon."""
    frames = dict(ur5.frames)
    frames["urdf:shoulder_link"] = FrameSpec(  # where `check --to urdf:shoulder_link` puts it
        "urdf:shoulder_link", 1, Offset((0.0, 0.0, 0.0), (np.pi / 2, 0.0, np.pi)), "shoulder_link"
    )
    c = coverage(replace(ur5, frames=frames), "base", "urdf:shoulder_link", TOL, TOL)
    # A half turn (Rz(π)·Rx(π/2) turns by π) is flat along α1's turn too: carried.
    assert [n.name for n in c.by_status("not-identifiable")] == ["α1", "θ1"]
    assert (
        "α1, θ1 not identifiable (the offset of [frames.urdf:shoulder_link] could absorb them)"
        in (c.gaps())
    )


def test_a_translation_across_the_first_axis_hides_nothing(ur5):
    frames = dict(ur5.frames)
    frames["side"] = FrameSpec("side", 0, Offset((0.3, -0.2, 0.0)))
    c = coverage(replace(ur5, frames=frames), "side", "tool0", TOL, TOL)
    assert c.complete, c.gaps()


@pytest.mark.parametrize(("field", "offset"), [
    ("base", Offset(rpy=(0.0, 0.0, np.pi))),  # a [base] turned π
    ("tool", Offset(xyz=(0.0, 0.0, 0.1))),  # a [tool] 100 mm off
    ("tool", Offset(rpy=(0.0, 0.0, np.pi / 2))),  # or 90° off
])  # fmt: skip
def test_base_and_tool_outside_the_pair_are_not_covered(ur5, field, offset):
    c = coverage(replace(ur5, **{field: offset}), "base", "tool0", TOL, TOL)
    assert {n.group for n in c.by_status("not-covered")} == {f"[{field}]"}
    assert not c.complete
    assert f"[{field}] not covered (outside base → tool0)" in c.summary()
    # The pair through world and TCP covers it: its numbers then trade with d1, θ…
    wide = coverage(replace(ur5, **{field: offset}), "world", "tcp", TOL, TOL)
    assert wide.complete, wide.gaps()


@pytest.mark.parametrize("pair", [("tcp", "tcp"), ("tool0", "flange"), ("world", "base")])
def test_a_pair_spanning_no_joint_verifies_no_table_number(ur5, pair):
    c = coverage(ur5, *pair, TOL, TOL)
    assert c.spans_no_joint
    assert not c.complete
    assert c.count("verified") == 0
    assert c.summary() == f"table not verified: the pair {pair[0]} → {pair[1]} spans no joint"


def test_a_pair_spanning_only_the_first_joint_is_partial(ur5):
    c = coverage(ur5, "world", "on1", TOL, TOL)
    assert c.joints_spanned == (1,)
    assert c.summary().startswith("table partly verified: joints 1 of 6;")
    assert {n.name for n in c.by_status("not-covered")} >= {"a2", "θ6"}


def test_a_number_the_offsets_almost_absorb_is_not_identifiable_with_its_resolution():
    from fkcheck.model.read import model_from_dict

    # z1 is 1e-4 rad from z0: an offset along z0 at DH frame 0 takes all of d1 and
    # all but 1e-4 of d2, so d2 errors up to ~tol / 1e-4 = 10 mm would pass.
    model = model_from_dict({
        "name": "almost", "convention": "standard",
        "joint": [
            {"name": "j1", "a": 0.0, "alpha": 1e-4, "d": 0.1, "theta": 0.0},
            {"name": "j2", "a": 0.5, "alpha": 1.2, "d": 0.2, "theta": 0.0},
            {"name": "j3", "a": 0.3, "alpha": 0.0, "d": 0.0, "theta": 0.0},
        ],
        "frames": {"lifted": {"dh": 0, "xyz": [0.0, 0.0, 0.01]}},
    })  # fmt: skip
    c = coverage(model, "lifted", "tcp", TOL, TOL)
    by_name = {n.name: n for n in c.numbers}
    assert by_name["d1"].status == "not-identifiable"
    assert by_name["d1"].absorbed_by.startswith("[frames.lifted]: translation along z")
    d2 = by_name["d2"]
    assert d2.status == "not-identifiable"
    assert "would stay within tolerance" in d2.absorbed_by
    # Without the offset, both are verified, each to its tolerance.
    clean = coverage(model, "world", "tcp", TOL, TOL)
    assert clean.complete
    assert RESOLUTION_LIMIT == 10.0


def test_a_placed_urdf_link_named_with_a_colon_is_named_whole(ur5):
    wrong = replace(ur5, joints=(replace(ur5.joints[0], d=ur5.joints[0].d + 0.01), *ur5.joints[1:]))
    frames = {k: v for k, v in wrong.frames.items() if k != "base"}  # placed from the URDF:
    frames["urdf:base"] = FrameSpec("urdf:base", 0, Offset((0.0, 0.0, 0.01)), "base")
    c = coverage(replace(wrong, frames=frames), "urdf:base", "tool0", TOL, TOL)
    assert c.gaps() == "d1 not identifiable (the offset of [frames.urdf:base] could absorb it)"


def _rebuilt_pose(model, q, pair, number, h, chain=None):
    """``from_T_to`` with ``number`` nudged by ``h``, the whole chain rebuilt (the slow way)."""
    from fkcheck.core import dh
    from fkcheck.core.geometry import invert
    from fkcheck.model.coverage import _twist_matrix

    chain, q = chain or model.chain, q.copy()
    offsets = {side: spec.offset.matrix for side, spec in zip(("from", "to"), pair, strict=True)}
    base, tool = chain.world_T_base, chain.flange_T_tool
    if number.kind == "row":
        values = getattr(chain, number.param).copy()
        values[number.index] += h
        chain = replace(chain, **{number.param: values})
    elif number.kind in ("joint", "flip"):
        q[:, number.index] += h
    elif number.kind == "base":
        base = base @ _twist_matrix(number.index, h)
    elif number.kind == "tool":
        tool = tool @ _twist_matrix(number.index, h)
    else:
        offsets[number.kind] = offsets[number.kind] @ _twist_matrix(number.index, h)
    chain = replace(chain, world_T_base=base, flange_T_tool=tool)
    frames = dh.fk_reference(chain, q, all_frames=True)
    ends = []
    for side, spec in zip(("from", "to"), pair, strict=True):
        if spec.dh == "world":
            anchor = np.broadcast_to(np.eye(4), frames[:, 0].shape)
        elif spec.dh == "tcp":
            anchor = frames[:, -1] @ tool
        else:
            anchor = frames[:, int(spec.dh)]
        ends.append(anchor @ offsets[side])
    return invert(ends[0]) @ ends[1]


@pytest.mark.parametrize(
    ("name", "pair", "offsets"),
    [
        ("ur5", ("on1", "base_link"), {"from", "to"}),  # standard, an offset on each side
        ("ur5", ("world", "on0"), {"to"}),
        ("panda", ("panda_link2", "tcp"), {"tool"}),  # modified (Craig), a tool
        ("stanford", ("world", "tcp"), set()),  # a prismatic joint
        ("baxter_left", ("world", "tcp"), {"base"}),
    ],
)
def test_a_nudged_number_moves_the_pose_as_the_whole_chain_rebuilt_does(ur5, name, pair, offsets):
    # The analysis moves only the ends after a nudged link (F_i · A' · F_(i+1)⁻¹ · F_k)
    # instead of recomputing the chain per number; it must give the rebuilt chain's pose.
    from fkcheck.model.coverage import _numbers, _Pose

    model = ur5 if name == "ur5" else load_model(name)
    specs = [_resolve(model, f) for f in pair]
    q = np.random.default_rng(5).uniform(-2.0, 2.0, size=(7, model.dof))
    pose = _Pose(model, q, *specs)
    numbers = _numbers(model, tuple(specs))
    joints = [replace(numbers[0], kind="joint", index=i) for i in range(model.dof)]
    kinds = set()
    for number in [*numbers, *joints]:
        for h in (0.3, -1e-6):
            got = pose.pose(number, h)
            want = _rebuilt_pose(model, q, specs, number, h)
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-12, err_msg=str(number))
        kinds.add(number.kind)
    np.testing.assert_allclose(pose.pose(), _rebuilt_pose(model, q, specs, numbers[0], 0.0),
                               rtol=0, atol=1e-12)  # fmt: skip
    for i in range(model.dof):  # a joint turned the other way
        sign = model.chain.sign.copy()
        sign[i] = -sign[i]
        want = _rebuilt_pose(model, q, specs, numbers[0], 0.0, replace(model.chain, sign=sign))
        np.testing.assert_allclose(pose.flipped(i), want, rtol=0, atol=1e-12)
    assert kinds == {"row", "flip", "joint", *offsets}


def _resolve(model, name):
    from fkcheck.model.types import resolve_frame

    return resolve_frame(model, name)


def test_the_analysis_stops_at_its_time_limit_in_one_line(ur5):
    from fkcheck.errors import TimeLimitError

    with pytest.raises(TimeLimitError, match=r"^per-number evidence of ur5 \(world → tcp\) did "
                       r"not finish within the check's time limit of 0 s; give it more with "
                       r"--timeout$"):  # fmt: skip
        coverage(ur5, "world", "tcp", TOL, TOL, time_limit_s=0.0)
    assert coverage(ur5, "world", "tcp", TOL, TOL, time_limit_s=60.0).joints_spanned


@pytest.mark.parametrize("limits", [(0.0, 0.0), (-1e-9, 1e-9)], ids=["zero", "1e-9 rad"])
def test_numbers_a_frozen_joint_keeps_together_are_the_limits_to_hide(limits):
    """Issue 30, item 3: UR5's elbow held still hides a2 against a3; free, it separates them."""
    model = load_model("ur5")
    joints = list(model.joints)
    joints[2] = replace(joints[2], limits=limits)
    frozen = replace(model, joints=tuple(joints))
    numbers = {n.name: n for n in coverage(frozen, "base", "tool0", TOL, TOL).numbers}
    for name in ("a2", "a3", "flip3"):
        assert (numbers[name].status, numbers[name].reason) == ("not-identifiable", "limits")
    assert "the limits of joint 3" in numbers["a2"].absorbed_by
    assert numbers["d2"].status == "verified"  # parallel d2, d3, d4: the kinematics' trade
    assert numbers["d2"].trades_with == ("d3", "d4")
    assert coverage(model, "base", "tool0", TOL, TOL).complete  # the same arm, free
