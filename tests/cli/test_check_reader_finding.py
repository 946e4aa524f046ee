"""``fkcheck check``: one MJCF reader agrees with the table, the other not: a reader finding.

Menagerie's UR5e with a table of Menagerie's own rounded numbers: MuJoCo reads it
exactly; Pinocchio 4.1.0 drops the jointless root body's π turn (pinocchio#2782).
Whether the installed Pinocchio still does is measured first, so each test asserts
what that Pinocchio must produce.
"""

from __future__ import annotations

import json
import re
from importlib import metadata

import numpy as np
import pytest

from fkcheck.cli.main import main
from fkcheck.mjcf import mujoco_poses, pinocchio_poses, read_mjcf
from fkcheck.model.read import bundled_model_paths

PIN = metadata.version("pin")
MUJOCO = metadata.version("mujoco-core")
ROUNDED = {  # Menagerie's numbers (tests/mjcf/test_twins.py names each)
    "d = 0.1625\n": "d = 0.163\n",
    "a = -0.3922\n": "a = -0.392\n",
    "d = 0.1333\n": "d = 0.134\n",
    "d = 0.0997\n": "d = 0.100\n",
    "d = 0.0996\n": "d = 0.100\n",
}
FINDING = (
    f"pinocchio-mjcf (pinocchio {PIN}) disagrees with mujoco-mjcf (mujoco {MUJOCO}), which "
    "agrees with the table: a finding about the reader, not the table"
)
ARGV = ["--samples", "30", "--against", "mujoco-mjcf,pinocchio-mjcf,rtb-dh"]


def pinocchio_drops_the_turn() -> bool:
    """Whether the installed Pinocchio still reads Menagerie's UR5e π turned (pinocchio#2782)."""
    path = bundled_model_paths()["ur5e"].parent / "mujoco_menagerie/universal_robots_ur5e/ur5e.xml"
    desc = read_mjcf(path)
    q = np.zeros((1, 6))
    return not np.allclose(
        pinocchio_poses(desc, ["attachment_site"], q), mujoco_poses(desc, ["attachment_site"], q)
    )


def rounded_ur5e(tmp_path, record: str = ""):
    """The bundled UR5e twin, its table rounded as Menagerie's, its records now ``record``."""
    text = bundled_model_paths()["ur5e_menagerie"].read_text(encoding="utf-8")
    text = text.split("# Menagerie's numbers are not UR's")[0]
    for old, new in ROUNDED.items():
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "ur5e_rounded.toml"
    path.write_text(text + record, encoding="utf-8")
    return path


def record(versions: str) -> str:
    return (
        '\n[[known_difference]]\nbackends = ["pinocchio-mjcf"]\n'
        f'versions = "{versions}"\nfinding = "pinocchio#2782: the root body\'s turn dropped"\n'
        "max_position_m = 1.95\nmax_angle_rad = 3.141592653589793\n"
    )


def run(tmp_path, model, capsys, *extra: str):
    out = tmp_path / "check.json"
    code = main(["check", str(model), *ARGV, "--json", str(out), *extra])
    text = capsys.readouterr()
    assert "Traceback" not in text.err + text.out
    rows = {b["name"]: b for b in json.loads(out.read_text(encoding="utf-8"))["backends"]}
    return code, text.out, rows


def test_the_disagreeing_reader_is_named_with_its_version_and_the_table_is_not_blamed(
    tmp_path, capsys
):
    code, out, rows = run(tmp_path, rounded_ur5e(tmp_path), capsys)
    assert rows["mujoco-mjcf"]["status"] == "pass"
    if not pinocchio_drops_the_turn():  # a fixed Pinocchio: both readers agree
        assert (code, rows["pinocchio-mjcf"]["status"]) == (0, "pass")
        return
    assert code == 1  # the reader still disagrees: not a silent pass
    assert rows["pinocchio-mjcf"]["status"] == "fail"
    assert rows["pinocchio-mjcf"]["reader_finding"] == FINDING
    assert rows["mujoco-mjcf"]["reader_finding"] is None
    assert f"pinocchio-mjcf: {FINDING} — " in out
    rows_shown = {cells[0]: cells for line in out.splitlines() if line.startswith("│ ")
                  for cells in [[c.strip() for c in line.strip("│").split("│")]]}  # fmt: skip
    assert "fail (reader)" in rows_shown["pinocchio-mjcf"]  # the row's status says it
    assert "pass" in rows_shown["mujoco-mjcf"]
    assert out.count("fail (reader)") == 1
    assert "table PARTLY verified: mujoco-mjcf agrees (evidence independent of the table)" in out
    assert "table FAILED" not in out
    assert "table disagrees" not in out
    assert "verdict: fail — a reader disagrees where another reader of the same description" in out
    assert "diagnosis (pinocchio-mjcf)" not in out  # no table number is blamed
    assert "fkcheck diagnose" not in out
    # The hint names the installed version of the reader's library, not a placeholder ...
    hint = (
        "hint: a reader's finding, not the table's: record it for the reader's version with "
        f'[[known_difference]] backends = ["pinocchio-mjcf"], versions = "<={PIN}" '
        "(docs/reference/model-file.md)"
    )
    assert hint in out.splitlines()
    # ... and the versions it prints, recorded as it says, make the finding expected.
    (versions,) = re.findall(r'versions = "([^"]*)"', hint)
    code, _, rows = run(tmp_path, rounded_ur5e(tmp_path, record(versions)), capsys)
    assert (code, rows["pinocchio-mjcf"]["status"]) == (0, "xfail")


def test_the_hint_says_version_when_the_readers_library_is_not_known(tmp_path, capsys, monkeypatch):
    # A reader whose distribution names no installed version (a plugin's, say): the hint
    # asks for the version rather than inventing one. The finding itself is unchanged.
    from fkcheck.engine import expected

    monkeypatch.setattr(expected, "library_of", lambda backend: None)
    code, out, rows = run(tmp_path, rounded_ur5e(tmp_path), capsys)
    if not pinocchio_drops_the_turn():
        assert code == 0
        return
    assert rows["pinocchio-mjcf"]["reader_finding"] == FINDING
    assert 'backends = ["pinocchio-mjcf"], versions = "<=VERSION" (docs/' in out


def test_a_known_difference_for_the_installed_version_records_it(tmp_path, capsys):
    code, _, rows = run(tmp_path, rounded_ur5e(tmp_path, record(f"<={PIN}")), capsys)
    if not pinocchio_drops_the_turn():  # the record is stale on a fixed Pinocchio
        assert (code, rows["pinocchio-mjcf"]["status"]) == (1, "xpass")
        return
    assert code == 0
    assert rows["pinocchio-mjcf"]["status"] == "xfail"
    assert rows["pinocchio-mjcf"]["message"].startswith(
        f"expected failure, known difference (pinocchio {PIN}, recorded for versions <={PIN}): "
        "pinocchio#2782: the root body's turn dropped — "
    )


def test_a_known_difference_for_other_versions_does_not_apply_and_says_so(tmp_path, capsys):
    code, _, rows = run(tmp_path, rounded_ur5e(tmp_path, record(f"<{PIN}")), capsys)
    said = (
        f"(the model's known difference for pinocchio-mjcf is recorded for versions <{PIN} only "
        f"and does not apply to pinocchio {PIN})"
    )
    assert said in rows["pinocchio-mjcf"]["message"]
    if pinocchio_drops_the_turn():
        assert (code, rows["pinocchio-mjcf"]["status"]) == (1, "fail")
        assert rows["pinocchio-mjcf"]["reader_finding"] == FINDING
    else:
        assert (code, rows["pinocchio-mjcf"]["status"]) == (0, "pass")


#: How each report's backends table shows the reader's row: the status, ``fail (reader)``.
SHOWN = {
    "html": '<span class="status fail" data-status="fail">fail (reader)</span>',
    "junit": "fail (reader): pinocchio-mjcf disagrees with another reader of the same "
    "description, which agrees with the table (base -&gt; tool0)",
    "summary": "| pinocchio-mjcf | ❌ fail (reader) | ",
}


@pytest.mark.parametrize("fmt", ["html", "junit", "summary"])
def test_every_report_says_the_finding(tmp_path, capsys, fmt):
    out = tmp_path / f"r.{fmt}"
    code = main(["check", str(rounded_ur5e(tmp_path)), *ARGV, f"--{fmt}", str(out)])
    capsys.readouterr()
    if not pinocchio_drops_the_turn():
        assert code == 0
        return
    assert code == 1
    text = out.read_text(encoding="utf-8")
    assert SHOWN[fmt] in text
    assert text.count("fail (reader)") == 1  # mujoco-mjcf's row is not
    assert FINDING in text.replace("&#39;", "'").replace("&quot;", '"').replace("\\_", "_")


def test_diagnose_against_the_disagreeing_reader_says_the_table_is_not_blamed(tmp_path, capsys):
    model = rounded_ur5e(tmp_path)
    main(["diagnose", str(model), "--against", "pinocchio-mjcf"])
    out = capsys.readouterr().out
    note = (
        f"note: {FINDING}; the explanations above fit the table to pinocchio-mjcf's reading, "
        "they do not say the table is wrong"
    )
    assert (note in out) is pinocchio_drops_the_turn()
    assert main(["diagnose", str(model), "--against", "mujoco-mjcf"]) == 0
    out = capsys.readouterr().out
    assert "the table agrees with the reference" in out
    assert "note:" not in out


def test_the_annotation_and_the_index_say_it_is_the_readers(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("GITHUB_ACTIONS", "true")
    model = rounded_ur5e(tmp_path)
    code = main(["check", str(model), *ARGV])
    out = capsys.readouterr().out
    if not pinocchio_drops_the_turn():
        assert code == 0
        return
    assert code == 1
    errors = [line for line in out.splitlines() if line.startswith("::error")]
    assert len(errors) == 1
    assert (  # a property's ':' and ',' escaped, as GitHub reads them
        "title=fkcheck ur5e_menagerie%3A fail (reader)%3A pinocchio-mjcf disagrees with another "
        "reader of the same description%2C which agrees with the table::"
    ) in errors[0]
    assert "in-house core" not in errors[0]
    reports = tmp_path / "reports"
    assert main(["check", str(model), "ur3", *ARGV, "--out-dir", str(reports)]) == 1
    capsys.readouterr()
    index = (reports / "index.html").read_text(encoding="utf-8")
    assert index.count('<span class="status fail" data-status="fail">fail (reader)</span>') == 1
