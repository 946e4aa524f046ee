"""fkcheck.testing: assert_pose_close and assert_fk_matches, and what their messages say."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from fkcheck.core.geometry import matrix_from_xyz_rpy
from fkcheck.errors import ToleranceError
from fkcheck.model.read import load_model
from fkcheck.model.types import Offset
from fkcheck.model.write import model_to_toml
from fkcheck.testing import assert_fk_matches, assert_pose_close
from tests.helpers import ur5_ros1
from tests.paths import REPO_ROOT
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
    with pytest.raises(ValueError, match=r"^tol_pos_m: must be > 0 and at most 0\.01 m"):
        assert_pose_close(_pose(), _pose(), tol_pos_m=-1.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"tol_pos_m": 1000.0}, r"^tol_pos_m: must be > 0 and at most 0\.01 m .*, got 1000$"),
        ({"tol_pos_m": 0.0}, r"^tol_pos_m: must be > 0 .*, got 0$"),
        ({"tol_rot_rad": 10.0}, r"^tol_rot_rad: must be > 0 and at most 0\.1 rad .*, got 10$"),
        ({"tol_rot_rad": math.pi}, r"^tol_rot_rad: .*at π accepts every rotation\), got 3\.14159$"),
        ({"tol_rot_rad": float("nan")}, r"^tol_rot_rad: .*, got nan$"),
    ],
)
def test_pose_close_tolerances_are_bounded(kwargs, match):
    with pytest.raises(ToleranceError, match=match):  # a ValueError too
        assert_pose_close(_pose(), _pose(), **kwargs)
    assert_pose_close(_pose(), _pose(x=0.105), tol_pos_m=0.01, tol_rot_rad=0.1)  # the bounds


def _scaled(T: np.ndarray) -> np.ndarray:
    out = T.copy()
    out[:3, :3] *= 2.0
    return out


def _sheared(T: np.ndarray) -> np.ndarray:
    out = T.copy()
    out[:3, :3] = out[:3, :3] @ np.array([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    return out


def _bottom_row(T: np.ndarray) -> np.ndarray:
    out = T.copy()
    out[3] = 5.0
    return out


def _reflected(T: np.ndarray) -> np.ndarray:
    out = T.copy()
    out[:3, 2] *= -1.0
    return out


NOT_RIGID = {
    "scaled": (_scaled, r"its 3×3 part is a rotation scaled by 2$"),
    "sheared": (
        _sheared,
        r"its 3×3 part is sheared or unevenly scaled \(singular values 1\.281, 1, 0\.7808\), "
        r"not a rotation$",
    ),
    "bottom_row": (_bottom_row, r"its bottom row is \[5, 5, 5, 5\], not \[0, 0, 0, 1\]$"),
    "reflected": (_reflected, r"its 3×3 part has det -1: a reflection, not a rotation$"),
}


@pytest.mark.parametrize("case", sorted(NOT_RIGID))
def test_pose_close_refuses_a_matrix_that_is_not_a_rigid_transform(case):
    # Before, a matrix scaled by 2, a sheared one and one ending [5, 5, 5, 5] passed.
    make, defect = NOT_RIGID[case]
    good = _pose()
    with pytest.raises(AssertionError, match=r"^Poses not comparable: desired is not a rigid "
                       r"transform: " + defect):  # fmt: skip
        assert_pose_close(good, make(good), tol_pos_m=0.01, tol_rot_rad=0.1)
    batch = np.stack([good, good, make(good)])
    with pytest.raises(AssertionError, match=r"^ur5\nPoses not comparable: actual is not a rigid "
                       r"transform at index \(2,\): " + defect):  # fmt: skip
        assert_pose_close(batch, np.stack([good] * 3), err_msg="ur5")


def test_pose_close_accepts_matrices_as_rigid_as_their_printed_digits():
    # A 3×3 part typed with six decimals is within 2e-6 of a rotation, with four within 2e-4:
    # rigid enough at a rotation tolerance of that size; a scale beyond it is refused.
    exact = _pose()
    typed = np.round(exact, 6)
    assert_pose_close(typed, exact, tol_pos_m=1e-6, tol_rot_rad=2e-6)
    assert_pose_close(np.round(exact, 4), exact, tol_pos_m=1e-4, tol_rot_rad=3e-4)
    slightly = exact.copy()
    slightly[:3, :3] *= 1.0 + 1e-4
    with pytest.raises(AssertionError, match=r"rotation scaled by 1\.0001$"):
        assert_pose_close(exact, slightly, tol_rot_rad=1e-5)
    assert_pose_close(exact, slightly, tol_rot_rad=1e-3)  # within the precision asked for


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
        r"pinocchio-urdf: fail — max position error \d+ mm \(\S+ m\), max rotation error 180° \(\S+"
        r" rad\); \d+ of \d+ configurations beyond tolerance \(1e-06 m, 1e-06 rad\)",
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


#: A user's test file: a table whose d1 the base frame's offset could absorb, checked with
#: ``require=["table"]``, and two poses 1 mm apart.
USER_TESTS = """\
import numpy as np
from fkcheck.testing import assert_fk_matches, assert_pose_close


def test_arm_table():
    assert_fk_matches("hidden.toml", against="pinocchio-urdf", samples=20, require=["table"])


def test_two_poses():
    moved = np.eye(4)
    moved[0, 3] = 1e-3
    assert_pose_close(np.eye(4), moved)
"""


def test_failures_in_a_users_pytest_run_are_short_and_name_the_number(tmp_path: Path) -> None:
    # Each failure was about 70 lines, most of them fkcheck's own source (no
    # __tracebackhide__), and "1 not identifiable" did not say which number.
    pytest.importorskip("pinocchio")
    model = ur5_ros1()
    frames = dict(model.frames)
    frames["base"] = replace(frames["base"], offset=Offset((0.0, 0.0, 0.01)))
    joints = list(model.joints)
    joints[0] = replace(joints[0], d=joints[0].d + 0.01)  # the base frame's offset absorbs it
    hidden = replace(model, frames=frames, joints=tuple(joints))
    (tmp_path / "hidden.toml").write_text(model_to_toml(hidden), encoding="utf-8")
    (tmp_path / "test_arm.py").write_text(USER_TESTS, encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTEST_", "GITHUB_"))}
    env["PYTHONPATH"] = str(REPO_ROOT / "src")
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", "test_arm.py"],
        cwd=tmp_path, env=env, capture_output=True, text=True, check=False, timeout=300,
    )  # fmt: skip
    out = proc.stdout
    assert proc.returncode == 1, out + proc.stderr
    assert "2 failed" in out
    assert (
        "E       table PARTLY verified: pinocchio-urdf agrees (evidence independent of the "
        "table), but d1 not identifiable (the offset of [frames.base] could absorb it) — "
        "required (require = table)"
    ) in out.splitlines()
    assert "E       Max position difference: 1.00 mm (1.000e-03 m)" in out.splitlines()
    # No line of fkcheck's own code: the user's line, then the message.
    assert "testing.py" not in out
    assert "raise AssertionError" not in out
    failures = re.split(r"^=+ short test summary info", out, flags=re.M)[0]
    sections = re.split(r"^_{3,} test_\w+ _{3,}$", failures, flags=re.M)[1:]
    assert len(sections) == 2
    for section in sections:
        lines = section.strip().splitlines()
        assert len(lines) <= 15, section
        assert re.fullmatch(r"test_arm\.py:\d+: AssertionError", lines[-1]), section


_XDIST_WORKER = """
import os
from fkcheck.process.threads import thread_limit
from fkcheck.testing import assert_fk_matches

assert thread_limit() is None  # importing fkcheck shares nothing
assert_fk_matches("ur5", against="rtb-dh", samples=5)
print(thread_limit(), os.environ.get("OPENBLAS_NUM_THREADS"))
"""


@pytest.mark.parametrize(("workers", "share"), [("4", "1 1"), (None, "None None")])
def test_assert_fk_matches_in_an_xdist_worker_shares_the_cores(workers, share):
    # One of 4 workers on this machine (2 cores, or fewer usable): 1 thread a pool. Not
    # under xdist: the pools stay as they are.
    pytest.importorskip("roboticstoolbox")
    from fkcheck.process.cpus import usable_cores

    assert usable_cores() <= 7  # 4 workers get one thread each (7 // 4 == 1)
    names = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS")
    env = {k: v for k, v in os.environ.items() if k not in names and not k.startswith("PYTEST_")}
    if workers is not None:
        env["PYTEST_XDIST_WORKER_COUNT"] = workers
    done = subprocess.run([sys.executable, "-c", _XDIST_WORKER], env=env, capture_output=True,
                          text=True, timeout=300, check=False)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == share.split()
