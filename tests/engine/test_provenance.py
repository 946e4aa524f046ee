"""A URDF fkcheck wrote from the checked table never verifies it, however it was renamed.

Issue 20, item 4: ``fkcheck urdf --write-model`` from a wrong table, then
``check --require table``, said "table verified independently".
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from fkcheck.backends.registry import make_backend
from fkcheck.cli.main import main
from fkcheck.engine.runner import run_check
from fkcheck.model.read import bundled_model_paths, load_model
from tests.backend_cases import URDF_BACKENDS


def _wrong_ur5(directory: Path) -> Path:
    """The UR5 with d1 10 mm too long."""
    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    assert "d = 0.089159\n" in text
    path = directory / "wrong.toml"
    path.write_text(text.replace("d = 0.089159\n", "d = 0.099159\n", 1), encoding="utf-8")
    return path


def _disguised_export(tmp_path: Path, *, unmark: bool) -> Path:
    """``fkcheck urdf --write-model`` of the wrong table, its URDF renamed and stripped.

    Returns:
        The written model, pointing at the renamed URDF: comments gone, and with
        ``unmark`` fkcheck's mark gone and every generated link renamed too.
    """
    table = _wrong_ur5(tmp_path)
    urdf, mapped = tmp_path / "out" / "robot.urdf", tmp_path / "mapped.toml"
    assert main(["urdf", str(table), "-o", str(urdf), "--write-model", str(mapped)]) == 0
    text = re.sub(r"<!--.*?-->", "", urdf.read_text(encoding="utf-8"), flags=re.DOTALL)
    model = re.sub(r"#[^\n]*", "", mapped.read_text(encoding="utf-8")).replace(
        "out/robot.urdf", "out/ur5_vendor.urdf"
    )
    if unmark:
        text = re.sub(r"<fkcheck:written-from[^>]*/>", "", text)
        text = text.replace(' xmlns:fkcheck="urn:fkcheck:urdf-provenance"', "")
        text, model = (s.replace("dh_frame_", "link_") for s in (text, model))
    urdf.unlink()
    (tmp_path / "out" / "ur5_vendor.urdf").write_text(text, encoding="utf-8")
    mapped.write_text(model, encoding="utf-8")
    return mapped


@pytest.mark.parametrize("unmark", [False, True], ids=["comments-stripped", "mark-removed"])
def test_a_self_written_urdf_of_a_wrong_table_leaves_it_unverified(tmp_path, capsys, unmark):
    model = _disguised_export(tmp_path, unmark=unmark)
    capsys.readouterr()
    code = main(["check", str(model), "--require", "table", "--samples", "20"])
    out = capsys.readouterr().out
    assert code == 1, out
    assert "table verified" not in out
    assert "verdict: unverified" in out
    assert "table NOT CHECKED" in out
    flat = " ".join(out.split())  # the console folds long lines
    how = "is what fkcheck urdf writes" if unmark else "was written by fkcheck"
    assert f"{', '.join(URDF_BACKENDS)}: the URDF {how} from this table" in flat
    assert "it cannot verify the table" in flat


def test_a_dressed_export_of_a_table_748_mm_off_leaves_it_unverified(tmp_path, capsys):
    """Issue 30, item 5: mark deleted, inertia added to every link: still the table's own."""
    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    assert "a = -0.425\n" in text
    table = tmp_path / "wrong.toml"
    table.write_text(text.replace("a = -0.425\n", "a = -1.173\n", 1), encoding="utf-8")
    urdf, mapped = tmp_path / "out" / "robot.urdf", tmp_path / "mapped.toml"
    assert main(["urdf", str(table), "-o", str(urdf), "--write-model", str(mapped)]) == 0
    dressed = re.sub(r"<!--.*?-->", "", urdf.read_text(encoding="utf-8"), flags=re.DOTALL)
    dressed = re.sub(r"<fkcheck:written-from[^>]*/>", "", dressed)
    dressed = dressed.replace(' xmlns:fkcheck="urn:fkcheck:urdf-provenance"', "")
    dressed = re.sub(
        r'<link name="([^"]+)" />',
        r'<link name="\1"><inertial><mass value="3.7" /><inertia ixx="0.01" ixy="0" ixz="0" '
        r'iyy="0.01" iyz="0" izz="0.01" /></inertial></link>',
        dressed,
    )
    assert "fkcheck" not in dressed
    assert dressed.count("<inertial>") >= 8
    urdf.write_text(dressed, encoding="utf-8")
    capsys.readouterr()
    code = main(["check", str(mapped), "--require", "table", "--samples", "20"])
    out = capsys.readouterr().out
    assert code == 1, out
    assert "verdict: unverified" in out
    assert "table verified" not in out
    assert "is what fkcheck urdf writes from this table" in " ".join(out.split())
    # the right table against that URDF: 748 mm apart at zero, and said so
    right = load_model(mapped)
    joints = list(right.joints)
    joints[1] = replace(joints[1], a=-0.425)
    check = run_check(replace(right, joints=tuple(joints)), [make_backend("pinocchio-urdf")],
                      samples=8)  # fmt: skip
    assert check.verdict == "fail"
    assert check.backends[0].evidence == "table"
    assert 0.74 < (check.backends[0].max_position_error_m or 0.0) < 1.5


def test_its_urdf_backends_count_as_implementation_evidence(tmp_path):
    model = load_model(_disguised_export(tmp_path, unmark=False))
    check = run_check(model, [make_backend(n) for n in URDF_BACKENDS], samples=8)
    assert [(r.name, r.status, r.evidence) for r in check.backends] == [
        (name, "pass", "implementation") for name in URDF_BACKENDS
    ]
    assert all("it cannot verify the table" in r.message for r in check.backends)
    assert check.evidence.table.status == "not-checked"


def test_a_bundled_model_with_its_real_urdf_is_still_table_verified(capsys):
    pytest.importorskip("example_robot_data")
    code = main(["check", "ur5", "--require", "table", "--samples", "20"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "verdict: pass — table verified independently" in out
    assert "cannot verify the table" not in out


def _poses_from_fk(tmp_path: Path, model: Path, capsys, noise_m: float = 0.0) -> Path:
    """A poses file assembled from ``fkcheck fk``'s output for seeded configurations."""
    q = np.random.default_rng(7).uniform(-3.0, 3.0, (24, 6))
    q_file = tmp_path / "q.csv"
    q_file.write_text("".join(",".join(repr(float(v)) for v in row) + "\n" for row in q))
    capsys.readouterr()
    assert main(["fk", str(model), "--q-file", str(q_file), "--format", "rotvec"]) == 0
    poses = np.array(
        [[float(v) for v in line.split()] for line in capsys.readouterr().out.split("\n") if line]
    )
    poses[:, :3] += noise_m * np.random.default_rng(8).standard_normal((24, 3))
    header = "q1,q2,q3,q4,q5,q6,x,y,z,rx,ry,rz\n"
    rows = "".join(
        ",".join(repr(float(v)) for v in (*a, *b)) + "\n" for a, b in zip(q, poses, strict=True)
    )
    path = tmp_path / "measured.csv"
    path.write_text(header + rows, encoding="utf-8")
    return path


def test_poses_computed_from_the_table_are_implementation_evidence(tmp_path, capsys):
    """Issue 30, item 5: poses written from fkcheck fk's output of the table itself."""
    wrong = _wrong_ur5(tmp_path)
    poses = _poses_from_fk(tmp_path, wrong, capsys)
    capsys.readouterr()
    against = ["--against", f"poses:{poses}"]
    assert main(["check", str(wrong), *against, "--require", "table"]) == 1
    out = " ".join(capsys.readouterr().out.split())
    assert "verdict: unverified" in out
    assert "table verified" not in out
    assert "computed from this table (fkcheck fk, or a program given it)" in out
    # The same file is evidence against another table: the right UR5 fails on it.
    assert main(["check", "ur5", *against]) == 1
    assert "table FAILED" in capsys.readouterr().out


def test_poses_with_a_measurements_noise_stay_table_evidence(tmp_path, capsys):
    model = load_model("ur5")
    poses = _poses_from_fk(tmp_path, bundled_model_paths()["ur5"], capsys, noise_m=1e-7)
    check = run_check(model, [make_backend(f"poses:{poses}")], tol_pos_m=1e-6)
    (result,) = check.backends
    assert result.status == "pass"
    assert result.evidence == "table"
    assert "computed from this table" not in result.message
