"""``fkcheck:<subpath>``: files bundled with fkcheck, and nothing outside them."""

from __future__ import annotations

import re

import pytest

from fkcheck.cli.main import main
from fkcheck.errors import INSTALL_REFERENCE, BackendUnavailable, UrdfError
from fkcheck.model.read import bundled_models_dir
from fkcheck.urdf.locate import (
    bundled_location,
    display_path,
    example_robot_data_dir,
    locate,
    locate_urdf,
    urdf_spec_for,
)

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


# --- display_path: how every output names a file to a person -------------------------------------


def test_a_bundled_file_is_shown_by_its_fkcheck_spec_which_reads_back(monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)  # elsewhere, as a user of an installed fkcheck
    ur5 = bundled_models_dir() / "ur5.toml"
    assert display_path(ur5) == "fkcheck:ur5.toml"
    assert display_path(str(ur5)) == "fkcheck:ur5.toml"
    assert bundled_location(display_path(ur5)).resolve() == ur5.resolve()
    assert display_path(bundled_models_dir() / "ur_description" / "urdf") == (
        "fkcheck:ur_description/urdf"
    )


def test_a_bundled_file_is_shown_by_its_spec_from_inside_the_checkout_too(monkeypatch):
    monkeypatch.chdir(bundled_models_dir())  # under the current directory, but bundled first
    assert display_path(bundled_models_dir() / "planar2.toml") == "fkcheck:planar2.toml"


def test_a_file_under_the_current_directory_is_shown_relative_to_it(monkeypatch, tmp_path):
    (tmp_path / "robots").mkdir()
    arm = tmp_path / "robots" / "arm.toml"
    arm.write_text("", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert display_path(arm) == "robots/arm.toml"
    assert display_path("robots/arm.toml") == "robots/arm.toml"  # relative: as given


def test_any_other_file_is_shown_as_given(monkeypatch, tmp_path):
    (tmp_path / "here").mkdir()
    monkeypatch.chdir(tmp_path / "here")
    outside = tmp_path / "arm.toml"
    assert display_path(outside) == str(outside)
    assert display_path("../arm.toml") == "../arm.toml"


def test_without_example_robot_data_its_urdfs_name_the_extra(monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name == "example_robot_data" else real(name, *a),
    )
    with pytest.raises(BackendUnavailable, match=re.escape(f"not installed ({INSTALL_REFERENCE})")):
        example_robot_data_dir()
