"""``fkcheck check --jacobian`` from the command line: flags, the model's [check], plugins."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import pytest

from fkcheck.cli.main import main
from fkcheck.model.read import load_model
from tests.paths import PLUGINS_DIR

UR5_TCP = ["ur5", "--from", "world", "--to", "tcp", "--samples", "20"]


def _cli(argv, tmp_path, env_plugins=False):
    """Run the CLI in a subprocess (plugins run in their own process and need the path)."""
    env = dict(os.environ)
    if env_plugins:
        env["PYTHONPATH"] = os.pathsep.join([str(PLUGINS_DIR), env.get("PYTHONPATH", "")])
    return subprocess.run(
        [sys.executable, "-m", "fkcheck", *argv],
        capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600,
    )  # fmt: skip


@pytest.mark.parametrize("reference", ["world-aligned", "local"])
@pytest.mark.parametrize(
    ("spec", "verdict", "first", "named"),
    [
        ("ur5_jacobians:correct", "pass", None, ""),
        ("ur5_jacobians:end_effector", "fail", "shoulder_pan", "in the frame's own axes (local"),
        ("ur5_jacobians:angular_first", "fail", "shoulder_pan", "rows are angular first"),
    ],
)
def test_a_plugins_own_jacobian_is_compared_and_a_mistake_named(
    tmp_path, spec, verdict, first, named, reference
):
    """In any reference: the engine re-expresses the plugin's world-aligned answer."""
    out = tmp_path / "r.json"
    done = _cli(["check", *UR5_TCP, "--jacobian-reference", reference, "--against", spec,
                 "--json", str(out)],
                tmp_path, env_plugins=True)  # fmt: skip
    assert done.returncode == (0 if verdict == "pass" else 1), done.stderr + done.stdout
    doc = json.loads(out.read_text())
    (b,) = doc["backends"]
    assert b["status"] == "pass"  # the poses agree in every case
    assert b["jacobian"]["method"] == f"python callable {spec}_jacobian"
    assert b["jacobian"]["status"] == verdict
    assert b["jacobian"]["first_disagreeing_joint"] == first
    if reference == "world-aligned":  # in local, jacobe's frame is turned twice: unnamed
        assert named in b["jacobian"]["diagnosis"]
    if verdict == "fail":
        assert "the poses agree, a Jacobian disagrees" in done.stdout
        assert "  diagnosis: " in done.stdout


def test_a_plugin_without_a_jacobian_is_differentiated(tmp_path):
    out = tmp_path / "r.json"
    # At the TCP and world-aligned: the one place a plugin's own Jacobian is asked for.
    done = _cli(["check", *UR5_TCP, "--jacobian", "--against", "ur5_closed_form:forward",
                 "--json", str(out)], tmp_path, env_plugins=True)  # fmt: skip
    assert done.returncode == 0, done.stderr + done.stdout
    j = json.loads(out.read_text())["backends"][0]["jacobian"]
    assert j["method"] == "central differences of its poses, step 1e-06"
    assert j["status"] == "pass"
    assert j["max_linear"] < 1e-7


def test_the_models_check_section_turns_it_on_and_no_jacobian_off(tmp_path, capsys):
    text = (load_model("ur5").path.read_text() + "jacobian = true\n"
            'jacobian_reference = "world"\ntol_jacobian = 1e-7\n')  # fmt: skip
    path = tmp_path / "ur5j.toml"
    path.write_text(text)
    out = tmp_path / "r.json"
    assert main(["check", str(path), "--against", "rtb-dh", "--samples", "5",
                 "--json", str(out)]) == 0  # fmt: skip
    doc = json.loads(out.read_text())
    assert doc["jacobian"]["reference"] == "world"
    assert doc["jacobian"]["tolerance"] == 1e-7
    assert doc["backends"][0]["jacobian"]["status"] == "pass"
    assert main(["check", str(path), "--against", "rtb-dh", "--samples", "5",
                 "--no-jacobian", "--json", str(out)]) == 0  # fmt: skip
    doc = json.loads(out.read_text())
    assert "jacobian" not in doc
    assert "jacobian" not in doc["backends"][0]
    assert "--no-jacobian" in doc["command"]


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ('jacobian = "yes"', r"check\.jacobian: expected true or false"),
        (
            'jacobian_reference = "base"',
            r"check\.jacobian_reference: unknown reference frame.*"
            r"references are: world, local, world-aligned",
        ),
        ("tol_jacobian = -1", r"check\.tol_jacobian: must be > 0 and at most 0\.01 .*, got -1$"),
        (
            "tol_jacobian = 1e300",
            r"check\.tol_jacobian: must be > 0 and at most 0\.01 .*, got 1e\+300$",
        ),
    ],
)
def test_bad_check_keys_are_one_line_and_exit_2(tmp_path, capsys, line, message):
    path = tmp_path / "bad.toml"
    path.write_text(load_model("ur5").path.read_text() + line + "\n")
    assert main(["check", str(path), "--against", "rtb-dh", "--samples", "5"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert str(path.name) in err
    assert re.search(message, err), err


def test_bad_tolerance_and_moving_from_frame_exit_2(capsys):
    assert main(["check", *UR5_TCP, "--tol-jacobian", "0", "--against", "rtb-dh"]) == 2
    assert (
        "--tol-jacobian: must be > 0 and at most 0.01 m/rad and rad/rad" in capsys.readouterr().err
    )
    argv = ["check", "panda", "--from", "panda_link2", "--jacobian", "--against", "rtb-dh"]
    assert main(argv) == 2
    assert "moves with joints 1–2" in capsys.readouterr().err
