"""``check --jacobian``: every bundled model against the references, and seeded mistakes caught.

The references' own Jacobians (Robotics Toolbox, Pinocchio from DH and from the
URDF) in all three reference frames, and central differences of yourdfpy's
poses, must agree with the core's; backends that get a convention wrong must
fail, with the first disagreeing joint column named.
"""

from __future__ import annotations

import json
import re
import sys

import numpy as np
import pytest

from fkcheck.backends.pinocchio_dh import PinocchioDH
from fkcheck.backends.registry import make_backend
from fkcheck.core.tolerances import FINITE_DIFFERENCE, ROUNDED_URDF, SAME_CHAIN
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.diagnose.jacobian import explain_sample
from fkcheck.engine.jacobian import JacobianSpec
from fkcheck.engine.runner import run_check
from fkcheck.errors import FkcheckError
from fkcheck.model.read import bundled_model_paths, load_model
from tests.paths import DATA_DIR

MODELS = sorted(bundled_model_paths())


def _urdf_models() -> list[str]:
    """Models whose URDF agrees with the table (a recorded known difference would show here too)."""
    return [
        name
        for name in MODELS
        if load_model(name).urdf is not None and not load_model(name).known_differences
    ]


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
def test_every_model_agrees_with_both_dh_references_in_every_reference_frame(name, reference):
    model = load_model(name)
    backends = [make_backend("rtb-dh"), make_backend("pinocchio-dh")]
    check = run_check(
        model,
        backends,
        samples=40,
        seed=3,
        jacobian=True,
        jacobian_reference=reference,
        tol_jacobian=1e-6,
    )
    assert check.verdict == "pass", [(b.name, b.message, b.jacobian) for b in check.backends]
    for b in check.backends:
        assert b.jacobian is not None
        assert b.jacobian.status == "pass", b.jacobian
        assert "its own" not in b.jacobian.method  # the library's call is named
        assert b.jacobian.max_linear_error < SAME_CHAIN
        assert b.jacobian.max_angular_error < SAME_CHAIN


@pytest.mark.parametrize("name", _urdf_models())
@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
def test_urdf_models_agree_with_pinocchio_urdf_and_yourdfpy_differences(name, reference):
    model = load_model(name)
    backends = [make_backend("pinocchio-urdf"), make_backend("yourdfpy-urdf")]
    check = run_check(
        model,
        backends,
        samples=10,
        seed=5,
        jacobian=True,
        jacobian_reference=reference,
        tol_jacobian=1e-6,
    )
    assert check.verdict == "pass", [(b.name, b.message, b.jacobian) for b in check.backends]
    pin, yourdfpy = check.backends
    assert pin.jacobian.max_linear_error < ROUNDED_URDF
    assert pin.jacobian.max_angular_error < ROUNDED_URDF
    assert "central differences" in yourdfpy.jacobian.method
    assert yourdfpy.jacobian.tolerance == max(1e-6, FINITE_DIFFERENCE)
    assert yourdfpy.jacobian.max_linear_error < FINITE_DIFFERENCE
    assert yourdfpy.jacobian.max_angular_error < FINITE_DIFFERENCE


class _Seeded(PinocchioDH):
    """Pinocchio from DH with one convention mistake in its Jacobian."""

    def __init__(self, mistake: str) -> None:
        super().__init__()
        self.mistake = mistake
        self.name = f"seeded-{mistake}"

    def frame_jacobian(self, model, q, frame, reference):
        if self.mistake == "local-for-world-aligned":
            return super().frame_jacobian(model, q, frame, "local")
        if self.mistake == "tool-offset-left-out":
            return super().frame_jacobian(model, q, "tool0", reference)
        jac = np.array(super().frame_jacobian(model, q, frame, reference))
        if self.mistake == "angular-first":
            return np.concatenate([jac[:, 3:], jac[:, :3]], axis=1)
        if self.mistake == "column-3-flipped":
            jac[:, :, 2] *= -1
            return jac
        raise AssertionError(self.mistake)


@pytest.mark.parametrize(
    ("mistake", "first_column", "named"),
    [
        ("local-for-world-aligned", 0, r"in the frame's own axes \(local.*where world-aligned"),
        ("angular-first", 0, r"rows are angular first, then linear"),
        ("column-3-flipped", 2, r"joint 3 \(elbow\) has the opposite sign"),
        ("tool-offset-left-out", 0, r"offset of \(0\.000, 0\.000, -?100\.000\) mm"),
    ],
)
def test_seeded_mistakes_fail_and_are_named(mistake, first_column, named):
    # ur5 with a 10 cm tool so that the TCP and tool0 differ.
    model = load_model("ur5")
    from dataclasses import replace

    from fkcheck.model.types import Offset

    model = replace(model, tool=Offset(xyz=(0.0, 0.0, 0.1)))
    check = run_check(
        model,
        [make_backend("rtb-dh"), _Seeded(mistake)],
        samples=30,
        frame_from="base",
        frame_to="tcp",
        jacobian=True,
        jacobian_reference="world-aligned",
        tol_jacobian=1e-6,
        explain_jacobian=explain_sample,
    )
    good, bad = check.backends
    assert good.status == "pass"
    assert good.jacobian.status == "pass"
    assert bad.status == "pass"  # the poses agree
    assert bad.jacobian.status == "fail"
    assert bad.jacobian.first_bad_column == first_column
    assert f"first column to disagree: joint {first_column + 1}" in bad.jacobian.message
    assert re.search(named, bad.jacobian.diagnosis), bad.jacobian.diagnosis
    assert good.jacobian.diagnosis == ""  # only a failure is diagnosed
    assert check.verdict == "fail"
    assert check.evidence.implementation.status == "verified"  # what the poses proved stays


def test_a_flipped_column_leaves_the_other_columns_in_agreement():
    check = run_check(
        load_model("panda"),
        [_Seeded("column-3-flipped")],
        samples=30,
        jacobian=True,
        jacobian_reference="local",
        tol_jacobian=1e-6,
    )
    j = check.backends[0].jacobian
    columns = np.maximum(j.column_linear, j.column_angular)
    assert columns[2] > 0.1
    assert np.delete(columns, 2).max() < SAME_CHAIN


def test_a_moving_from_frame_is_refused_before_anything_runs():
    with pytest.raises(FkcheckError, match=r"moves with joints 1–3.*fixed to the base"):
        run_check(
            load_model("panda"),
            [make_backend("rtb-dh")],
            samples=5,
            frame_from="panda_link3",
            jacobian=True,
            jacobian_reference="world-aligned",
            tol_jacobian=1e-6,
        )


def test_measured_poses_have_no_jacobian_and_say_why():
    check = run_check(
        load_model("ur5"),
        [make_backend(f"poses:{DATA_DIR / 'ur5_pendant.csv'}")],
        jacobian=True,
        jacobian_reference="world-aligned",
        tol_jacobian=1e-6,
    )
    (measured,) = check.backends
    assert measured.jacobian.status == "skipped"
    assert "no neighbouring configurations" in measured.jacobian.message


def test_a_jacobian_that_raises_is_that_backends_jacobian_error_and_the_poses_stand():
    class Broken(PinocchioDH):
        name = "broken-jacobian"

        def frame_jacobian(self, model, q, frame, reference):
            raise RuntimeError("no Jacobian today")

    check = run_check(
        load_model("ur5"),
        [Broken()],
        samples=5,
        jacobian=True,
        jacobian_reference="world",
        tol_jacobian=1e-6,
    )
    (b,) = check.backends
    assert b.status == "pass"
    assert b.jacobian.status == "error"
    assert b.jacobian.message == "RuntimeError: no Jacobian today"
    assert check.verdict == "error"


def test_a_jacobian_of_the_wrong_shape_is_an_error_naming_both_shapes():
    class Wrong(PinocchioDH):
        name = "wrong-shape"

        def frame_jacobian(self, model, q, frame, reference):
            return np.zeros((q.shape[0], 6, model.dof + 1))

    check = run_check(
        load_model("ur5"),
        [Wrong()],
        samples=5,
        jacobian=True,
        jacobian_reference="world",
        tol_jacobian=1e-6,
    )
    assert check.backends[0].jacobian.status == "error"
    assert "shape (" in check.backends[0].jacobian.message
    assert ", 6, 7)" in check.backends[0].jacobian.message


def test_without_jacobian_nothing_is_compared():
    check = run_check(load_model("ur5"), [make_backend("rtb-dh")], samples=5)
    assert check.jacobian is None
    assert check.backends[0].jacobian is None


def test_json_junit_and_markdown_carry_the_jacobian(tmp_path):
    from fkcheck.report.json_report import result_to_dict
    from fkcheck.report.junit import junit_xml
    from fkcheck.report.markdown import markdown_summary

    check = run_check(
        load_model("ur5"),
        [make_backend("rtb-dh"), _Seeded("column-3-flipped")],
        samples=10,
        jacobian=True,
        jacobian_reference="world-aligned",
        tol_jacobian=1e-6,
    )
    doc = json.loads(json.dumps(result_to_dict(check)))
    assert doc["jacobian"]["reference"] == "world-aligned"
    assert doc["jacobian"]["tolerance"] == 1e-6
    good, bad = doc["backends"]
    assert good["jacobian"]["status"] == "pass"
    assert bad["jacobian"]["status"] == "fail"
    assert bad["jacobian"]["first_disagreeing_joint"] == "elbow"
    assert [c["joint"] for c in bad["jacobian"]["columns"]][2] == "elbow"
    assert bad["jacobian"]["columns"][2]["max_angular"] == pytest.approx(2.0)
    xml = junit_xml(check).decode()
    assert 'name="seeded-column-3-flipped jacobian tool0 (world-aligned)"' in xml
    assert "seeded-column-3-flipped&apos;s Jacobian disagrees" in xml or (
        "seeded-column-3-flipped's Jacobian disagrees" in xml
    )
    assert 'failures="1"' in xml
    md = markdown_summary([check])
    assert "Jacobian of tool0 (world-aligned)" in md
    assert "| seeded-column-3-flipped | " in md


def test_the_html_report_has_the_per_column_section(tmp_path):
    from fkcheck.report.html import write_html

    check = run_check(
        load_model("ur5"),
        [make_backend("rtb-dh"), _Seeded("column-3-flipped")],
        samples=10,
        jacobian=True,
        jacobian_reference="world-aligned",
        tol_jacobian=1e-6,
    )
    path = write_html(check, tmp_path / "r.html", plots=False)
    html = path.read_text()
    assert 'id="jacobian"' in html
    assert 'id="jacobian-columns"' in html
    assert html.count('data-first="1"') == 1
    assert "3 elbow" in html


@pytest.mark.parametrize("reference", ["local", "world"])
@pytest.mark.parametrize("backend", ["rtb-dh", "yourdfpy-urdf"])
def test_a_core_mistake_in_the_local_or_world_jacobian_fails_the_check(
    monkeypatch, reference, backend
):
    """The core's own local/world code is what is compared, not its world-aligned one moved."""
    import fkcheck.core.jacobian as core

    core_jacobian = core.jacobian

    def broken(*args, **kwargs):
        out = core_jacobian(*args, **kwargs)
        if kwargs.get("reference", "world-aligned") != "world-aligned":
            out = out.copy()
            out[:, 3:, 0] += 0.5  # a wrong angular row of joint 1
        return out

    monkeypatch.setattr(core, "jacobian", broken)
    check = run_check(
        load_model("ur5"),
        [make_backend(backend)],
        samples=5,
        jacobian=True,
        jacobian_reference=reference,
        tol_jacobian=1e-6,
    )
    assert check.backends[0].jacobian.status == "fail"
    assert check.backends[0].jacobian.first_bad_column == 0
    assert check.verdict == "fail"


@pytest.mark.parametrize("tol", [float("nan"), 0.0, -1e-6, float("inf"), 1e300, 0.0100001])
def test_a_jacobian_tolerance_out_of_its_range_is_refused(tol):
    with pytest.raises(FkcheckError, match=r"^Jacobian tolerance: must be > 0 and at most 0\.01 "):
        JacobianSpec("world-aligned", tol)


def test_a_recorded_known_difference_makes_the_jacobian_an_expected_failure_too():
    model = load_model("jaco2_6s")
    entry = model.known_differences[0]
    check = run_check(
        model,
        [make_backend("pinocchio-urdf"), make_backend("pinocchio-dh")],
        samples=10,
        jacobian=True,
        jacobian_reference="world-aligned",
        tol_jacobian=1e-6,
    )
    urdf, dh = check.backends
    assert urdf.status == "xfail"
    assert urdf.jacobian.status == "xfail"  # the 0.05 mm wrist lengths move the Jacobian too
    assert urdf.jacobian.message.startswith(f"expected failure, known difference: {entry.finding}")
    assert dh.jacobian.status == "pass"
    assert check.verdict == "pass"


@pytest.mark.parametrize("name", ["xarm7", "jaco2_6s", "baxter_left"])
def test_a_wrong_core_jacobian_is_not_excused_by_a_pose_record(name, monkeypatch):
    """The record bounds the Jacobian too: a flipped column of the core's fails."""
    import fkcheck.engine.jacobian as engine_jacobian

    real = engine_jacobian.frame_jacobian

    def flipped(model, q, frame, reference):
        jac = np.array(real(model, q, frame, reference))
        jac[..., 2] *= -1
        return jac

    monkeypatch.setattr(engine_jacobian, "frame_jacobian", flipped)
    check = run_check(
        load_model(name), [make_backend("pinocchio-urdf")], samples=10,
        jacobian=True, jacobian_reference="world-aligned", tol_jacobian=1e-6,
    )  # fmt: skip
    (urdf,) = check.backends
    assert urdf.status == "xfail"  # the poses differ as recorded
    assert urdf.jacobian.status == "fail"
    assert urdf.jacobian.message.startswith("beyond the recorded known difference (linear")
    assert check.verdict == "fail"


def test_a_known_difference_applies_only_at_the_models_own_tolerances():
    """jaco2's recorded 0.1 mm is inside 1 mm: that is a pass, not a stale record."""
    check = run_check(
        load_model("jaco2_6s"), [make_backend("pinocchio-urdf")], samples=10, tol_pos_m=1e-3
    )
    assert check.backends[0].status == "pass"
    assert check.verdict == "pass"


def test_a_jacobian_only_failure_is_named_by_the_verdict_line_and_the_annotations():
    from fkcheck.report.annotations import github_annotations
    from fkcheck.report.page import verdict_line

    check = run_check(
        load_model("ur5"),
        [make_backend("rtb-dh"), _Seeded("column-3-flipped")],
        samples=10,
        jacobian=True,
        jacobian_reference="world-aligned",
        tol_jacobian=1e-6,
    )
    line = verdict_line(check)
    assert line.startswith("2 of 2 backends that ran agree with the in-house core")
    assert "the Jacobian of 1 disagrees: seeded-column-3-flipped" in line
    (annotation,) = github_annotations(check, ())
    assert annotation.startswith("::error ")
    assert "seeded-column-3-flipped's Jacobian fails" in annotation
    assert "first column to disagree: joint 3 (elbow)" in annotation


# --- a pose-only backend whose poses are too coarse to differentiate -------------------


class _PosesOnly(PinocchioDH):
    """Pinocchio's poses of ``model``, rounded to ``decimals``; no Jacobian of its own."""

    name = "poses-only"

    def __init__(self, decimals: int | None = None, a2_m: float = 0.0) -> None:
        super().__init__()
        self.decimals, self.a2_m = decimals, a2_m

    def frame_jacobian(self, model, q, frame, reference):
        return None  # differentiated by the engine

    def frame_poses(self, model, q, frames):
        from dataclasses import replace

        if self.a2_m:  # a table that differs a little: a smooth, real difference
            joints = list(model.joints)
            joints[1] = replace(joints[1], a=joints[1].a + self.a2_m)
            model = replace(model, joints=tuple(joints))
        poses = super().frame_poses(model, q, frames)
        return poses if self.decimals is None else np.round(poses, self.decimals)


def test_poses_too_coarse_to_differentiate_are_an_error_not_a_wrong_jacobian():
    # Rounded to 7 decimals the poses agree (5e-8 m < 1e-6 m); their differences
    # over a 1e-6 step are off by up to ~0.05 m/rad: no finding, and no pass.
    check = run_check(
        load_model("ur5"), [_PosesOnly(decimals=7)], samples=20,
        jacobian=True, jacobian_reference="world-aligned", tol_jacobian=1e-6,
        explain_jacobian=explain_sample,
    )  # fmt: skip
    (b,) = check.backends
    assert b.status == "pass"
    assert b.jacobian.status == "error"
    assert b.jacobian.message.startswith(
        "Jacobian (world-aligned) not compared: the backend's poses are too coarse"
    )
    stray = re.search(r"smooth chain by up to (\S+) m / (\S+) rad", b.jacobian.message)
    assert stray is not None
    assert 1e-8 < float(stray.group(1)) < 4e-7  # rounding to 7 decimals: ≤ 4 × 5e-8
    assert "print every digit (%.17g, repr)" in b.jacobian.message
    assert check.verdict == "error"


def test_coarse_poses_far_from_the_origin_are_an_error_in_the_world_reference_too():
    # world: v + p × ω, so the angular noise, times |p| = 10 m, reaches the linear part
    # (counted in the allowance; at 10 m the factor of 3 alone would also cover it).
    from dataclasses import replace

    from fkcheck.model.types import Offset

    model = replace(load_model("ur5"), base=Offset(xyz=(10.0, 0.0, 0.0)))
    check = run_check(
        model, [_PosesOnly(decimals=7)], samples=20, frame_from="world", frame_to="tcp",
        jacobian=True, jacobian_reference="world", tol_jacobian=1e-6,
    )  # fmt: skip
    assert check.backends[0].jacobian.status == "error", check.backends[0].jacobian.message
    assert "too coarse to differentiate" in check.backends[0].jacobian.message


def test_a_wrong_jacobian_is_not_excused_by_a_few_rough_configurations(monkeypatch):
    """A backend rough only at some configurations excuses only those, not the run."""
    import fkcheck.engine.jacobian as engine_jacobian

    real = engine_jacobian.frame_jacobian

    def off(model, q, frame, reference):
        jac = np.array(real(model, q, frame, reference))
        jac[..., :3, 1] *= 1.2  # the core's column 2, linear part, 20 % off
        return jac

    class RoughAtZero(_PosesOnly):
        def frame_poses(self, model, q, frames):
            poses = super().frame_poses(model, q, frames)
            near = np.all(np.abs(q) < 1e-3, axis=1)  # rough only around q = 0
            poses[:, near, :3, 3] = np.round(poses[:, near, :3, 3], 4)
            return poses

    monkeypatch.setattr(engine_jacobian, "frame_jacobian", off)
    check = run_check(
        load_model("ur5"), [RoughAtZero()], samples=40,
        jacobian=True, jacobian_reference="world-aligned", tol_jacobian=1e-6,
    )  # fmt: skip
    assert check.backends[0].jacobian.status == "fail", check.backends[0].jacobian.message


def test_a_smooth_backend_whose_jacobian_differs_still_fails():
    # a2 longer by 0.5 µm: poses within 1e-6 m, the Jacobian off by ~5e-7 m/rad > 1e-7.
    check = run_check(
        load_model("ur5"), [_PosesOnly(a2_m=5e-7)], samples=20,
        jacobian=True, jacobian_reference="world-aligned", tol_jacobian=FINITE_DIFFERENCE,
    )  # fmt: skip
    (b,) = check.backends
    assert b.status == "pass"
    assert b.jacobian.status == "fail", b.jacobian.message
    assert 2e-7 < b.jacobian.max_linear_error < 1e-6


def test_a_program_printing_seven_digits_is_too_coarse_for_its_jacobian():
    from fkcheck.backends.command import CommandBackend
    from fkcheck.backends.registry import BackendOptions
    from tests.paths import PLUGINS_DIR

    spec = f"{sys.executable} {PLUGINS_DIR / 'fk_stdio.py'} seven-digits"
    program = CommandBackend(spec, BackendOptions(timeout_s=60.0))
    check = run_check(
        load_model("ur5"), [program], samples=10, frame_from="world", frame_to="tcp",
        jacobian=True, jacobian_reference="world-aligned", tol_jacobian=1e-6,
    )  # fmt: skip
    (b,) = check.backends
    assert b.status == "pass"  # 7 digits: poses within 1e-6
    assert b.jacobian.status == "error"
    assert "too coarse to differentiate" in b.jacobian.message
