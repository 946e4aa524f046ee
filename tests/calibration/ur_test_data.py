"""UR's own calibration test data, and the three files a UR arm's calibration comes in.

The deltas are those of ``ur_calibration``'s tests (UniversalRobots/Universal_Robots_ROS2_Driver,
``ur_calibration/test/calibration_test.cpp``, BSD-3-Clause, © 2019 FZI Forschungszentrum
Informatik, created on behalf of Universal Robots A/S): one UR10 and two UR10e
calibrations, all three linearised (d2 + d3 + d4 ≈ 0 with d2 of 1.4 m to 439 m). A
fourth, *not linearised*, is made here from the first's small numbers (its d2, d3, d4
replaced by small deltas of the same size as its d1, d5, d6), applied to a UR5e.

The writers put each calibration in each of UR's three forms as UR writes them:
``calibration.conf`` as the controller keeps it, KinematicsInfo as UR's driver logs
it (``std::setprecision(15)``), and the YAML as ``ur_calibration`` writes it — its
chain correction and Eigen's ``eulerAngles(0, 1, 2)`` ported here as the test's own,
independent composition (the C++ is in the file named above).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DELTAS = {
    # name: (nominal, status, d, a, theta, alpha)
    "ur10-test": (
        "ur10",
        2,
        (0.00065609212979853, 1.4442162376284788, 0.854147723854608, -2.2989425877563705,
         -1.573498686836816e-05, 1.9072435590711256e-05),
        (4.6311376834935676e-05, -0.00012568315331862312, 0.00186216581161458,
         9.918593870679266e-05, 4.215462720453189e-06, 0),
        (-7.290070070824746e-05, -0.01713897289704999, -0.03707159413492756,
         0.054279462160583214, 1.488984257025741e-07, 1.551499479707493e-05),
        (0.000211987863869334, -0.0072553625957652995, -0.013483226769541364,
         0.0013495820227329425, -0.001263136163679901, 0),
    ),
    "ur10e-test-a": (
        "ur10e",
        2,
        (-0.000144894975118076141, 303.469135666158195, -309.88394307789747,
         6.41459904397394975, -4.48232900190081995e-05, -0.00087071402790364627),
        (0.000108651068627930392, 0.240324175250532346, 0.00180628180213493472,
         2.63076149165684402e-05, 3.96638632500012715e-06, 0),
        (1.59613525316931737e-07, -0.917209621528830232, 7.12936131346499469,
         0.0710299029424392298, -1.64258976526054923e-06, 9.17286101034808787e-08),
        (-0.000444781952841921679, -0.00160215112531214153, 0.00631917793331091861,
         -0.00165055247340828437, 0.000763682515545038854, 0),
    ),
    "ur10e-test-b": (
        "ur10e",
        2,
        (-0.000160188285741325043, 439.140974079900957, -446.027059806332147,
         6.88618689642360149, -3.86588496858186748e-05, -0.00087908274257374186),
        (2.12234865571205891e-05, 0.632017132627700651, 0.00229833638891230319,
         -4.61409023720933908e-05, -6.39280053471801522e-05, 0),
        (-2.41478068943590252e-07, 1.60233952386694556, -1.68607190752171299,
         0.0837331147700118711, -1.01260355871157781e-07, 3.91986209186123702e-08),
        (-0.000650246557584166496, 0.00139416666825590402, 0.00693818880325995126,
         -0.000811641562390219562, 0.000411120504570705592, 0),
    ),
    # Not linearised: ur10-test's small numbers, its d2..d4 replaced by small deltas.
    "ur5e-small": (
        "ur5e",
        1,
        (0.00065609212979853, 0.00031, -0.00042, 0.00012,
         -1.573498686836816e-05, 1.9072435590711256e-05),
        (4.6311376834935676e-05, -0.00012568315331862312, 0.00186216581161458,
         9.918593870679266e-05, 4.215462720453189e-06, 0),
        (-7.290070070824746e-05, -0.0017, 0.0021,
         0.0005, 1.488984257025741e-07, 1.551499479707493e-05),
        (0.000211987863869334, -0.00072553625957652995, -0.0013483226769541364,
         0.0013495820227329425, -0.001263136163679901, 0),
    ),
}  # fmt: skip


@dataclass(frozen=True)
class Table:
    """A standard-DH table, rows θ, a, d, α (rad, m)."""

    theta: tuple[float, ...]
    a: tuple[float, ...]
    d: tuple[float, ...]
    alpha: tuple[float, ...]


def composed(nominal_joints, name: str) -> Table:
    """Nominal + delta, composed by hand from the model's joints."""
    _, _, d, a, theta, alpha = DELTAS[name]
    js = list(nominal_joints)
    return Table(
        theta=tuple(j.theta + v for j, v in zip(js, theta, strict=True)),
        a=tuple(j.a + v for j, v in zip(js, a, strict=True)),
        d=tuple(j.d + v for j, v in zip(js, d, strict=True)),
        alpha=tuple(j.alpha + v for j, v in zip(js, alpha, strict=True)),
    )


def _list(values, sep: str = ", ") -> str:
    return sep.join(repr(float(v)) for v in values)


def write_conf(path: Path, name: str) -> Path:
    """The controller's calibration.conf (deltas), as UR's controller writes it."""
    _, status, d, a, theta, alpha = DELTAS[name]
    path.write_text(
        "[mounting]\n"
        f"delta_theta = [ {_list(theta)}]\n"
        f"delta_a = [ {_list(a)}]\n"
        f"delta_d = [ {_list(d)}]\n"
        f"delta_alpha = [ {_list(alpha)}]\n"
        "joint_checksum = [ 0xb3241580, 0xb10112f1, 0x290cac88, 0xa8d3f155, 0xa8b7e9eb, "
        "0xa8dbbfa3]\n"
        f"calibration_status = {status} # 0 == notInitialized / 1 == notLinearised / "
        "2 == Linearised\n"
        "joint_raw_offset = [ 3.74, 3.72, -3.14, 2.35, 2.38, 2.36]\n"
        "file_save_count = 1\n",
        encoding="utf-8",
    )
    return path


def _g15(values) -> str:
    return " ".join(f"{float(v):.15g}" for v in values) + " "


def write_kinematics_info(path: Path, table: Table, status: int) -> Path:
    """KinematicsInfo::toString as UR's driver logs it (15 significant digits)."""
    path.write_text(
        "[INFO] [ur_calibration]: Got the following kinematics info:\n"
        "checksum: [3005486464 2969637617 688696456 2832462165 2830625259 2832973731 ]\n"
        f"dh_theta: [{_g15(table.theta)}]\n"
        f"dh_a: [{_g15(table.a)}]\n"
        f"dh_d: [{_g15(table.d)}]\n"
        f"dh_alpha: [{_g15(table.alpha)}]\n"
        f"calibration_status: {status}\n",
        encoding="utf-8",
    )
    return path


# --- ur_calibration's YAML: its chain correction and Eigen's eulerAngles(0, 1, 2) ---


def _rz(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rx(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _h(rot: np.ndarray, pos) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rot
    out[:3, 3] = pos
    return out


def _chain(table: Table) -> list[np.ndarray]:
    out = []
    for i in range(6):
        out.append(_h(_rz(table.theta[i]), (0.0, 0.0, table.d[i])))
        out.append(_h(_rx(table.alpha[i]), (table.a[i], 0.0, 0.0)))
    return out


def _correct_axis(chain: list[np.ndarray], table: Table, i: int) -> None:
    d_theta, a_alpha = chain[2 * i], chain[2 * i + 1]
    if d_theta[2, 3] == 0.0:
        return
    root = d_theta @ a_alpha
    start = root[:3, 3]
    end = (root @ chain[2 * i + 2])[:3, 3]
    direction = (end - start) / np.linalg.norm(end - start)
    t = -start[2] / direction[2]  # where the next axis meets the xy-plane
    point = start + t * direction
    subtract = math.pi if abs(a_alpha[0, 3]) > 0 else 0.0
    new_theta = math.atan2(point[1], point[0]) - subtract
    sign = 1.0 if direction[2] > 0 else -1.0
    d_theta[2, 3] = 0.0
    d_theta[:3, :3] = _rz(new_theta)
    a_alpha[0, 3] = -float(np.linalg.norm(point))
    a_alpha[:3, :3] = _rz(table.theta[i] - new_theta) @ _rx(table.alpha[i])
    chain[2 * i + 2][2, 3] -= t * sign


def _euler_012(rot: np.ndarray) -> tuple[float, float, float]:
    """Eigen 3.4's ``eulerAngles(0, 1, 2)``: rot = Rx(a0)·Ry(a1)·Rz(a2), a0 in [0, π]."""
    r0 = math.atan2(rot[1, 2], rot[2, 2])
    c2 = math.hypot(rot[0, 0], rot[0, 1])
    if r0 > 0:
        r0 -= math.pi
        r1 = math.atan2(-rot[0, 2], -c2)
    else:
        r1 = math.atan2(-rot[0, 2], c2)
    s1, c1 = math.sin(r0), math.cos(r0)
    r2 = math.atan2(s1 * rot[2, 0] - c1 * rot[1, 0], c1 * rot[1, 1] - s1 * rot[2, 1])
    return -r0, -r1, -r2


def _rpy_extrinsic(rot: np.ndarray) -> tuple[float, float, float]:
    """URDF rpy (rot = Rz(y)·Ry(p)·Rx(r)), by SciPy."""
    from scipy.spatial.transform import Rotation

    r, p, y = Rotation.from_matrix(rot).as_euler("xyz")
    return float(r), float(p), float(y)


def yaml_links(table: Table, *, as_ur_writes: bool = True) -> list[tuple[tuple, tuple]]:
    """The six joint origins of ur_calibration's YAML: ``(xyz, rpy)`` each.

    ``as_ur_writes``: the angles from Eigen's ``eulerAngles(0, 1, 2)`` as
    ur_calibration writes them; otherwise URDF's own rpy of the same rotations.
    """
    chain = _chain(table)
    _correct_axis(chain, table, 1)
    _correct_axis(chain, table, 2)
    simplified = [chain[0]] + [chain[i] @ chain[i + 1] for i in range(1, 11, 2)]
    angles = _euler_012 if as_ur_writes else _rpy_extrinsic
    return [(tuple(float(v) for v in s[:3, 3]), angles(s[:3, :3])) for s in simplified]


LINKS = ("shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3")


def write_yaml(path: Path, table: Table, *, as_ur_writes: bool = True, hash_: str = "calib_12345"):
    """ur_calibration's YAML for ``table``."""
    lines = ["kinematics:"]
    for link, (xyz, rpy) in zip(LINKS, yaml_links(table, as_ur_writes=as_ur_writes), strict=True):
        lines.append(f"  {link}:")
        for key, value in zip(("x", "y", "z"), xyz, strict=True):
            lines.append(f"    {key}: {value!r}")
        for key, value in zip(("roll", "pitch", "yaw"), rpy, strict=True):
            lines.append(f"    {key}: {value!r}")
    lines.append(f"  hash: {hash_}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def fk(table: Table, q) -> np.ndarray:
    """``base_T_tool0`` of a standard-DH table, the test's own composition: (N, 4, 4).

    Each row composed from elementary transforms, ``Rz(θ+q)·Tz(d) · Tx(a)·Rx(α)``
    (not the DH matrix written out, as fkcheck's core has it), batched over q.
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    out = np.broadcast_to(np.eye(4), (q.shape[0], 4, 4)).copy()
    for i in range(6):
        angle = table.theta[i] + q[:, i]
        turn = np.broadcast_to(np.eye(4), out.shape).copy()
        turn[:, 0, 0], turn[:, 0, 1] = np.cos(angle), -np.sin(angle)
        turn[:, 1, 0], turn[:, 1, 1] = np.sin(angle), np.cos(angle)
        fixed = _h(np.eye(3), (0.0, 0.0, table.d[i])) @ _h(
            _rx(table.alpha[i]), (table.a[i], 0.0, 0.0)
        )
        out = out @ turn @ fixed
    return out
