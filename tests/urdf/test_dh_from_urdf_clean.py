"""table-from writes a table fkcheck lint finds clean: round numbers snapped, --deg."""

from __future__ import annotations

import math

import pytest

from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.urdf.to_dh import CLEAN_TOL, clean_number
from tests.helpers import BUNDLED

#: Bundled models with a URDF, and the URDF links their [check] compares.
WITH_URDF = [n for n in BUNDLED if load_model(n).urdf is not None]


def test_every_bundled_model_with_a_urdf_is_covered():
    assert set(WITH_URDF) >= {"ur3", "ur5", "ur10", "panda"}


def test_clean_number_snaps_only_within_the_tolerance():
    assert clean_number(math.pi / 2 - 4.9e-12, angle=True) == math.pi / 2
    assert clean_number(-math.pi / 2 + 4.1e-10, angle=True) == -math.pi / 2
    assert clean_number(math.pi + 1e-12, angle=True) == math.pi
    assert clean_number(2.07e-13, angle=True) == 0.0
    assert math.copysign(1, clean_number(-2.07e-13, angle=True)) == 1  # no "-0.0" in a table
    assert clean_number(1.5708, angle=True) == 1.5708  # 3.7e-6 off: the URDF says so, kept
    assert clean_number(0.08230000000000001, angle=False) == 0.0823
    assert clean_number(1.07e-10, angle=False) == 0.0
    assert clean_number(0.089159 + 5e-10, angle=False) == 0.089159
    assert clean_number(1.07e-6, angle=False) == 1.07e-6  # a real micrometre, kept
    assert clean_number(0.1 + 2 * CLEAN_TOL, angle=False) == 0.1 + 2 * CLEAN_TOL


@pytest.mark.parametrize("deg", [False, True], ids=["rad", "deg"])
@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("name", WITH_URDF)
def test_dh_from_urdf_of_every_bundled_urdf_lints_clean(name, convention, deg, tmp_path, capsys):
    model = load_model(name)
    base = model.frames[model.check.frame_from].urdf or model.check.frame_from
    tip = model.frames[model.check.frame_to].urdf or model.check.frame_to
    out = tmp_path / f"{name}.toml"
    argv = ["table-from", model.urdf.path, "--base", base, "--tip", tip, "--convention",
            convention, "-o", str(out)]  # fmt: skip
    if model.urdf.xacro:  # UR's ROS 2 description, bundled: fkcheck:ur_description
        argv += ["--allow-xacro"]
        argv += [f"--arg={k}={v}" for k, v in model.urdf.xacro_args.items()]
        argv += [f"--package={k}={v}" for k, v in model.urdf.packages.items()]
    assert main([*argv, "--deg"] if deg else argv) == 0
    rounded = bool(model.known_differences)  # these URDFs write right angles rounded
    capsys.readouterr()
    if rounded:  # the URDF's 1.5708 is kept; lint says so, or names the published table
        assert main(["lint", str(out)]) in (0, 1)
        warnings = [ln for ln in capsys.readouterr().out.splitlines() if "warning" in ln]
        assert all("[rounded-angle]" in ln or "[published]" in ln for ln in warnings), warnings
        return
    assert main(["lint", str(out)]) == 0, capsys.readouterr().out
    text = out.read_text(encoding="utf-8")
    body = "\n".join(line for line in text.splitlines() if not line.startswith("#"))
    assert "e-1" not in body  # no 1e-12-style noise anywhere in the numbers
    assert "00000000" not in body  # nor 0.08230000000000001 / 360.0000000000237
    assert f'angle_unit = "{"deg" if deg else "rad"}"' in text
    if deg:
        assert "alpha = -90.0" in body or "alpha = 90.0" in body


def test_dh_from_urdf_ur5_in_degrees_reads_like_the_vendor_sheet(tmp_path, capsys):
    out = tmp_path / "ur5.toml"
    spec = "example-robot-data:ur_description/urdf/ur5_robot.urdf"
    assert main(["table-from", spec, "--base", "base_link", "--tip", "tool0", "--deg",
                 "-o", str(out)]) == 0  # fmt: skip
    extracted = load_model(out)
    assert [j.d for j in extracted.joints] == [0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823]
    assert [round(math.degrees(j.alpha), 12) for j in extracted.joints] == [-90, 0, 0, -90, 90, 0]
    assert [j.theta for j in extracted.joints][:5] == [0.0] * 5
    assert extracted.joints[0].limits == (-2 * math.pi, 2 * math.pi)
    assert "limits = [-360.0, 360.0]" in out.read_text(encoding="utf-8")
