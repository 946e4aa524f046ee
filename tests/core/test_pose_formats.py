"""Pose formats at the boundary, each against an independent formula."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fkcheck.core.geometry import (
    GIMBAL_LOCK_COS,
    matrix_from_rpy,
    matrix_from_xyz_rpy,
    rpy_from_matrix,
)
from fkcheck.core.metrics import rotation_error_rad
from fkcheck.core.pose_formats import (
    POSE_FORMATS,
    format_pose,
    matrix_from_pose,
    pose_from_matrix,
    pose_record,
)
from fkcheck.core.tolerances import SAME_CHAIN
from tests import seed_ur5
from tests.helpers import assert_pose_close


def random_poses(rng, n):
    """Random rigid transforms: rotations from normalised Gaussian quaternions."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    x, y, z, w = q.T
    R = np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
            np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
            np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )
    T = np.zeros((n, 4, 4))
    T[:, :3, :3] = R
    T[:, :3, 3] = rng.uniform(-1, 1, size=(n, 3))
    T[:, 3, 3] = 1
    return T


def paper_abc(T):
    """The ARma6 paper's eqs. 20–22, as printed (n, o, a = the columns of R)."""
    n, o, a = T[:3, 0], T[:3, 1], T[:3, 2]
    A = math.atan2(n[1], n[0])
    B = math.atan2(-n[2], n[0] * math.cos(A) + n[1] * math.sin(A))
    C = math.atan2(
        a[0] * math.sin(A) - a[1] * math.cos(A), -o[0] * math.sin(A) + o[1] * math.cos(A)
    )
    return A, B, C


def test_zyx_matches_the_arma6_paper_equations_20_to_22(rng):
    for T in random_poses(rng, 200):
        A, B, C = paper_abc(T)
        np.testing.assert_allclose(pose_from_matrix(T, "zyx")[3:], [A, B, C], atol=1e-12)


def test_zyx_on_the_seed_ur5_pose_matches_the_paper_equations():
    T = seed_ur5.T0[6]
    # Printed to six decimals: re-orthonormalise before comparing at 1e-9.
    U, _, Vt = np.linalg.svd(T[:3, :3])
    T = T.copy()
    T[:3, :3] = U @ Vt
    np.testing.assert_allclose(pose_from_matrix(T, "zyx")[3:], paper_abc(T), atol=1e-9)


def test_rpy_is_urdf_rpy_and_zyx_reversed(rng):
    for T in random_poses(rng, 50):
        rpy = pose_from_matrix(T, "rpy")[3:]
        np.testing.assert_allclose(matrix_from_rpy(rpy), T[:3, :3], atol=SAME_CHAIN)
        np.testing.assert_allclose(rpy, pose_from_matrix(T, "zyx")[3:][::-1], atol=0)


def test_rotvec_is_axis_times_angle(rng):
    for T in random_poses(rng, 50):
        rv = pose_from_matrix(T, "rotvec")[3:]
        angle = np.linalg.norm(rv)
        assert angle == pytest.approx(rotation_error_rad(np.eye(4), T), abs=1e-12)
        axis = rv / angle
        np.testing.assert_allclose(T[:3, :3] @ axis, axis, atol=1e-12)  # the axis is fixed


def test_ur_pendant_rotvec_of_a_known_pose():
    # Tool pointing straight down, turned 90° about z: a pose often seen on a UR pendant.
    T = matrix_from_xyz_rpy([0.1, 0.2, 0.3], [math.pi, 0, math.pi / 2])
    rv = pose_from_matrix(T, "rotvec")
    angle = np.linalg.norm(rv[3:])
    assert angle == pytest.approx(math.pi, abs=1e-12)
    # Axis of Rz(π/2)·Rx(π): (1, 1, 0)/√2 up to sign, at angle π.
    np.testing.assert_allclose(np.abs(rv[3:]), [math.pi / math.sqrt(2)] * 2 + [0], atol=1e-12)


def test_quaternion_is_xyzw_with_nonnegative_w(rng):
    T = random_poses(rng, 100)
    q = pose_from_matrix(T, "quat")[:, 3:]
    assert (q[:, 3] >= 0).all()
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-15)
    # Rotation by 90° about z: (0, 0, sin 45°, cos 45°).
    Rz = matrix_from_xyz_rpy([0, 0, 0], [0, 0, math.pi / 2])
    np.testing.assert_allclose(
        pose_from_matrix(Rz, "quat")[3:], [0, 0, 0.5**0.5, 0.5**0.5], atol=1e-15
    )


@pytest.mark.parametrize("fmt", POSE_FORMATS)
def test_round_trip_single_and_batch(fmt, rng):
    T = random_poses(rng, 64)
    assert_pose_close(matrix_from_pose(pose_from_matrix(T, fmt), fmt), T, SAME_CHAIN, fmt)
    one = matrix_from_pose(pose_from_matrix(T[0], fmt), fmt)
    assert one.shape == (4, 4)
    assert_pose_close(one, T[0], SAME_CHAIN, fmt)
    assert pose_from_matrix(T[0], fmt).shape == ((7,) if fmt == "quat" else (6,))


@pytest.mark.parametrize("fmt", ["rpy", "zyx"])
def test_gimbal_lock_round_trips_without_warning(fmt):
    # pytest turns warnings into errors: no gimbal-lock warning may escape.
    T = matrix_from_xyz_rpy([0, 0, 0], [0.3, math.pi / 2, 0.7])
    assert_pose_close(matrix_from_pose(pose_from_matrix(T, fmt), fmt), T, SAME_CHAIN, fmt)


#: Pitches at the lock (±π/2) and 1e-9 rad on either side of it.
LOCK_PITCHES = [
    pytest.param(lock + off, id=f"{name}{tag}")
    for lock, name in ((math.pi / 2, "+pi/2"), (-math.pi / 2, "-pi/2"))
    for off, tag in ((0.0, ""), (1e-9, "+1e-9"), (-1e-9, "-1e-9"))
]


def _wrapped(angle):
    """``angle`` in ``(-π, π]`` (as a float near ±π may land on either end: compare with care)."""
    return math.atan2(math.sin(angle), math.cos(angle))


@pytest.mark.parametrize("pitch", LOCK_PITCHES)
def test_rpy_round_trips_to_1e_12_at_and_near_the_gimbal_lock(pitch, rng):
    roll_yaw = rng.uniform(-math.pi, math.pi, size=(200, 2))
    R = np.stack([matrix_from_rpy([r, pitch, y]) for r, y in roll_yaw])
    rpy = rpy_from_matrix(R)  # batched: (200, 3)
    back = np.stack([matrix_from_rpy(angles) for angles in rpy])
    np.testing.assert_allclose(back, R, rtol=0, atol=1e-12)
    assert (np.abs(rpy[:, 1]) <= math.pi / 2).all()
    # The pitch read back is the magnitude asked for, folded into [-π/2, π/2].
    folded = math.copysign(math.pi - abs(pitch), pitch) if abs(pitch) > math.pi / 2 else pitch
    np.testing.assert_allclose(rpy[:, 1], folded, rtol=0, atol=1e-15)
    if abs(pitch) == math.pi / 2:
        # The documented rule at the exact lock: yaw is 0 and roll carries the turn about
        # the locked axis, Rz(y)·Ry(±π/2)·Rx(r) = Ry(±π/2)·Rx(r ∓ y).
        assert (rpy[:, 2] == 0.0).all()
        expected_roll = roll_yaw[:, 0] - math.copysign(1.0, pitch) * roll_yaw[:, 1]
        gap = [_wrapped(a - b) for a, b in zip(rpy[:, 0], expected_roll, strict=True)]
        np.testing.assert_allclose(gap, 0.0, atol=1e-12)
    else:
        # 1e-9 rad away the lock rule does not apply: yaw is read, not set to 0.
        assert np.hypot(R[:, 0, 0], R[:, 1, 0]).min() > GIMBAL_LOCK_COS
        assert (rpy[:, 2] != 0.0).all()


def _one_joint_model(path, tool_rpy):
    """A one-joint model whose tool pose is ``Rz(q)·tool``: its pitch is the tool's at any q."""
    path.write_text(
        'name = "lock"\nconvention = "standard"\n'
        "[[joint]]\na = 0.1\nalpha = 0.0\nd = 0.2\n"
        f"[tool]\nxyz = [0.01, 0.02, 0.03]\nrpy = [{', '.join(map(repr, tool_rpy))}]\n",
        encoding="utf-8",
    )
    return path


@pytest.mark.parametrize("pitch", LOCK_PITCHES)
def test_fk_format_rpy_and_the_poses_reader_share_one_rpy_vocabulary(pitch, tmp_path, capsys):
    """What ``fk --format rpy`` prints is rpy_from_matrix's; the poses: reader takes it back."""
    from fkcheck import load_model
    from fkcheck.backends.measured import read_poses_file
    from fkcheck.cli.main import main

    model = load_model(_one_joint_model(tmp_path / "m.toml", [0.3, pitch, 0.5]))
    q = np.array([[0.0], [0.2], [-2.5]])
    (tmp_path / "q.csv").write_text("0\n0.2\n-2.5\n", encoding="utf-8")
    argv = ["fk", str(model.path), "--q-file", str(tmp_path / "q.csv"), "--format", "rpy"]
    assert main(argv) == 0
    lines = [line for line in capsys.readouterr().out.split("\n") if line]
    printed = np.array([[float(v) for v in line.split()] for line in lines])
    expected = model.fk(q)
    # fk prints exactly rpy_from_matrix's numbers (so at the lock, yaw is exactly 0) ...
    np.testing.assert_array_equal(printed[:, 3:], rpy_from_matrix(expected))
    if abs(pitch) == math.pi / 2:
        assert (printed[:, 5] == 0.0).all()
    # ... and those lines, read back as measured poses, are fk's matrices again.
    poses = tmp_path / "poses.csv"
    rows = [f"{float(qi[0])!r} {line}".replace(" ", ",") for qi, line in zip(q, lines, strict=True)]
    poses.write_text("q1,x,y,z,roll,pitch,yaw\n" + "\n".join(rows) + "\n", encoding="utf-8")
    q_read, read, _ = read_poses_file(poses, model)
    np.testing.assert_array_equal(q_read, q)
    np.testing.assert_allclose(read, expected, rtol=0, atol=1e-12)


def test_quaternion_input_is_normalised_and_zero_is_refused():
    T = matrix_from_pose([0, 0, 0, 0, 0, 0.7072, 0.7071], "quat")  # rounded display values
    assert rotation_error_rad(T, matrix_from_xyz_rpy([0, 0, 0], [0, 0, math.pi / 2])) < 2e-4
    with pytest.raises(ValueError, match="zero length"):
        matrix_from_pose([0, 0, 0, 0, 0, 0, 0], "quat")


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="unknown pose format 'euler'"):
        pose_from_matrix(np.eye(4), "euler")
    with pytest.raises(ValueError, match="needs 6 numbers"):
        matrix_from_pose([1, 2, 3], "rpy")
    with pytest.raises(ValueError, match=r"shape \(3, 3\)"):
        pose_from_matrix(np.eye(3), "rpy")


def test_format_pose_text_and_record():
    T = matrix_from_xyz_rpy([0.5, -0.25, 0.125], [0, 0, math.pi / 2])
    assert format_pose(T, "rpy", degrees=True) == (
        "x=0.500000 y=-0.250000 z=0.125000 m  roll=0.000000 pitch=0.000000 yaw=90.000000 deg"
    )
    assert format_pose(T, "rotvec", mm=True) == (
        "x=500.000 y=-250.000 z=125.000 mm  rx=0.000000 ry=0.000000 rz=1.570796 rad"
    )
    record = pose_record(T, "zyx")
    assert record["position_m"] == [0.5, -0.25, 0.125]
    np.testing.assert_allclose(record["zyx_abc_rad"], [math.pi / 2, 0, 0], atol=1e-15)


def test_format_pose_never_prints_a_minus_sign_on_zero():
    # Round-off far below the printed digits (1e-8 m, 1e-9 rad) must not print as "-0.000000".
    T = matrix_from_xyz_rpy([-1e-8, 0.25, -4e-7], [-1e-9, 0, math.pi / 2])
    assert format_pose(T, "rpy") == (
        "x=0.000000 y=0.250000 z=0.000000 m  roll=0.000000 pitch=0.000000 yaw=1.570796 rad"
    )
    assert format_pose(T, "rpy", degrees=True, mm=True) == (
        "x=0.000 y=250.000 z=0.000 mm  roll=0.000000 pitch=0.000000 yaw=90.000000 deg"
    )
    assert format_pose(matrix_from_xyz_rpy([-6e-7, 0, 0], [0, 0, -6e-7]), "rpy") == (
        "x=-0.000001 y=0.000000 z=0.000000 m  roll=0.000000 pitch=0.000000 yaw=-0.000001 rad"
    )  # a value that rounds to a digit keeps its sign


def test_fk_prints_no_minus_sign_on_zero_in_matrices_and_formats(capsys):
    from fkcheck.cli.main import main

    # q6 = 1e-8 rad leaves round-off of about 1e-8 where the zero pose has exact zeros.
    assert main(["fk", "ur5", "--q", "0,0,0,0,0,1e-8", "--format", "rpy"]) == 0
    out = capsys.readouterr().out
    assert "pitch=0.000000" in out
    assert main(["fk", "ur5", "--q", "0,0,0,0,0,1e-8"]) == 0
    matrix = capsys.readouterr().out
    assert "-0.000000" not in matrix
    assert matrix.split("\n")[0].split() == ["1.000000", "0.000000", "0.000000", "-0.817250"]


def test_fk_format_flag_prints_zyx_of_the_seed_pose(capsys):
    from fkcheck.cli.main import main

    code = main(["fk", "ur5", "--q", "30,-60,90,-120,-90,45", "--deg", "--format", "zyx"])
    out = capsys.readouterr().out
    assert code == 0
    fields = dict(item.split("=") for item in out.replace(" m ", " ").split() if "=" in item)
    np.testing.assert_allclose([float(fields[k]) for k in "xyz"], seed_ur5.T0[6][:3, 3], atol=1e-6)
    A, B, C = (math.degrees(v) for v in paper_abc(seed_ur5.T0[6]))
    assert float(fields["A"]) == pytest.approx(A, abs=1e-3)
    assert float(fields["B"]) == pytest.approx(B, abs=1e-3)
    assert abs(float(fields["C"])) == pytest.approx(abs(C), abs=1e-3)  # ±180° are the same


def test_fk_format_batch_lines_round_trip(tmp_path, capsys):
    from fkcheck import load_model
    from fkcheck.cli.main import main

    q_file = tmp_path / "q.csv"
    q_file.write_text("0,0,0,0,0,0\n0.1,-0.5,1.0,-1.2,-1.5,0.7\n")
    assert main(["fk", "ur5", "--q-file", str(q_file), "--format", "rotvec"]) == 0
    rows = np.array(
        [[float(v) for v in line.split()] for line in capsys.readouterr().out.split("\n") if line]
    )
    expected = load_model("ur5").fk(np.loadtxt(q_file, delimiter=","))
    assert_pose_close(matrix_from_pose(rows, "rotvec"), expected, SAME_CHAIN)
