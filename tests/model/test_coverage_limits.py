"""A held joint's combinations: the limits', never verified (fkcheck.model.coverage).

The fuzz profile of :mod:`tests.engine.test_subset_limits_property` found tables
whose joint is held still by its limits (``[v, v]``) and whose numbers a
combination changes that the held joint hides: within the limits the change is
far below one tolerance, so the reference agrees, yet with the joint free it
shows. Coverage used to blame the limits only when the free joint showed such a
combination at three tenths per tolerance (root mean square); shown at one to
three tenths, it was read as a trade and the numbers as verified. An error of
:data:`~fkcheck.model.coverage.RESOLUTION_LIMIT` tolerances along it would then
show with the joint free: other kinematics, which only the limits hide. These
are the three tables found (seeds 1-3), each held as the property held it, and
one the default profile found when the bar first moved.

A held slide was freed only a metre either side, the sampling default of a slide
without limits: the seeds then found a slide whose hidden change grows with its
displacement but shows under a tenth of a tolerance per tolerance within a metre.
It is freed :data:`~fkcheck.model.coverage.FREED_PRISMATIC_M` either side now.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from fkcheck.backends.registry import make_backend
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.engine.runner import run_check
from fkcheck.model.coverage import coverage
from fkcheck.model.names import PARAMS, param_symbol
from fkcheck.model.read import load_model
from fkcheck.model.types import Joint, Model, Offset
from fkcheck.urdf.export import model_for_urdf, urdf_from_model
from tests.engine.test_subset_limits_property import HIDDEN_TOLERANCES, _held, _hidden, _moved
from tests.urdf.test_map_never_hides_property import reframe_moving_links

TOL = 1e-6


def _prismatic_tilt() -> tuple[Model, int, float, int]:
    """Two slides and a turn, the last slide held at its lower limit."""
    joints = (
        Joint("j0", 0.0, 0.0, 0.0, 0.0, "prismatic", True,
              (-0.08003460729409162, 0.4103854037199034)),
        Joint("j1", 1e-09, -6.126342164655016, 0.0, 0.0, "revolute", True,
              (-2.45678878735058, 1.9542508596408439)),
        Joint("j2", 0.0, 0.0, 5.0, -1e-09, "prismatic", True,
              (-0.982900878482029, 0.009955196872569518)),
    )  # fmt: skip
    model = Model(
        name="random", convention="standard", joints=joints,
        base=Offset((-1e-09, 0.0, 0.0), (-math.pi, 0.0, 0.0)),
        tool=Offset((3.8265133569873484, 0.0, 0.0), (4.347568429656949, 4.35411377529989, 0.0)),
    )  # fmt: skip
    return model, 2, 0.0, 0


def _zero_lengths() -> tuple[Model, int, float, int]:
    """Three turns with no length at all (seed 1): joint 3 held at -1 rad."""
    joints = tuple(
        Joint(f"j{i}", 0.0, alpha, 0.0, 0.0, "revolute", False, (-1.0, 0.0))
        for i, alpha in enumerate((0.0, 3.0, 0.0))
    )
    return Model(name="random", convention="standard", joints=joints), 2, 0.0, 0


def _held_slide() -> tuple[Model, int, float, int]:
    """Three turns and a slide (seed 2): the slide held at 0.26 of its range."""
    joints = (
        Joint("j0", 5.0, 0.0, 0.0, 0.0, "revolute", True,
              (-1.8983555059199113, 0.42679826252316594)),
        Joint("j1", 0.0, 0.0, 0.0, -1e-09, "revolute", False,
              (-1.302361096810775, 1.5447897994914956)),
        Joint("j2", 0.0, -1.0, 0.0, 0.0, "revolute", True, (0.0, 1.0182223391481495)),
        Joint("j3", -1e-09, -math.pi, 5.0, math.pi, "prismatic", False,
              (-9.58899361787896e-22, 0.9142109182905116)),
    )  # fmt: skip
    model = Model(
        name="random", convention="standard", joints=joints,
        base=Offset((0.0, 0.0, 5.0), (0.0, math.pi / 2, 0.0)),
        tool=Offset((0.0, 5.0, -5.0), (math.pi, math.pi, -math.pi / 2)),
    )  # fmt: skip
    return model, 3, 0.26259251180571647, 3


def _mixed_basis() -> tuple[Model, int, float, int]:
    """Six joints, slides among them (the default profile, once the bar was a tenth).

    With joint 4 held, the free joint shows two combinations at a tenth and more;
    read in one sparsest basis together with those it shows only at the worst
    configuration, every combination mixed in one the limits do not hide, and
    none was kept: each set's basis is read on its own.
    """
    joints = (
        Joint("j0", 0.0, math.pi / 2, 0.0, 0.0, "revolute", False,
              (-0.2638412430581263, 1.7554946229229979e-65)),
        Joint("j1", -5.0, 3.3951516530794734, -1.2026930489871592, -3.0040774231306784e-147,
              "prismatic", False, (-0.0644377554197837, 1.192092896e-07)),
        Joint("j2", 1e-09, -math.pi / 2, 0.0, math.pi / 2, "prismatic", True,
              (-0.21993641404948394, 0.5)),
        Joint("j3", 0.0, -7.8505514318318e-59, -4.0, 1.0, "revolute", False,
              (-3.0676490891648425, 0.830981926219337)),
        Joint("j4", 0.0, 0.0, 4.914759847322943, math.pi / 2, "revolute", True,
              (-2.2559057590312155, 2.1458610943795096)),
        Joint("j5", -1e-09, -0.8682924382342883, -5.0, -4.82556081598641e-88, "prismatic", False,
              (-0.9882573810717019, 0.24051657362410556)),
    )  # fmt: skip
    model = Model(
        name="random", convention="standard", joints=joints,
        base=Offset((-1e-09, 2.7105180136607565, -5.0), (3.068925351744692, -1e-09, -math.pi)),
        tool=Offset((4.344037717313146, -5.0, -0.99999),
                    (0.0, 5.283185307179586, -2.007676818350986)),
    )  # fmt: skip
    return model, 3, 0.5743983219006478, 1748


def _tilted_slide() -> tuple[Model, int, float, int]:
    """A turn, a slide, a turn, no lengths (seeds 1-3, the slide freed a metre): the slide held.

    Held at its lower limit (-1 m), the change tilts the slide (α1 against α2) and
    takes back with d1, d2 and d3 what that moves at -1 m; the tilt's effect grows
    with the slide's displacement from there: 0.067 per tolerance (root mean
    square) within a metre, 0.67 within ten.
    """
    joints = (
        Joint("j0", 0.0, 0.0, 0.0, 0.0, "revolute", False, (-1.0, 0.0)),
        Joint("j1", 0.0, 3.0, 0.0, 0.0, "prismatic", False, (-1.0, 0.0)),
        Joint("j2", 0.0, 0.0, 0.0, 0.0, "revolute", False, (-1.0, 0.0)),
    )
    return Model(name="random", convention="standard", joints=joints), 1, 0.0, 0


CASES = {"prismatic tilt": _prismatic_tilt, "zero lengths": _zero_lengths,
         "held slide": _held_slide, "mixed basis": _mixed_basis,
         "tilted slide": _tilted_slide}  # fmt: skip


@pytest.fixture(params=list(CASES), scope="module")
def held(request):
    """The right table held, the wrong one (moved along the hidden change), the held joint."""
    model, joint, where, seed = CASES[request.param]()
    right = _held(model, joint, where)
    change = _hidden(right, joint, np.random.default_rng(seed))
    assert change is not None
    wrong = _moved(right, HIDDEN_TOLERANCES * TOL * change)
    return right, wrong, joint, change


def test_within_the_limits_the_wrong_table_is_the_right_one(held):
    """The premise: no configuration the limits allow tells the tables apart."""
    right, wrong, _joint, _change = held
    lo, hi = right.limits[:, 0], right.limits[:, 1]
    q = lo + (hi - lo) * np.random.default_rng(5).random((2000, right.dof))
    a, b = right.fk(q), wrong.fk(q)
    # A hundred tolerances of change, under a tenth of one within the limits.
    assert position_error_m(a, b).max() < 0.1 * TOL
    assert rotation_error_rad(a, b).max() < 0.1 * TOL


def test_a_combination_the_held_joint_hides_is_the_limits_never_verified(held):
    """Never verified: what is not is the limits', the held joint named, the change's largest.

    A number of the change can still be verified alone (the held joint's θ, whose
    error alone moves every pose): the table is not, its combination being the limits'.
    """
    right, wrong, joint, change = held

    # The change's numbers by their textbook names (its columns: a, α, d, θ per row).
    def name(k: int) -> str:
        return param_symbol(right, k // 4, PARAMS[k % 4])

    largest = name(int(np.argmax(np.abs(change))))
    for table in (right, wrong):
        evidence = coverage(table, "world", "tcp", TOL, TOL)
        assert not evidence.complete
        left = [n for n in evidence.table_numbers if n.status != "verified"]
        assert largest in [n.name for n in left]
        for n in left:
            assert (n.status, n.reason) == ("not-identifiable", "limits"), n.name
            assert f"the limits of joint {joint + 1} " in n.absorbed_by, n.name


def test_the_joint_free_the_same_tables_are_verified(held):
    """Free, the joint tells the combination: the limits were all that hid it."""
    right, _wrong, joint, _change = held
    joints = list(right.joints)
    lo, hi = right.limits[joint]
    joints[joint] = replace(joints[joint], limits=(lo - 0.5, hi + 0.5))
    free = replace(right, joints=tuple(joints))
    evidence = coverage(free, "world", "tcp", TOL, TOL)
    assert not [n.name for n in evidence.table_numbers if n.reason == "limits"]


def _trades(model: Model) -> dict[str, tuple[str, ...]]:
    return {n.name: n.trades_with for n in coverage(model, "world", "tcp", TOL, TOL).table_numbers}


def test_a_held_slide_keeps_the_kinematics_own_trades():
    """Freed ten metres, a slide blames on its limits only what its displacement shows.

    The tilted slide's table, the slide held: θ1 and θ2 turn about one axis (the
    slide's θ is a constant) and d1, d2 slide along it, whatever the slide's
    value. Those trades are the kinematics' own, as with the slide free: θ1 and θ2
    stay verified, each trading the other only; d1 and d2 still name each other,
    within the combination the held slide hides.
    """
    model, joint, where, _seed = _tilted_slide()
    right = _held(model, joint, where)
    joints = list(right.joints)
    joints[joint] = replace(joints[joint], limits=(-1.5, -0.5))
    free = _trades(replace(right, joints=tuple(joints)))
    trades = {"d1": ("d2",), "θ1": ("θ2",), "d2": ("d1",), "θ2": ("θ1",)}
    assert {k: v for k, v in free.items() if v} == trades
    evidence = {n.name: n for n in coverage(right, "world", "tcp", TOL, TOL).table_numbers}
    for name in ("θ1", "θ2"):
        assert (evidence[name].status, evidence[name].trades_with) == ("verified", free[name])
    for name in ("d1", "d2"):
        assert evidence[name].reason == "limits"
        assert set(free[name]) <= set(evidence[name].trades_with)


def test_a_slide_held_mid_range_on_stanford_keeps_its_own_d_trade():
    """The Stanford arm, its slide (joint 3) held at mid-range: d3 and d4 still trade.

    d3 (the slide's own offset) and d4 slide along one axis whatever the slide's
    value: verified, as a trade, not the limits'. What the limits hide is what a
    displacement of the slide shows: a2, θ2, α3, θ3 and θ4 (as with the slide
    freed one metre: ten do not add a number).
    """
    stanford = load_model("stanford")
    lo, hi = stanford.limits[2]
    held = _held(stanford, 2, 0.5)
    assert held.limits[2][0] == held.limits[2][1] == pytest.approx((lo + hi) / 2)
    evidence = {n.name: n for n in coverage(held, "world", "tcp", TOL, TOL).table_numbers}
    limited = sorted(name for name, n in evidence.items() if n.reason == "limits")
    assert limited == sorted(["a2", "θ2", "α3", "θ3", "θ4"])
    for name in limited:
        assert "the limits of joint 3 " in evidence[name].absorbed_by
    assert (evidence["d3"].status, evidence["d3"].trades_with) == ("verified", ("d4",))
    assert (evidence["d4"].status, evidence["d4"].trades_with) == ("verified", ("d3",))
    assert sorted(name for name, n in evidence.items() if n.status != "verified") == limited


def test_the_tilted_slide_the_check_of_the_right_table_passes_the_wrong_one_is_not_verified(
    tmp_path,
):
    """End to end: the held slide's tables pass against a URDF of the right one, in part verified.

    The wrong table agrees with the same URDF within the limits (the change is
    under a tenth of a tolerance there), so only its evidence can tell: it reads
    partly verified, never verified.
    """

    model, joint, where, seed = _tilted_slide()
    right = _held(model, joint, where)
    change = _hidden(right, joint, np.random.default_rng(seed))
    assert change is not None
    wrong = _moved(right, HIDDEN_TOLERANCES * TOL * change)
    path = tmp_path / "robot.urdf"
    # Another robot's description of the same arm, as the property gives it: its
    # moving links' own frames (a table's own export proves nothing).
    urdf = reframe_moving_links(urdf_from_model(right).text, np.random.default_rng(seed))
    path.write_text(urdf, encoding="utf-8")
    for table in (right, wrong):
        mapped = model_for_urdf(table, urdf_from_model(table), str(path))
        check = run_check(mapped, [make_backend("pinocchio-urdf")], samples=64, seed=1)
        assert (check.evidence.table.status, check.backends[0].status) == (
            "partly-verified",
            "pass",
        )
        assert check.evidence.table.gaps == (
            "α1, d1, α2, d2, d3 not identifiable (the joint limits keep any configuration"
            " from telling them apart: are the limits right?)"
        )


@pytest.mark.parametrize("where", [100.0, 1000.0])
def test_a_slide_held_far_out_still_blames_its_limits(where):
    """Stanford's slide held at 100 m or 1 km: what the held slide hides is never verified.

    The hidden change's sparsest basis weighs lengths by the displacement (a tilt of the
    distal chain at ``where`` metres is mostly a translation, which lengths make up), so a
    fixed ten metres either side showed it at a tenth of what it shows at the held
    value: freed only that far, a slide held at 100 m read the whole table verified, while
    a change of a hundred tolerances moved no pose within the limits by 4e-10 m. Freed
    its held displacement either side as well, it is the limits' again.
    """
    stanford = load_model("stanford")
    joints = list(stanford.joints)
    joints[2] = replace(joints[2], limits=(where, where))
    right = replace(stanford, joints=tuple(joints))
    change = _hidden(right, 2, np.random.default_rng(1))
    assert change is not None
    wrong = _moved(right, HIDDEN_TOLERANCES * TOL * change)
    q = right.limits[:, 0] + np.zeros((50, right.dof))
    q[:, [0, 1, 3, 4, 5]] = np.random.default_rng(5).uniform(-3, 3, (50, 5))
    assert position_error_m(right.fk(q), wrong.fk(q)).max() < 0.1 * TOL  # hidden
    names = [param_symbol(right, k // 4, PARAMS[k % 4]) for k in range(4 * right.dof)]
    largest = names[int(np.argmax(np.abs(change)))]
    evidence = coverage(right, "world", "tcp", TOL, TOL)
    assert not evidence.complete
    limited = {n.name for n in evidence.table_numbers if n.reason == "limits"}
    assert largest in limited
    assert {"a2", "θ2", "α3", "θ3"} <= limited  # what it hides held at 0.79 m too
