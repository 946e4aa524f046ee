"""``[[known_difference]] versions = …`` for a backend with no library: exit 2, one line."""

from __future__ import annotations

import pytest

from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths

RECORD = (
    '\n[[known_difference]]\nbackends = ["poses:rec.csv"]\nversions = "<=1.0"\n'
    'finding = "the robot\'s encoders"\nmax_position_m = 0.01\nmax_angle_rad = 0.01\n'
)


@pytest.mark.parametrize("command", ["check", "lint", "diagnose"])
def test_versions_for_measured_poses_are_refused_before_anything_runs(tmp_path, capsys, command):
    path = tmp_path / "ur5.toml"
    path.write_text(bundled_model_paths()["ur5"].read_text(encoding="utf-8") + RECORD)
    argv = [command, str(path)] + (["--samples", "2"] if command == "check" else [])
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == ""  # nothing ran: no header, no table
    assert err.strip().splitlines() == [
        f"fkcheck: error: {path}: known_difference[0].versions: 'poses:rec.csv' computes with "
        "no library (it names no distributions): versions = '<=1.0' has no version to match "
        "and the record would never apply; drop versions, or record them for: pinocchio-urdf, "
        "yourdfpy-urdf, rtb-urdf, mujoco-urdf, idyntree-urdf, mujoco-mjcf, pinocchio-mjcf, "
        "rtb-model:…, or a third-party backend that names its distributions"
    ]
