"""Ranking: one true cause above an over-fit; a recorded known difference counts as explained."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import pytest

import fkcheck.backends.registry as registry
from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.diagnose import diagnose, format_text
from fkcheck.diagnose.findings import Change, Explanation, rank
from fkcheck.diagnose.paramfit import explain_parameter_fit
from fkcheck.diagnose.problem import Problem, Residual, diagnosis_configurations
from fkcheck.model.types import Model
from tests.paths import REPO_ROOT

TOL = (1e-6, 1e-6)


@pytest.fixture(scope="module")
def reference():
    return registry.make_backend("pinocchio-urdf")


def with_joint(model: Model, index: int, **changes: object) -> Model:
    joints = list(model.joints)
    joints[index] = replace(joints[index], **changes)  # type: ignore[arg-type]
    return replace(model, joints=tuple(joints))


def explanation(kind, residual, explains, numbers) -> Explanation:
    return Explanation(kind, f"{kind} {numbers}", residual, explains, numbers=numbers)


def test_rank_puts_fewer_changed_numbers_first_at_equal_residual():
    before = Residual(0.1, 0.1)
    overfit = explanation("fit", Residual(1e-14, 1e-14), True, 29)
    one = explanation("parameter", Residual(4e-7, 1e-9), True, 1)  # both explain
    assert rank([overfit, one], before, TOL) == (one, overfit)
    # Partial ones: equal residuals (within the tolerances) by fewer numbers, else by residual.
    wide = explanation("fit", Residual(0.02, 0.01), False, 12)
    narrow = explanation("parameter", Residual(0.02 + 5e-7, 0.01), False, 1)
    closer = explanation("fit", Residual(0.01, 0.005), False, 12)
    assert rank([wide, closer, narrow], before, TOL) == (closer, narrow, wide)
    # Without a tolerance to call them equal, the smaller residual first.
    assert rank([narrow, wide], before) == (wide, narrow)


def test_an_explanation_counts_its_numbers():
    residual = Residual(0.0, 0.0)
    assert explanation("degrees", residual, True, None).changed == 1  # a setting
    assert explanation("known", residual, True, 0).changed == 0


@pytest.mark.parametrize(
    ("joint", "param", "wrong"),
    [(3, "d", 0.1113), (1, "a", -0.4262), (3, "alpha", "sign"), (4, "alpha", "sign")],
)
def test_one_wrong_number_is_the_top_explanation_above_a_fit_of_everything(
    joint, param, wrong, reference
):
    good = load_model("ur5")
    value = -getattr(good.joints[joint], param) if wrong == "sign" else wrong
    bad = with_joint(good, joint, **{param: value})
    result = diagnose(bad, reference, samples=50)
    best = result.best
    assert best is not None
    assert best is result.explanations[0]
    assert [c.field for c in best.changes] == [f"joint[{joint}].{param}"]
    assert best.changes[0].new == pytest.approx(getattr(good.joints[joint], param), abs=1e-9)
    assert best.changed == 1
    # The least-squares fit of every parameter, added: ranked below. (A length it
    # matches, moving as many numbers or more — d2…d4 along UR's parallel axes; a
    # sign, π away, it does not reach in its budget.)
    q = diagnosis_configurations(bad, 50, 0)
    problem = Problem.build(bad, reference, q, ("base", "tool0"), TOL)
    [fit] = explain_parameter_fit(problem)
    assert fit.explains == (param != "alpha")
    assert fit.changed >= 1
    ranked = rank([fit, *result.explanations], result.before, TOL)
    assert ranked[0] is best
    assert fit not in ranked[:1]


@pytest.mark.parametrize("name", ["jaco2_6s", "xarm7"])
def test_a_recorded_known_difference_is_named_first_above_the_fit(name, reference, capsys):
    model = load_model(name)
    [known] = model.known_differences
    result = diagnose(model, reference, samples=50)
    assert not result.agrees
    first = result.explanations[0]
    assert first.kind == "known"
    assert first.explains
    assert first.changed == 0
    assert known.finding in first.title
    # The fit still says where the recorded difference comes from, below it.
    fits = [e for e in result.explanations if e.kind == "fit"]
    assert fits
    assert fits[0].explains
    assert result.explanations.index(fits[0]) > 0
    assert "1. [known] the model file records this difference with pinocchio-urdf" in (
        format_text(result)
    )
    # Only where the check applies the record: the model's pair and tolerances.
    other = diagnose(model, reference, samples=20, tol_pos_m=2e-6)
    assert all(e.kind != "known" for e in other.explanations)


def test_beyond_a_known_difference_one_wrong_number_ranks_above_the_overfit(reference):
    model = load_model("xarm7")  # records α1…α6 written as ±1.5708 in the URDF
    [known] = model.known_differences
    bad = with_joint(model, 2, d=0.303)  # d3 10 mm long
    result = diagnose(bad, reference, samples=50)
    assert result.before.position_m > known.max_position_m
    best = result.best
    assert best is not None
    assert best is result.explanations[0]
    assert [c.field for c in best.changes] == ["joint[2].d"]
    assert best.changes[0].new == pytest.approx(0.293, abs=known.max_position_m)
    # It leaves the recorded difference, not nothing: said, and counted as explaining.
    assert best.residual.position_m > result.tol_pos_m
    assert any("within the difference the model file records" in line for line in best.details)
    [fit] = [e for e in result.explanations if e.kind == "fit"]
    assert fit.explains
    assert fit.changed > 1
    assert result.explanations.index(fit) > 0


def test_beyond_a_known_difference_degrees_read_as_radians_ranks_above_the_overfit(
    reference, tmp_path
):
    """Baxter's 7-joint table: the over-fit moves more than a dozen numbers."""
    text = (REPO_ROOT / "models" / "baxter_left.toml").read_text(encoding="utf-8")
    path: Path = tmp_path / "baxter_left.toml"
    path.write_text(text.replace('angle_unit = "deg"', 'angle_unit = "rad"'), encoding="utf-8")
    result = diagnose(load_model(path), reference, samples=50)
    best = result.best
    assert best is not None
    assert best is result.explanations[0]
    assert best.kind == "degrees"
    assert best.residual.position_m > 0.05  # the recorded 61 mm is left
    [fit] = [e for e in result.explanations if e.kind == "fit"]
    assert fit.explains
    assert fit.changed > 10
    assert result.explanations.index(fit) > 0


def test_json_says_how_many_numbers_each_explanation_changes(tmp_path, capsys):
    out = tmp_path / "diag.json"
    assert main(["diagnose", "jaco2_6s", "--samples", "20", "--json", str(out)]) == 0
    data = json.loads(out.read_text(encoding="utf-8"))
    first, *rest = data["explanations"]
    assert (first["kind"], first["numbers_changed"]) == ("known", 0)
    assert all(e["numbers_changed"] >= 1 for e in rest)


def test_a_sign_flip_is_said_as_one_not_as_a_difference_of_180_degrees():
    flip = Change("joint[3].alpha", "α4 (wrist_1)", -math.pi / 2, math.pi / 2, angle=True)
    assert flip.sign_flip
    assert flip.text() == (
        "α4 (wrist_1) = -90° (-1.5708 rad) here, 90° (1.5708 rad) would match: the sign flipped"
    )
    length = Change("joint[0].d", "d1 (shoulder_pan)", -0.089159, 0.089159, angle=False)
    assert length.text().endswith("0.089159 would match: the sign flipped")
    # A half turn from 0 is a difference, not a sign flip.
    turn = Change("joint[1].alpha", "α2 (shoulder)", 0.0, math.pi, angle=True)
    assert not turn.sign_flip
    assert turn.text().endswith("would match, Δ = +180.0000°")
    shift = Change("joint[0].d", "d1 (shoulder_pan)", 0.089459, 0.089159, angle=False)
    assert shift.text() == "d1 (shoulder_pan) = 0.089459 here, 0.089159 would match, Δ = -0.300 mm"


def test_a_rounded_radian_reads_apart_from_the_value_that_matches(tmp_path, capsys):
    """θ2 = -1.5708 in a radian file against a URDF at exactly -π/2: the two must read apart.

    (They read "-90° (-1.5708 rad) here, -90° (-1.5708 rad) would match".)
    """
    from tests.vendor_arms import FANUC, VendorArm, write_arm

    arm = VendorArm(FANUC.name, FANUC.rows, (), {})
    path = write_arm(arm, tmp_path, (0.0, 0.0, 180.0), unit="rad", rounded=("J2",))
    assert "theta = -1.5708\n" in path.read_text(encoding="utf-8")
    assert main(["diagnose", str(path), "--samples", "20"]) == 0
    out = capsys.readouterr().out
    assert "1. [parameter] one number differs: θ2 (J2)\n" in out
    assert (
        "θ2 (J2) = -90.0002° (-1.5708 rad) here, -90° (-1.570796 rad) would match, Δ = +0.0002°"
        in out
    )
    for line in out.splitlines():  # no line shows the same value twice
        if " here, " in line and "would match" in line:
            here, match = line.split(" = ", 1)[1].split(" here, ")
            assert here != match.split(" would match")[0], line
