"""JUnit XML: one test case per backend, so CI systems show the check natively.

A failing case's ``<failure>`` says, once each: what failed (verdict), by how
much (the numbers and the tolerance) and why (the headline of its diagnosis,
when the check was diagnosed). The diagnoses are passed in, already run
(:func:`fkcheck.diagnose.failures.diagnose_failures`); nothing here runs one.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.engine.verdict import evidence_sentences, numbers_line
from fkcheck.io.atomic import write_bytes_atomic
from fkcheck.io.text import xml_safe_tree
from fkcheck.report.diagnosis import diagnosis_for, diagnosis_headline

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis

__all__ = ["failure_text", "junit_xml", "write_junit"]


def _numbers(result: BackendResult, check: CheckResult) -> str:
    """``max position error … m, max rotation error … rad (tolerance … m, … rad)``."""
    return (
        f"max position error {result.max_position_error_m:.3g} m, "
        f"max rotation error {result.max_rotation_error_rad:.3g} rad "
        f"(tolerance {check.tol_pos_m:g} m, {check.tol_rot_rad:g} rad)"
    )


def failure_text(
    result: BackendResult, check: CheckResult, diagnoses: Sequence[BackendDiagnosis] = ()
) -> tuple[str, str]:
    """A failing backend's one-line summary and its full text: verdict, numbers, cause.

    Args:
        result: A backend result whose status is ``fail``.
        check: The check it belongs to (tolerances, frames).
        diagnoses: The check's diagnoses; the one standing for ``result`` gives the cause.

    Returns:
        ``(summary, text)``: the summary names the backend and the cause (or the
        numbers when there is no diagnosis); the text holds the verdict line, the
        engine's reasons with the numbers and the tolerance, and the diagnosis
        headline with the command that reproduces it — each once.
    """
    lines = [f"fail: {result.name} disagrees with the in-house core "
             f"({check.frame_from} -> {check.frame_to})"]  # fmt: skip
    reasons = result.message
    if "max position error" not in reasons:
        reasons = f"{reasons}; {_numbers(result, check)}" if reasons else _numbers(result, check)
    else:
        reasons = f"{reasons} (tolerance {check.tol_pos_m:g} m, {check.tol_rot_rad:g} rad)"
    lines.append(reasons)
    summary = f"{result.name} disagrees: {reasons}"
    outcome = diagnosis_for(diagnoses, result.name)
    if outcome is not None:
        short = diagnosis_headline(outcome)
        lines.append(f"diagnosis: {short}")
        summary = f"{result.name} disagrees: {short}"
        if outcome.command:
            lines.append(f"explain it: {outcome.command}")
    return summary, "\n".join(lines)


def _jacobian_case(
    suite: ET.Element, name: str, result: BackendResult, check: CheckResult, counts: dict[str, int]
) -> None:
    """One test case for a backend's Jacobian (``check --jacobian``), with the same rules."""
    j = result.jacobian
    assert j is not None
    case = ET.SubElement(
        suite, "testcase", classname=name,
        name=f"{result.name} jacobian {check.frame_to} ({j.reference})",
    )  # fmt: skip
    counts["tests"] += 1
    detail = j.message
    if j.ran:
        numbers = (
            f"max linear difference {j.max_linear_error:.3g} m/rad, max angular difference "
            f"{j.max_angular_error:.3g} rad/rad (tolerance {j.tolerance:g}; {j.method})"
        )
        detail = f"{detail}; {numbers}" if detail else numbers
    if j.status == "fail":
        summary = f"{result.name}'s Jacobian disagrees: {j.diagnosis or j.message}"
        if j.diagnosis:
            detail = "\n".join([detail, f"diagnosis: {j.diagnosis}", *j.diagnosis_details])
        ET.SubElement(case, "failure", message=summary, type="disagreement").text = detail
        counts["failures"] += 1
    elif j.status == "error":
        ET.SubElement(case, "error", message=detail, type="error").text = detail
        counts["errors"] += 1
    elif j.status == "skipped":
        ET.SubElement(case, "skipped", message=detail)
        counts["skipped"] += 1
    else:
        ET.SubElement(case, "system-out").text = detail


def junit_xml(check: CheckResult, *, diagnoses: Sequence[BackendDiagnosis] = ()) -> bytes:
    """The JUnit document: a suite per check, a case per backend.

    ``fail`` → ``<failure>`` (text: :func:`failure_text`, which names the
    diagnosis from ``diagnoses`` when there is one), ``error`` → ``<error>``,
    ``skipped`` → ``<skipped>``.
    Two more cases say what the run proved, one per kind of evidence
    (implementation, table): passed when verified, ``<failure>`` when it
    disagrees or is required and missing, ``<skipped>`` (with the reason) when
    not checked — so a table nothing independent looked at never shows as a
    green test. A run where nothing was cross-checked gets an extra erroring
    case, so the suite is red.
    """
    name = f"fkcheck.{check.model.name}"
    suite = ET.Element("testsuite", name=name, timestamp=check.created,
                       time=f"{check.duration_s:.3f}")  # fmt: skip
    counts = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    for result in check.backends:
        case = ET.SubElement(
            suite, "testcase", classname=name,
            name=f"{result.name} {check.frame_from}->{check.frame_to}",
            time=f"{result.duration_s:.3f}",
        )  # fmt: skip
        counts["tests"] += 1
        detail = result.message
        if result.ran:
            detail = f"{_numbers(result, check)}. {result.message}".strip()
        if result.status == "fail":
            summary, text = failure_text(result, check, diagnoses)
            ET.SubElement(case, "failure", message=summary, type="disagreement").text = text
            counts["failures"] += 1
        elif result.status == "error":
            ET.SubElement(case, "error", message=detail, type="error").text = detail
            counts["errors"] += 1
        elif result.status == "xpass":
            ET.SubElement(case, "failure", message=result.message, type="stale-known-difference")
            counts["failures"] += 1
        elif result.status in ("skipped", "xfail"):
            ET.SubElement(case, "skipped", message=detail)
            counts["skipped"] += 1
        else:
            ET.SubElement(case, "system-out").text = detail
        if result.jacobian is not None:
            _jacobian_case(suite, name, result, check, counts)
    evidence = check.evidence
    for kind, sentence in zip(
        ("implementation", "table"), evidence_sentences(evidence), strict=True
    ):
        case = ET.SubElement(
            suite, "testcase", classname=name, name=f"evidence: {kind} verified independently"
        )
        counts["tests"] += 1
        status = evidence.of(kind).status  # type: ignore[arg-type]
        text = sentence
        if kind == "table" and check.numbers is not None:
            text += "\n" + numbers_line(check.numbers, status)
        if status == "failed":
            ET.SubElement(case, "failure", message=sentence, type="disagreement").text = text
            counts["failures"] += 1
        elif status != "verified" and kind in evidence.unmet:
            ET.SubElement(case, "failure", message=sentence, type="required").text = text
            counts["failures"] += 1
        elif status != "verified":
            ET.SubElement(case, "skipped", message=sentence).text = text
            counts["skipped"] += 1
        else:
            ET.SubElement(case, "system-out").text = text
    if not check.ran:
        case = ET.SubElement(suite, "testcase", classname=name, name="cross-check ran")
        text = "no reference backend ran: nothing was cross-checked"
        ET.SubElement(case, "error", message=text, type="nothing-checked").text = text
        counts["tests"] += 1
        counts["errors"] += 1
    for key, value in counts.items():
        suite.set(key, str(value))
    suites = ET.Element("testsuites")
    suites.append(suite)
    xml_safe_tree(suites)  # text from input: no character XML 1.0 cannot carry
    ET.indent(suites)
    data: bytes = ET.tostring(suites, encoding="utf-8", xml_declaration=True)
    return data


def write_junit(
    check: CheckResult, path: Path | str, *, diagnoses: Sequence[BackendDiagnosis] = ()
) -> Path:
    """Write the JUnit XML (with the diagnoses' headlines in its failures), atomically."""
    return write_bytes_atomic(path, junit_xml(check, diagnoses=diagnoses))
