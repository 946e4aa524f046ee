"""What the controller recorded (RTDE) against the calibrated and the nominal table."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from fkcheck.cli.main import main
from fkcheck.model.read import load_model
from tests.calibration.ur_test_data import composed, fk, write_conf
from tests.rtde_cases import near_half_turn_configurations


def _write_recording(path: Path, table, q: np.ndarray) -> Path:
    """A recording as UR's recorder writes one, poses from the test's own composition."""
    T = fk(table, q)
    rotvec = Rotation.from_matrix(T[:, :3, :3]).as_rotvec()
    names = ["timestamp"]
    names += [f"actual_q_{i}" for i in range(6)] + [f"actual_TCP_pose_{i}" for i in range(6)]
    lines = [" ".join(names)]
    for k in range(q.shape[0]):
        values = [0.008 * k, *q[k], *T[k, :3, 3], *rotvec[k]]
        lines.append(" ".join(repr(float(v)) for v in values))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_recording_passes_against_the_calibrated_model_and_not_the_nominal(tmp_path, capsys):
    nominal = load_model("ur10")
    conf = write_conf(tmp_path / "calibration.conf", "ur10-test")
    model = tmp_path / "robot.toml"
    assert main(["calibration", "ur10", str(conf), "-o", str(model)]) == 0
    rng = np.random.default_rng(23)
    calibrated = load_model(model)
    q = np.vstack(
        [rng.uniform(-np.pi, np.pi, (60, 6)), near_half_turn_configurations(calibrated, rng, 4)]
    )
    recording = _write_recording(
        tmp_path / "recording.csv", composed(nominal.joints, "ur10-test"), q
    )
    capsys.readouterr()
    against = ["--against", f"poses:{recording}"]
    assert main(["check", str(model), *against]) == 0, capsys.readouterr()
    out = capsys.readouterr().out
    assert "poses:" in out
    assert "pass" in out
    # Against the nominal table: the calibration's size, in millimetres, not just "fail".
    assert main(["check", "ur10", *against]) == 1
    out = capsys.readouterr().out
    sizes = re.search(r"position max ([0-9.]+) mm, median ([0-9.]+) mm", out)
    assert sizes is not None, out
    assert 1.0 < float(sizes.group(1)) < 10.0
