"""What a verdict proved: implementation vs table evidence, in every output format.

Acceptance cases of "a verdict that says what it proved": a wrong table with no
independent evidence must never read as verified (terminal, JSON, JUnit,
Markdown, HTML), ``--require table`` makes that fatal, a URDF declared but never
compared is an error, and a wrong answer is a failure with its reason.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from fkcheck.cli.main import main
from fkcheck.model.frames import frame_poses_from_dh, relative_pose
from fkcheck.model.read import bundled_model_paths, load_model
from tests.backend_cases import URDF_BACKENDS
from tests.paths import PLUGINS_DIR

PLUGINS = PLUGINS_DIR


def variant(tmp_path: Path, name: str, old: str, new: str) -> Path:
    text = bundled_model_paths()[name].read_text()
    assert text.count(old) >= 1, old
    path = tmp_path / f"{name}_variant.toml"
    path.write_text(text.replace(old, new, 1))
    return path


def run(capsys, tmp_path: Path, model: Path | str, *extra: str) -> tuple[int, dict, str, Path]:
    out_dir = tmp_path / "out"
    out_dir.mkdir(exist_ok=True)
    outputs = ["--json", str(out_dir / "r.json"), "--junit", str(out_dir / "r.xml"),
               "--summary", str(out_dir / "r.md")]  # fmt: skip
    code = main(["check", str(model), "--samples", "16", *outputs, *extra])
    out, err = capsys.readouterr()
    return code, json.loads((out_dir / "r.json").read_text()), out + err, out_dir


def without_urdf(name: str) -> str:
    """A bundled UR model's file without its [urdf], [frames] and [check]: nothing independent."""
    text = bundled_model_paths()[name].read_text()
    return text[: text.index("# UR's own ROS 2 description")]


def ur5e_d1_10mm(tmp_path: Path) -> Path:
    path = tmp_path / "ur5e_d1.toml"
    path.write_text(without_urdf("ur5e").replace("d = 0.1625", "d = 0.1725", 1))
    return path


def ur5e_alpha4_flipped(tmp_path: Path) -> Path:
    # joint[3] (wrist_1) is the second `alpha = 90`.
    text = without_urdf("ur5e")
    head, _, tail = text.partition('name = "wrist_1"')
    path = tmp_path / "ur5e_alpha4.toml"
    path.write_text(head + 'name = "wrist_1"' + tail.replace("alpha = 90", "alpha = -90", 1))
    return path


@pytest.mark.parametrize("make", [ur5e_d1_10mm, ur5e_alpha4_flipped], ids=["d1+10mm", "alpha4"])
def test_a_wrong_table_without_independent_evidence_never_reads_as_verified(capsys, tmp_path, make):
    code, doc, out, out_dir = run(capsys, tmp_path, make(tmp_path))
    # The implementations agree (they run the same wrong table): exit 0 ...
    assert code == 0, out
    assert doc["verdict"] == "pass"
    # ... but nothing anywhere says the table is right.
    assert doc["evidence"]["implementation"]["status"] == "verified"
    assert doc["evidence"]["table"]["status"] == "not-checked"
    assert doc["evidence"]["table"]["agreed"] == []
    assert "implementation only" in doc["headline"]
    assert "table NOT CHECKED" in out
    assert "implementation only" in out
    assert "table verified" not in out
    suite = ET.parse(out_dir / "r.xml").getroot().find("testsuite")
    case = suite.find("testcase[@name='evidence: table verified independently']")
    assert case is not None
    assert case.find("skipped") is not None
    assert "NOT CHECKED" in case.find("skipped").get("message")
    summary = (out_dir / "r.md").read_text()
    assert "❔ table NOT CHECKED" in summary
    html_path = tmp_path / "r.html"
    assert main(["check", str(make(tmp_path)), "--samples", "4", "--html", str(html_path)]) == 0
    capsys.readouterr()
    html = html_path.read_text()
    assert 'data-kind="table" data-status="not-checked"' in html
    assert "table verified" not in html
    # The badge itself is not a plain green PASS.
    assert 'class="big-badge pass partial"' in html
    assert '<small id="verdict-badge-note">implementation only</small>' in html


@pytest.mark.parametrize("make", [ur5e_d1_10mm, ur5e_alpha4_flipped], ids=["d1+10mm", "alpha4"])
def test_require_table_makes_an_unchecked_table_fatal(capsys, tmp_path, make):
    code, doc, out, out_dir = run(capsys, tmp_path, make(tmp_path), "--require", "table")
    assert code == 1
    assert doc["verdict"] == "unverified"
    assert doc["evidence"]["required"] == ["table"]
    assert doc["evidence"]["unmet"] == ["table"]
    assert "verdict: unverified" in out
    suite = ET.parse(out_dir / "r.xml").getroot().find("testsuite")
    case = suite.find("testcase[@name='evidence: table verified independently']")
    assert case.find("failure").get("type") == "required"
    assert "UNVERIFIED" in (out_dir / "r.md").read_text()


def test_require_in_the_model_file_works_like_the_flag(capsys, tmp_path):
    path = tmp_path / "ur5e_required.toml"
    path.write_text(without_urdf("ur5e") + '\n[check]\nrequire = ["table"]\n')
    code, doc, _, _ = run(capsys, tmp_path, path)
    assert (code, doc["verdict"], doc["evidence"]["unmet"]) == (1, "unverified", ["table"])


def test_require_table_passes_where_the_urdf_verifies_it(capsys, tmp_path):
    code, doc, out, _ = run(capsys, tmp_path, "ur5", "--require", "table")
    assert code == 0, out
    assert doc["evidence"]["table"]["status"] == "verified"
    assert doc["evidence"]["table"]["agreed"] == list(URDF_BACKENDS)
    assert doc["headline"].startswith("pass — table verified independently")
    html_path = tmp_path / "r.html"
    assert main(["check", "ur5", "--samples", "4", "--html", str(html_path)]) == 0
    capsys.readouterr()
    html = html_path.read_text()
    assert 'class="big-badge pass"' in html
    assert "verdict-badge-note" not in html


def test_unknown_require_kind_is_bad_input(capsys):
    assert main(["check", "ur5", "--require", "tabel"]) == 2
    err = capsys.readouterr().err
    assert "'tabel' is not a kind of evidence; kinds are: implementation, table" in err


def test_the_same_d1_change_fails_where_a_urdf_exists(capsys, tmp_path):
    model = variant(tmp_path, "ur5", "d = 0.089159", "d = 0.099159")  # 10 mm
    code, doc, _, _ = run(capsys, tmp_path, model)
    assert code == 1
    assert doc["verdict"] == "fail"
    assert doc["evidence"]["table"]["status"] == "failed"
    assert set(doc["evidence"]["table"]["disagreed"]) == set(URDF_BACKENDS)
    assert doc["evidence"]["implementation"]["status"] == "verified"
    rows = {b["name"]: b for b in doc["backends"]}
    assert rows["pinocchio-urdf"]["max_position_error_m"] == pytest.approx(0.010, rel=1e-6)


def test_a_urdf_declared_but_not_mapped_is_an_error_naming_what_to_map(
    capsys, tmp_path, monkeypatch
):
    monkeypatch.setenv("COLUMNS", "1000")  # one line per row: the message is not folded
    text = bundled_model_paths()["ur5"].read_text()
    text = text[: text.index("# DH frame 0 is the controller")]  # no [frames], no [check]
    path = tmp_path / "ur5_unmapped.toml"
    path.write_text(text)
    code, doc, out, _ = run(capsys, tmp_path, path)
    assert code == 1
    assert doc["verdict"] == "error"
    rows = {b["name"]: b for b in doc["backends"]}
    for name in ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf"):
        assert rows[name]["status"] == "error"
        assert "has no URDF twin" in rows[name]["message"]
        assert "[frames.world]" in rows[name]["message"]
        assert (
            "URDF links: world, base_link, base_link_inertia, shoulder_link"
            in rows[name]["message"]
        )
    assert doc["evidence"]["table"]["status"] == "not-checked"
    assert "(no urdf" not in out  # the old skip text with its hole is gone
    assert "[frames.world]" in out  # printed literally, not eaten as rich markup


def test_a_non_rigid_answer_is_a_failure_with_reason_and_position_error(
    capsys, tmp_path, monkeypatch
):
    monkeypatch.syspath_prepend(str(PLUGINS))
    code, doc, out, _ = run(
        capsys, tmp_path, "ur5", "--from", "world", "--to", "tool0", "--against", "nonrigid:forward"
    )
    assert code == 1
    assert doc["verdict"] == "fail"
    (row,) = doc["backends"]
    assert row["status"] == "fail"
    assert row["evidence"] == "implementation"
    assert row["message"].startswith("not a rigid transform: defect ")
    assert " at q = [" in row["message"]
    assert row["max_position_error_m"] is not None
    assert row["max_position_error_m"] < 1e-12  # the position column is right
    assert "nothing was cross-checked" not in out
    assert "verdict: fail" in out


def test_ur_frames_are_named_as_their_descriptions_name_them():
    """tool0 → flange as UR's ROS 2 description has it (mapped); ee_link as ROS 1's (not)."""
    for name in ("ur3", "ur5", "ur10"):
        model = load_model(name)
        q = np.zeros((1, 6))
        poses = frame_poses_from_dh(
            model, model.fk(q, all_frames=True), model.fk(q), ["tool0", "flange", "ee_link"]
        )
        tool0_T_flange = relative_pose(poses[0], poses[1])[0]
        np.testing.assert_allclose(
            tool0_T_flange[:3, :3], [[0, 1, 0], [0, 0, 1], [1, 0, 0]], atol=1e-15
        )
        np.testing.assert_allclose(tool0_T_flange[:3, 3], 0.0, atol=0)
        # flange is ee_link turned 180° about x.
        ee_link_T_flange = relative_pose(poses[2], poses[1])[0]
        np.testing.assert_allclose(ee_link_T_flange[:3, :3], np.diag([1, -1, -1]), atol=1e-15)
        assert model.frames["flange"].urdf == "flange"
        assert model.frames["ee_link"].urdf is None  # the ROS 2 URDF has no ee_link


def test_a_urdf_link_names_the_frame_mapped_onto_it(capsys, tmp_path):
    code, doc, out, _ = run(capsys, tmp_path, "ur5", "--from", "urdf:base_link", "--to",
                            "urdf:flange")  # fmt: skip
    assert code == 0, out
    assert (doc["from"], doc["to"]) == ("base_link", "flange")
    assert doc["evidence"]["table"]["status"] == "verified"


def test_a_urdf_link_of_a_model_without_a_urdf_is_bad_input(capsys):
    # (A model with a [urdf] compares any of its links: tests/cli/test_map.py.)
    assert main(["check", "puma560", "--to", "urdf:link6"]) == 2
    err = capsys.readouterr().err
    assert "no declared frame has URDF twin 'link6'" in err
    assert err.count("\n") == 1


def test_the_headline_claims_no_implementation_check_that_did_not_run(capsys, tmp_path):
    code, doc, out, _ = run(capsys, tmp_path, "ur5", "--against", "pinocchio-urdf")
    assert code == 0, out
    assert doc["evidence"]["implementation"]["status"] == "not-checked"
    assert doc["headline"] == (
        "pass — table verified independently, θ1, α6, θ6 on the word of [frames.base_link], "
        '[frames.flange] ("Universal_Robots_ROS2_Description 2.4.5, ur_macro.xacro: jo…"); '
        "no second implementation ran"
    )
    assert "pinocchio-urdf agrees (evidence independent of the table)" in " ".join(out.split())


def test_a_closed_stdout_neither_changes_the_exit_code_nor_loses_the_reports(tmp_path):
    """`fkcheck check … | head -1`: the JSON is written and the exit code is the check's."""
    import subprocess
    import sys

    report = tmp_path / "r.json"
    proc = subprocess.Popen(
        [sys.executable, "-m", "fkcheck", "check", "planar2", "--samples", "2", "--against",
         "rtb-dh", "--json", str(report)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )  # fmt: skip
    assert proc.stdout is not None
    proc.stdout.readline()
    proc.stdout.close()  # like `head -1`
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err
    assert err == b""
    assert json.loads(report.read_text())["verdict"] == "pass"
