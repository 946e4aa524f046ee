"""`fkcheck expand` and `table-from --allow-xacro` as a user runs them."""

from __future__ import annotations

import numpy as np
import pytest

from fkcheck.cli.main import main
from fkcheck.model.read import load_model
from fkcheck.urdf.chain import urdf_kinematics
from fkcheck.urdf.tree import read_urdf
from tests.helpers import deadline
from tests.xacro_cases import TOP, grow_macro, twin_urdf, write_description


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_expand_writes_the_plain_urdf(tmp_path, capsys):
    top, package = write_description(tmp_path)
    out_file = tmp_path / "robot.urdf"
    code, out, err = run(
        capsys, "expand", top, "--arg", "reach=0.4", "--package", f"arm_description={package}",
        "-o", out_file,
    )  # fmt: skip
    assert code == 0, err
    assert out == f"wrote {out_file}: 5 links, 4 joints (3 moving), root base\n"
    written, twin = read_urdf(out_file), tmp_path / "twin.urdf"
    twin.write_text(twin_urdf("0.4"))
    q = np.random.default_rng(5).uniform(-3, 3, size=(32, 3))
    kin_a, kin_b = urdf_kinematics(written), urdf_kinematics(read_urdf(twin))
    np.testing.assert_allclose(
        kin_a.chain_poses(kin_a.chain("base", "tip"), q),
        kin_b.chain_poses(kin_b.chain("base", "tip"), q),
        rtol=0,
        atol=1e-12,
    )


def test_expand_refuses_to_overwrite_its_input(tmp_path, capsys):
    top, package = write_description(tmp_path)
    code, _, err = run(capsys, "expand", top, "--package", f"arm_description={package}", "-o", top)
    assert code == 2
    assert err.count("\n") == 1
    assert "Traceback" not in err
    assert top.read_text() == TOP


def test_expand_refuses_to_overwrite_a_file_it_includes(tmp_path, capsys):
    top, package = write_description(tmp_path)
    parts = package / "urdf" / "parts.xacro"
    before = parts.read_text()
    # through a symlink too: the included file is named by its resolved path
    (tmp_path / "link.xacro").symlink_to(parts)
    for target in (parts, tmp_path / "link.xacro"):
        code, _, err = run(
            capsys, "expand", top, "--package", f"arm_description={package}", "-o", target
        )
        assert code == 2, err
        assert err.count("\n") == 1
        assert "a file the xacro file includes" in err, err
        assert parts.read_text() == before


@pytest.mark.parametrize(
    ("edit", "argv", "expected"),
    [
        (("$(arg reach)", "$(arg offset)"), [], "xacro argument 'offset' is not given"),
        ((), ["--package", "other=."], "package 'arm_description' is not declared"),
        (('value="0.25"', 'value="${1/0}"'), [], "division by zero"),
        (
            ('<link name="base"/>', grow_macro("", 40) + '<link name="base"/>'),
            ["--timeout", "1"],
            "did not end within 1 s",
        ),
        ((), ["--arg", "reach"], "--arg 'reach': expected NAME=VALUE"),
        ((), ["--package", "bad name=."], "is not a package name"),
        ((), ["--timeout", "0"], "--timeout: must be > 0 and at most 86400 s"),
    ],
)
def test_expand_bad_input_is_one_line_and_writes_nothing(tmp_path, capsys, edit, argv, expected):
    top_text = TOP.replace(*edit) if edit else TOP
    top, package = write_description(tmp_path, top_text)
    packages = [] if "--package" in argv else ["--package", f"arm_description={package}"]
    out_file = tmp_path / "robot.urdf"
    with deadline(30):
        code, out, err = run(capsys, "expand", top, *packages, *argv, "-o", out_file)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1
    assert "Traceback" not in err
    assert expected in err, err
    assert not out_file.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm_description", "robot"]


def test_dh_from_urdf_needs_the_opt_in_and_then_writes_a_model_that_checks(tmp_path, capsys):
    top, package = write_description(tmp_path)
    model = tmp_path / "robot" / "derived.toml"
    base = ["table-from", top, "--base", "base", "--tip", "tip", "-o", model]
    code, _, err = run(capsys, *base)
    assert code == 2
    assert "--allow-xacro" in err
    code, _, err = run(capsys, *base, "--arg", "reach=0.4")
    assert code == 2
    assert "--arg goes with --allow-xacro" in err
    package_arg = f"arm_description={package}"
    code, _, err = run(
        capsys, *base, "--allow-xacro", "--arg", "reach=0.4", "--package", package_arg
    )
    assert code == 0, err
    derived = load_model(model)
    assert derived.urdf is not None
    assert derived.urdf.xacro
    assert derived.urdf.xacro_args == {"reach": "0.4"}
    assert derived.urdf.packages == {"arm_description": "../arm_description"}
    code, out, err = run(capsys, "check", model, "--quiet", "--samples", "20")
    assert code == 0, out + err
