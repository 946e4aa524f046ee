"""JUnit XML: one test case per backend, so CI systems show the check natively.

A failing case's ``<failure>`` says, once each: what failed (verdict), by how
much (the numbers and the tolerance) and why (the headline of its diagnosis,
when the check was diagnosed). Every text comes from the check's record
(:mod:`fkcheck.report.record`). The diagnoses are passed in, already run
(:func:`fkcheck.diagnose.failures.diagnose_failures`); nothing here runs one.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from fkcheck._version import __version__
from fkcheck.engine.results import BackendResult, CheckResult
from fkcheck.io.atomic import write_bytes_atomic
from fkcheck.io.text import xml_safe_tree
from fkcheck.report.record import BackendRecord, backend_record, check_record

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis

__all__ = ["failure_text", "junit_xml", "write_junit"]


def failure_text(
    result: BackendResult, check: CheckResult, diagnoses: Sequence[BackendDiagnosis] = ()
) -> tuple[str, str]:
    """A failing backend's one-line summary and its full text: verdict, numbers, cause.

    Args:
        result: A backend result whose status is ``fail``.
        check: The check it belongs to (tolerances, frames).
        diagnoses: The check's diagnoses; the one standing for ``result`` gives the cause.

    Returns:
        ``(summary, text)``: see :func:`_failure`.
    """
    return _failure(backend_record(check, result, diagnoses), check)


def _failure(record: BackendRecord, check: CheckResult) -> tuple[str, str]:
    """``(summary, text)`` of a failing backend, from its record.

    The summary names the backend and the cause (or its reasons when there is
    no diagnosis); the text holds the verdict line, the reasons (the engine's
    message, the numbers, the tolerance: :attr:`BackendRecord.reasons`) and the
    diagnosis headline with the command that reproduces it — each once.
    """
    whom = ("another reader of the same description, which agrees with the table"
            if record.reader_finding else "the in-house core")  # fmt: skip
    lines = [f"{record.label}: {record.name} disagrees with {whom} "
             f"({check.frame_from} -> {check.frame_to})", record.reasons]  # fmt: skip
    summary = f"{record.name} disagrees: {record.reasons}"
    if record.diagnosis:
        lines.append(f"diagnosis: {record.diagnosis}")
        summary = f"{record.name} disagrees: {record.diagnosis}"
        if record.diagnosis_command:
            lines.append(f"explain it: {record.diagnosis_command}")
    return summary, "\n".join(lines)


def _jacobian_case(
    suite: ET.Element, name: str, record: BackendRecord, check: CheckResult, counts: dict[str, int]
) -> None:
    """One test case for a backend's Jacobian (``check --jacobian``), with the same rules."""
    j = record.jacobian
    assert j is not None
    case = ET.SubElement(
        suite, "testcase", classname=name,
        name=f"{record.name} jacobian {check.frame_to} ({j.reference})",
    )  # fmt: skip
    counts["tests"] += 1
    detail = j.detail
    if j.status == "fail":
        summary = f"{record.name}'s Jacobian disagrees: {j.diagnosis or j.message}"
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
    # The version that wrote it: first in the suite, as the JUnit schema orders them.
    properties = ET.SubElement(suite, "properties")
    ET.SubElement(properties, "property", name="fkcheck_version", value=__version__)
    counts = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    record = check_record(check, diagnoses)
    for result in record.backends:
        case = ET.SubElement(
            suite, "testcase", classname=name,
            name=f"{result.name} {check.frame_from}->{check.frame_to}",
            time=f"{result.duration_s:.3f}",
        )  # fmt: skip
        counts["tests"] += 1
        detail = result.message
        if result.ran:
            detail = f"{result.summary}. {result.message}".strip()
        if result.status == "fail":
            summary, text = _failure(result, check)
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
    for evidence in record.evidence:
        kind, sentence, status = evidence.kind, evidence.sentence, evidence.status
        case = ET.SubElement(
            suite, "testcase", classname=name, name=f"evidence: {kind} verified independently"
        )
        counts["tests"] += 1
        text = sentence
        if kind == "table":
            text += "".join(
                "\n" + line for line in (record.numbers_line, record.calibration_line) if line
            )
        if status == "failed":
            ET.SubElement(case, "failure", message=sentence, type="disagreement").text = text
            counts["failures"] += 1
        elif status != "verified" and evidence.required:
            ET.SubElement(case, "failure", message=sentence, type="required").text = text
            counts["failures"] += 1
        elif status != "verified":
            ET.SubElement(case, "skipped", message=sentence).text = text
            counts["skipped"] += 1
        else:
            ET.SubElement(case, "system-out").text = text
    if not record.answered:
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
