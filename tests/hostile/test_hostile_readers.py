"""One reader's limits are that reader's; only input no reader may accept is exit 2.

Round four of the hostile inputs (issue 31): a valid URDF whose non-root link is
named ``world`` ended the whole check "MuJoCo cannot read it" (exit 2) although
four readers read it; a floating joint above the mapped chain (a mobile base)
ended it "iDynTree cannot load it". Each is now that backend skipped, with its
reason, and the others answer. An axis no reader can normalise (``0 0 1e-300``,
``0 1e300 1e300``) and a ``<mimic>`` naming no joint, a missing one or a fixed one
are refused by fkcheck's own screen, in one line.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.backend_cases import ARM3_TOML, ARM3_URDF

ARGS = ["--samples", "2", "--from", "base", "--to", "tip"]


def _write(tmp_path: Path, urdf: str, toml: str = ARM3_TOML) -> Path:
    (tmp_path / "arm3.urdf").write_text(urdf, encoding="utf-8")
    path = tmp_path / "arm3.toml"
    path.write_text(toml, encoding="utf-8")
    return path


def _check(model: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "fkcheck", "check", str(model), *ARGS, *extra],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip


WORLD_LINK = (
    ARM3_URDF.replace('<link name="l3"/>', '<link name="world"/>')
    .replace('<child link="l3"/>', '<child link="world"/>')
    .replace('<parent link="l3"/>', '<parent link="world"/>'),
    ARM3_TOML.replace('urdf = "l3"', 'urdf = "world"'),
    {"mujoco-urdf": "MuJoCo cannot read arm3.urdf: Error: joint found in world body"},
)
MOBILE_BASE = (
    ARM3_URDF.replace(
        '<robot name="arm3">',
        '<robot name="arm3">\n  <link name="odom"/>\n  <joint name="mobile" type="floating">'
        '<parent link="odom"/><child link="base"/></joint>',
    ),
    ARM3_TOML,
    {
        "mujoco-urdf": "MuJoCo cannot read arm3.urdf: Error: free joint can only be used on top",
        "idyntree-urdf": "iDynTree cannot load arm3.urdf: JointElement :: setAttributes : Joint "
        "mobile has type floating that is not currently supported by iDynTree.",
    },
)


@pytest.mark.parametrize(("urdf", "toml", "unavailable"), [WORLD_LINK, MOBILE_BASE],
                         ids=["link-named-world", "floating-mobile-base"])  # fmt: skip
def test_a_reader_that_cannot_read_a_valid_urdf_is_unavailable_and_the_others_answer(
    tmp_path, urdf, toml, unavailable
):
    pytest.importorskip("mujoco")
    pytest.importorskip("idyntree")
    report = tmp_path / "r.json"
    done = _check(_write(tmp_path, urdf, toml), "--json", str(report))
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "Traceback" not in done.stderr
    backends = {b["name"]: b for b in json.loads(report.read_text())["backends"]}
    for name, reason in unavailable.items():
        assert backends[name]["status"] == "skipped"
        assert backends[name]["message"].startswith(reason), backends[name]["message"]
    answered = {n for n, b in backends.items() if b["status"] == "pass"}
    assert {"pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf"} <= answered
    assert answered.isdisjoint(unavailable)


@pytest.mark.parametrize(
    ("axis", "shown"),
    [("0 0 -1e-300", "'0 0 -1e-300'"), ("0 1e300 1e300", "'0 1e300 1e300'")],
)
def test_an_axis_no_reader_can_normalise_is_one_line_and_exit_2(tmp_path, axis, shown):
    model = _write(tmp_path, ARM3_URDF.replace('<axis xyz="0 0 -1"/>', f'<axis xyz="{axis}"/>'))
    done = _check(model, "--against", "pinocchio-urdf")
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        f"fkcheck: error: {model.parent / 'arm3.urdf'}: line 16: joint 'j2': <axis xyz> is "
        f"{shown}, whose length no reader can take (its square is not a normal float: "
        "1.49e-154 … 6.7e+153); write the direction as a unit vector"
    ]


_MIMIC = (
    '<link name="finger"/><joint name="grip" type="revolute"><parent link="tip"/>'
    '<child link="finger"/><origin xyz="0 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>'
    '<limit lower="0" upper="1" effort="1" velocity="1"/>{mimic}</joint>\n</robot>'
)


@pytest.mark.parametrize(
    ("mimic", "says"),
    [
        ('<mimic joint="nowhere"/>', "<mimic joint> is 'nowhere', which is not a joint; joints "
         "are: j1, j2, j3, tip_joint, grip"),
        ('<mimic joint="tip_joint"/>', "<mimic joint> is 'tip_joint', a fixed joint; a mimic "
         "follows a revolute, continuous or prismatic joint"),
        ("<mimic/>", "<mimic joint> names no joint; it must name the joint it follows"),
        ('<mimic joint="grip"/>', "<mimic joint> is the joint itself"),
    ],
)  # fmt: skip
def test_a_mimic_that_follows_no_moving_joint_is_one_line_and_exit_2(tmp_path, mimic, says):
    urdf = ARM3_URDF.replace("</robot>", _MIMIC.format(mimic=mimic))
    model = _write(tmp_path, urdf)
    done = _check(model, "--against", "pinocchio-urdf")
    assert done.returncode == 2
    lines = done.stderr.splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith(f"fkcheck: error: {model.parent / 'arm3.urdf'}: line ")
    assert lines[0].endswith(f"joint 'grip': {says}")


@pytest.mark.parametrize(
    ("header", "says"),
    [
        ("q1_mm,q2,q3,q4,q5,q6,x,y,z,rx,ry,rz", "column q1_mm: _mm is for a length, but q1 is "
         "joint 1 (j1), revolute; name it q1 or q1_deg"),
        ("q1,q2,q3,q4,q5,q6,x_deg,y,z,rx,ry,rz", "column x_deg: _deg is for an angle, but x is a "
         "position; name it x or x_mm"),
        ("q1,q2,q3,q4,q5,q6,x,y,z,rx_mm,ry,rz", "column rx_mm: _mm is for a length, but rx is an "
         "angle; name it rx or rx_deg"),
        ("q1,q2,q3_deg,q4,q5,q6,x,y,z,rx,ry,rz", "column q3_deg: _deg is for an angle, but q3 is "
         "joint 3 (j3), prismatic; name it q3 or q3_mm"),
    ],
)  # fmt: skip
def test_a_poses_column_with_the_unit_of_another_quantity_is_one_line(tmp_path, header, says):
    # q1_mm on a revolute joint was read as milliradians, x_deg as a position, rx_mm as a
    # rotation; on the Stanford arm _mm went to the revolute joints, not the prismatic one.
    path = tmp_path / "p.csv"
    path.write_text(header + "\n0,0,0.5,0,0,0,0,0,1,0,0,0\n", encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "fkcheck", "check", "stanford", "--against", f"poses:{path}"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 2
    assert done.stderr.splitlines() == [f"fkcheck: error: {path}: {says}"]


@pytest.mark.parametrize("entry", ["../outside.toml", "{outside}"])
def test_a_project_models_file_outside_the_project_is_one_line(tmp_path, entry):
    # Absolute and ../ entries of [tool.fkcheck] models were read (directories and globs
    # were already held to the project, as the documentation says of every entry).
    outside = tmp_path / "outside.toml"
    outside.write_text('name = "arm"\nconvention = "standard"\n[[joint]]\na = 0.1\nalpha = 0\n'
                       "d = 0\n", encoding="utf-8")  # fmt: skip
    project = tmp_path / "p"
    project.mkdir()
    shown = entry.format(outside=outside)
    (project / "pyproject.toml").write_text(
        f"[tool.fkcheck]\nmodels = [{json.dumps(shown)}]\n", encoding="utf-8"
    )
    done = subprocess.run(
        [sys.executable, "-m", "fkcheck", "check", "--against", "rtb-dh", "--samples", "2"],
        capture_output=True, text=True, timeout=300, cwd=project,
    )  # fmt: skip
    assert done.returncode == 2
    assert done.stdout == ""
    assert done.stderr.splitlines() == [
        f"fkcheck: error: {project / 'pyproject.toml'}: tool.fkcheck.models: {shown!r}: a file "
        "outside the project"
    ]


def test_diagnose_against_a_reader_that_cannot_read_the_urdf_is_one_line(tmp_path):
    # Its BackendUnavailable (a Skip, not bad input) ended in a traceback.
    pytest.importorskip("mujoco")
    urdf, toml, _ = WORLD_LINK
    model = _write(tmp_path, urdf, toml)
    done = subprocess.run(
        [sys.executable, "-m", "fkcheck", "diagnose", str(model), "--against", "mujoco-urdf",
         "--from", "base", "--to", "tip"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    # diagnose needs that one reader: one line, exit 2, in the words check uses.
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        "fkcheck: error: cannot diagnose against mujoco-urdf: it cannot run here: MuJoCo "
        "cannot read arm3.urdf: Error: joint found in world body"
    ]
