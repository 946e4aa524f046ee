"""The report opened in a real headless browser (Debian's chromium), as a person would.

Checks that the page loads without a console message (a blocked resource, a
Content-Security-Policy violation or a script error would each log one), that
the verdict and every number the browser shows equal the JSON, and saves
screenshots under ``reports/screenshots/`` (git-ignored) for a person to look at.
Skipped, with the reason, where no chromium is installed; ``.ci/run`` installs it.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import pytest

from fkcheck.cli.main import main
from fkcheck.io.format import format_deg, format_mm, format_rad
from fkcheck.model.types import UrdfSpec
from fkcheck.model.write import model_to_toml
from fkcheck.urdf.locate import example_robot_data_dir
from tests.cli.test_report_cli import URDF_BACKENDS, ur5_variant
from tests.helpers import ur5_ros1
from tests.paths import REPO_ROOT
from tests.report_cases import page_numbers

SCREENSHOTS = REPO_ROOT / "reports" / "screenshots"
BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")

pytestmark = pytest.mark.skipif(
    BROWSER is None,
    reason="no chromium on PATH (apt-get install chromium; .ci/run installs it)",
)


@pytest.fixture(autouse=True)
def _no_ci_summary(monkeypatch):
    monkeypatch.delenv("GITHUB_STEP_SUMMARY", raising=False)


def chromium(tmp_path: Path, url: str, *args: str) -> subprocess.CompletedProcess[str]:
    """Run headless chromium on a page with a throw-away profile; fail on a non-zero exit."""
    assert BROWSER is not None
    command = [
        BROWSER, "--headless", "--no-sandbox", "--disable-gpu",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-first-run", "--hide-scrollbars", f"--user-data-dir={tmp_path / 'profile'}",
        "--enable-logging=stderr", "--v=0", *args, url,
    ]  # fmt: skip
    done = subprocess.run(command, capture_output=True, text=True, timeout=180, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    return done


def console_messages(stderr: str) -> list[str]:
    """Lines chromium logs for the page's console (errors, CSP violations, blocked loads)."""
    return [line for line in stderr.splitlines() if ":CONSOLE" in line]


@pytest.fixture(scope="module")
def d1_report(tmp_path_factory):
    """The UR5 with the older d1 = 0.08946 checked against the URDF: a FAIL report + JSON."""
    tmp = tmp_path_factory.mktemp("d1")
    model = ur5_variant(tmp, "d = 0.089159", "d = 0.08946", name="ur5-d1")
    html, js = tmp / "ur5-d1.html", tmp / "ur5-d1.json"
    argv = ["check", str(model), "--samples", "256", "--against", f"rtb-dh,{URDF_BACKENDS}",
            "--html", str(html), "--json", str(js)]  # fmt: skip
    assert main(argv) == 1
    return html, json.loads(js.read_text(encoding="utf-8"))


def test_browser_shows_the_json_verdict_and_numbers(d1_report, tmp_path):
    html, doc = d1_report
    done = chromium(tmp_path, html.as_uri(), "--dump-dom")
    assert console_messages(done.stderr) == []
    dom = done.stdout
    found = page_numbers(dom)
    assert found.verdict == doc["verdict"] == "fail"
    assert found.status == {b["name"]: b["status"] for b in doc["backends"]}
    for b in doc["backends"]:
        for key in ("max_position_error_m", "p99_position_error_m", "median_position_error_m",
                    "max_rotation_error_rad", "p99_rotation_error_rad",
                    "median_rotation_error_rad"):  # fmt: skip
            assert float(found.values[(b["name"], key)]) == b[key], (b["name"], key)
    # What a person reads: the numbers as shown, formatted from the JSON's values.
    for b in doc["backends"]:
        pos, rot = b["max_position_error_m"], b["max_rotation_error_rad"]
        assert f">{format_mm(pos)}<" in dom
        assert f">{format_rad(rot)}<" in dom
        assert f">{format_deg(rot)}<" in dom
    # The URDF readers' identical errors share one bullet, naming each of them.
    assert re.search(r"pinocchio-urdf(, [a-z-]+)*: max position error 0\.301 mm", dom), dom
    # The diagnosis, as the browser shows it: the one number that differs, and by how much.
    assert "d1 (shoulder_pan) = 0.08946 here, 0.089159 would match, Δ = -0.301 mm" in dom


def test_browser_screenshots(d1_report, tmp_path):
    html, _ = d1_report
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    for name, size in (("ur5-d1-first-screen.png", "1280,900"),
                       ("ur5-d1-full.png", "1280,6000")):  # fmt: skip
        target = SCREENSHOTS / name
        target.unlink(missing_ok=True)
        done = chromium(tmp_path, html.as_uri(), f"--screenshot={target}", f"--window-size={size}")
        assert console_messages(done.stderr) == []
        data = target.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
        assert (width, height) == tuple(int(v) for v in size.split(","))
        assert len(data) > 20_000  # a rendered page, not a blank one


def test_browser_reports_a_console_message_when_there_is_one(tmp_path):
    """The console check works: a page that loads a remote image logs a CSP violation."""
    page = tmp_path / "bad.html"
    page.write_text(
        "<!DOCTYPE html><html><head><meta http-equiv='Content-Security-Policy' "
        "content=\"default-src 'none'\"></head><body><img src='https://example.invalid/x.png'>"
        "</body></html>",
        encoding="utf-8",
    )
    done = chromium(tmp_path, page.as_uri(), "--dump-dom")
    messages = console_messages(done.stderr)
    assert len(messages) == 1
    assert "violates the following Content Security Policy directive" in messages[0]


def test_browser_shows_where_a_flipped_alpha_parts(tmp_path):
    model = ur5_variant(tmp_path, "alpha = 90", "alpha = -90", after='name = "wrist_1"',
                        name="ur5-alpha4-flipped")  # fmt: skip
    html = tmp_path / "ur5-alpha4-flipped.html"
    argv = ["check", str(model), "--samples", "64", "--against", f"rtb-dh,{URDF_BACKENDS}",
            "--html", str(html)]  # fmt: skip
    assert main(argv) == 1
    done = chromium(tmp_path, html.as_uri(), "--dump-dom")
    assert console_messages(done.stderr) == []
    head = done.stdout[done.stdout.index('id="verdict"') : done.stdout.index('id="summary"')]
    assert "the DH table parts from the URDF at DH frame 4 (after joint 4, wrist_1)" in head
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    target = SCREENSHOTS / "ur5-alpha4-flipped-first-screen.png"
    target.unlink(missing_ok=True)
    chromium(tmp_path, html.as_uri(), f"--screenshot={target}", "--window-size=1280,900")
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


#: Measures, once the page has loaded, how far each table runs past the box it sits in
#: and how far the page scrolls sideways; the result goes into ``<body data-overflow>``.
_MEASURE = """<script>
addEventListener('load', () => {
  const out = [];
  for (const table of document.querySelectorAll('table')) {
    const box = table.parentElement.getBoundingClientRect();
    const past = table.getBoundingClientRect().right - box.right;
    if (past > 0.5) {
      const where = table.closest('section');
      out.push((where ? where.id : '?') + ':' + table.rows[0].textContent.trim().slice(0, 30)
               + ':' + Math.round(past) + 'px');
    }
  }
  const sideways = document.documentElement.scrollWidth - document.documentElement.clientWidth;
  if (sideways > 0) out.push('page:' + sideways + 'px');
  document.body.setAttribute('data-overflow', out.join(' | ') || 'none');
});
</script>"""


def overflow_at(tmp_path: Path, page: Path, width: int) -> str:
    """What runs past its box when chromium lays ``page`` out ``width`` pixels wide.

    The copy measured has the page's Content-Security-Policy taken out, so that the
    measuring script may run; the layout is the page's own.
    """
    text = page.read_text(encoding="utf-8")
    text, n = re.subn(r'<meta http-equiv="Content-Security-Policy"[^>]*>', "", text)
    assert n == 1
    measured = tmp_path / f"measured-{width}.html"
    measured.write_text(text.replace("</body>", _MEASURE + "</body>"), encoding="utf-8")
    done = chromium(tmp_path, measured.as_uri(), "--dump-dom", f"--window-size={width},900",
                    "--virtual-time-budget=5000")  # fmt: skip
    found = re.search(r'data-overflow="([^"]*)"', done.stdout)
    assert found, done.stdout[-2000:]
    return found[1]


def test_no_table_runs_past_its_column_at_1280_px(tmp_path):
    # A URDF of one's own sits deep in a workspace: its path, unbroken, pushed the frames
    # table 368 px past its half of the page, and the 10-column DH table ran over Aᵢ.
    deep = tmp_path / "ws" / "src" / "fanuc_lrmate200id_support_and_other_packages" / "urdf"
    deep.mkdir(parents=True)
    shutil.copy(example_robot_data_dir() / "ur_description" / "urdf" / "ur5_robot.urdf", deep)
    model = ur5_ros1()
    joints = list(model.joints)
    joints[0] = replace(joints[0], d=0.08946)  # a failing report: every section shown
    model = replace(model, joints=tuple(joints),
                    urdf=UrdfSpec(str((deep / "ur5_robot.urdf").relative_to(tmp_path)),
                                  model.urdf.joints))  # fmt: skip
    path = tmp_path / "ur5-own-urdf.toml"
    path.write_text(model_to_toml(model), encoding="utf-8")
    html = tmp_path / "ur5-own-urdf.html"
    argv = ["check", str(path), "--samples", "32", "--against", f"rtb-dh,{URDF_BACKENDS}",
            "--html", str(html)]  # fmt: skip
    assert main(argv) == 1
    assert "fanuc_lrmate200id_support_and_other_packages/urdf/ur5_robot.urdf" in html.read_text(
        encoding="utf-8"
    )
    for width in (1280, 1024):
        assert overflow_at(tmp_path, html, width) == "none", width


def test_the_overflow_measure_sees_a_table_that_runs_past_its_column(tmp_path):
    page = tmp_path / "wide.html"
    page.write_text(
        '<!DOCTYPE html><html><head><meta http-equiv="Content-Security-Policy" '
        'content="default-src \'none\'"></head><body><section id="s" style="width:300px">'
        f"<table><tr><td>{'x' * 200}</td></tr></table></section></body></html>",
        encoding="utf-8",
    )
    assert re.fullmatch(r"s:x+:\d+px \| page:\d+px", overflow_at(tmp_path, page, 1280))
