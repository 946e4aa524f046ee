"""Which link is the DH frame is a choice: competing links and vouches (issue 30, items 1 and 4).

A description often has several links fixed together at an end of the chain (UR's
``base_link`` and ``base``, a half turn apart; ``tool0``, ``flange`` and
``ft_frame``). A table whose θ1 is off by a half turn maps onto ``base_link`` as
cleanly as the right one maps onto ``base``: choosing among such links is fitting
an offset. These tests break exactly that, at the model level, where
:func:`fkcheck.model.coverage.coverage` is told which links compete.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from fkcheck.core.geometry import matrix_from_xyz_rpy
from fkcheck.model.coverage import MAX_COMPETITORS, Competitor, coverage
from fkcheck.model.read import load_model
from fkcheck.model.types import FrameSpec, Model, Offset

TOL = (1e-6, 1e-6)


def _table(name: str = "ur5e", **changes: tuple[int, str, float]) -> Model:
    """A bundled table with no frames but world and tcp, each change ``(row, param, +value)``."""
    model = load_model(name)
    joints = list(model.joints)
    for row, param, delta in changes.values():
        joints[row] = replace(joints[row], **{param: getattr(joints[row], param) + delta})
    frames = {k: v for k, v in model.frames.items() if k in ("world", "tcp")}
    return replace(model, joints=tuple(joints), frames=frames, urdf=None)


def _with(model: Model, *frames: FrameSpec) -> Model:
    return replace(model, frames={**model.frames, **{f.name: f for f in frames}})


def _rz(deg: float) -> Offset:
    return Offset(rpy=(0.0, 0.0, math.radians(deg)))


def _status(c, name: str):  # type: ignore[no-untyped-def]
    return next(n for n in c.table_numbers if n.name == name)


def test_a_half_turn_in_theta1_hides_behind_the_choice_of_base_link():
    # θ1 + 180°: base_link sits on the wrong table's DH frame 0, base half a turn from it.
    wrong = _with(
        _table(t=(0, "theta", math.pi)),
        FrameSpec("base_link", 0, Offset(), "base_link"),
        FrameSpec("tool0", 6, Offset(), "tool0"),
    )
    rivals = {"base_link": [Competitor("base", _rz(180).matrix)]}
    c = coverage(wrong, "base_link", "tool0", *TOL, competitors=rivals)
    theta1 = _status(c, "θ1")
    assert theta1.status == "not-identifiable"
    assert theta1.reason == "link"
    assert theta1.competing == ("base",)
    assert "with θ1 changed by" in theta1.absorbed_by
    assert "180°" in theta1.absorbed_by
    assert not c.complete
    assert "link base of the description could be the DH frame" in c.summary()
    # Without the competitor (what the check said before), the same pair verified it.
    assert coverage(wrong, "base_link", "tool0", *TOL).complete


def test_the_right_table_with_the_same_links_is_ambiguous_too_until_vouched():
    right = _with(
        _table(),
        FrameSpec("base", 0, Offset(), "base"),
        FrameSpec("tool0", 6, Offset(), "tool0"),
    )
    rivals = {"base": [Competitor("base_link", _rz(180).matrix)]}
    c = coverage(right, "base", "tool0", *TOL, competitors=rivals)
    assert _status(c, "θ1").reason == "link"
    # The vendor says base is DH frame 0: verified, on that word, and the summary says so.
    vouched = _with(right, FrameSpec("base", 0, Offset(), "base", source="UR: base is DH 0"))
    c = coverage(vouched, "base", "tool0", *TOL, competitors=rivals)
    assert c.complete
    assert _status(c, "θ1").on_word_of == ("[frames.base]",)
    assert c.vouches == (("[frames.base]", "UR: base is DH 0"),)
    assert c.summary() == 'table verified, θ1 on the word of [frames.base] ("UR: base is DH 0")'


def test_a_vouched_competitor_settles_the_choice_only_where_the_description_bears_it_out():
    right = _with(
        _table(),
        FrameSpec("base", 0, Offset(), "base"),
        FrameSpec("tool0", 6, Offset(), "tool0"),
        FrameSpec("base_link", 0, _rz(180), "base_link", source="base = base_link · Rz(π)"),
    )
    rivals = {"base": [Competitor("base_link", _rz(180).matrix)]}
    c = coverage(right, "base", "tool0", *TOL, competitors=rivals)
    assert c.complete
    assert _status(c, "θ1").on_word_of == ("[frames.base_link]",)
    # A vouch the description contradicts (it says 90°, the URDF puts it at 180°) settles nothing.
    lying = _with(right, replace(right.frames["base_link"], offset=_rz(90)))
    c = coverage(lying, "base", "tool0", *TOL, competitors=rivals)
    assert _status(c, "θ1").reason == "link"


@pytest.mark.parametrize(
    ("rival", "competes"),
    [
        (matrix_from_xyz_rpy([0, 0, 0.05], [0, 0, 0]), ("d1",)),  # a shift along z: d1
        (matrix_from_xyz_rpy([0, 0, 0.05], [0, 0, 1.0]), ("d1", "θ1")),  # a screw about z
        (matrix_from_xyz_rpy([0, 0, 0], [0.5, 0, 0]), ()),  # a tilt: no number produces it
        (matrix_from_xyz_rpy([0.3, 0, 0], [0, 0, 0]), ()),  # a shift across z
        # A tilt and a half turn: θ1 + 180° leaves a bare tilt, which carries no number:
        # as tidy a choice as the compared link, under the other table.
        (matrix_from_xyz_rpy([0, 0, 0], [0.5, 0, math.pi]), ("θ1",)),
        (np.eye(4), ()),  # on the same place: nothing to choose
    ],
)
def test_at_dh_frame_0_a_turn_about_or_a_shift_along_z_competes(rival, competes):
    model = _with(
        _table(), FrameSpec("b", 0, Offset(), "b"), FrameSpec("tool0", 6, Offset(), "tool0")
    )
    c = coverage(model, "b", "tool0", *TOL, competitors={"b": [Competitor("other", rival)]})
    hidden = tuple(n.name for n in c.table_numbers if n.reason == "link")
    assert hidden == competes


def test_at_the_last_frame_a_half_turn_in_alpha6_hides_behind_ft_frame():
    wrong = _with(
        _table(a=(5, "alpha", math.pi)),
        FrameSpec("base", 0, Offset(), "base"),
        FrameSpec("ft_frame", 6, Offset(), "ft_frame"),
    )
    rx180 = Offset(rpy=(math.pi, 0.0, 0.0)).matrix
    c = coverage(wrong, "base", "ft_frame", *TOL,
                 competitors={"ft_frame": [Competitor("tool0", rx180)]})  # fmt: skip
    assert _status(c, "α6").reason == "link"
    assert _status(c, "α6").competing == ("tool0",)


def test_a_tidy_offset_at_the_chosen_link_does_not_clear_a_rival_on_the_dh_frame():
    # FANUC-like θ6 + 180°: the chosen flange sits at a tidy 90° about y, which carries
    # nothing of θ6; tool0, fixed beside it, would be DH frame 6 with θ6 180° off.
    wrong = _with(
        _table(t=(5, "theta", math.pi)),
        FrameSpec("base", 0, Offset(), "base"),
        FrameSpec("flange", 6, Offset(rpy=(0.0, math.pi / 2, 0.0)), "flange"),
    )
    assert coverage(wrong, "base", "flange", *TOL).complete  # what it said before
    c = coverage(wrong, "base", "flange", *TOL,
                 competitors={"flange": [Competitor("tool0", _rz(180).matrix)]})  # fmt: skip
    assert _status(c, "θ6").reason == "link"


def test_a_vouched_offset_that_absorbs_d1_is_shown_as_the_word_it_rests_on():
    # Item 4: a [frames.base] vouched for by anything over a d1 10 mm too long.
    wrong = _with(
        _table(d=(0, "d", 0.01)),
        FrameSpec("base", 0, Offset(xyz=(0.0, 0.0, 0.01)), "base", source="anything"),
        FrameSpec("tool0", 6, Offset(), "tool0"),
    )
    c = coverage(wrong, "base", "tool0", *TOL)
    assert c.complete  # the vouch is taken …
    assert _status(c, "d1").on_word_of == ("[frames.base]",)  # … and said
    assert 'd1 on the word of [frames.base] ("anything")' in c.summary()


def test_a_long_source_is_cut_in_the_summary_and_kept_whole_in_the_record():
    source = "x" * 300
    model = _with(
        _table(d=(0, "d", 0.01)),
        FrameSpec("base", 0, Offset(xyz=(0.0, 0.0, 0.01)), "base", source=source),
        FrameSpec("tool0", 6, Offset(), "tool0"),
    )
    c = coverage(model, "base", "tool0", *TOL)
    assert c.vouches == (("[frames.base]", source),)
    assert source not in c.summary()
    assert "x" * 59 + "…" in c.summary()


def test_more_links_fixed_at_an_end_than_analysed_leave_its_numbers_unidentified(rng):
    # A hostile description: hundreds of links fixed around the base. Solving each
    # would cost time out of proportion; the end's numbers are reported unanalysed.
    model = _with(
        _table(), FrameSpec("b", 0, Offset(), "b"), FrameSpec("tool0", 6, Offset(), "tool0")
    )
    many = [
        Competitor(f"l{i}", matrix_from_xyz_rpy(rng.uniform(-1, 1, 3), rng.uniform(-3, 3, 3)))
        for i in range(MAX_COMPETITORS + 1)
    ]
    c = coverage(model, "b", "tool0", *TOL, competitors={"b": many})
    for name in ("d1", "θ1"):
        assert _status(c, name).reason == "link"
        assert "more than the 128 fkcheck analyses" in _status(c, name).absorbed_by
    vouched = _with(model, FrameSpec("b", 0, Offset(), "b", source="vendor: b is DH 0"))
    c = coverage(vouched, "b", "tool0", *TOL, competitors={"b": many})
    assert c.complete
    assert _status(c, "θ1").on_word_of == ("[frames.b]",)
