"""``[urdf] xacro_files``, ``expand --arg-file``: a xacro argument naming a file, that file only.

A calibration (UR's ``kinematics_params``) lives next to the model, outside the
description: the model names it in ``xacro_files``, the expansion gets its
absolute path and may read that one file besides the description's directory
and packages. A file that is a directory, missing or too large, a name given
both as a value and as a file, are one line; a symbolic link is followed, as an
include's is (the file it leads to is the one readable — naming a file is as
much trust as naming a package directory, which may be any directory); a file
next to the named one stays out of reach.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from fkcheck.urdf.screen import MAX_URDF_BYTES
from tests.helpers import deadline
from tests.xacro_cases import TOP, write_description, write_model

PACKAGES = 'packages = { arm_description = "../arm_description" }'
FILES = 'xacro_files = { calib = "../cal/robot_calibration.yaml" }'
SECRET = "s3cr3t-next-to-the-calibration"


def calibrated_top(load: str = "calib_file") -> str:
    """:data:`TOP` with the tip's reach read from the yaml file the argument ``calib`` names."""
    head = (
        '<xacro:arg name="calib" default=""/>'
        '<xacro:property name="calib_file" value="$(arg calib)"/>'
        f'<xacro:property name="cal" value="${{xacro.load_yaml({load})}}"/>'
    )
    top = TOP.replace('<link name="base"/>', f'{head}<link name="base"/>')
    top = top.replace('<origin xyz="$(arg reach) 0 0"', "<origin xyz=\"${cal['reach']} 0 0\"")
    return top.replace('<link name="tip"/>', '<link name="tip"/><gazebo>$(arg calib)</gazebo>')


@pytest.fixture
def workdir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The description, a calibration outside it and a secret next to the calibration."""
    monkeypatch.chdir(tmp_path)
    write_description(tmp_path, calibrated_top())
    (tmp_path / "cal").mkdir()
    (tmp_path / "cal" / "robot_calibration.yaml").write_text("reach: 0.4\n")
    (tmp_path / "cal" / "secret.yaml").write_text(f"reach: {SECRET}\n")
    return tmp_path


def sparse(path: Path) -> Path:
    path.write_bytes(b"")
    return path


def run(capfd: pytest.CaptureFixture[str], argv: list[str | Path]) -> tuple[int, str, str]:
    with deadline(60.0):
        code = main([str(a) for a in argv])
    out, err = capfd.readouterr()
    return code, out, err


def one_line(err: str, pattern: str) -> None:
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert re.search(pattern, lines[0]), err
    assert "Traceback" not in err
    assert SECRET not in err


def test_the_named_file_is_read_and_passed_as_its_absolute_path(workdir, capfd):
    model = write_model(workdir, "0.4", f"xacro = true\n{PACKAGES}\n{FILES}")
    code, out, err = run(capfd, ["check", model, "--samples", "5", "--against", "pinocchio-urdf"])
    assert code == 0, out + err
    top = workdir / "robot" / "arm.urdf.xacro"
    package = f"arm_description={workdir / 'arm_description'}"
    calibration = "calib=cal/robot_calibration.yaml"
    argv = [
        "expand",
        top,
        "--package",
        package,
        "--arg-file",
        calibration,
        "-o",
        workdir / "x.urdf",
    ]
    code, _, err = run(capfd, argv)
    assert code == 0, err
    calibration = (workdir / "cal" / "robot_calibration.yaml").resolve()
    assert f"<gazebo>{calibration}</gazebo>" in (workdir / "x.urdf").read_text()


def test_the_model_fails_against_another_calibration(workdir, capfd):
    """The file's numbers are used: a model of reach 0.3 fails against a 0.4 calibration."""
    model = write_model(workdir, "0.3", f"xacro = true\n{PACKAGES}\n{FILES}")
    code, out, err = run(capfd, ["check", model, "--samples", "5", "--against", "pinocchio-urdf"])
    assert code == 1, out + err


@pytest.mark.parametrize(
    ("name", "make", "refusal"),
    [
        ("directory", lambda cal: cal.mkdir(), r"is a directory"),
        ("missing", lambda cal: None, r"(does not exist|no such file|not found)"),
        ("too-large", lambda cal: os.truncate(sparse(cal), MAX_URDF_BYTES + 1), r"too large"),
        ("fifo", os.mkfifo, r"FIFO|fifo|named pipe"),
    ],
)
def test_a_file_that_cannot_be_one_is_one_line(workdir, capfd, name, make, refusal):
    cal = workdir / "cal" / "bad.yaml"
    make(cal)
    files = 'xacro_files = { calib = "../cal/bad.yaml" }'
    model = write_model(workdir, "0.4", f"xacro = true\n{PACKAGES}\n{files}")
    code, _, err = run(capfd, ["check", model, "--samples", "5", "--against", "pinocchio-urdf"])
    assert code == 2
    one_line(err, r"xacro argument file calib=.*bad\.yaml: .*" + f"(?i:{refusal})")


def test_a_name_both_a_value_and_a_file_is_one_line(workdir, capfd):
    extra = f'xacro = true\n{PACKAGES}\n{FILES}\nxacro_args = {{ calib = "x" }}'
    model = write_model(workdir, "0.4", extra)
    code, _, err = run(capfd, ["check", model, "--samples", "5"])
    assert code == 2
    one_line(err, r"xarm\.toml: urdf\.xacro_files\.calib: also in urdf\.xacro_args")
    top = workdir / "robot" / "arm.urdf.xacro"
    argv = ["expand", top, "--arg", "calib=x", "--arg-file", "calib=cal/robot_calibration.yaml",
            "-o", workdir / "out.urdf"]  # fmt: skip
    code, _, err = run(capfd, argv)
    assert code == 2
    one_line(err, r"--arg-file calib: calib is given twice")


def test_a_file_next_to_the_named_one_stays_out_of_reach(workdir, capfd):
    top = calibrated_top("calib_file.replace('robot_calibration', 'secret')")
    (workdir / "robot" / "arm.urdf.xacro").write_text(top)
    model = write_model(workdir, "0.4", f"xacro = true\n{PACKAGES}\n{FILES}")
    code, _, err = run(capfd, ["check", model, "--samples", "5", "--against", "pinocchio-urdf"])
    assert code == 2
    one_line(err, r"load_yaml of '.*/cal/secret\.yaml': outside the xacro file's directory")


def test_a_symlink_is_followed_and_only_its_target_is_readable(workdir, capfd):
    """A link to /etc/passwd gives /etc/passwd (as the path would), nothing else in /etc."""
    (workdir / "cal" / "link.yaml").symlink_to("/etc/passwd")
    files = 'xacro_files = { calib = "../cal/link.yaml" }'
    model = write_model(workdir, "0.4", f"xacro = true\n{PACKAGES}\n{files}")
    code, _, err = run(capfd, ["check", model, "--samples", "5", "--against", "pinocchio-urdf"])
    assert code == 2  # /etc/passwd is no calibration: read as one string, cal['reach'] fails
    one_line(err, r"xacro expansion failed: .*cal\['reach'\]")
    top = calibrated_top("calib_file.replace('passwd', 'shadow')")
    (workdir / "robot" / "arm.urdf.xacro").write_text(top)
    code, _, err = run(capfd, ["check", model, "--samples", "5", "--against", "pinocchio-urdf"])
    assert code == 2
    one_line(err, r"load_yaml of '/etc/shadow': outside the xacro file's directory")
