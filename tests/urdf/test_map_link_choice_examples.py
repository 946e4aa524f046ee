"""The link-choice property's falsifying examples, as plain deterministic tests.

:mod:`tests.urdf.test_map_link_choice_property` (a right table mapped onto its
URDF is verified, or only a choice among links is not) failed in CI on two
generated tables, after the merges of session 11. Neither was a regression:
both give the same evidence with the code of 6962fd4, where the property
passed; that run's examples did not reach them. The cause of both was the
property's oracle, which knew too few of the links a choice is among:

- a frame of the model itself (exported as a link of the URDF) sat exactly where
  a change of the last rows would put the last DH frame, so the map's report of
  it as a competing link was right; the oracle now finds such frames on its own
  (:func:`~tests.urdf.test_map_never_hides_property.rival_frames`, a least-squares
  fit over the rows, not coverage's search);
- with a rival beside the last DH frame's link, every link at that end hides some
  numbers, and the map's pair ended on the one hiding the fewest: the last
  joint's own link, whose random frame carries α6, d6 and θ6. The oracle now
  allows any link at an end where a rival is.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import tests.urdf.test_map_never_hides_property as workflow
from fkcheck.model.types import FrameSpec, Joint, Model, Offset
from tests.urdf.test_map_link_choice_property import _urdf, rival_at_base, rival_at_tip
from tests.urdf.test_map_never_hides_property import (
    mapped_check,
    rival_frames,
    verified_or_a_link_choice,
)

_NONE = Offset(xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0))


def _joint(name: str, alpha: float, kind: str, flip: bool, limits: tuple[float, float]) -> Joint:
    return Joint(name, 0.0, alpha, 0.0, 0.0, kind, flip, limits)  # type: ignore[arg-type]


def _last_rows_rival(tilt: float = 0.0) -> Model:
    """CI's first example: ``extra1`` on the TCP, turned about x (α6) and shifted.

    With every a and d zero, α4 = 0 and α5 = −90°, the shift is what d4 + d5 (along
    the fifth axis, y of the last frame), a5 + a6 (x) and d6 (z) produce, the turn
    what α6 does: the changed table ends on ``extra1`` exactly. ``tilt`` turns it
    about its y as well, which no number of the table produces.
    """
    joints = (
        _joint("j0", 0.0, "revolute", True, (-1.401298464324817e-45, 2.008307184596885)),
        _joint("j1", 0.0, "revolute", True, (-1.0, 2.472314861341197)),
        _joint("j2", 5.464838025197569, "revolute", False,
               (-0.1821031627918217, 0.6329456146026421)),
        _joint("j3", 0.0, "revolute", True, (-2.449430326515294, 1.961874347268561)),
        _joint("j4", -1.5707963267948966, "revolute", True,
               (-0.9999999999999999, 0.8857224421069101)),
        _joint("j5", 0.0, "prismatic", False, (-0.332989162170482, 0.9775425572891268)),
    )  # fmt: skip
    extra0 = Offset(
        xyz=(-2.2250738585e-313, 1e-07, -0.135424817600088),
        rpy=(-1.1093900614777931e-10, 1.874351734198644, -0.9728389991097393),
    )
    extra1 = Offset(
        xyz=(0.26503831349790397, -0.18821704050078786, -0.4278909334518741),
        rpy=(1.673448653602497, tilt, 0.0),
    )
    frames = {
        "world": FrameSpec("world", "world", _NONE),
        "tcp": FrameSpec("tcp", "tcp", _NONE),
        "extra0": FrameSpec("extra0", 0, extra0),
        "extra1": FrameSpec("extra1", "tcp", extra1),
    }
    return Model(name="random", convention="standard", joints=joints, frames=frames)


def test_a_frame_of_the_model_a_changed_last_row_puts_the_dh_frame_on_is_a_rival():
    assert rival_frames(_last_rows_rival()) == {"extra1"}
    # Turned about y too (no number does that), and extra0's turn across z₀: none.
    assert rival_frames(_last_rows_rival(tilt=0.3)) == set()


@pytest.mark.parametrize("tilt", [0.0, 0.3])
def test_a_right_table_whose_own_frame_is_a_rival_is_verified_but_for_that_choice(
    tilt, tmp_path, monkeypatch
):
    monkeypatch.setattr(workflow, "note", lambda _: None)  # Hypothesis' notes: no test of it
    model = _last_rows_rival(tilt)
    status, _block, check = mapped_check(model, _urdf(model, 0), tmp_path)
    outcome = verified_or_a_link_choice(status, check, model)
    if tilt:  # no rival: every number verified
        assert outcome == "fully verified"
        return
    assert outcome == "a choice among links (link)"
    left = {n.name: n.competing for n in check.evidence.numbers.table_numbers
            if n.status != "verified"}  # fmt: skip
    # The numbers the choice could hide, and only they; extra1 the link named.
    assert left == dict.fromkeys(("d4", "a5", "d5", "a6", "α6", "d6"), ("extra1",))


def _bare() -> Model:
    """CI's second table: the first one's rows, no frames of its own."""
    model = _last_rows_rival()
    return replace(model, frames={k: model.frames[k] for k in ("world", "tcp")})


@pytest.mark.parametrize("tip", [True, False], ids=["rival at each end", "rival at the base"])
def test_a_rival_beside_the_last_frame_lets_the_pair_end_on_the_link_hiding_the_fewest(
    tip, tmp_path, monkeypatch
):
    monkeypatch.setattr(workflow, "note", lambda _: None)
    model = _bare()
    rivals = {"rival_base": ("dh_frame_0", rival_at_base(model, 0.9, 0.05))}
    if tip:  # θ6 + 180°, d6 + 30 mm, a6 + 20 mm, α6 − 0.3 rad
        change = np.array([math.pi, 0.03, 0.02, -0.3])
        rivals["rival_tip"] = ("dh_frame_6", rival_at_tip(model, change))
    status, _block, check = mapped_check(model, _urdf(model, 311, rivals), tmp_path)
    outcome = verified_or_a_link_choice(status, check, model, frozenset(rivals))
    left = {n.name: (n.reason, n.competing, n.by)
            for n in check.evidence.numbers.table_numbers if n.status != "verified"}  # fmt: skip
    base = {name: ("link", ("rival_base",), ("[frames.urdf_world]",))
            for name in ("d1", "θ1", "d2", "θ2", "d3", "θ3")}  # fmt: skip
    if not tip:  # the last DH frame's link hides nothing: the pair ends there
        assert outcome == "a choice among links (link)"
        assert left == base
        return
    assert outcome == "a choice among links (link, offset)"
    assert check.model.check.frame_to == "dh_joint_6"
    carried = {name: ("offset", (), ("[frames.dh_joint_6]",)) for name in ("α6", "d6", "θ6")}
    # What the rival's change moves beyond the joint's frame (d4, d5: along one axis).
    linked = {name: ("link", ("rival_tip",), ("[frames.dh_joint_6]",))
              for name in ("d4", "a5", "d5", "a6")}  # fmt: skip
    assert left == base | carried | linked
