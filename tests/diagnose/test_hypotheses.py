"""Degrees read as radians: the whole file's unit, or a few angles typed in degrees."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import fkcheck.backends.registry as registry
from fkcheck import load_model
from fkcheck.diagnose import diagnose, format_text
from fkcheck.diagnose.hypotheses import fit_single_parameters
from fkcheck.diagnose.problem import Problem, diagnosis_configurations
from fkcheck.engine.runner import run_check
from fkcheck.model.types import Model, Offset
from fkcheck.urdf.export import model_for_urdf, urdf_from_model
from tests.paths import REPO_ROOT

#: The one sentence that names the mix-up (the issue's wording).
DEGREES_READ_AS_RADIANS = (
    'the table\'s angles are in degrees but were read as radians: set angle_unit = "deg"'
)


@pytest.fixture(scope="module")
def reference():
    return registry.make_backend("pinocchio-urdf")


def with_joint(model: Model, index: int, **changes: object) -> Model:
    joints = list(model.joints)
    joints[index] = replace(joints[index], **changes)  # type: ignore[arg-type]
    return replace(model, joints=tuple(joints))


@pytest.fixture(scope="module")
def ur5_in_degrees_read_as_radians(tmp_path_factory) -> Model:
    """models/ur5.toml, written in degrees, with its unit line changed to radians."""
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
    assert 'angle_unit = "deg"' in text
    directory = tmp_path_factory.mktemp("ur5rad")
    path = directory / "ur5.toml"
    path.write_text(text.replace('angle_unit = "deg"', 'angle_unit = "rad"'), encoding="utf-8")
    return load_model(path)


def test_the_bundled_ur5_in_degrees_read_as_radians_is_named_first(
    ur5_in_degrees_read_as_radians, reference
):
    bad = ur5_in_degrees_read_as_radians
    assert bad.joints[0].alpha == 90.0  # read as 90 rad
    result = diagnose(bad, reference, samples=50)
    best = result.explanations[0]
    assert best is result.best
    assert best.kind == "degrees"
    assert best.title == DEGREES_READ_AS_RADIANS
    assert best.changed == 1  # one setting: angle_unit
    assert result.before.position_m > 0.1
    assert best.residual.position_m < 1e-9
    # The published UR5 table explains it too, by changing three numbers: ranked after.
    others = [e for e in result.explanations[1:] if e.explains]
    assert others
    assert all(e.changed > 1 for e in others)
    assert f"1. [degrees] {DEGREES_READ_AS_RADIANS}" in format_text(result)
    # The fix is the file as it should have been read: limits, poses and frames too.
    good = load_model("ur5")
    fixed = best.model
    assert fixed is not None
    for ours, theirs in zip(fixed.joints, good.joints, strict=True):
        assert ours.alpha == pytest.approx(theirs.alpha, abs=1e-15)
        assert ours.limits == pytest.approx(theirs.limits, abs=1e-12)
    assert fixed.poses["home"] == pytest.approx(good.poses["home"], abs=1e-15)
    np.testing.assert_allclose(
        fixed.frames["base_link"].offset.matrix, good.frames["base_link"].offset.matrix, atol=1e-15
    )
    check = run_check(fixed, [reference], samples=16, seed=1)
    assert check.backends[0].status == "pass"


@pytest.fixture(scope="module")
def mixed_units(tmp_path_factory) -> Model:
    """A UR5 whose θ2 offset is -90°, written as -90 in a file whose other angles are radians.

    The reference is the URDF exported from the right table (θ2 = -π/2).
    """
    truth = with_joint(load_model("ur5"), 1, theta=-math.pi / 2)
    export = urdf_from_model(truth)
    path: Path = tmp_path_factory.mktemp("mixed") / "ur5_theta2.urdf"
    path.write_text(export.text, encoding="utf-8")
    mapped = replace(model_for_urdf(truth, export, str(path)), angle_unit="rad")
    return with_joint(mapped, 1, theta=-90.0)


def test_one_angle_typed_in_degrees_is_named_not_fitted_modulo_a_turn(mixed_units, reference):
    result = diagnose(mixed_units, reference, samples=50)
    best = result.best
    assert best is not None
    assert best is result.explanations[0]
    assert best.kind == "degrees"
    assert best.title.startswith(
        'θ2 (shoulder_lift) is in degrees but was read as radians (angle_unit = "rad")'
    )
    [change] = best.changes
    assert change.field == "joint[1].theta"
    assert (change.old, change.new) == (-90.0, pytest.approx(-math.pi / 2, abs=1e-15))
    # The whole-file hypothesis would ruin the α that are radians: not proposed.
    assert DEGREES_READ_AS_RADIANS not in [e.title for e in result.explanations]
    # Nothing proposes -89.5354 rad (-90 moved to the nearest angle ≡ -90° modulo a turn).
    news = [c.new for e in result.explanations for c in e.changes if c.field == "joint[1].theta"]
    assert all(abs(new + 89.5354) > 1e-3 for new in news)


def test_a_single_angle_fit_that_lands_on_its_degrees_says_so(mixed_units, reference):
    q = diagnosis_configurations(mixed_units, 30, 0)
    problem = Problem.build(mixed_units, reference, q, ("base", "tool0"), (1e-6, 1e-6))
    [theta2] = [e for e in fit_single_parameters(problem) if e.explains]
    [change] = theta2.changes
    assert change.field == "joint[1].theta"
    # -90 rad moved to the nearest angle that is -90° modulo a turn: -89.5354 rad.
    assert change.new == pytest.approx(-math.pi / 2 - 14 * 2 * math.pi, abs=1e-6)
    assert "-90 is in degrees but was read as radians" in change.note


def test_radians_read_as_degrees_is_named(reference):
    good = load_model("ur5")
    # A file in radians with angle_unit = "deg": each angle is read as its number of degrees.
    joints = tuple(replace(j, alpha=math.radians(j.alpha)) for j in good.joints)
    frames = {
        name: replace(
            spec, offset=Offset(spec.offset.xyz, tuple(map(math.radians, spec.offset.rpy)))
        )
        for name, spec in good.frames.items()
    }
    bad = replace(good, joints=joints, frames=frames, angle_unit="deg")
    best = diagnose(bad, reference, samples=30).best
    assert best is not None
    assert best.kind == "degrees"
    assert best.title == (
        'the table\'s angles are in radians but were read as degrees: set angle_unit = "rad"'
    )


def test_a_fit_on_the_spread_configurations_is_judged_on_all_of_them():
    # A long recording's kept rows: more configurations than a fit evaluates at each step.
    from fkcheck.diagnose.problem import SPREAD_CONFIGURATIONS
    from tests.rtde_cases import poses_of

    ur5 = load_model("ur5")
    q = np.random.default_rng(7).uniform(-3, 3, (SPREAD_CONFIGURATIONS + 76, 6))
    d1 = ur5.joints[0].d + 3e-4
    reference = poses_of(with_joint(ur5, 0, d=d1), q)  # the tests' composition, not the core
    problem = Problem(ur5, "recording", "base", "tool0", q, reference, 1e-6, 1e-6)
    spread = problem.spread()
    assert spread.q.shape[0] == SPREAD_CONFIGURATIONS
    np.testing.assert_array_equal(spread.q[[0, -1]], q[[0, -1]])  # from first to last
    [fitted] = [e for e in fit_single_parameters(problem) if e.explains]
    assert [(c.field, c.new) for c in fitted.changes] == [("joint[0].d", pytest.approx(d1))]
    # One row the fit never saw, 1 mm further off: the same fit no longer explains.
    unseen = next(k for k in range(q.shape[0]) if not (spread.q == q[k]).all(axis=1).any())
    moved = reference.copy()
    moved[unseen, 2, 3] += 1e-3
    problem = Problem(ur5, "recording", "base", "tool0", q, moved, 1e-6, 1e-6)
    assert not [e for e in fit_single_parameters(problem) if e.explains]
    few = problem.spread(2 * q.shape[0])
    assert few is problem
