"""A calibrated model against its calibration file: as recorded, or edited since (issue 31).

The sha256 ``fkcheck calibration`` records was never compared with the file: a file
or a table edited after calibrating still printed the calibration as its provenance.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from fkcheck.calibration.effect import nominal_model
from fkcheck.calibration.provenance import calibration_provenance
from fkcheck.cli.main import main
from fkcheck.model.read import load_model
from tests.calibration.ur_test_data import composed, write_kinematics_info
from tests.helpers import deadline

DATA = Path(__file__).parents[1] / "data" / "calibration" / "ur10e-test-b"


@pytest.fixture
def made(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capfd) -> Path:
    """``robot.toml`` made by ``fkcheck calibration ur10e calibration.conf`` in ``tmp_path``."""
    monkeypatch.chdir(tmp_path)
    shutil.copy(DATA / "calibration.conf", tmp_path / "calibration.conf")
    assert main(["calibration", "ur10e", "calibration.conf", "-o", "robot.toml"]) == 0
    capfd.readouterr()
    return tmp_path / "robot.toml"


def _provenance(path: Path):
    model = load_model(path)
    return calibration_provenance(model, nominal_model(model))


def test_a_model_as_made_is_as_recorded(made: Path):
    provenance = _provenance(made)
    assert (provenance.state, provenance.note) == ("as recorded", "")


def test_a_file_edited_since_is_said_even_when_its_numbers_are_the_same(made: Path):
    conf = made.parent / "calibration.conf"
    conf.write_text(conf.read_text(encoding="utf-8") + "# checked 2026-11-28\n", encoding="utf-8")
    provenance = _provenance(made)
    assert provenance.state == "file edited since"
    assert provenance.note.startswith(
        "file edited since the model was made: calibration.conf's sha256 is "
    )


def test_a_delta_edited_in_the_file_is_a_file_edited_since(made: Path):
    conf = made.parent / "calibration.conf"
    text = conf.read_text(encoding="utf-8")
    conf.write_text(text.replace("delta_a = [ 2.12", "delta_a = [ 3.12", 1), encoding="utf-8")
    assert _provenance(made).state == "file edited since"


def test_a_table_edited_since_names_the_first_number_that_differs(made: Path):
    text = made.read_text(encoding="utf-8")
    d1 = "d = 0.18053981171425867\n"
    assert text.count(d1) == 1
    made.write_text(text.replace(d1, "d = 0.1807\n"), encoding="utf-8")
    provenance = _provenance(made)
    assert provenance.state == "table edited since"
    assert provenance.note == (
        "table edited since calibrating: joint[0].d (shoulder_pan) = 0.1807, where "
        "calibration.conf on ur10e gives 0.180539811714"
    )


def test_a_missing_file_leaves_the_provenance_unverified(made: Path):
    (made.parent / "calibration.conf").unlink()
    provenance = _provenance(made)
    assert provenance.state == "unverified"
    assert provenance.note.startswith("provenance unverified: calibration.conf: ")


def test_kinematics_info_as_made_is_as_recorded(tmp_path: Path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    table = composed(load_model("ur10e").joints, "ur10e-test-b")
    write_kinematics_info(tmp_path / "info.log", table, 2)
    assert main(["calibration", "ur10e", "info.log", "-o", "robot.toml"]) == 0
    assert _provenance(tmp_path / "robot.toml").state == "as recorded"


def test_a_table_made_from_the_yaml_alone_is_made_again_from_it(tmp_path: Path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    shutil.copy(DATA / "robot_calibration.yaml", tmp_path / "robot_calibration.yaml")
    with deadline(120.0):
        assert main(["calibration", "ur10e", "robot_calibration.yaml", "-o", "robot.toml"]) == 0
        assert _provenance(tmp_path / "robot.toml").state == "as recorded"
        model = tmp_path / "robot.toml"
        text = model.read_text(encoding="utf-8")
        head, tail = text.split("alpha = ", 1)
        value, rest = tail.split("\n", 1)
        model.write_text(f"{head}alpha = {float(value) + 1e-6!r}\n{rest}", encoding="utf-8")
        provenance = _provenance(model)
    assert provenance.state == "table edited since"
    assert "joint[0].alpha (shoulder_pan)" in provenance.note


def test_every_output_of_a_check_says_it(made: Path, capfd):
    conf = made.parent / "calibration.conf"
    conf.write_text(conf.read_text(encoding="utf-8") + "\n", encoding="utf-8")
    report = made.parent / "r.json"
    html = made.parent / "r.html"
    with deadline(120.0):
        code = main(["check", "robot.toml", "--json", str(report), "--html", str(html)])
    out, _ = capfd.readouterr()
    assert code == 0, out
    line = next(line for line in out.splitlines() if line.startswith("calibration "))
    assert line.startswith(
        "calibration calibration.conf (file edited since the model was made: "
        "calibration.conf's sha256 is "
    )
    result = json.loads(report.read_text(encoding="utf-8"))
    assert result["calibration"]["provenance"] == "file edited since"
    assert "file edited since the model was made" in result["calibration"]["line"]
    page = html.read_text(encoding="utf-8")
    assert page.count("file edited since the model was made") >= 2  # the source and the line
