"""One record per backend: every format shows the record's text, and the CLI writes as the API.

The record (:mod:`fkcheck.report.record`) is built once from the check and its
diagnoses; these tests pin that the terminal, JSON, JUnit, Markdown, HTML, the
GitHub annotations and :func:`fkcheck.testing.check_message` each show the
record's values (not a sentence of their own), and that ``fkcheck check`` and
:func:`fkcheck.write_report` write the same files.
"""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from dataclasses import replace
from html import escape
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from fkcheck.api import Outcome
from fkcheck.engine.jacobian import JacobianSpec
from fkcheck.engine.results import BackendResult, CheckResult, JacobianResult
from fkcheck.io.text import terminal_text
from fkcheck.report.annotations import github_annotations
from fkcheck.report.html import render_report
from fkcheck.report.json_report import result_to_dict
from fkcheck.report.junit import junit_xml
from fkcheck.report.markdown import escape_markdown, markdown_summary
from fkcheck.report.page import build_report_page
from fkcheck.report.record import CheckRecord, check_record
from fkcheck.testing import check_message
from tests.report_cases import Q, golden_check, golden_diagnoses, scrub

N = Q.shape[0]


def _jacobian(status: str, linear: float, angular: float, message: str = "") -> JacobianResult:
    """A Jacobian comparison on the 3R model: the first joint's column carries the error."""
    column_linear = np.array([linear, 0.0, 0.0])
    column_angular = np.array([angular, 0.0, 0.0])
    return JacobianResult(
        status,  # type: ignore[arg-type]
        message,
        "rtb jacob0",
        "world-aligned",
        1e-6,
        np.full(N, linear),
        np.full(N, angular),
        column_linear,
        column_angular,
        2,
        diagnosis="the columns are in the local frame" if status == "fail" else "",
    )


def checked() -> tuple[CheckResult, list[Any]]:
    """The golden check, with Jacobians: one agreeing, one disagreeing."""
    check = golden_check()
    backends = list(check.backends)
    backends[0] = replace(backends[0], jacobian=_jacobian("pass", 1e-12, 2e-12))
    backends[2] = replace(
        backends[2], jacobian=_jacobian("fail", 0.25, 0.5, "1 of 3 columns differ")
    )
    check = replace(check, backends=tuple(backends), jacobian=JacobianSpec("world-aligned", 1e-6))
    return check, golden_diagnoses(check)


@pytest.fixture(scope="module")
def case() -> tuple[CheckResult, list[Any], CheckRecord]:
    check, diagnoses = checked()
    return check, diagnoses, check_record(check, diagnoses)


def test_the_record_holds_the_numbers_and_the_sentences(case):
    _, _, record = case
    shifted, twisted = record.backend("shifted"), record.backend("twisted-dh")
    assert shifted.max_position_m == pytest.approx(3e-4)
    assert shifted.beyond == N == shifted.configurations
    assert twisted.beyond == 5  # the first configuration agrees
    assert twisted.worst_q_text == "[-160.00°, 100.00°, 75.00°]"
    assert twisted.worst_origin == "random"
    assert twisted.summary == (
        "max position error 500 mm (5.00e-01 m), max rotation error 172° (3.00e+00 rad); "
        "5 of 6 configurations beyond tolerance (1e-06 m, 1e-06 rad)"
    )
    assert twisted.diagnosis == "one number differs: α2 (shoulder)"
    assert twisted.diagnosis_field == "joint[1].alpha"
    assert twisted.diagnosed_with == ("twisted-dh",)
    assert record.backend("raises").summary == "ZeroDivisionError: boom (fake.py:1)"
    assert record.backend("raises").numbers == ""
    jac = twisted.jacobian
    assert jac is not None
    assert (jac.first_joint, jac.first_label) == ("waist", "joint 1 (waist)")
    assert (
        jac.numbers
        == "max linear difference 2.50e-01 m/rad, max angular difference 5.00e-01 rad/rad"
    )
    assert record.of("table").sentence.startswith("table NOT CHECKED")
    assert record.headline.startswith("fail — implementation disagrees")
    assert record.numbers_line.startswith("numbers (base → tool): ")
    with pytest.raises(KeyError):
        record.backend("nobody")


def test_json_carries_the_records_values(case):
    check, _, record = case
    doc = result_to_dict(check)
    assert doc["headline"] == record.headline
    assert doc["numbers"]["line"] == record.numbers_line
    assert [doc["evidence"][e.kind]["summary"] for e in record.evidence] == [
        e.sentence for e in record.evidence
    ]
    for row, r in zip(doc["backends"], record.backends, strict=True):
        assert (row["name"], row["status"], row["message"]) == (r.name, r.status, r.message)
        assert row["max_position_error_m"] == r.max_position_m
        assert row["p99_rotation_error_rad"] == r.p99_rotation_rad
        assert row["worst_q"] == (None if r.worst_q is None else list(r.worst_q))
        if r.jacobian is not None:
            assert row["jacobian"]["max_linear"] == r.jacobian.max_linear
            assert row["jacobian"]["first_disagreeing_joint"] == r.jacobian.first_joint


def test_junit_shows_the_records_reasons_summary_and_jacobian_detail(case):
    check, diagnoses, record = case
    doc = ET.fromstring(junit_xml(check, diagnoses=diagnoses))
    cases = {c.get("name", ""): c for c in doc.iter("testcase")}
    for r in record.backends:
        case_ = cases[f"{r.name} base->tool"]
        if r.status == "fail":
            failure = case_.find("failure")
            assert failure is not None
            assert r.reasons in (failure.text or "").splitlines()
            assert failure.get("message") == f"{r.name} disagrees: {r.diagnosis or r.reasons}"
        elif r.status == "pass":
            out = case_.find("system-out")
            assert out is not None
            assert (out.text or "").startswith(r.summary)
        if r.jacobian is not None:
            jac_case = cases[f"{r.name} jacobian tool (world-aligned)"]
            assert r.jacobian.detail in ET.tostring(jac_case, encoding="unicode")
    table = cases["evidence: table verified independently"]
    assert ET.tostring(table, encoding="unicode").count(escape(record.numbers_line)) == 1


def test_markdown_shows_the_records_sentences(case):
    check, diagnoses, record = case
    text = markdown_summary([check], diagnoses={check.model.name: diagnoses})
    for sentence in (record.headline, record.verdict_line, record.numbers_line):
        assert escape_markdown(sentence) in text
    for evidence in record.evidence:
        assert escape_markdown(evidence.sentence) in text
    for r in record.backends:
        assert f"| {escape_markdown(r.name)} |" in text
        if r.diagnosis:
            assert (
                f"**{escape_markdown(r.name)}** — diagnosis: {escape_markdown(r.diagnosis)}" in text
            )


def test_html_shows_the_records_summary_rows_and_sentences(case):
    check, diagnoses, record = case
    page = build_report_page(check, diagnoses=diagnoses, versions={}, plots=False)
    failing = [r for r in record.backends if r.status == "fail"]
    assert page.headline[: len(failing)] == tuple(f"{r.name}: {r.summary}" for r in failing)
    assert page.verdict_headline == record.headline
    assert page.verdict_line == record.verdict_line
    assert [e.text for e in page.evidence] == [e.sentence for e in record.evidence]
    for row, r in zip(page.backends, record.backends, strict=True):
        assert row.pos_max.value == r.max_position_m
        assert row.rot_median.value == r.median_rotation_rad
        assert row.worst_q == (r.worst_q_text if r.ran else "")
    assert page.numbers is not None
    assert page.numbers.line == record.numbers_line
    html = render_report(page)
    for r in failing:
        assert escape(f"{r.name}: {r.summary}", quote=True) in html


def test_annotations_show_the_records_message_and_diagnosis(case, tmp_path):
    check, diagnoses, record = case
    lines = github_annotations(check, diagnoses)
    twisted = record.backend("twisted-dh")
    assert any(
        line.endswith(f"::{twisted.message}; diagnosis: {twisted.diagnosis}") for line in lines
    )


def test_testing_message_is_the_records_text(case):
    check, diagnoses, record = case
    text = check_message(Outcome(check, tuple(diagnoses)))
    lines = text.splitlines()
    assert lines[0] == f"fkcheck golden-3r: base → tool: {record.headline}"
    for r in record.backends:
        assert f"{terminal_text(r.name)}: {r.status} — {terminal_text(r.summary)}" in lines
    twisted = record.backend("twisted-dh")
    assert f"  worst q: {twisted.worst_q_text}" in lines
    assert f"  diagnosis: {twisted.diagnosis_short}" in lines
    assert twisted.jacobian is not None
    assert f"  Jacobian fail: {twisted.jacobian.message}" in lines
    assert lines[-1] == record.numbers_line


def test_terminal_shows_the_records_text(case, capsys, monkeypatch):
    from fkcheck.cli.check_output import print_summary

    monkeypatch.setenv("COLUMNS", "400")  # a wide table: no cell folds

    check, _, record = case
    print_summary(check, title=True)
    out = " ".join(capsys.readouterr().out.split())  # rich wraps long lines
    assert record.headline in out
    for evidence in record.evidence:
        assert evidence.sentence in out
    assert record.numbers_line in out
    twisted = record.backend("twisted-dh")
    assert twisted.worst_q_text in out
    assert twisted.jacobian is not None
    assert twisted.jacobian.first_label in out


def test_a_failure_whose_message_states_no_numbers_gets_them_once():
    """The engine's numbers are in its message only when configurations are beyond tolerance.

    JUnit used to look for ``max position error`` in the message; a message that
    quotes those words for another reason (a non-rigid pose, here) lost the
    numbers. The record counts the configurations instead.
    """
    check = golden_check()
    within = np.full(N, 1e-9)
    odd = BackendResult(
        "odd", "fail", "not a rigid transform: defect 0.01 (max position error unknown)",
        "plugin", 0.1, within, within, 3,
    )  # fmt: skip
    check = replace(check, backends=(*check.backends, odd))
    r = check_record(check).backend("odd")
    assert r.beyond == 0
    assert r.reasons == (
        "not a rigid transform: defect 0.01 (max position error unknown); "
        f"{r.numbers} (tolerance 1e-06 m, 1e-06 rad)"
    )
    doc = ET.fromstring(junit_xml(check))
    failure = next(c for c in doc.iter("testcase") if c.get("name", "").startswith("odd "))
    text = failure.find("failure")
    assert text is not None
    assert r.numbers in (text.text or "")


def _scrubbed(path: Path) -> str:
    """A report with what differs between two runs of one check (times) removed."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".json":
        doc = json.loads(text)
        doc.pop("created"), doc.pop("duration_s")
        for backend in doc["backends"]:
            backend.pop("duration_s")
        return json.dumps(doc, indent=1)
    if path.suffix == ".xml":
        return re.sub(r' (time|timestamp)="[^"]*"', "", text)
    if path.suffix == ".html":
        text = re.sub(r"(<td[^>]*>)\d+ ms(</td>)", r"\1MS\2", text)  # backend durations
        return scrub(text)
    return text


def test_the_cli_writes_its_reports_as_the_api_does(tmp_path, monkeypatch):
    """``fkcheck check`` calls :func:`fkcheck.report.write.write_reports`, as ``write_report``."""
    pytest.importorskip("pinocchio")
    import fkcheck
    import fkcheck.report.write as write
    from fkcheck.cli.main import main

    monkeypatch.delenv("GITHUB_STEP_SUMMARY", raising=False)
    monkeypatch.chdir(tmp_path)  # no pyproject.toml around: the defaults
    calls: list[dict[str, Any]] = []
    original = write.write_reports

    def spy(*args: Any, **kwargs: Any) -> tuple[Path, ...]:
        calls.append(kwargs)
        return original(*args, **kwargs)

    monkeypatch.setattr(write, "write_reports", spy)
    names = {"html": "r.html", "json": "r.json", "junit": "r.junit.xml", "summary": "r.md"}
    cli, api = tmp_path / "cli", tmp_path / "api"
    cli.mkdir(), api.mkdir()
    argv = ["check", "ur5", "--samples", "8", "--against", "pinocchio-dh"]
    argv += [x for key, name in names.items() for x in (f"--{key}", str(cli / name))]
    assert main(argv) == 0
    assert len(calls) == 1
    asked = {k: Path(v) for k, v in calls[0].items() if v is not None}
    assert asked == {k: cli / name for k, name in names.items()}
    outcome = fkcheck.check("ur5", ["pinocchio-dh"], samples=8)
    command = json.loads((cli / "r.json").read_text(encoding="utf-8"))["command"]
    outcome = Outcome(replace(outcome.check, command=command), outcome.diagnoses)
    fkcheck.write_report(outcome, **{k: api / name for k, name in names.items()})
    for name in names.values():
        assert _scrubbed(cli / name) == _scrubbed(api / name), name


def test_the_engines_message_states_the_numbers_exactly_when_configurations_are_beyond(
    monkeypatch,
):
    """What :attr:`BackendRecord.reasons` relies on, pinned on a real engine failure."""
    import fkcheck
    from tests.paths import PLUGINS_DIR

    monkeypatch.syspath_prepend(str(PLUGINS_DIR))
    outcome = fkcheck.check(
        "ur5", ["nonrigid:forward"], frame_from="world", frame_to="tool0", samples=8,
        diagnose=False,
    )  # fmt: skip
    (r,) = check_record(outcome.check).backends
    assert r.status == "fail"
    assert ("max position error" in r.message) == (r.beyond > 0)
    assert r.reasons.count("max position error") == 1


def test_the_verdict_sentence_blames_what_the_evidence_blames():
    from fkcheck.report.record import verdict_line

    check = golden_check()
    # shifted and twisted-dh read the table: they disagree with the in-house core.
    assert verdict_line(check).startswith(
        "2 of 3 backends that ran disagree with the in-house core: shifted, twisted-dh;"
    )
    # Independent of the table (a URDF), while "agrees" computes the same table: the table
    # is what disagrees — the sentence said "disagree with the in-house core" while the
    # headline said "table disagrees".
    urdf = tuple(replace(b, evidence="table") if b.status == "fail" else b for b in check.backends)
    assert verdict_line(replace(check, backends=urdf)) == (
        "2 of 3 backends that ran disagree with the table: shifted, twisted-dh; 1 other "
        "implementation of the table agrees with the in-house core: agrees; 1 errored: raises; "
        "1 skipped: absent."
    )


def test_identical_diagnosis_and_failure_bullets_show_once():
    from fkcheck.report.page import _diagnosis_bullets

    check = golden_check()
    twin = replace(check.backends[1], name="shifted-too")  # the same errors, another name
    check = replace(check, backends=(*check.backends, twin))
    page = build_report_page(check, diagnoses=golden_diagnoses(check), plots=False, versions={})
    fails = [line for line in page.headline if "configurations beyond tolerance" in line]
    assert [line.split(":", 1)[0] for line in fails] == ["shifted, shifted-too", "twisted-dh"]
    # Two diagnoses that say the same thing (not grouped as "also"): one bullet.
    first = page.diagnoses[0]
    views = (first, replace(first, backend="other", also=()), page.diagnoses[-1])
    bullets = _diagnosis_bullets(views)
    assert len(bullets) == len({first.short, page.diagnoses[-1].short})
    assert bullets[0].startswith(f"Diagnosis against {first.backend} (and ")
    assert bullets[0].count(first.short) == 1
    assert "other" in bullets[0].split(":", 1)[0]
