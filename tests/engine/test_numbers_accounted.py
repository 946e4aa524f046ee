"""Every number accounted for, end to end: the issue's false greens, each through the CLI.

A table error moved into a frame offset (what ``fkcheck map`` does with a wrong
d1), ``urdf:`` pairs placed from the same table, base/tool outside the pair,
pairs spanning no joint: each check says which numbers it verified, in every
output, and never "table verified" for more than it tested.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths

FAST = ["--samples", "16"]
URDF_BACKENDS = ["--against", "pinocchio-urdf"]


def ur5_text() -> str:
    return bundled_model_paths()["ur5"].read_text(encoding="utf-8")


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def d1_in_the_base(tmp_path: Path) -> Path:
    """UR5 with d1 10 mm long and its `base` frame lifted 10 mm: what `map` proposed."""
    text = ur5_text().replace("d = 0.089159", "d = 0.099159", 1)
    old = '[frames.base]\ndh = 0\nurdf = "base"\n'
    assert old in text
    text = text.replace(old, '[frames.base]\ndh = 0\nxyz = [0.0, 0.0, 0.01]\nurdf = "base"\n')
    return write(tmp_path, "ur5_d1", text)


def test_a_table_error_moved_into_a_frame_offset_is_never_table_verified(
    capsys, tmp_path, monkeypatch
):
    model = d1_in_the_base(tmp_path)
    out = {k: tmp_path / f"r.{k}" for k in ("json", "html", "junit")}
    summary = tmp_path / "summary.md"
    monkeypatch.setenv("GITHUB_ACTIONS", "true")
    code = main(["check", str(model), *FAST, *URDF_BACKENDS, "--json", str(out["json"]),
                 "--html", str(out["html"]), "--junit", str(out["junit"]),
                 "--summary", str(summary)])  # fmt: skip
    printed = capsys.readouterr().out
    assert code == 0  # the poses agree: nothing disagreed
    headline = (
        "pass — table verified except d1 not identifiable (the offset of [frames.base] "
        "could absorb it); no second implementation ran"
    )
    # terminal: the verdict line and the one numbers line
    assert f"verdict: {headline}" in " ".join(printed.split())
    assert "numbers (base → tool0): 30 in the table: 29 verified, 1 not identifiable" in printed
    # and a GitHub warning naming it
    assert "::warning file=" in printed
    assert "table partly verified" in printed
    # JSON
    doc = json.loads(out["json"].read_text(encoding="utf-8"))
    assert doc["headline"] == headline
    assert doc["evidence"]["table"]["status"] == "partly-verified"
    assert doc["numbers"]["counts"] == {"verified": 29, "not-identifiable": 1}
    d1 = next(n for n in doc["numbers"]["numbers"] if n["name"] == "d1")
    assert d1["status"] == "not-identifiable"
    assert d1["absorbed_by"] == "[frames.base]: translation along z of DH frame 0"
    # JUnit: the table-evidence case is skipped, with the numbers line
    root = ET.parse(out["junit"]).getroot()
    case = next(c for c in root.iter("testcase") if c.get("name", "").startswith("evidence: table"))
    skipped = case.find("skipped")
    assert skipped is not None
    assert "29 verified, 1 not identifiable" in (skipped.text or "")
    # Markdown and HTML
    assert "PASS (table partly verified)" in summary.read_text(encoding="utf-8")
    page = out["html"].read_text(encoding="utf-8")
    assert 'data-number="d1" data-status="not-identifiable"' in page
    assert 'data-number="a2" data-status="verified"' in page
    # --require table: every table number verified, so this is unverified (exit 1)
    assert main(["check", str(model), *FAST, *URDF_BACKENDS, "--require", "table"]) == 1
    assert "unverified" in capsys.readouterr().out


def test_the_same_pair_on_the_right_table_stays_table_verified(capsys):
    assert main(["check", "ur5", *FAST, *URDF_BACKENDS, "--require", "table"]) == 0
    assert "table verified independently" in capsys.readouterr().out


def test_urdf_links_placed_from_a_wrong_table_do_not_verify_it(capsys, tmp_path):
    text = ur5_text().replace("d = 0.089159", "d = 0.099159", 1)
    frames_start = text.index("# DH frame 0 is the controller's")
    model = write(tmp_path, "ur5_urdf_only", text[:frames_start])
    argv = ["check", str(model), *FAST, "--from", "urdf:base", "--to", "urdf:tool0"]
    assert main([*argv, "--json", str(tmp_path / "r.json")]) == 0
    doc = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert doc["evidence"]["table"]["status"] == "partly-verified"
    hidden = [n["name"] for n in doc["numbers"]["numbers"] if n["status"] == "not-identifiable"]
    assert "d1" in hidden
    capsys.readouterr()
    assert main([*argv, "--require", "table"]) == 1


@pytest.mark.parametrize(
    ("edit", "uncovered"),
    [
        (("[urdf]", "[base]\nrpy = [0, 0, 180]\n\n[urdf]"), "[base]"),  # [base] turned π
        (("[urdf]", "[tool]\nxyz = [0, 0, 0.1]\n\n[urdf]"), "[tool]"),  # [tool] 100 mm off
    ],
)
def test_base_and_tool_outside_the_pair_are_not_covered(capsys, tmp_path, edit, uncovered):
    model = write(tmp_path, "ur5_bt", ur5_text().replace(*edit, 1))
    assert (
        main(["check", str(model), *FAST, *URDF_BACKENDS, "--json", str(tmp_path / "r.json")]) == 0
    )
    doc = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert doc["evidence"]["table"]["status"] == "partly-verified"
    assert f"{uncovered} not covered (outside base → tool0)" in doc["headline"]


@pytest.mark.parametrize(
    "pair", [("tcp", "tcp"), ("world", "base"), ("tool0", "ee_link"), ("base", "base_link")]
)
def test_a_pair_spanning_no_joint_never_verifies_the_table(capsys, tmp_path, pair):
    argv = ["check", "ur5", *FAST, "--from", pair[0], "--to", pair[1]]
    main([*argv, "--json", str(tmp_path / "r.json")])
    doc = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert doc["evidence"]["table"]["status"] != "verified"
    assert doc["numbers"]["joints_spanned"] == []
    capsys.readouterr()
    # Asking it to verify the table is bad input, in one line.
    assert main([*argv, "--require", "table"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert f"the frame pair {pair[0]} → {pair[1]} spans no joint" in err[0]


def test_a_loose_tolerance_is_named_with_its_source_in_the_headline(capsys, tmp_path):
    """Each looser tolerance with its own source (the model's, a flag's)."""
    text = ur5_text().replace('to = "tool0"', 'to = "tool0"\ntol_rot_rad = 0.001', 1)
    model = write(tmp_path, "ur5_loose", text)
    main(["check", str(model), *FAST, *URDF_BACKENDS, "--tol-pos", "0.005",
          "--json", str(tmp_path / "m.json")])  # fmt: skip
    doc = json.loads((tmp_path / "m.json").read_text(encoding="utf-8"))
    assert doc["headline"].endswith(
        "[tolerance looser than the default: 0.005 m (default 1e-06 m) from --tol-pos and "
        f"0.001 rad (default 1e-06 rad) from the model's [check] of {model}]"
    )
    main(["check", "ur5", *FAST, *URDF_BACKENDS, "--tol-pos", "0.005",
          "--json", str(tmp_path / "r.json")])  # fmt: skip
    doc = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert doc["headline"].endswith(
        "[tolerance looser than the default: 0.005 m (default 1e-06 m) from --tol-pos]"
    )
