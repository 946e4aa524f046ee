"""``fkcheck:<subpath>``: files bundled with fkcheck, and nothing outside them."""

from __future__ import annotations

import re

import pytest

from fkcheck.cli.main import main
from fkcheck.errors import UrdfError
from fkcheck.model.read import bundled_models_dir
from fkcheck.urdf.locate import bundled_location, locate, locate_urdf, urdf_spec_for

UR_XACRO = "fkcheck:ur_description/urdf/ur.urdf.xacro"


def test_a_bundled_file_and_directory_resolve_under_the_bundled_models():
    root = bundled_models_dir()
    assert bundled_location(UR_XACRO) == root / "ur_description" / "urdf" / "ur.urdf.xacro"
    assert locate("fkcheck:ur_description").is_dir()
    path, _ = locate_urdf(UR_XACRO)
    assert path.is_file()
    assert urdf_spec_for(path, None) == UR_XACRO  # and back


@pytest.mark.parametrize(
    "spec",
    [
        "fkcheck:../pyproject.toml",
        "fkcheck:ur_description/../../pyproject.toml",
        "fkcheck:/etc/passwd",
        "fkcheck:..",
        "fkcheck: ",
    ],
)
def test_an_escape_is_one_line(spec):
    with pytest.raises(UrdfError, match=r"relative path without '\.\.'"):
        bundled_location(spec)


def test_a_bundled_symlink_leading_out_is_refused(monkeypatch, tmp_path):
    (tmp_path / "out").symlink_to("/etc")
    monkeypatch.setattr("fkcheck.model.read.bundled_models_dir", lambda: tmp_path)
    with pytest.raises(UrdfError, match="leads outside fkcheck's bundled models"):
        bundled_location("fkcheck:out/passwd")


def test_expand_takes_the_prefix_for_the_file_and_the_package(tmp_path, capsys):
    out = tmp_path / "ur5e.urdf"
    argv = ["expand", UR_XACRO, "--arg", "ur_type=ur5e", "--arg", "name=ur5e",
            "--package", "ur_description=fkcheck:ur_description", "-o", str(out)]  # fmt: skip
    assert main(argv) == 0, capsys.readouterr().err
    assert "root world" in capsys.readouterr().out
    assert 'name="flange"' in out.read_text()


def test_expand_refuses_a_package_leaving_the_bundle(tmp_path, capsys):
    argv = ["expand", UR_XACRO, "--package", "p=fkcheck:../..", "-o", str(tmp_path / "x.urdf")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert re.fullmatch(r"fkcheck: error: 'fkcheck:\.\./\.\.': .*\n", err), err


def test_map_writes_a_bundled_package_with_the_prefix(tmp_path, capsys):
    model = tmp_path / "ur5e.toml"
    text = (bundled_models_dir() / "ur5e.toml").read_text(encoding="utf-8")
    model.write_text(text[: text.index("# UR's own ROS 2 description")], encoding="utf-8")
    argv = ["map", str(model), UR_XACRO, "--allow-xacro", "--arg", "ur_type=ur5e",
            "--arg", "name=ur5e", "--package", "ur_description=fkcheck:ur_description"]  # fmt: skip
    assert main(argv) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    assert f'path = "{UR_XACRO}"' in out
    assert 'packages = { "ur_description" = "fkcheck:ur_description" }' in out
    assert 'rpy = [-90.0, -90.0, 0.0]\nurdf = "flange"' in out  # as the bundled model has it
