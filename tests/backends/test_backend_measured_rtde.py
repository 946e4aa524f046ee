"""``poses:`` reads what UR's RTDE recorder wrote, as it is (issue 23, item 4).

The recordings are written by :mod:`tests.rtde_cases` from a model's table (the in-house
core through the model, rotation vectors from SciPy), as UR's recorder writes them:
space-separated, full precision, the 12 columns read among others. Rotations within
1e-6 rad of a half turn, about ``u`` and ``-u``, and written the other way round
(``r − 2π r/|r|``: the same rotation) are compared as rotations.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from fkcheck import load_model
from fkcheck.backends.measured import MeasuredPoses, PosesFileError, read_poses_file
from fkcheck.cli.main import main
from fkcheck.core.metrics import position_error_m, rotation_error_rad
from tests.paths import DATA_DIR, REPO_ROOT
from tests.rtde_cases import (
    RTDE_HEADER,
    near_half_turn_configurations,
    poses_of,
    rtde_rows,
    write_rtde_csv,
)


@pytest.fixture(scope="module")
def ur5():
    return load_model("ur5")


@pytest.fixture(scope="module")
def recorded_q(ur5):
    """Random configurations, eight near a half turn (both signs), a robot standing still."""
    rng = np.random.default_rng(20261126)
    near_pi = near_half_turn_configurations(ur5, rng, 8)
    moving = rng.uniform(-np.pi, np.pi, size=(40, 6))
    standing = np.repeat(near_pi[:1], 5, axis=0)  # the same sample, recorded five times
    return np.vstack([moving, near_pi, near_pi, standing])


@pytest.fixture(scope="module")
def flip(recorded_q):
    """The second copy of the near-π rows, and every other standing row, written flipped."""
    return [False] * 48 + [True] * 8 + [False, True, False, True, False]


def test_recording_passes_against_the_table_it_was_written_from(
    ur5, recorded_q, flip, tmp_path, capsys
):
    path = write_rtde_csv(tmp_path / "rec.csv", ur5, recorded_q, flip=flip)
    report = tmp_path / "r.json"
    code = main(["check", "ur5", "--against", f"poses:{path}", "--json", str(report)])
    out = capsys.readouterr().out
    assert code == 0, out
    doc = json.loads(report.read_text())
    assert doc["configurations"] == recorded_q.shape[0]
    (backend,) = doc["backends"]
    assert backend["status"] == "pass"
    assert backend["max_position_error_m"] < 1e-12
    assert backend["max_rotation_error_rad"] < 1e-12
    assert backend["method"] == (
        "UR RTDE recording (space-separated): joints actual_q_0…actual_q_5 (rad), pose "
        "actual_TCP_pose_0…actual_TCP_pose_5 (x, y, z in m, rotation vector in rad); "
        f"{len(RTDE_HEADER) - 12} other columns ignored"
    )


def test_half_turns_compare_as_rotations_whichever_way_the_vector_points(
    ur5, recorded_q, flip, tmp_path
):
    path = write_rtde_csv(tmp_path / "rec.csv", ur5, recorded_q, flip=flip)
    q, poses, pair = read_poses_file(path, ur5)
    assert pair is None  # the recorder writes no comment: the model's [check] pair applies
    np.testing.assert_array_equal(q, recorded_q)
    expected = poses_of(ur5, recorded_q)
    assert position_error_m(poses, expected).max() < 1e-12
    assert rotation_error_rad(poses, expected).max() < 1e-12
    rotvec = np.array(rtde_rows(ur5, recorded_q, flip))[:, 7:13][:, 3:]
    written = np.linalg.norm(rotvec, axis=1)
    assert (np.abs(written[40:48] - np.pi) < 1e-6).all()  # near π, as written
    assert (written[48:56] > np.pi).all()  # the same rotations, written the other way
    # One rotation, two opposite vectors: each flipped row points against its twin.
    assert (np.einsum("ij,ij->i", rotvec[40:48], rotvec[48:56]) < 0).all()


def test_comma_separated_and_columns_in_any_order_read_the_same(ur5, recorded_q, tmp_path):
    spaces = write_rtde_csv(tmp_path / "a.csv", ur5, recorded_q)
    commas = write_rtde_csv(tmp_path / "b.csv", ur5, recorded_q, delimiter=",")
    for got, want in zip(read_poses_file(commas, ur5), read_poses_file(spaces, ur5), strict=True):
        np.testing.assert_array_equal(got, want)
    backend = MeasuredPoses(str(commas))
    backend.configurations(ur5)
    assert backend.method.startswith("UR RTDE recording (comma-separated)")


def test_other_columns_are_ignored_even_when_not_numbers(ur5, tmp_path):
    q = np.zeros((1, 6))
    row = rtde_rows(ur5, q)[0]
    text = " ".join(map(repr, row)).replace("7.0", "nan", 1)  # robot_mode: not read
    (tmp_path / "r.csv").write_text(" ".join(RTDE_HEADER) + "\n" + text + "\n", encoding="utf-8")
    got, poses, _ = read_poses_file(tmp_path / "r.csv", ur5)
    np.testing.assert_array_equal(got, q)
    assert position_error_m(poses, poses_of(ur5, q)).max() < 1e-15


def test_a_standing_robot_with_one_pose_is_fine_and_two_poses_are_not(ur5, tmp_path):
    q = np.repeat(np.array([[0.1, -1.2, 1.3, -0.4, 1.5, 0.6]]), 4, axis=0)
    write_rtde_csv(tmp_path / "still.csv", ur5, q)
    assert read_poses_file(tmp_path / "still.csv", ur5)[0].shape == (4, 6)
    rows = rtde_rows(ur5, q)
    rows[2][7] += 1e-3  # actual_TCP_pose_0 of line 4: 1 mm off for the same actual_q
    lines = [" ".join(RTDE_HEADER), *(" ".join(map(repr, r)) for r in rows)]
    (tmp_path / "two.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(PosesFileError, match=r"lines 2 and 4 have the same configuration but "):
        read_poses_file(tmp_path / "two.csv", ur5)


def test_a_one_millimetre_table_change_fails_with_its_size(ur5, recorded_q, tmp_path, capsys):
    path = write_rtde_csv(tmp_path / "rec.csv", ur5, recorded_q)
    text = (REPO_ROOT / "models" / "ur5.toml").read_text(encoding="utf-8")
    assert text.count("a = -0.425\n") == 1
    model = tmp_path / "ur5_a2.toml"
    model.write_text(text.replace("a = -0.425\n", "a = -0.426\n"), encoding="utf-8")
    code = main(["check", str(model), "--against", f"poses:{path}"])
    out = " ".join(capsys.readouterr().out.split())  # the terminal folds long lines
    assert code == 1, out
    assert (
        f"over the {recorded_q.shape[0]} rows: position max 1.000 mm, median 1.000 mm, "
        "95th percentile 1.000 mm; rotation max 0.0000°, median 0.0000°, "
        "95th percentile 0.0000°"
    ) in out


def test_a_model_of_another_joint_count_is_refused(tmp_path):
    path = write_rtde_csv(tmp_path / "rec.csv", load_model("ur5"), np.zeros((1, 6)))
    with pytest.raises(PosesFileError, match=r"an RTDE recording holds 6 joints .* has 7"):
        read_poses_file(path, load_model("xarm7"))


def test_the_docs_recording_passes_its_table_and_shows_the_nominal_tables_millimetres(
    capsys,
):
    """docs/reference/measured-poses.md: the recording and the numbers it shows."""
    recording = DATA_DIR / "ur5_rtde_recording.csv"
    code = main(["check", str(DATA_DIR / "ur5_rtde_calibrated.toml"), "--against",
                 f"poses:{recording}"])  # fmt: skip
    assert code == 0, capsys.readouterr().out
    capsys.readouterr()
    assert main(["check", "ur5", "--against", f"poses:{recording}"]) == 1
    out = " ".join(capsys.readouterr().out.split())
    assert (
        "over the 45 rows: position max 2.090 mm, median 1.557 mm, 95th percentile 1.895 mm; "
        "rotation max 0.0100°, median 0.0100°, 95th percentile 0.0100°"
    ) in out


def test_a_recording_is_for_the_models_check_pair_and_says_so(ur5, tmp_path):
    from fkcheck.backends.base import FrameUnavailable

    path = write_rtde_csv(tmp_path / "rec.csv", ur5, np.zeros((2, 6)))
    backend = MeasuredPoses(str(path))
    q = backend.configurations(ur5)
    assert backend.frame_poses(ur5, q, ("base", "tool0")).shape == (2, 2, 4, 4)
    match = (
        r"holds poses of tool0 in base, not base → flange "
        r"\(the pair is the file's .*, else the model's \[check\] pair\)"
    )
    with pytest.raises(FrameUnavailable, match=match):
        backend.frame_poses(ur5, q, ("base", "flange"))


@pytest.mark.parametrize("rtde", [True, False], ids=["rtde", "poses-csv"])
def test_rows_beyond_the_row_limit_are_refused_at_the_first_one_unparsed(
    tmp_path, monkeypatch, rtde
):
    # The byte limit let 10 million short rows through (236 s, 7.7 GB): rows are
    # counted as they stream, and the first beyond the limit ends the read.
    import fkcheck.backends.measured as measured

    monkeypatch.setattr(measured, "MAX_POSES_ROWS", 3)
    ur5 = load_model("ur5")
    if rtde:
        head = " ".join([f"actual_q_{i}" for i in range(6)] + [f"actual_TCP_pose_{i}" for i in
                                                                range(6)])  # fmt: skip
        row = "0 0 0 0 0 0 1 0 0 0 0 0"
    else:
        head, row = "q1,q2,q3,q4,q5,q6,x,y,z,rx,ry,rz", "0,0,0,0,0,0,1,0,0,0,0,0"
    path = tmp_path / "r.csv"
    path.write_text("\n".join([head, row, row, row]) + "\n")
    assert read_poses_file(path, ur5)[0].shape == (3, 6)  # at the limit: read
    path.write_text("\n".join([head, row, row, row, "not even numbers"]) + "\n")
    match = r"r\.csv: line 5: more than 3 data rows \(at most 3\); cut the recording or keep "
    with pytest.raises(PosesFileError, match=match + r"every k-th row$"):
        read_poses_file(path, ur5)


def _stanford_csv(path, header, q_si):
    """A poses CSV of the Stanford arm: joints in the header's units, poses in m and rad."""
    from fkcheck.core.pose_formats import pose_from_matrix

    stanford = load_model("stanford")
    poses = pose_from_matrix(stanford.fk(q_si), "rotvec")
    scale = [180 / np.pi if n.endswith("_deg") else 1e3 if n.endswith("_mm") else 1.0
             for n in header[:6]]  # fmt: skip
    rows = [
        ",".join(repr(float(v)) for v in [*(q * scale), *p])
        for q, p in zip(q_si, poses, strict=True)
    ]
    path.write_text(",".join(header) + "\n" + "\n".join(rows) + "\n")
    return stanford


def test_each_joint_reads_the_suffix_of_its_own_quantity(tmp_path):
    # Stanford: the prismatic joint 3 in millimetres, the revolute ones in degrees. The
    # _mm factor went to the revolute joints and not the prismatic one: 499 m off.
    header = ["q1_deg", "q2_deg", "q3_mm", "q4_deg", "q5_deg", "q6", "x", "y", "z", "rx", "ry",
              "rz"]  # fmt: skip
    q = np.array([[0.1, -0.2, 0.5, 0.3, 0.4, -0.5], [0.0, 0.3, 1.0, 0.0, -0.2, 0.1]])
    stanford = _stanford_csv(tmp_path / "p.csv", header, q)
    read_q, poses, _ = read_poses_file(tmp_path / "p.csv", stanford)
    np.testing.assert_allclose(read_q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(poses, stanford.fk(q), rtol=0, atol=1e-9)


@pytest.mark.parametrize(
    ("rename", "says"),
    [
        ({"q1": "q1_mm"}, "column q1_mm: _mm is for a length, but q1 is joint 1 (j1), revolute; "
         "name it q1 or q1_deg"),
        ({"q3": "q3_deg"}, "column q3_deg: _deg is for an angle, but q3 is joint 3 (j3), "
         "prismatic; name it q3 or q3_mm"),
        ({"x": "x_deg"}, "column x_deg: _deg is for an angle, but x is a position; name it x or "
         "x_mm"),
        ({"rx": "rx_mm"}, "column rx_mm: _mm is for a length, but rx is an angle; name it rx or "
         "rx_deg"),
    ],
)  # fmt: skip
def test_a_suffix_for_another_quantity_is_refused_in_one_line(tmp_path, rename, says):
    header = ["q1", "q2", "q3", "q4", "q5", "q6", "x", "y", "z", "rx", "ry", "rz"]
    header = [rename.get(n, n) for n in header]
    stanford = _stanford_csv(tmp_path / "p.csv", header, np.array([[0, 0, 0.5, 0, 0, 0]]))
    with pytest.raises(PosesFileError, match=rf"p\.csv: {re.escape(says)}$"):
        read_poses_file(tmp_path / "p.csv", stanford)
