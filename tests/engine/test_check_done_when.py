"""The engine's acceptance cases, through `fkcheck check` as a user runs it.

Expected sizes are derived from the tables, not from fkcheck's output: a d1 of
0.08946 instead of 0.089159 moves every pose 0.301 mm along the base z axis; a
base frame turned π about z moves a point p by 2·|p_xy| and turns it by π; tool0
and flange differ by the fixed rotation of UR's ROS 2 description, flange → tool0
rpy(π/2, 0, π/2) (the rotation [[0,1,0],[0,0,1],[1,0,0]]), an angle of 2π/3.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from fkcheck.backends import registry
from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths
from tests.backend_cases import URDF_BACKENDS as URDF_READERS
from tests.paths import PLUGINS_DIR

URDF_BACKENDS = ",".join(URDF_READERS)
PLUGINS = PLUGINS_DIR


def ur5_variant(tmp_path: Path, old: str, new: str, count: int = 1) -> Path:
    text = bundled_model_paths()["ur5"].read_text()
    assert text.count(old) >= count, old
    path = tmp_path / "ur5_variant.toml"
    path.write_text(text.replace(old, new, count))
    return path


def check(capsys, tmp_path, model, *extra):
    report = tmp_path / "result.json"
    code = main(["check", str(model), "--samples", "64", "--json", str(report), *extra])
    out, err = capsys.readouterr()
    return code, json.loads(report.read_text()), out + err


def by_name(doc):
    return {b["name"]: b for b in doc["backends"]}


def test_ur5_passes_against_every_default_backend(capsys, tmp_path):
    code, doc, out = check(capsys, tmp_path, "ur5")
    assert code == 0, out
    assert doc["verdict"] == "pass"
    assert [b["name"] for b in doc["backends"]] == list(registry.default_names())
    assert [b["status"] for b in doc["backends"]] == ["pass"] * len(registry.default_names())
    assert doc["cross_checked"] == len(registry.default_names())


def test_older_d1_fails_against_the_urdf_by_0_3_mm(capsys, tmp_path):
    model = ur5_variant(tmp_path, "d = 0.089159", "d = 0.08946")
    code, doc, out = check(capsys, tmp_path, model)
    assert code == 1
    assert doc["verdict"] == "fail"
    rows = by_name(doc)
    for name in URDF_BACKENDS.split(","):
        assert rows[name]["status"] == "fail"
        assert rows[name]["max_position_error_m"] == pytest.approx(0.08946 - 0.089159, abs=1e-9)
        assert rows[name]["max_rotation_error_rad"] < 1e-9  # position only: a shift along z
    for name in ("rtb-dh", "pinocchio-dh"):  # the same (wrong) table: they agree with it
        assert rows[name]["status"] == "pass"
    assert "hint: explain it: fkcheck diagnose" in out


def test_one_flipped_alpha_fails(capsys, tmp_path):
    # wrist_1's alpha is the fourth "alpha = 90": flip it to -90.
    text = bundled_model_paths()["ur5"].read_text()
    head, sep, tail = text.partition('name = "wrist_1"')
    model = tmp_path / "ur5_alpha.toml"
    model.write_text(head + sep + tail.replace("alpha = 90", "alpha = -90", 1))
    code, doc, _ = check(capsys, tmp_path, model, "--against", URDF_BACKENDS)
    assert code == 1
    assert all(b["status"] == "fail" for b in doc["backends"])
    assert min(b["max_position_error_m"] for b in doc["backends"]) > 1e-2


def test_base_link_without_its_pi_turn_fails_by_about_2_m_and_pi(capsys, tmp_path):
    model = ur5_variant(tmp_path, "rpy = [0, 0, 180]", "rpy = [0, 0, 0]")
    code, doc, _ = check(
        capsys, tmp_path, model, "--from", "base_link", "--to", "tool0", "--against", URDF_BACKENDS
    )
    assert code == 1
    # UR5 reach in the xy plane: a2 + a3 plus the wrist offsets, about 0.95 m.
    reach_xy = math.hypot(0.425 + 0.39225 + 0.09465, 0.10915 + 0.0823)
    for b in doc["backends"]:
        assert b["status"] == "fail"
        assert 1.5 < b["max_position_error_m"] <= 2 * reach_xy
        assert b["max_rotation_error_rad"] == pytest.approx(math.pi, abs=1e-6)


def test_tool0_mapped_onto_flange_fails_on_rotation_alone(capsys, tmp_path):
    model = ur5_variant(tmp_path, 'urdf = "tool0"', 'urdf = "flange"')
    code, doc, _ = check(capsys, tmp_path, model, "--against", URDF_BACKENDS)
    assert code == 1
    for b in doc["backends"]:
        assert b["status"] == "fail"
        assert b["max_position_error_m"] < 1e-9
        assert b["max_rotation_error_rad"] == pytest.approx(2 * math.pi / 3, abs=1e-9)


def test_every_mapped_frame_pair_passes(capsys, tmp_path):
    for frame_from, frame_to in [
        ("base_link", "flange"),
        ("base", "flange"),
        ("base_link", "tool0"),
    ]:
        code, doc, out = check(capsys, tmp_path, "ur5", "--from", frame_from, "--to", frame_to)
        assert code == 0, out
        assert doc["cross_checked"] == len(registry.default_names())


def test_missing_library_is_skipped_with_its_reason(capsys, tmp_path, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name == "roboticstoolbox" else real(name, *a),
    )
    code, doc, _ = check(capsys, tmp_path, "ur5", "--against", "rtb-dh,pinocchio-dh")
    rtb, pin = doc["backends"]
    assert rtb["status"] == "skipped"
    assert "roboticstoolbox" in rtb["message"]
    assert rtb["max_position_error_m"] is None
    assert pin["status"] == "pass"
    assert (code, doc["verdict"]) == (0, "pass")
    code, doc, out = check(capsys, tmp_path, "ur5", "--against", "rtb-dh")
    assert (code, doc["verdict"], doc["cross_checked"]) == (1, "error", 0)
    assert "nothing was cross-checked" in out


def test_plugin_through_the_cli(capsys, tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(PLUGINS))
    code, doc, out = check(capsys, tmp_path, "ur5", "--against", "ur5_closed_form:forward")
    assert code == 0, out
    assert doc["backends"][0]["status"] == "pass"
    code, doc, _ = check(capsys, tmp_path, "ur5", "--against", "bad_plugins:raises")
    assert code == 1
    assert doc["verdict"] == "error"
    assert doc["backends"][0]["status"] == "error"


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["--against", "rtb-model:UR7"], r"unknown backend 'UR7'|UR7"),
        (["--to", "tool"], r"frame 'tool' not in model ur5"),
        (["--tol-pos", "-1"], r"--tol-pos: must be > 0 and at most 0\.01 m .*, got -1$"),
    ],
)
def test_bad_input_is_exit_2(capsys, argv, match):
    code = main(["check", "ur5", "--samples", "8", *argv])
    _, err = capsys.readouterr()
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    assert re.search(match, err), err
