"""The arms bundled from vendors' (or cited) DH tables check exactly as their files record.

Each compares the published table with example-robot-data's URDF. Where they
disagree the model file records it (``[[known_difference]]``); the check must
then show exactly those backends as expected failures, within the recorded
bounds, and never call the table verified.
"""

from __future__ import annotations

import json

import pytest

from fkcheck import load_model
from fkcheck.cli.main import main

#: model → backends expected to disagree as recorded (empty: the table must agree).
ARMS = {
    "xarm7": ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "idyntree-urdf"),
    "baxter_left": ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "idyntree-urdf"),
    "baxter_right": ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "idyntree-urdf"),
    "jaco2_6s": ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "idyntree-urdf"),
}


@pytest.mark.parametrize("name", sorted(ARMS))
def test_arm_checks_exactly_as_recorded(capsys, tmp_path, name):
    model = load_model(name)
    assert model.urdf is not None
    assert model.urdf.path.startswith("example-robot-data:")
    recorded = {b for k in model.known_differences for b in k.backends}
    assert recorded == set(ARMS[name])
    report = tmp_path / "r.json"
    code = main(["check", name, "--samples", "128", "--json", str(report)])
    out = "".join(capsys.readouterr())
    assert code == 0, out
    doc = json.loads(report.read_text())
    status = {b["name"]: b["status"] for b in doc["backends"]}
    assert status["rtb-dh"] == status["pinocchio-dh"] == "pass"
    for backend in ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "idyntree-urdf"):
        assert status[backend] == ("xfail" if backend in ARMS[name] else "pass")
    table = doc["evidence"]["table"]["status"]
    assert table == ("expected-failure" if ARMS[name] else "verified")
