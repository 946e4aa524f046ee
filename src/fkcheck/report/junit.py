"""JUnit XML: one test case per backend, so CI systems show the check natively."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from fkcheck.engine.results import CheckResult
from fkcheck.engine.verdict import evidence_sentences
from fkcheck.io.atomic import write_bytes_atomic
from fkcheck.io.text import xml_safe_tree

__all__ = ["junit_xml", "write_junit"]


def junit_xml(check: CheckResult) -> bytes:
    """The JUnit document: a suite per check, a case per backend.

    ``fail`` → ``<failure>``, ``error`` → ``<error>``, ``skipped`` → ``<skipped>``.
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
            detail = (
                f"max position error {result.max_position_error_m:.3g} m, "
                f"max rotation error {result.max_rotation_error_rad:.3g} rad "
                f"(tolerance {check.tol_pos_m:g} m, {check.tol_rot_rad:g} rad). {result.message}"
            ).strip()
        if result.status == "fail":
            ET.SubElement(case, "failure", message=detail, type="disagreement").text = detail
            counts["failures"] += 1
        elif result.status == "error":
            ET.SubElement(case, "error", message=detail, type="error").text = detail
            counts["errors"] += 1
        elif result.status == "skipped":
            ET.SubElement(case, "skipped", message=detail)
            counts["skipped"] += 1
        else:
            ET.SubElement(case, "system-out").text = detail
    evidence = check.evidence
    for kind, sentence in zip(
        ("implementation", "table"), evidence_sentences(evidence), strict=True
    ):
        case = ET.SubElement(
            suite, "testcase", classname=name, name=f"evidence: {kind} verified independently"
        )
        counts["tests"] += 1
        status = evidence.of(kind).status  # type: ignore[arg-type]
        if status == "failed":
            ET.SubElement(case, "failure", message=sentence, type="disagreement").text = sentence
            counts["failures"] += 1
        elif status == "not-checked" and kind in evidence.unmet:
            ET.SubElement(case, "failure", message=sentence, type="required").text = sentence
            counts["failures"] += 1
        elif status == "not-checked":
            ET.SubElement(case, "skipped", message=sentence)
            counts["skipped"] += 1
        else:
            ET.SubElement(case, "system-out").text = sentence
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


def write_junit(check: CheckResult, path: Path | str) -> Path:
    """Write the JUnit XML, atomically."""
    return write_bytes_atomic(path, junit_xml(check))
