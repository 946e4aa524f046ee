"""Known differences in the verdict: expected failure, stale record, beyond the bounds.

The UR5 with the older d1 (0.08946 instead of 0.089159) disagrees with its URDF
by 0.3 mm (tests/engine/test_check_done_when.py); recording that as a known
difference (``reads = "urdf"``) turns every URDF backend into an expected failure.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths
from tests.backend_cases import URDF_BACKENDS as URDF

HEAD = (
    '\n[[known_difference]]\nreads = "urdf"\nfinding = "d1 +0.3 mm: the table has the older d1"\n'
)
RECORD = HEAD + "max_position_m = 1e-3\nmax_angle_rad = 1e-3\n"  # the error is 0.3 mm


def ur5(tmp_path: Path, *, older_d1: bool, record: str) -> Path:
    text = bundled_model_paths()["ur5"].read_text()
    if older_d1:
        text = text.replace("d = 0.089159", "d = 0.08946", 1)
    path = tmp_path / "ur5_known.toml"
    path.write_text(text + record)
    return path


def run(capsys, tmp_path, model):
    out = {k: tmp_path / f"r.{k}" for k in ("json", "junit", "summary")}
    code = main(["check", str(model), "--samples", "64", "--json", str(out["json"]),
                 "--junit", str(out["junit"]), "--summary", str(out["summary"])])  # fmt: skip
    text = "".join(capsys.readouterr())
    doc = json.loads(out["json"].read_text())
    return code, doc, text, out


def test_recorded_difference_is_an_expected_failure_never_table_verified(capsys, tmp_path):
    code, doc, text, out = run(capsys, tmp_path, ur5(tmp_path, older_d1=True, record=RECORD))
    assert code == 0, text
    assert doc["verdict"] == "pass"
    status = {b["name"]: b["status"] for b in doc["backends"]}
    assert [status[n] for n in URDF] == ["xfail"] * len(URDF)
    assert status["rtb-dh"] == status["pinocchio-dh"] == "pass"
    table = doc["evidence"]["table"]
    assert table["status"] == "expected-failure"
    assert "d1 +0.3 mm" in next(b for b in doc["backends"] if b["name"] == "rtb-urdf")["message"]
    assert "table NOT VERIFIED, expected failure" in text
    assert "table verified" not in text
    suite = ET.parse(out["junit"]).getroot().find("testsuite")
    assert suite is not None
    assert suite.get("failures") == "0"
    skipped = [c for c in suite if c.find("skipped") is not None]
    messages = [c.find("skipped").get("message", "") for c in skipped]  # type: ignore[union-attr]
    assert sum("known difference: d1 +0.3 mm" in m for m in messages) == len(URDF)
    summary = out["summary"].read_text()
    assert "PASS (expected failure: known difference)" in summary
    assert summary.count("xfail") >= len(URDF)


def test_required_table_is_unmet_by_an_expected_failure(capsys, tmp_path):
    model = ur5(tmp_path, older_d1=True, record=RECORD)
    code = main(["check", str(model), "--samples", "32", "--require", "table"])
    assert code == 1
    assert "unverified" in "".join(capsys.readouterr())


def test_known_difference_no_longer_seen_fails_the_check(capsys, tmp_path):
    code, doc, text, out = run(capsys, tmp_path, ur5(tmp_path, older_d1=False, record=RECORD))
    assert code == 1
    assert doc["verdict"] == "fail"
    assert {b["name"]: b["status"] for b in doc["backends"] if b["name"] in URDF} == dict.fromkeys(
        URDF, "xpass"
    )
    assert doc["evidence"]["table"]["status"] == "failed"
    assert "known difference no longer seen" in text
    suite = ET.parse(out["junit"]).getroot().find("testsuite")
    assert suite is not None
    assert int(suite.get("failures", "0")) >= 3


def test_an_error_beyond_the_recorded_bound_fails(capsys, tmp_path):
    bounded = HEAD + "max_position_m = 1e-4\nmax_angle_rad = 1e-3\n"  # the error is 0.3 mm
    code, doc, _text, _ = run(capsys, tmp_path, ur5(tmp_path, older_d1=True, record=bounded))
    assert code == 1
    rows = {b["name"]: b for b in doc["backends"]}
    for name in URDF:
        assert rows[name]["status"] == "fail"
        assert rows[name]["message"].startswith("beyond the recorded known difference (position")
    assert doc["evidence"]["table"]["status"] == "failed"


def test_within_the_recorded_bounds_is_still_expected(capsys, tmp_path):
    bounded = HEAD + "max_position_m = 4e-4\nmax_angle_rad = 1e-9\n"  # 0.3 mm, no rotation
    code, doc, _, _ = run(capsys, tmp_path, ur5(tmp_path, older_d1=True, record=bounded))
    assert code == 0
    assert {b["status"] for b in doc["backends"] if b["name"] in URDF} == {"xfail"}


def test_another_frame_pair_is_not_touched_by_the_record(capsys, tmp_path):
    model = ur5(tmp_path, older_d1=False, record=RECORD)
    code = main(["check", str(model), "--samples", "32", "--from", "base_link", "--to", "tool0"])
    assert code == 0, "".join(capsys.readouterr())


def test_a_record_naming_one_backend_leaves_the_other_urdf_readers_failing(capsys, tmp_path):
    named = RECORD.replace('reads = "urdf"', 'backends = ["pinocchio-urdf"]')
    code, doc, _, _ = run(capsys, tmp_path, ur5(tmp_path, older_d1=True, record=named))
    assert code == 1
    status = {b["name"]: b["status"] for b in doc["backends"]}
    assert status["pinocchio-urdf"] == "xfail"
    assert {status[n] for n in URDF if n != "pinocchio-urdf"} == {"fail"}


OLD_READERS = ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf")  # the URDF readers of its day


def test_a_record_naming_the_readers_of_its_day_covers_the_ones_that_joined(capsys, tmp_path):
    """Issue 30, item 8: a known difference of the description, recorded reader by reader."""
    assert set(OLD_READERS) < set(URDF)  # readers joined since
    listed = ", ".join(f'"{n}"' for n in OLD_READERS)
    record = (
        "\n[[known_difference]]\nbackends = ["
        + listed
        + ']\nfinding = "d1 +0.3 mm: the table has the older d1"\n'
        "max_position_m = 1e-3\nmax_angle_rad = 1e-3\n"
    )
    code, doc, text, _ = run(capsys, tmp_path, ur5(tmp_path, older_d1=True, record=record))
    assert code == 0, text
    status = {b["name"]: b["status"] for b in doc["backends"]}
    assert [status[n] for n in URDF] == ["xfail"] * len(URDF)
    assert doc["evidence"]["table"]["status"] == "expected-failure"
    # beyond its bound, a reader that joined still fails
    tight = record.replace("max_position_m = 1e-3", "max_position_m = 1e-4")
    code, doc, text, _ = run(capsys, tmp_path, ur5(tmp_path, older_d1=True, record=tight))
    assert code == 1
    assert {b["name"]: b["status"] for b in doc["backends"]}["mujoco-urdf"] == "fail"


def test_lint_suggests_reads_urdf_for_a_record_naming_the_readers(capsys, tmp_path):
    listed = ", ".join(f'"{n}"' for n in OLD_READERS)
    record = RECORD.replace('reads = "urdf"', f"backends = [{listed}]")
    model = ur5(tmp_path, older_d1=False, record=record)
    assert main(["lint", str(model), "--json"]) == 1
    (finding,) = json.loads(capsys.readouterr().out)["findings"]
    assert (finding["rule"], finding["field"]) == (
        "known-difference",
        "known_difference[0].backends",
    )
    assert 'write reads = "urdf" instead' in finding["message"]
    assert main(["lint", str(model), "--ignore", "known-difference"]) == 0
    capsys.readouterr()
    # the current form, and one reader named alone (a parser's own difference), are clean
    for clean in (RECORD, RECORD.replace('reads = "urdf"', 'backends = ["pinocchio-urdf"]')):
        assert main(["lint", str(ur5(tmp_path, older_d1=False, record=clean))]) == 0
