"""The Diagnosis section of a failed check's HTML report (``fkcheck diagnose`` run for the page)."""

from __future__ import annotations

import html as html_lib
import json
import math
import re
import tomllib
from dataclasses import replace

import numpy as np
import pytest

import fkcheck.diagnose.failures
from fkcheck import load_model
from fkcheck.cli.main import main
from fkcheck.core.tolerances import ROUNDED_URDF
from fkcheck.diagnose import Diagnosis, Explanation
from fkcheck.diagnose.failures import (
    BackendDiagnosis,
    diagnose_command,
    diagnose_failures,
    same_disagreement,
)
from fkcheck.diagnose.problem import Residual
from fkcheck.report.diagnosis import diagnosis_view
from fkcheck.report.html import render_report, write_html
from fkcheck.report.json_report import TIME_FIELDS
from fkcheck.report.page import build_report_page
from tests.cli.test_report_cli import first_screen, ur5_variant
from tests.diagnose.test_diagnose import with_joint, write_pendant_csv
from tests.report_cases import SPEC, backends, golden_check, golden_model, page_numbers

XSS = "<script>alert(1)</script>"


def diagnosis_section(page: str) -> str:
    """The Diagnosis section of a report page."""
    start = page.index('<section id="diagnosis">')
    return page[start : page.index("</section>", start)]


def text_of(fragment: str) -> str:
    """What a person reads: tags dropped, entities decoded."""
    return html_lib.unescape(re.sub(r"<[^>]+>", "", fragment))


def fix_toml(section: str) -> str:
    """The first fixing TOML snippet shown."""
    found = re.search(r'<pre class="fix-toml">(.*?)</pre>', section, re.DOTALL)
    assert found is not None, "no fixing TOML on the page"
    return html_lib.unescape(found.group(1))


def data_values(fragment: str) -> list[float]:
    """The exact numbers behind the shown measures, in page order."""
    return [float(v) for v in re.findall(r'data-value="([^"]+)"', fragment)]


# --------------------------------------------------------------------------- real UR5


@pytest.fixture(scope="module")
def d1_pages(tmp_path_factory):
    """UR5 with the older d1 = 0.08946 against two URDF backends: report + JSON, with and
    without --no-diagnose."""
    tmp = tmp_path_factory.mktemp("d1")
    model = ur5_variant(tmp, "d = 0.089159", "d = 0.08946", name="ur5-d1")
    out = {}
    for label, extra in (("with", []), ("without", ["--no-diagnose"])):
        page, doc = tmp / f"{label}.html", tmp / f"{label}.json"
        argv = ["check", str(model), "--samples", "32", "--against",
                "rtb-dh,pinocchio-urdf,yourdfpy-urdf", "--html", str(page), "--json", str(doc),
                *extra]  # fmt: skip
        assert main(argv) == 1
        out[label] = (page.read_text(encoding="utf-8"), json.loads(doc.read_text("utf-8")))
    return model, out


def test_d1_diagnosis_names_d1_and_its_0_301_mm(d1_pages):
    model, out = d1_pages
    page, _ = out["with"]
    # First screen: the diagnosis in a line, for the backend diagnosed and the one it stands for.
    head = text_of(first_screen(page))
    assert "Diagnosis against pinocchio-urdf (and yourdfpy-urdf): " in head
    assert "d1 (shoulder_pan) = 0.08946 here, 0.089159 would match, Δ = -0.301 mm" in head
    # The section sits right after the backend table.
    assert page.index('id="backends"') < page.index('id="diagnosis"') < page.index('id="pictures"')
    section = diagnosis_section(page)
    assert section.count('class="card diagnosis"') == 1  # both URDF backends: one diagnosis
    assert 'data-backend="pinocchio-urdf"' in section
    text = text_of(section)
    assert "Also for yourdfpy-urdf: the same errors at every configuration" in text
    assert "Disagreement as given, on 205 configurations: position 0.301 mm (3.01e-04 m)" in text
    # Most likely first: the one number, then the equally good base shift (the honest ambiguity).
    kinds = re.findall(r'<li data-kind="([a-z-]+)" data-explains="(yes|no)"', section)
    assert kinds[:2] == [("parameter", "yes"), ("offset", "yes")]
    first = section[section.index('data-kind="parameter"') : section.index('data-kind="offset"')]
    before_pos, after_pos, before_rot, after_rot = data_values(first)
    assert before_pos == pytest.approx(0.08946 - 0.089159, abs=1e-9)
    assert after_pos < ROUNDED_URDF
    assert before_rot < ROUNDED_URDF
    assert after_rot < ROUNDED_URDF
    assert "explains it: position 0.301 mm (3.01e-04 m) → " in text_of(first)
    offset = section[section.index('data-kind="offset"') :]
    fix = tomllib.loads(fix_toml(offset))["frames"]["base"]
    # (UR's ROS 2 YAML writes π/2 as 1.570796327: the fitted shift is 0.301 mm to ~1e-10 m)
    assert fix.pop("xyz") == pytest.approx([0.0, 0.0, 0.000301], abs=1e-10)
    assert fix == {"dh": 0, "urdf": "base"}
    assert "exactly what d1" in text_of(offset)
    # Joint axes: joint 2's is the first that differs, by Δd1, turned by nothing.
    axes = section[section.index('class="diagnosis-axes"') :]
    rows = re.findall(r"<tr class=\"([^\"]*)\"><td>([^<]*)</td>(.*?)</tr>", axes)
    assert [label for _, label, _ in rows] == [
        "1 · shoulder_pan", "2 · shoulder_lift", "3 · elbow", "4 · wrist_1", "5 · wrist_2",
        "6 · wrist_3",
    ]  # fmt: skip
    status = [text_of(cells.rsplit("<td>", 1)[1]) for _, _, cells in rows]
    assert status == ["agrees", "differs (first)", "differs", "differs", "differs", "differs"]
    assert [css for css, _, _ in rows] == ["", "row-differs row-first", *["row-differs"] * 4]
    angle, distance = data_values(rows[1][2])
    assert distance == pytest.approx(0.08946 - 0.089159, abs=1e-9)
    assert angle <= ROUNDED_URDF
    assert re.search(
        r'<p class="axes-note">First axis that differs: joint 2 \(shoulder_lift\); in standard '
        r"DH it is z1, .*: look at row 1\.</p>",
        section,
    )
    assert "Hypotheses tried" in text
    assert "a published table" in text
    assert "two URDF joints swapped in [urdf].joints" in text
    assert (
        f"Reproduce: fkcheck diagnose {model} --against pinocchio-urdf --from base --to tool0"
        in text
    )


def test_no_diagnose_leaves_the_section_out_and_the_json_is_the_same(d1_pages):
    _, out = d1_pages
    page_without, doc_without = out["without"]
    page_with, doc_with = out["with"]
    assert 'id="diagnosis"' not in page_without
    assert "Diagnosis against" not in page_without
    assert 'href="#diagnosis"' not in page_without
    # The JSON is a contract: the diagnosis adds nothing to it. Only the command line
    # (which names the other files and the flag) and the times differ.
    for doc in (doc_with, doc_without):
        for key in (*TIME_FIELDS, "command"):
            doc.pop(key)
        for b in doc["backends"]:
            b.pop("duration_s")
    assert doc_with == doc_without
    assert set(doc_with) == {
        "model", "samples", "seed", "sampler", "timeout_s", "configurations", "from", "to",
        "tolerance", "reference", "backends", "verdict", "headline", "evidence", "numbers",
        "cross_checked", "fkcheck_version", "config", "calibration", "derived", "lint",
    }  # fmt: skip
    assert page_numbers(page_with).verdict == page_numbers(page_without).verdict == "fail"


def test_base_link_without_its_rz_pi_says_base_link_vs_base_and_the_fix_passes(tmp_path):
    broken = ur5_variant(tmp_path, 'rpy = [0, 0, 180]\nurdf = "base_link"', 'urdf = "base_link"',
                         name="ur5-base-link")  # fmt: skip
    page_path = tmp_path / "base_link.html"
    argv = ["check", str(broken), "--samples", "16", "--against", "pinocchio-urdf",
            "--from", "base_link", "--to", "tool0", "--html", str(page_path)]  # fmt: skip
    assert main(argv) == 1
    page = page_path.read_text(encoding="utf-8")
    assert "base_link vs base" in text_of(first_screen(page))
    section = diagnosis_section(page)
    best = section[section.index("<li data-kind=") :]
    assert best.startswith('<li data-kind="frames" data-explains="yes">')
    assert "the reference&#39;s base_link is the table&#39;s turned Rz(π): base_link vs base" in (
        best
    )
    snippet = fix_toml(best)
    fix = tomllib.loads(snippet)
    assert fix["frames"]["base_link"].pop("source").startswith("Universal_Robots_ROS2")  # kept
    assert fix == {
        "frames": {"base_link": {"dh": 0, "rpy": [0.0, 0.0, 180.0], "urdf": "base_link"}}
    }
    # Paste the printed fix over the broken table: the check passes, and a passing
    # report has no Diagnosis section.
    text = broken.read_text(encoding="utf-8")
    assert '[frames.base_link]\ndh = 0\nurdf = "base_link"\nsource = ' in text
    start = text.index("[frames.base_link]")
    block = text[start : text.index("\n\n", start) + 1]  # with its source line
    fixed = tmp_path / "fixed.toml"
    fixed.write_text(text.replace(block, snippet), encoding="utf-8")
    fixed_page = tmp_path / "fixed.html"
    argv[1], argv[-1] = str(fixed), str(fixed_page)
    assert main(argv) == 0
    page = fixed_page.read_text(encoding="utf-8")
    assert page_numbers(page).verdict == "pass"
    assert 'id="diagnosis"' not in page


def test_measured_poses_are_diagnosed_at_their_own_configurations(tmp_path, rng):
    robot = with_joint(load_model("ur5"), 0, d=0.089459)  # the "real" robot differs in d1
    csv = tmp_path / "pendant.csv"
    write_pendant_csv(csv, robot, np.round(rng.uniform(-170, 170, size=(24, 6)), 2))
    page_path = tmp_path / "pendant.html"
    argv = ["check", "ur5", "--against", f"poses:{csv}", "--html", str(page_path)]
    assert main(argv) == 1
    text = text_of(diagnosis_section(page_path.read_text(encoding="utf-8")))
    assert "Disagreement as given, on 24 configurations" in text
    assert "d1 (shoulder_pan) = 0.089159 here, 0.089459 would match, Δ = +0.300 mm" in text


# --------------------------------------------------------------------------- no libraries


def test_passing_check_is_not_diagnosed(tmp_path, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("a passing check must not be diagnosed")

    monkeypatch.setattr(fkcheck.diagnose, "diagnose", never)
    page_path = tmp_path / "pass.html"
    argv = ["check", "ur5", "--samples", "8", "--against", "rtb-dh", "--html", str(page_path)]
    assert main(argv) == 0
    page = page_path.read_text(encoding="utf-8")
    assert page_numbers(page).verdict == "pass"
    assert 'id="diagnosis"' not in page
    assert "Diagnosis against" not in page


def test_without_diagnoses_the_page_has_no_diagnosis_and_runs_none(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(fkcheck.diagnose.failures, "diagnose", lambda *a, **k: calls.append(a))
    page = tmp_path / "r.html"
    write_html(golden_check(), page, plots=False)
    assert calls == []
    assert 'id="diagnosis"' not in page.read_text(encoding="utf-8")


def test_a_diagnosis_that_raises_is_shown_and_the_report_is_written(tmp_path, monkeypatch):
    message = "the URDF vanished\nsecond line <b>kept</b>"

    def broken(*args, **kwargs):
        raise RuntimeError(message)

    monkeypatch.setattr(fkcheck.diagnose.failures, "diagnose", broken)
    check = golden_check()
    diagnoses = diagnose_failures(check, backends())
    path = write_html(check, tmp_path / "r.html", diagnoses=diagnoses, plots=False)
    page = path.read_text(encoding="utf-8")
    assert page.rstrip().endswith("</html>")
    section = diagnosis_section(page)
    assert section.count('class="card diagnosis"') == 2  # shifted and twisted-dh differ
    for backend in ("shifted", "twisted-dh"):
        card = section[section.index(f'data-backend="{backend}"') :]
        assert f"The diagnosis against {backend} could not run." in card
        errors = re.findall(r'<pre class="diagnosis-error">(.*?)</pre>', card, re.DOTALL)
        assert html_lib.unescape(errors[0]) == f"RuntimeError: {message}"  # in full
    assert "<b>kept</b>" not in page
    # The two could-not-run bullets say the same: one bullet names both.
    head = text_of(first_screen(page))
    assert (
        "Diagnosis against shifted (and twisted-dh): could not run: RuntimeError: the URDF vanished"
    ) in head
    assert head.count("could not run: RuntimeError") == 1


def test_model_text_in_a_failing_report_stays_text(tmp_path):
    joints = [dict(j) for j in SPEC["joint"]]
    joints[1]["name"] = '<img src=x onerror="alert(2)">'
    check = golden_check(golden_model(name=XSS, joint=joints))
    diagnoses = diagnose_failures(check, backends())
    path = write_html(check, tmp_path / "xss.html", diagnoses=diagnoses, plots=False)
    page = path.read_text(encoding="utf-8")
    section = diagnosis_section(page)
    tags = page_numbers(page).tags
    assert not [t for t, _ in tags if t == "script"], "a <script> element reached the page"
    assert not [(t, a) for t, a in tags if any(k.startswith("on") for k, _ in a)]
    assert "<img src=x" not in page
    assert XSS not in page
    # The real diagnosis names the joint and the model: escaped, and reads as typed.
    assert "one number differs: α2 (&lt;img src=x onerror=&#34;alert(2)&#34;&gt;)" in section
    text = text_of(section)
    assert f"Reproduce: fkcheck diagnose '{XSS}' --against shifted" in text
    assert 'one number differs: α2 (<img src=x onerror="alert(2)">)' in text


def test_each_distinct_disagreement_is_diagnosed_once():
    check = golden_check()
    _, shifted, twisted, _, _ = check.backends
    assert same_disagreement(check, shifted, shifted)
    assert not same_disagreement(check, shifted, twisted)
    assert not same_disagreement(check, shifted, check.backends[3])  # errored: no errors to compare
    outcomes = diagnose_failures(check, backends())
    assert [(o.backend, o.also, o.error) for o in outcomes] == [
        ("shifted", (), ""),
        ("twisted-dh", (), ""),
    ]
    twisted_diagnosis = outcomes[1].diagnosis
    assert twisted_diagnosis is not None
    assert twisted_diagnosis.best is not None
    assert [c.field for c in twisted_diagnosis.best.changes] == ["joint[1].alpha"]
    assert twisted_diagnosis.best.changes[0].new == pytest.approx(math.pi, abs=1e-9)
    assert outcomes[1].command == (
        "fkcheck diagnose golden-3r --against twisted-dh --from base --to tool --seed 7"
    )
    with pytest.raises(ValueError, match=r"2 backend objects for 5 results"):
        diagnose_failures(check, backends()[:2])


def test_diagnose_command_names_only_what_differs_from_the_model_file():
    check = golden_check()  # seed 7, the model file's tolerances (1e-6 m, 1e-6 rad)
    assert diagnose_command(check, "x y") == (
        "fkcheck diagnose golden-3r --against 'x y' --from base --to tool --seed 7"
    )
    looser = replace(
        check, options=replace(check.options, seed=0), tol_pos_m=2.5e-5, tol_rot_rad=1e-4
    )
    assert diagnose_command(looser, "rtb-urdf") == (
        "fkcheck diagnose golden-3r --against rtb-urdf --from base --to tool "
        "--tol-pos 2.5e-05 --tol-rot 0.0001"
    )
    # A --timeout other than the default: a recording's read is within it.
    slower = replace(check, options=replace(check.options, timeout_s=600.0))
    assert diagnose_command(slower, "poses:rec.csv") == (
        "fkcheck diagnose golden-3r --against poses:rec.csv --from base --to tool --seed 7 "
        "--timeout 600.0"
    )


def test_a_checks_diagnosis_reads_a_recording_within_the_checks_timeout(monkeypatch):
    asked = []

    def diagnose(model, backend, **kwargs):
        asked.append(kwargs)
        raise RuntimeError("not run here")

    monkeypatch.setattr(fkcheck.diagnose.failures, "diagnose", diagnose)
    check = golden_check()
    slower = replace(check, options=replace(check.options, timeout_s=600.0))
    result, text = fkcheck.diagnose.failures._run_one(slower, backends()[0])
    assert (result, text) == (None, "RuntimeError: not run here")
    assert [a["timeout_s"] for a in asked] == [600.0]


SHIFTED_BEFORE = Residual(3e-4, 0.0)


def _hand_built(explanations, before=SHIFTED_BEFORE):
    check = golden_check()
    return Diagnosis(check.model, "shifted", "base", "tool", 10, before, 1e-6, 1e-6, explanations)


def test_verdicts_for_partial_and_no_disagreement():
    partial = Explanation("offset", "half of it", Residual(1e-4, 0.0), explains=False)
    outcome = BackendDiagnosis("shifted", _hand_built((partial,)))
    view = diagnosis_view(outcome)
    assert not view.explained
    assert view.verdict.startswith("Not explained: no single change makes the disagreement")
    assert view.explanations[0].verdict == "explains part of it"
    assert view.explanations[0].position_after.primary == "0.100 mm"
    agrees = diagnosis_view(BackendDiagnosis("shifted", _hand_built((), Residual(0.0, 0.0))))
    assert "finds the table within tolerance of shifted" in agrees.verdict
    assert agrees.short == "no disagreement on the diagnosis's own configurations"
    page = render_report(build_report_page(golden_check(), plots=False, diagnoses=[outcome]))
    assert 'data-explained="no"' in diagnosis_section(page)
