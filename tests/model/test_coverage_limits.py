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
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from fkcheck.core.metrics import position_error_m, rotation_error_rad
from fkcheck.model.coverage import coverage
from fkcheck.model.names import PARAMS, param_symbol
from fkcheck.model.types import Joint, Model, Offset
from tests.engine.test_subset_limits_property import HIDDEN_TOLERANCES, _held, _hidden, _moved

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


CASES = {"prismatic tilt": _prismatic_tilt, "zero lengths": _zero_lengths,
         "held slide": _held_slide, "mixed basis": _mixed_basis}  # fmt: skip


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
