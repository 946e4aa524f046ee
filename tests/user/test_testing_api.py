"""fkcheck.testing: assert_pose_close and assert_fk_matches, and what their messages say."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from fkcheck.core.geometry import matrix_from_xyz_rpy
from fkcheck.model.read import load_model
from fkcheck.testing import assert_fk_matches, assert_pose_close
from tests.user.userrepo import WRONG_ALPHA, bad_ur5_text


def _pose(x: float = 0.1, yaw: float = 0.3) -> np.ndarray:
    return matrix_from_xyz_rpy([x, 0.2, 0.3], [0.1, 0.2, yaw])


def test_pose_close_passes_within_tolerance() -> None:
    a = _pose()
    b = a.copy()
    b[0, 3] += 5e-7
    assert_pose_close(a, b)  # 0.5 µm < 1 µm: no exception
    assert_pose_close(np.stack([a, a]), np.stack([b, a]))


def test_pose_close_message_gives_mm_degrees_and_worst_index() -> None:
    a = np.stack([_pose()] * 4)
    b = a.copy()
    b[2, 1, 3] += 0.002  # 2 mm at index 2
    b[3] = _pose(yaw=0.3 + math.radians(1.5))  # 1.5° at index 3
    with pytest.raises(AssertionError) as info:
        assert_pose_close(a, b, tol_pos_m=1e-6, tol_rot_rad=1e-6, err_msg="ur5 tcp")
    text = str(info.value)
    assert text.splitlines()[0] == "ur5 tcp"
    assert "Mismatched poses: 2 / 4 (50%)" in text
    assert "Max position difference: 2.00 mm (2.000e-03 m) at index (2,)" in text
    assert "Max rotation difference: 1.50° (2.618e-02 rad) at index (3,)" in text


def test_pose_close_single_pose_has_no_index() -> None:
    a, b = _pose(), _pose(x=0.1 + 3e-4)
    with pytest.raises(AssertionError, match=r"Max position difference: 0\.300 mm") as info:
        assert_pose_close(a, b)
    assert "index" not in str(info.value)
    assert_pose_close(a, b, tol_pos_m=1e-3)  # within a looser tolerance


def test_pose_close_refuses_shapes_and_nan() -> None:
    with pytest.raises(AssertionError, match=r"shapes \(4, 4\) and \(2, 4, 4\)"):
        assert_pose_close(_pose(), np.stack([_pose()] * 2))
    bad = np.stack([_pose()] * 3)
    bad[1, 0, 0] = np.nan
    with pytest.raises(AssertionError, match=r"actual has NaN or infinite values at index \(1,\)"):
        assert_pose_close(bad, np.stack([_pose()] * 3))
    with pytest.raises(ValueError, match="tol_pos_m must be a finite number"):
        assert_pose_close(_pose(), _pose(), tol_pos_m=-1.0)


def test_fk_matches_returns_the_outcome_when_it_agrees() -> None:
    outcome = assert_fk_matches("ur5", against="rtb-dh", samples=20)
    assert outcome.verdict == "pass"
    assert [b.name for b in outcome.backends] == ["rtb-dh"]


def test_fk_matches_message_names_backend_numbers_worst_q_and_diagnosis(tmp_path: Path) -> None:
    pytest.importorskip("pinocchio")
    bad = tmp_path / "bad.toml"
    bad.write_text(bad_ur5_text(), encoding="utf-8")
    with pytest.raises(AssertionError) as info:
        assert_fk_matches(bad, against="pinocchio-urdf", samples=20)
    lines = str(info.value).splitlines()
    assert lines[0] == "fkcheck ur5: base → tool0: fail — table disagrees"
    assert re.fullmatch(
        r"pinocchio-urdf: fail — max position error \d+ mm, max rotation error 180°"
        r" \(tolerance 0\.00100 mm, 5\.73e-05°; \d+ configurations\)",
        lines[1],
    ), lines[1]
    assert re.fullmatch(r"  worst q: \[(-?\d+\.\d\d°, ){5}-?\d+\.\d\d°\]", lines[3]), lines[3]
    assert lines[4].startswith(f"  diagnosis: {WRONG_ALPHA}")


def test_fk_matches_fails_when_the_backend_is_skipped() -> None:
    # The 2R planar arm has no [urdf]: a URDF backend does not apply, which proves nothing.
    with pytest.raises(AssertionError) as info:
        assert_fk_matches("planar2", against=["rtb-dh", "pinocchio-urdf"], frames=None, samples=5)
    text = str(info.value)
    assert "rtb-dh: pass" in text
    assert re.search(r"pinocchio-urdf: skipped — .*urdf", text), text


def test_assert_fk_matches_uses_the_models_check_and_honours_its_known_differences():
    """jaco2_6s has no tool0 frame, and its URDF differs as its model file records."""
    outcome = assert_fk_matches("jaco2_6s", against="pinocchio-urdf", samples=10)
    (result,) = outcome.backends
    assert result.status == "xfail"
    assert outcome.check.frame_to == load_model("jaco2_6s").check.frame_to
