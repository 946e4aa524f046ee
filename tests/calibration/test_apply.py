"""A UR calibration applied to its nominal model: the table, its provenance, its fit, its effect."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from fkcheck.calibration.apply import FIT_LIMIT_M, apply_calibration
from fkcheck.calibration.effect import calibration_effect
from fkcheck.calibration.ur_files import CalibrationError, read_ur_calibration
from fkcheck.model.read import load_model, model_from_dict
from fkcheck.model.write import model_to_toml
from tests.calibration.ur_test_data import (
    DELTAS,
    Table,
    composed,
    fk,
    write_conf,
    write_kinematics_info,
)

#: Parameters equal to the hand-composed table (m, rad). KinematicsInfo's 15
#: significant digits leave up to 4.5e-13 m on a linearised d2 of 303 m.
TABLE_TOL = 1e-12


def _apply(nominal_name: str, path: Path):
    nominal = load_model(nominal_name)
    return apply_calibration(
        nominal, read_ur_calibration(path), nominal_ref=nominal_name, file_ref=path.name
    )


def _table(model) -> Table:
    js = model.joints
    return Table(
        tuple(j.theta for j in js), tuple(j.a for j in js), tuple(j.d for j in js),
        tuple(j.alpha for j in js),
    )  # fmt: skip


def _assert_same_table(got: Table, want: Table) -> None:
    for field in ("theta", "a", "d", "alpha"):
        np.testing.assert_allclose(
            getattr(got, field), getattr(want, field), rtol=0, atol=TABLE_TOL
        )


@pytest.mark.parametrize("name", sorted(DELTAS))
@pytest.mark.parametrize("form", ["conf", "info"])
def test_calibrated_table_is_the_one_composed_by_hand(tmp_path: Path, name: str, form: str) -> None:
    nominal_name, status = DELTAS[name][:2]
    want = composed(load_model(nominal_name).joints, name)
    if form == "conf":
        path = write_conf(tmp_path / "calibration.conf", name)
    else:
        path = write_kinematics_info(tmp_path / "info.log", want, status)
    result = _apply(nominal_name, path)
    _assert_same_table(_table(result.model), want)
    spec = result.model.calibration
    assert spec is not None
    assert (spec.nominal, spec.file, spec.status) == (nominal_name, path.name, status)
    assert spec.form == ("calibration.conf" if form == "conf" else "KinematicsInfo")
    # Written and read back: the same numbers, the provenance kept, no degree warnings
    # for a linearised table's θ of several radians.
    again = model_from_dict(__import__("tomllib").loads(model_to_toml(result.model)))
    _assert_same_table(_table(again), want)
    assert again.calibration == spec
    assert again.warnings == ()


@pytest.mark.parametrize("name", sorted(DELTAS))
def test_effect_is_what_the_tables_give_composed_by_hand(tmp_path: Path, name: str) -> None:
    nominal_name = DELTAS[name][0]
    nominal = load_model(nominal_name)
    result = _apply(nominal_name, write_conf(tmp_path / "calibration.conf", name))
    q = np.random.default_rng(7).uniform(-np.pi, np.pi, (200, 6))
    effect = calibration_effect(result.model, nominal, q, "world", "tcp")
    ours, theirs = fk(composed(nominal.joints, name), q), fk(_table(nominal), q)
    position = np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=1)
    rotation = Rotation.from_matrix(
        np.einsum("nji,njk->nik", theirs[:, :3, :3], ours[:, :3, :3])
    ).magnitude()
    assert effect.max_position_m == pytest.approx(position.max(), abs=1e-12)
    assert effect.median_position_m == pytest.approx(np.median(position), abs=1e-12)
    assert effect.p95_position_m == pytest.approx(np.percentile(position, 95), abs=1e-12)
    assert effect.max_rotation_rad == pytest.approx(rotation.max(), abs=1e-9)
    assert effect.worst_q == tuple(q[int(np.argmax(position))])
    # UR's test calibrations move the tool by millimetres.
    assert 1e-3 < effect.max_position_m < 1e-2


def test_deltas_of_another_type_do_not_fit(tmp_path: Path) -> None:
    path = write_conf(tmp_path / "calibration.conf", "ur10e-test-a")
    with pytest.raises(
        CalibrationError,
        match=r"does not fit ur5e: the calibrated DH frame 6 is up to .* relative to DH frame 0",
    ):
        _apply("ur5e", path)


def test_full_values_taken_for_deltas_do_not_fit(tmp_path: Path) -> None:
    nominal = load_model("ur10e")
    table = composed(nominal.joints, "ur10e-test-b")
    path = tmp_path / "calibration.conf"
    rows = {"theta": table.theta, "a": table.a, "d": table.d, "alpha": table.alpha}
    path.write_text(
        "[mounting]\n"
        + "".join(f"delta_{k} = [ {', '.join(map(repr, v))}]\n" for k, v in rows.items()),
        encoding="utf-8",
    )
    with pytest.raises(CalibrationError, match="are these deltas, not full values"):
        _apply("ur10e", path)


def test_a_table_that_is_no_ur_arm_is_refused(tmp_path: Path) -> None:
    path = write_conf(tmp_path / "calibration.conf", "ur10-test")
    with pytest.raises(CalibrationError, match=r"cannot apply to 'panda': it has 7 joints"):
        _apply("panda", path)


def test_fit_limit_is_far_above_urs_calibrations_and_far_below_a_wrong_type() -> None:
    # UR's four test calibrations move the tool 3.3-7.9 mm; ur10e-test-a on a UR5e 180 mm.
    assert 0.01 < FIT_LIMIT_M < 0.18


@pytest.mark.parametrize("name", sorted(DELTAS))
def test_a_calibrated_table_is_no_lint_finding_though_the_same_numbers_uncalibrated_are(
    tmp_path: Path, name: str
) -> None:
    from dataclasses import replace

    from fkcheck.calibration.lint import lint_calibrated
    from fkcheck.model.lint import MEASURED_RULES, lint_model

    model = _apply(DELTAS[name][0], write_conf(tmp_path / "calibration.conf", name)).model
    assert lint_calibrated(model) == ([], True)
    # The exemption is what keeps it clean: the same table without it warns.
    bare = lint_model(model)
    assert bare == lint_calibrated(replace(model, calibration=None))[0]
    assert bare
    assert {f.rule for f in bare} <= MEASURED_RULES
    assert all(f.field.startswith("joint[") for f in bare)


def test_a_calibrated_model_is_still_held_to_the_other_rules(tmp_path: Path) -> None:
    from dataclasses import replace

    from fkcheck.calibration.lint import lint_calibrated

    model = _apply("ur10e", write_conf(tmp_path / "calibration.conf", "ur10e-test-a")).model
    wide = replace(
        model, joints=(replace(model.joints[0], limits=(-10.0, 10.0)), *model.joints[1:])
    )
    findings, measured = lint_calibrated(wide)
    assert measured
    assert [(f.rule, f.field) for f in findings] == [("limits", "joint[0].limits")]
