"""docs/howto/many-robots.md's fleet example, run as the page says: ``pytest -n 2``.

A fleet of two UR10e arms in a throw-away repository, each with the calibration from
``tests/data/calibration/ur10e-test-b``: ``robot-a``'s model is its calibrated table,
``robot-b``'s the nominal one (a robot whose model lacks its calibration). Each has
one RTDE recording its calibrated table wrote (the tests' own composition, not
fkcheck's core). The page's test file is the page's block, as it is: ``robot-a``'s item
passes, ``robot-b``'s fails by the calibration's millimetres, named by robot and
recording.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

from fkcheck.cli.main import main
from tests.calibration.ur_test_data import composed, fk
from tests.docs.examples import DOCS_DIR, blocks
from tests.paths import REPO_ROOT
from tests.rtde_cases import RTDE_HEADER

PAGE = DOCS_DIR / "howto" / "many-robots.md"


def _example() -> str:
    (block,) = [
        b
        for b in blocks(PAGE)
        if b.lang == "python" and b.not_run and "test_fleet_example" in b.not_run
    ]
    return block.text


def _recording(path: Path, table, q: np.ndarray) -> None:
    """An RTDE recording (every output of tests.rtde_cases) of ``table``'s poses at ``q``."""
    from scipy.spatial.transform import Rotation

    T = fk(table, q)
    pose = np.hstack([T[:, :3, 3], Rotation.from_matrix(T[:, :3, :3]).as_rotvec()])
    values = {"actual_TCP_pose": pose, "actual_q": q}
    lines = [" ".join(RTDE_HEADER)]
    for k in range(q.shape[0]):
        row = []
        for name in RTDE_HEADER:
            stem, _, index = name.rpartition("_")
            row.append(repr(float(values[stem][k, int(index)])) if stem in values else "0.0")
        lines.append(" ".join(row))
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def test_the_fleet_example_names_the_robot_whose_model_lacks_its_calibration(tmp_path, capsys):
    from fkcheck import load_model

    conf = REPO_ROOT / "tests" / "data" / "calibration" / "ur10e-test-b" / "calibration.conf"
    rng = np.random.default_rng(3504)
    table = composed(load_model("ur10e").joints, "ur10e-test-b")
    for robot in ("robot-a", "robot-b"):
        home = tmp_path / "fleet" / robot
        (home / "models").mkdir(parents=True)
        (home / "calibration.conf").write_bytes(conf.read_bytes())
        q = rng.uniform(-3.0, 3.0, size=(300, 6))
        _recording(home / "recordings" / "shift-1.csv", table, q)
    calibrated = tmp_path / "fleet" / "robot-a" / "models" / "model.toml"
    code = main(["calibration", "ur10e", str(calibrated.parent.parent / "calibration.conf"),
                 "-o", str(calibrated)])  # fmt: skip
    assert code == 0, capsys.readouterr()
    nominal = (REPO_ROOT / "models" / "ur10e.toml").read_text(encoding="utf-8")
    (tmp_path / "fleet" / "robot-b" / "models" / "model.toml").write_text(nominal)
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_fleet.py").write_text(_example(), encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTEST_", "GITHUB_"))}
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "src"), env.get("PYTHONPATH", "")])
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", "2", "-rA",
         "tests/test_fleet.py"],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip
    out = done.stdout
    assert done.returncode == 1, out[-3000:]
    assert re.search(r"^PASSED tests/test_fleet\.py::.*\[robot-a/shift-1\]$", out, re.M), out
    assert re.search(r"^FAILED tests/test_fleet\.py::.*\[robot-b/shift-1\]", out, re.M), out
    assert "1 failed, 1 passed" in out
    # The failure is the recording's: every row off by the calibration (millimetres).
    assert re.search(r"300 of 300 configurations differ: max position error [1-9]\.\d+ mm", out)
