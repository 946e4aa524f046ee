"""The HTML report and index: gold files, escaping, numbers equal to the JSON, evidence."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from importlib import resources

import numpy as np
import pytest

from fkcheck._version import __version__
from fkcheck.core.tolerances import SAME_CHAIN
from fkcheck.io.format import (
    format_angle_console,
    format_angle_summary,
    format_constant,
    format_deg,
    format_fixed,
    format_length_console,
    format_length_summary,
    format_microseconds,
    format_mm,
    format_pair,
    format_rad,
)
from fkcheck.report.html import render_index, render_report, write_html
from fkcheck.report.index import IndexEntry, build_index_page
from fkcheck.report.json_report import result_to_dict
from fkcheck.report.markdown import escape_markdown, markdown_summary
from fkcheck.report.page import build_report_page
from tests.paths import GOLDEN_DIR
from tests.report_cases import (
    SPEC,
    golden_check,
    golden_diagnoses,
    golden_model,
    page_numbers,
    scrub,
    twisted_model,
)

GOLDEN = GOLDEN_DIR
XSS = "<script>alert(1)</script>"


def _compare_with_gold(actual: str, name: str) -> None:
    """Compare with tests/golden/NAME; on a mismatch write NAME.actual beside it for review."""
    gold = GOLDEN / name
    stem, dot, ext = name.rpartition(".")
    actual_path = GOLDEN / f"{stem}.actual{dot}{ext}"
    if gold.exists() and gold.read_text(encoding="utf-8") == actual:
        actual_path.unlink(missing_ok=True)
        return
    actual_path.write_text(actual, encoding="utf-8")
    raise AssertionError(
        f"{name} differs from the gold file (or there is none): the output is in "
        f"{actual_path}; review it (diff -u {gold} {actual_path}) and, if it is right, "
        "move it over the gold file"
    )


@pytest.fixture(scope="module")
def golden_page() -> str:
    check = golden_check()
    return render_report(build_report_page(check, diagnoses=golden_diagnoses(check)))


def test_report_matches_the_gold_file(golden_page):
    _compare_with_gold(scrub(golden_page), "report_golden-3r.html")


def test_index_matches_the_gold_file():
    check = golden_check()
    page = build_index_page(
        [IndexEntry(check, "golden-3r.html", "golden-3r.json", "golden-3r.junit.xml")],
        command="fkcheck check --all --samples 3",
        created="2026-01-02T03:04:05+00:00",
    )
    _compare_with_gold(scrub(render_index(page)), "index_golden-3r.html")


def test_markdown_summary_matches_the_gold_file():
    # Its last line names the version that wrote it; the gold file says VERSION there.
    text = markdown_summary([golden_check()])
    version_line = f"<sub>fkcheck {__version__}</sub>\n"
    assert text.endswith(f"\n\n{version_line}")
    _compare_with_gold(text.replace(version_line, "<sub>fkcheck VERSION</sub>\n"),
                       "summary_golden-3r.md")  # fmt: skip


def test_scrub_removes_only_volatile_parts(golden_page):
    scrubbed = scrub(golden_page)
    assert "2026-01-02T03:04:05+00:00" in golden_page
    assert "2026-01-02T03:04:05+00:00" not in scrubbed
    assert "data:image/png;base64,iVBOR" in golden_page  # PNG magic, base64
    assert "base64,iVBOR" not in scrubbed
    assert "0.300 mm" in scrubbed
    assert "fkcheck check golden-3r --samples 3 --seed 7" in scrubbed


def test_verdict_and_numbers_on_the_page_equal_the_json(golden_page):
    doc = result_to_dict(golden_check())
    found = page_numbers(golden_page)
    assert found.verdict == doc["verdict"] == "fail"
    for b in doc["backends"]:
        assert found.status[b["name"]] == b["status"]
        for key in ("max_position_error_m", "p99_position_error_m", "median_position_error_m",
                    "max_rotation_error_rad", "p99_rotation_error_rad",
                    "median_rotation_error_rad"):  # fmt: skip
            shown = found.values[(b["name"], key)]
            if b[key] is None:
                assert shown == ""
            else:
                assert float(shown) == b[key], (b["name"], key)


def test_first_screen_names_the_disagreeing_backends_and_sizes(golden_page):
    head = golden_page[golden_page.index('id="verdict"') : golden_page.index('id="summary"')]
    assert ">FAIL<" in head
    assert "2 of 3 backends that ran disagree with the in-house core: shifted, twisted-dh" in head
    assert "shifted: max position error 0.300 mm (3.00e-04 m)" in head
    assert "Where the chains part: twisted-dh&#39;s chain parts from the in-house one at " in head
    assert "DH frame 2 (after joint 2, shoulder)" in head


def test_dh_parting_names_the_first_frame_that_differs():
    check = golden_check()
    twisted = check.backends[2]
    assert twisted.detail is not None
    parting = twisted.detail.dh_parting
    assert parting is not None
    assert parting.first == 2
    # Frames 0 and 1 are the same chain: identical to round-off.
    assert parting.position_error_m[:2].max() <= SAME_CHAIN
    assert parting.rotation_error_rad[:2].max() <= SAME_CHAIN
    # Joint 2's twist is off by π: frame 2's orientation turns by π about its x axis.
    assert parting.rotation_error_rad[2] == pytest.approx(math.pi)
    shifted = check.backends[1].detail
    assert shifted is not None
    assert shifted.dh_parting is None  # no DH frames: not a DH backend


def test_worst_case_matrices_mark_the_entries_that_differ(golden_page):
    check = golden_check()
    assert check.backends[1].detail is not None
    shifted = check.backends[1].detail.worst
    # 0.3 mm along the tool's z: only translation entries beyond 1 µm differ, marked
    # in both matrices and in the difference.
    beyond = np.abs(shifted.theirs[:, :3, 3] - shifted.ours[:, :3, 3]) > check.tol_pos_m
    section = golden_page[golden_page.index('id="backend-shifted"') :]
    section = section[: section.index('id="backend-twisted-dh"')]
    assert section.count('class="marked"') == 3 * int(beyond.sum())
    for row in re.findall(r"<tr>(.*?)</tr>", section):
        cells = re.findall(r"<td( class=\"marked\")?[^>]*>", row)
        if len(cells) == 4:  # a matrix row: only the last column may be marked
            assert not any(cells[:3]), row
    assert "difference (shifted − in-house)" in section


class _Tags:
    @staticmethod
    def of(page: str) -> list[tuple[str, dict[str, str | None]]]:
        found = page_numbers(page)
        return [(tag, dict(attrs)) for tag, attrs in found.tags]


def _hostile_model(where: str):
    if where in ("name", "description"):
        return golden_model(**{where: XSS})
    if where == "joint":
        joints = [dict(j) for j in SPEC["joint"]]
        joints[0]["name"] = '<img src=x onerror="alert(2)">'
        return golden_model(joint=joints)
    return golden_model()


@pytest.mark.parametrize("where", ["name", "description", "joint", "message"])
def test_model_text_is_escaped(where):
    model = _hostile_model(where)
    extra = f" {XSS}" if where == "message" else ""
    check = golden_check(model, message_extra=extra)
    page = render_report(build_report_page(check))
    tags = _Tags.of(page)
    assert not [t for t, _ in tags if t == "script"], "a <script> element reached the page"
    assert not [(t, a) for t, a in tags if any(k.startswith("on") for k in a)]
    assert "<img src=x" not in page
    if where == "joint":
        assert "&lt;img src=x onerror=&#34;alert(2)&#34;&gt;" in page
    else:
        assert "&lt;script&gt;alert(1)&lt;/script&gt;" in page
    summary = markdown_summary([check])
    assert "<script>" not in summary
    index = render_index(build_index_page([IndexEntry(check, "a.html", "a.json", "a.xml")]))
    assert "<script>" not in index
    assert not [t for t, _ in _Tags.of(index) if t == "script"]


def test_markdown_escaping_keeps_the_table_intact():
    assert escape_markdown("a|b `c` *d* [e](f) <g>") == (r"a\|b \`c\` \*d\* \[e\](f) &lt;g&gt;")
    assert escape_markdown("two\nlines") == "two lines"


def test_dollar_signs_in_names_do_not_break_the_plots(tmp_path):
    joints = [dict(j) for j in SPEC["joint"]]
    joints[0]["name"] = "$\\alpha$ {unclosed $"
    check = golden_check(golden_model(joint=joints))
    page = render_report(build_report_page(check))
    assert page.count("data:image/png;base64,iVBOR") == 4  # 2 plots + 2 arm drawings


def test_page_is_self_contained(golden_page):
    tags = _Tags.of(golden_page)
    for tag, attrs in tags:
        for key in ("src", "href"):
            value = attrs.get(key)
            if value is not None:
                assert value.startswith(("data:", "#")), (tag, key, value)
    assert not [t for t, _ in tags if t in ("script", "link", "iframe", "object")]
    csp = [a for t, a in tags if t == "meta" and a.get("http-equiv") == "Content-Security-Policy"]
    assert len(csp) == 1
    assert csp[0]["content"] == ("default-src 'none'; img-src data:; style-src 'unsafe-inline'")


def test_templates_ship_inside_the_package():
    templates = resources.files("fkcheck.report") / "templates"
    names = {p.name for p in templates.iterdir()}
    assert {"base.html.j2", "report.html.j2", "index.html.j2", "macros.html.j2", "summary.html.j2",
            "style.css"} <= names  # fmt: skip


def test_model_section_shows_the_table_and_a_i(golden_page):
    model = golden_page[golden_page.index('id="model"') :]
    assert "standard DH: Aᵢ = Rz(θᵢ) · Tz(dᵢ) · Tx(aᵢ) · Rx(αᵢ)" in model
    assert "−sin θᵢ cos αᵢ" in model
    # Row 3: elbow, θ offset 90°, flipped.
    assert (
        '<td>3</td><td>elbow</td><td>revolute (θ)</td><td class="n">0.3</td>'
        '<td class="n">0</td><td class="n">0</td><td class="n">90</td><td>yes</td>'
    ) in model
    assert "tool: DH frame 3 → TCP" in model
    assert "xyz (0, 0, 0.1) m, rpy (0, 0, 0)°" in model


def test_twisted_model_differs_only_in_joint_2():
    a, b = golden_model(), twisted_model(golden_model())
    assert [j.alpha for j in a.joints] != [j.alpha for j in b.joints]
    assert (a.joints[0], a.joints[2]) == (b.joints[0], b.joints[2])


def test_write_html_is_atomic_and_complete(tmp_path):
    path = write_html(golden_check(), tmp_path / "sub" / "r.html", plots=False)
    text = path.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>")
    assert text.rstrip().endswith("</html>")
    assert list(path.parent.iterdir()) == [path]  # no temporary file left behind


@pytest.mark.parametrize(
    ("value", "mm", "rad", "deg"),
    [
        (3.01e-4, "0.301 mm", "3.01e-04 rad", "0.0172°"),
        (0.0, "0.00 mm", "0.00e+00 rad", "0.00°"),
        (math.pi, "3.14e+03 mm", "3.14e+00 rad", "180°"),
        (0.2508, "251 mm", "2.51e-01 rad", "14.4°"),
    ],
)
def test_number_formats(value, mm, rad, deg):
    assert (format_mm(value), format_rad(value), format_deg(value)) == (mm, rad, deg)


def test_the_other_outputs_number_formats():
    # One rule (format_pair): the human unit first, the SI value in parentheses.
    assert format_pair("251 mm", "2.51e-01 m") == "251 mm (2.51e-01 m)"
    # Terminal table: small errors in the base unit only, larger ones in mm / ° then SI.
    assert format_length_console(3.01e-4) == "0.301 mm (0.000301 m)"
    assert format_length_console(2e-9) == "2e-09 m"
    assert format_angle_console(math.pi) == "180.000° (3.14 rad)"
    assert format_length_console(None) == format_angle_console(None) == "-"
    # Markdown summary: both units, missing as an en dash.
    assert format_length_summary(3.01e-4) == "0.301 mm (3.01e-04 m)"
    assert format_angle_summary(math.pi) == "180° (3.14e+00 rad)"
    assert format_length_summary(None) == format_angle_summary(None) == "–"
    # Table constants, fixed-point matrix entries (no "-0"), benchmark µs.
    assert (format_constant(0.089159), format_constant(-0.0), format_constant(90.0)) == (
        "0.089159",
        "0",
        "90",
    )
    assert (format_fixed(-1e-12, 9), format_fixed(-0.5, 3)) == ("0.000000000", "-0.500")
    assert (format_microseconds(12.345), format_microseconds(0.001234)) == ("12.3", "0.0012")


def test_importing_the_report_modules_loads_no_heavy_library():
    code = (
        "import sys, fkcheck.report.html, fkcheck.report.page, fkcheck.report.plots, "
        "fkcheck.report.markdown, fkcheck.report.diagnosis, fkcheck.cli.check; "
        "print(sorted(m for m in ('matplotlib', 'jinja2', 'scipy', 'pinocchio', "
        "'roboticstoolbox') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
