"""Flips and zeros found together: random arms, URDFs written apart, motions compared apart.

Random 6R tables get a random set of reversed joints and quarter-turn zeros in a
URDF written with numpy (:func:`tests.vendor_arms.urdf_text`). The edits
:func:`fkcheck.urdf.mapping.reconcile_table` finds must be no more than those
planted, and the table so edited must move as the URDF does — judged here
without fkcheck: the angle and the slide of every relative motion (invariant
under the constant frames at either end) from a DH product written in the test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from fkcheck.model.read import load_model
from fkcheck.urdf.chain import read_urdf_source, urdf_kinematics
from fkcheck.urdf.mapping import reconcile_table
from tests.vendor_arms import VendorArm, dh_row, write_arm

#: Relative motions agree to round-off (m, rad): products of six 4×4 matrices.
SAME = 1e-9


def _random_arm(rng: np.random.Generator) -> VendorArm:
    rows = []
    for k in range(6):
        a = float(rng.choice([0.0, rng.uniform(0.05, 0.5)]))
        d = float(rng.choice([0.0, rng.uniform(0.05, 0.5)]))
        alpha = float(rng.choice([-90.0, 0.0, 90.0]))
        rows.append((f"J{k + 1}", a, alpha, d, float(rng.choice([0.0, 90.0, -90.0]))))
    names = [r[0] for r in rows]
    reversed_ = tuple(n for n in names if rng.random() < 0.4)
    zeros = {n: float(rng.choice([90.0, -90.0, 180.0])) for n in names[1:5] if rng.random() < 0.3}
    return VendorArm("random_arm", tuple(rows), reversed_, zeros)


def _poses(rows, q: np.ndarray) -> np.ndarray:
    """``(N, 4, 4)`` tip poses of ``(a, α rad, d, θ rad, flip)`` rows, written out."""
    out = []
    for qs in q:
        T = np.eye(4)
        for (a, alpha, d, theta, flip), qi in zip(rows, qs, strict=True):
            T = T @ dh_row(a, alpha, d, theta + (-qi if flip else qi))
        out.append(T)
    return np.array(out)


def _invariants(T: np.ndarray) -> np.ndarray:
    """Angle and slide along the axis of each relative motion ``T[2i]⁻¹·T[2i+1]``."""
    rel = np.linalg.inv(T[0::2]) @ T[1::2]
    rotvec = Rotation.from_matrix(rel[:, :3, :3]).as_rotvec()
    angle = np.linalg.norm(rotvec, axis=1)
    axis = rotvec / angle[:, None]
    slide = np.einsum("ij,ij->i", axis, rel[:, :3, 3])
    return np.stack([angle, slide], axis=1)


@pytest.mark.parametrize("seed", range(6))
def test_reconciled_edits_are_no_more_than_planted_and_move_as_the_urdf(seed, tmp_path):
    rng = np.random.default_rng(seed)
    arm = _random_arm(rng)
    path = write_arm(arm, tmp_path)
    model = load_model(path)
    kin = urdf_kinematics(read_urdf_source(str(tmp_path / "random_arm.urdf")))
    found = reconcile_table(model, kin)
    planted = len(arm.reversed) + len(arm.zeros)
    assert found.edits.count <= planted, (arm, found.edits)
    assert found.fit_m <= SAME
    assert found.fit_rad <= SAME
    edited = found.edits.apply(model)
    q = rng.uniform(-2.5, 2.5, size=(40, 6))
    urdf_rows = [
        (a, math.radians(al), d, math.radians(th + arm.zeros.get(n, 0.0)), n in arm.reversed)
        for n, a, al, d, th in arm.rows
    ]
    table_rows = [(j.a, j.alpha, j.d, j.theta, j.flip) for j in edited.joints]
    np.testing.assert_allclose(
        _invariants(_poses(table_rows, q)), _invariants(_poses(urdf_rows, q)), atol=SAME
    )
