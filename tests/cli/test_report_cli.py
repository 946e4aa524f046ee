"""``fkcheck check --html/--summary/--all`` and the main job, with real backends."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from fkcheck import load_model
from fkcheck.cli._console import PIPE_WIDTH
from fkcheck.cli.main import MAIN_JOB, main
from fkcheck.model.options import DEFAULT_SAMPLES
from fkcheck.model.read import bundled_model_paths, bundled_models_dir
from fkcheck.report.markdown import escape_markdown
from tests.report_cases import page_numbers

UR5 = Path(load_model("ur5").path or "")
DH_BACKENDS = "rtb-dh,pinocchio-dh"
URDF_BACKENDS = "pinocchio-urdf,yourdfpy-urdf"


@pytest.fixture(autouse=True)
def _no_ci_summary(monkeypatch):
    """Never append to a real CI job summary from a test."""
    monkeypatch.delenv("GITHUB_STEP_SUMMARY", raising=False)


def ur5_variant(tmp_path: Path, old: str, new: str, after: str = "", name: str = "") -> Path:
    """The bundled UR5 file with one value changed (the first match after ``after``)."""
    text = UR5.read_text(encoding="utf-8")
    at = text.index(old, text.index(after) if after else 0)
    text = text[:at] + new + text[at + len(old) :]
    if name:
        text = text.replace('name = "ur5"', f'name = "{name}"', 1)
    path = tmp_path / f"{name or 'ur5_variant'}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def model_file_fact(page: str) -> str:
    """The report's ``model file`` fact, as the page shows it."""
    found = re.search(r"<dt>model file</dt>\s*<dd><span[^>]*>([^<]*)</span></dd>", page)
    assert found, page
    return found[1]


def first_screen(page: str) -> str:
    """The verdict header: what a person sees before scrolling."""
    return page[page.index('id="verdict"') : page.index('id="summary"')]


def test_html_summary_and_step_summary_are_written(tmp_path, monkeypatch, capsys):
    step = tmp_path / "step_summary.md"
    step.write_text("earlier step\n", encoding="utf-8")
    monkeypatch.setenv("GITHUB_STEP_SUMMARY", str(step))
    html, summary, js = tmp_path / "r.html", tmp_path / "s.md", tmp_path / "r.json"
    argv = ["check", "ur5", "--samples", "16", "--against", DH_BACKENDS, "--html", str(html),
            "--summary", str(summary), "--json", str(js)]  # fmt: skip
    assert main(argv) == 0
    page = html.read_text(encoding="utf-8")
    doc = json.loads(js.read_text(encoding="utf-8"))
    found = page_numbers(page)
    assert found.verdict == doc["verdict"] == "pass"
    assert found.status == {b["name"]: b["status"] for b in doc["backends"]}
    assert "fkcheck check ur5 --samples 16 --against rtb-dh,pinocchio-dh" in page
    text = summary.read_text(encoding="utf-8")
    # rtb-dh and pinocchio-dh only: the table was not checked, and the heading says so.
    assert text.startswith("## fkcheck ur5: ❔ PASS (implementation only)\n")
    assert "| rtb-dh | ✅ pass |" in text
    assert step.read_text(encoding="utf-8") == "earlier step\n" + text + "\n"
    # The bundled model by its spec, never its place in site-packages or the checkout.
    root = str(bundled_models_dir().resolve())
    assert model_file_fact(page) == "fkcheck:ur5.toml"
    assert '<code data-volatile="path">fkcheck:ur5.toml</code>' in page
    for output in (page, text, capsys.readouterr().out, js.read_text(encoding="utf-8")):
        assert root not in output


def test_a_model_under_the_current_directory_is_shown_relative_to_it(tmp_path, monkeypatch):
    (tmp_path / "robots").mkdir()
    model = ur5_variant(tmp_path / "robots", "d = 0.089159", "d = 0.089159", name="arm")
    monkeypatch.chdir(tmp_path)
    html = tmp_path / "r.html"
    argv = ["check", str(model), "--samples", "4", "--against", "rtb-dh", "--html", str(html)]
    assert main(argv) == 0
    page = html.read_text(encoding="utf-8")
    assert model_file_fact(page) == "robots/arm.toml"
    assert '<code data-volatile="path">robots/arm.toml</code>' in page  # the model section
    assert page.count(str(tmp_path)) == 2  # only in the command line, as it was typed


def test_older_d1_report_says_fail_names_backends_and_shows_0_3_mm(tmp_path):
    model = ur5_variant(tmp_path, "d = 0.089159", "d = 0.08946", name="ur5-d1")
    html, js = tmp_path / "d1.html", tmp_path / "d1.json"
    argv = ["check", str(model), "--samples", "64", "--against", f"{DH_BACKENDS},{URDF_BACKENDS}",
            "--html", str(html), "--json", str(js)]  # fmt: skip
    assert main(argv) == 1
    page = html.read_text(encoding="utf-8")
    head = first_screen(page)
    assert 'data-verdict="fail">FAIL<' in head
    # The sentence blames what the headline blames: the table, not the in-house core.
    assert (
        "2 of 4 backends that ran disagree with the table: pinocchio-urdf, yourdfpy-urdf; "
        "2 other implementations of the table agree with the in-house core: rtb-dh, pinocchio-dh"
    ) in head
    assert "disagree with the in-house core" not in head
    # The two URDF readers' identical errors: one bullet naming both.
    assert "pinocchio-urdf, yourdfpy-urdf: max position error 0.301 mm (3.01e-04 m)" in head
    # The table's joint axes against the URDF: joint 2's axis sits Δd1 = 0.301 mm off.
    assert "the DH table parts from the URDF at DH frame 1 (after joint 1, shoulder_pan)" in head
    # A constant error: every configuration is off by the same 0.301 mm, whatever the joints.
    doc = json.loads(js.read_text(encoding="utf-8"))
    urdf = next(b for b in doc["backends"] if b["name"] == "pinocchio-urdf")
    assert urdf["median_position_error_m"] == pytest.approx(urdf["max_position_error_m"], rel=1e-6)
    assert "A flat band across every panel is a constant error" in page


def test_flipped_alpha_report_names_the_first_frame_that_differs(tmp_path):
    model = ur5_variant(tmp_path, "alpha = 90", "alpha = -90", after='name = "wrist_1"')
    html = tmp_path / "alpha.html"
    argv = ["check", str(model), "--samples", "16", "--against", URDF_BACKENDS,
            "--html", str(html)]  # fmt: skip
    assert main(argv) == 1
    page = html.read_text(encoding="utf-8")
    assert "the DH table parts from the URDF at DH frame 4 (after joint 4, wrist_1)" in (
        first_screen(page)
    )
    assert re.search(
        r"The DH table parts from the URDF at DH frame 4 \(after joint 4, wrist_1\): the axis of "
        r"joint 5 \(wrist_2, URDF wrist_2_joint\) is [0-9.e-]+ mm off and turned 180° from the "
        r"URDF&#39;s; the axes of joints 1–4 agree\. Look at row 4 of the DH table\.",
        page,
    )


@pytest.mark.slow  # every bundled model's check and reports: `nox -s slow` (and crossval)
def test_all_writes_every_model_and_the_index(tmp_path, capsys):
    out = tmp_path / "reports"
    summary = tmp_path / "all.md"
    argv = ["check", "--all", "--samples", "4", "--against", "pinocchio-dh",
            "--out-dir", str(out), "--summary", str(summary)]  # fmt: skip
    assert main(argv) == 0
    names = sorted(bundled_model_paths())
    expected = {"index.html"} | {f"{n}{ext}" for n in names
                                 for ext in (".html", ".json", ".junit.xml")}  # fmt: skip
    assert {p.name for p in out.iterdir()} == expected
    index = (out / "index.html").read_text(encoding="utf-8")
    for n in names:
        assert f'<a href="{n}.html"><strong>{n}</strong></a>' in index
        doc = json.loads((out / f"{n}.json").read_text(encoding="utf-8"))
        assert doc["verdict"] == "pass"
        assert f"fkcheck check {n} --samples 4 --seed 0" in (out / f"{n}.html").read_text()
    # pinocchio-dh alone checks the implementation only: no model's table is verified.
    assert (
        f"{len(names)} models checked: {len(names)} pass; table verified independently "
        f"for 0 of {len(names)}." in index
    )
    assert index.count('data-table-evidence="not-checked"') == len(names)
    assert f'<small id="verdict-badge-note">table verified for 0 of {len(names)}</small>' in index
    text = summary.read_text(encoding="utf-8")
    assert text.startswith(f"## fkcheck: {len(names)} models, ✅ PASS\n")
    # A row per model, a column per backend: pinocchio-dh passes, the table is not checked.
    assert "| model | verdict | table verified | pinocchio-dh |" in text
    rows = [f"| {escape_markdown(n)} | ✅ pass | – | ✔ |" for n in names]  # baxter\_left
    assert sum(row in text for row in rows) == len(names)
    assert f"{len(names)} of {len(names)} models pass; reports in {out}/" in capsys.readouterr().out


@pytest.mark.slow  # every bundled model's check, diagnosis and reports: `nox -s slow`
def test_all_fails_when_one_model_disagrees(tmp_path, monkeypatch):
    # One bundled table 2 cm off its URDF (a tolerance under the round-off, which made
    # every model fail here, is refused now: issue 31).
    pytest.importorskip("pinocchio")
    wrong = tmp_path / "wrong.toml"
    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    wrong.write_text(text.replace("d = 0.089159", "d = 0.109159", 1), encoding="utf-8")
    bundled = {"ur5": bundled_model_paths()["ur5"], "wrong": wrong}
    monkeypatch.setattr("fkcheck.model.read.bundled_model_paths", lambda: bundled)
    out = tmp_path / "reports"
    argv = ["check", "--all", "--samples", "2", "--against", "pinocchio-urdf",
            "--out-dir", str(out)]  # fmt: skip
    assert main(argv) == 1
    assert "FAIL" in (out / "index.html").read_text(encoding="utf-8")


def test_check_help_names_every_kind_of_backend(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "400")  # argparse wraps at hyphens otherwise
    assert main(["check", "--help"]) == 0
    out = capsys.readouterr().out
    for name in ("rtb-model:NAME", "poses:FILE.csv", "cmd:PROGRAM", "module:function"):
        assert name in out


@pytest.mark.parametrize(("columns", "width"), [(None, PIPE_WIDTH), ("80", 80)])
def test_terminal_table_in_a_ci_log_keeps_backend_names_whole(columns, width, capsys, monkeypatch):
    """Stdout is a pipe (a CI log): the table is PIPE_WIDTH wide, or $COLUMNS; names never wrap."""
    monkeypatch.delenv("FORCE_COLOR", raising=False)
    if columns is None:
        monkeypatch.delenv("COLUMNS", raising=False)
    else:
        monkeypatch.setenv("COLUMNS", columns)
    assert main(["check", "ur5", "--samples", "2", "--against", URDF_BACKENDS]) == 0
    lines = capsys.readouterr().out.splitlines()
    # The table keeps the width; lines of text never wrap in a log (see test_cli_console).
    widest = max(len(line) for line in lines if line[:1] in "┏┃┡│└")
    assert widest <= width
    if columns is None:  # rich's own fallback would be 80 columns
        assert widest > 80
    for backend in URDF_BACKENDS.split(","):
        assert [line for line in lines if line.startswith(f"│ {backend} ")], backend


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["check", "--all", "ur5"], r"--all checks every bundled model: drop MODEL \('ur5'\)"),
        (["check"], r"give a MODEL \(e\.g\. ur5\) or --all"),
        (["check", "--all", "--json", "x.json"], r"--json does not go with --all"),
        (["check", "--all", "--from", "base"], r"--from does not go with --all"),
        (["check", "ur5", "--out-dir", "x", "--json", "y"], r"--json does not go with --out-dir"),
        (["check", "ur5", "ur3", "--html", "y.html"], r"--html writes one model's file: with "),
    ],
)
def test_bad_combinations_are_bad_input(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert re.search(message, err), err
    assert err.count("\n") == 1


def test_main_job_writes_the_ur5_report_says_where_and_ignores_the_project(
    tmp_path, monkeypatch, capsys
):
    assert MAIN_JOB == (
        "check", "ur5", "--isolated", "--json", "reports/ur5.json", "--html", "reports/ur5.html",
    )  # fmt: skip
    # Inside a project whose [tool.fkcheck] would change the check (and name no UR5):
    # plain fkcheck is the same check everywhere, and says it did not use the table.
    (tmp_path / "pyproject.toml").write_text(
        '[tool.fkcheck]\nmodels = ["robots/"]\nsamples = 7\nagainst = ["rtb-dh"]\n',
        encoding="utf-8",
    )
    monkeypatch.chdir(tmp_path)
    assert main([]) == 0
    page = (tmp_path / "reports" / "ur5.html").read_text(encoding="utf-8")
    doc = json.loads((tmp_path / "reports" / "ur5.json").read_text(encoding="utf-8"))
    assert page_numbers(page).verdict == doc["verdict"] == "pass"
    assert "fkcheck check ur5 --isolated --json reports/ur5.json --html reports/ur5.html" in page
    assert doc["samples"] == DEFAULT_SAMPLES
    assert len(doc["backends"]) > 2
    last = capsys.readouterr().out.rstrip("\n").splitlines()[-1]
    reports = tmp_path.resolve() / "reports"
    assert last == (
        f"fkcheck: wrote {reports / 'ur5.json'}, {reports / 'ur5.html'} (plain fkcheck runs: "
        "fkcheck check ur5 --isolated --json reports/ur5.json --html reports/ur5.html); the "
        "[tool.fkcheck] of pyproject.toml is not used: fkcheck check checks its models with "
        "its settings"
    )
