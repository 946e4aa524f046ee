"""CI artefacts carry the cause: JUnit, the Markdown summary and GitHub annotations."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import replace

import pytest

from fkcheck._version import __version__
from fkcheck.report.annotations import (
    escape_data,
    escape_property,
    field_line,
    github_annotations,
)
from fkcheck.report.junit import junit_xml
from fkcheck.report.markdown import LEGEND, markdown_summary
from tests.report_cases import golden_check, golden_diagnoses

TOML = """\
name = "arm"
convention = "standard"

[base]
xyz = [0, 0, 0.1]

[[joint]]
name = "j1"
alpha = 90
d = 0.1

[[joint]]
name = "j2"
d = 0.2
  alpha   = 0
"""


def _failure(check, diagnoses, backend: str) -> ET.Element:
    doc = ET.fromstring(junit_xml(check, diagnoses=diagnoses))
    case = next(c for c in doc.iter("testcase") if c.get("name", "").startswith(backend + " "))
    failure = case.find("failure")
    assert failure is not None
    return failure


def test_junit_failure_says_verdict_numbers_and_cause_once():
    check = golden_check()
    failure = _failure(check, golden_diagnoses(check), "twisted-dh")
    text = failure.text or ""
    assert text.splitlines() == [
        "fail: twisted-dh disagrees with the in-house core (base -> tool)",
        "5 of 6 configurations differ: max position error 500 mm (5.00e-01 m), max rotation "
        "error 172° (3.00e+00 rad) (tolerance 1e-06 m, 1e-06 rad)",
        "diagnosis: one number differs: α2 (shoulder)",
        "explain it: fkcheck diagnose golden-3r --against twisted-dh --from base --to tool "
        "--seed 7",
    ]
    assert text.count("max position error") == 1
    assert failure.get("message") == "twisted-dh disagrees: one number differs: α2 (shoulder)"


def test_junit_failure_without_a_diagnosis_keeps_the_numbers_once():
    failure = _failure(golden_check(), (), "shifted")
    assert (failure.text or "").count("max position error 0.300 mm (3.00e-04 m)") == 1
    assert "diagnosis" not in (failure.text or "")
    assert failure.get("message", "").startswith("shifted disagrees: 6 of 6 configurations")


def test_summary_of_one_model_adds_the_diagnosis_under_its_table():
    check = golden_check()
    text = markdown_summary([check], diagnoses={"golden-3r": golden_diagnoses(check)})
    assert text.endswith(
        "| absent | ⏭️ skipped | – | – | library not installed here |\n"
        "\n"
        "- ✘ **shifted** — diagnosis: not explained by any hypothesis tried\n"
        "- ✘ **twisted-dh** — diagnosis: one number differs: α2 (shoulder)\n"
        "\n"
        f"<sub>fkcheck {__version__}</sub>\n"
    )


def test_summary_of_many_models_is_a_row_per_model_with_a_legend_and_causes():
    check = golden_check()
    passing = replace(
        check,
        model=replace(check.model, name="fine"),
        backends=(check.backends[0], check.backends[4]),
        verdict="pass",
    )
    many = [check, *(replace(passing, model=replace(check.model, name=f"m{k}")) for k in range(24))]
    text = markdown_summary(many, diagnoses={"golden-3r": golden_diagnoses(check)})
    lines = text.splitlines()
    head = "| model | verdict | table verified | agrees | shifted | twisted-dh | raises | absent |"
    assert head in lines
    assert "| golden-3r | ❌ fail | – | ✔ | ✘ | ✘ | ! | – |" in lines
    assert "| m0 | ✅ pass | – | ✔ | – | – | – | – |" in lines
    assert (
        sum(re.match(r"\| m\d+ \|", line) is not None for line in lines) == 24
    )  # one row per model
    assert any(line.startswith(LEGEND) for line in lines)
    assert (
        "- ✘ **golden-3r · twisted-dh**: 5 of 6 configurations differ: max position error "
        "500 mm (5.00e-01 m), max rotation error 172° (3.00e+00 rad) — diagnosis: one number "
        "differs: α2 (shoulder)"
    ) in lines
    assert "- ! **golden-3r · raises**: ZeroDivisionError: boom (fake.py:1)" in lines
    assert len(lines) < 45  # compact: no per-backend rows, no per-model paragraphs


def test_github_escaping_follows_the_runner_rules():
    assert escape_data("50%\r\nnext") == "50%25%0D%0Anext"
    assert escape_property("a:b,c%\n") == "a%3Ab%2Cc%25%0A"


def test_field_line_finds_joint_and_table_keys_and_tolerates_absence():
    assert field_line(TOML, "joint[0].alpha") == 9
    assert field_line(TOML, "joint[1].alpha") == 15
    assert field_line(TOML, "joint[1].d") == 14
    assert field_line(TOML, "base.xyz[2]") == 5
    assert field_line(TOML, "joint[1].theta") is None
    assert field_line(TOML, "joint[7].alpha") is None
    assert field_line(TOML, "nonsense") is None


@pytest.mark.parametrize("quote", ['"""', "'''"])
def test_field_line_skips_what_a_multi_line_string_holds(quote):
    """A description that looks like TOML is text: the line is the parameter's own."""
    fake = f"description = {quote}\n[[joint]]\nalpha = 1\n[base]\nxyz = [0, 0, 0]\n{quote}\n"
    tricky = "title = \"a # and \\\" and ''' in one line\"\n"
    text = fake + tricky + TOML
    offset = text.count("\n") - TOML.count("\n")
    assert field_line(text, "joint[0].alpha") == 9 + offset
    assert field_line(text, "joint[1].alpha") == 15 + offset
    assert field_line(text, "base.xyz[2]") == 5 + offset


def test_annotations_point_at_the_file_and_the_parameter_line(tmp_path, monkeypatch):
    check = golden_check()
    path = tmp_path / "robots" / "arm.toml"
    check = replace(check, model=replace(check.model, path=path))
    monkeypatch.chdir(tmp_path)
    lines = github_annotations(check, golden_diagnoses(check), source=TOML)
    assert lines[0].startswith("::error file=robots/arm.toml,title=fkcheck golden-3r%3A shifted ")
    assert lines[1] == (
        "::error file=robots/arm.toml,line=15,title=fkcheck golden-3r%3A twisted-dh disagrees "
        "with the in-house core::5 of 6 configurations differ: max position error 500 mm "
        "(5.00e-01 m), max rotation error 172° (3.00e+00 rad); diagnosis: one number differs: "
        "α2 (shoulder)"
    )
    assert lines[2] == (
        "::error file=robots/arm.toml,title=fkcheck golden-3r%3A raises errored::"
        "ZeroDivisionError: boom (fake.py:1)"
    )
    assert len(lines) == 3
    # Without the text, or with a name holding a newline: still one line per annotation.
    hostile = replace(check, model=replace(check.model, name="x\ny"))
    for line in github_annotations(hostile, golden_diagnoses(hostile)):
        assert "\n" not in line
        assert "line=" not in line


def test_a_passing_check_has_no_annotation():
    check = golden_check()
    passing = replace(check, backends=check.backends[:1], verdict="pass")
    assert github_annotations(passing, (), source=TOML) == []


#: What GitHub turns into a link or a notification, from a model name, and its escaped form.
LINKING = [
    ("@octocat", "@\u200boctocat"),
    ("@org/team", "@\u200borg/team"),
    ("mail admin@example.com", "mail admin@\u200bexample.com"),
    ("https://evil.example/x", "https:\u200b//evil.example/x"),
    ("ftp://host/f", "ftp:\u200b//host/f"),
    ("www.evil.example", "www\u200b.evil.example"),
    ("WWW.Evil.Example", "WWW\u200b.Evil.Example"),
    ("fixes #12", "fixes \\#\u200b12"),
]


def test_summary_text_from_input_can_neither_link_nor_mention():
    """A zero-width space after @, the ':' of '://', '#', and in 'www.': it links nowhere."""
    check = golden_check()
    for raw, escaped in LINKING:
        named = replace(check, model=replace(check.model, name=raw))
        heading = markdown_summary([named]).splitlines()[0]
        assert heading == f"## fkcheck {escaped}: ❌ FAIL", raw
        assert not re.search(r"@\w|\w://|\bwww\.|#\d", heading, re.IGNORECASE), heading
