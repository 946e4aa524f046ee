"""The console of ``fkcheck check``: text from input stays literal, lines stay whole in a log,
and on GitHub Actions the failures become annotations at the model file's line."""

from __future__ import annotations

import itertools
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from fkcheck._version import __version__
from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths

pytest.importorskip("pinocchio")


@pytest.fixture(autouse=True)
def _a_plain_log(monkeypatch):
    """Stdout is a pipe, as in CI; no CI variables leak in from the machine."""
    for name in ("FORCE_COLOR", "COLUMNS", "GITHUB_ACTIONS", "GITHUB_STEP_SUMMARY"):
        monkeypatch.delenv(name, raising=False)


def _model(tmp_path: Path, name: str, old: str = "", new: str = "", after: str = "") -> Path:
    """ur5.toml renamed (and with ``old`` → ``new`` once, after ``after``), beside its URDF."""
    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    text = text.replace('name = "ur5"', f"name = {name!r}".replace("'", '"'), 1)
    if old:
        start = text.index(after) if after else 0
        text = text[:start] + text[start:].replace(old, new, 1)
    path = tmp_path / "robots" / "arm.toml"
    path.parent.mkdir(exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def test_square_brackets_in_skip_reasons_and_names_print_literally(tmp_path, capsys):
    model = bundled_model_paths()["planar2"]
    assert main(["check", str(model), "--samples", "2", "--against", "rtb-dh,pinocchio-urdf"]) == 0
    out = capsys.readouterr().out
    assert "model has no [urdf]" in out
    path = _model(tmp_path, "arm [bold]x[/bold] [/]")
    assert main(["check", str(path), "--samples", "2", "--against", "rtb-dh"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("fkcheck arm [bold]x[/bold] [/]: base → tool0, 2 sobol samples")
    assert "\n83 configurations compared\n" in out


def test_the_header_names_what_runs_and_keeps_brackets(tmp_path):
    from argparse import Namespace

    from fkcheck.backends.registry import make_backend
    from fkcheck.cli.check_output import header
    from fkcheck.model.read import load_model

    model = load_model(_model(tmp_path, "arm [red]x[/]"))
    args = Namespace(frame_from=None, frame_to=None, tol_pos=None, tol_rot=2e-6,
                     samples=200000, sampler="sobol", seed=3)  # fmt: skip
    text = header(model, [make_backend("rtb-dh"), make_backend("pinocchio-urdf")], args)
    from rich.console import Console

    console = Console(width=400, record=True, color_system=None)
    console.print(text)
    assert console.export_text() == (
        "fkcheck arm [red]x[/]: base → tool0, 200000 sobol samples (seed 3), tolerance "
        f"1e-06 m / 2e-06 rad, against rtb-dh, pinocchio-urdf; fkcheck {__version__}\n"
    )


def test_no_line_wraps_in_a_log(tmp_path, capsys):
    name = "a-model-name-long-enough-to-push-the-description-past-the-width-of-a-ci-log"
    path = _model(tmp_path, name)
    argv = ["check", str(path), "--samples", "2", "--tol-pos", "0.000123456",
            "--against", "rtb-dh"]  # fmt: skip
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    # The header, flushed before the check runs, is the log's first line.
    assert lines[0] == (
        f"fkcheck {name}: base → tool0, 2 sobol samples (seed 0), "
        f"tolerance 0.000123456 m / 1e-06 rad, against rtb-dh; fkcheck {__version__}"
    )
    assert lines[1] == "83 configurations compared"
    assert len(lines[0]) > 140  # longer than the log's width, and whole
    table_not_checked = next(x for x in lines if "table NOT CHECKED" in x)
    assert table_not_checked.endswith("agreement proves the arithmetic, not the numbers")


def test_on_github_actions_a_failure_is_annotated_at_the_parameter_line(
    tmp_path, capsys, monkeypatch
):
    path = _model(tmp_path, "arm", "alpha = -90", "alpha = 90", after='name = "wrist_2"')
    line = 1 + path.read_text(encoding="utf-8").splitlines().index("alpha = 90", 40)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("GITHUB_ACTIONS", "true")
    junit = tmp_path / "j.xml"
    argv = ["check", "robots/arm.toml", "--samples", "8", "--against",
            "rtb-dh,pinocchio-urdf", "--junit", str(junit)]  # fmt: skip
    assert main(argv) == 1
    out = capsys.readouterr().out
    annotations = [x for x in out.splitlines() if x.startswith("::error ")]
    assert annotations == [
        f"::error file=robots/arm.toml,line={line},title=fkcheck arm%3A pinocchio-urdf disagrees "
        "with the in-house core::" + annotations[0].split("::", 2)[2]
    ]
    assert annotations[0].endswith(
        "; diagnosis: α5 (wrist_2) has the wrong sign: 90° here, the opposite matches"
    )
    failure = next(
        c.find("failure") for c in ET.parse(junit).iter("testcase")
        if c.get("name", "").startswith("pinocchio-urdf")
    )  # fmt: skip
    assert "diagnosis: α5 (wrist_2) has the wrong sign" in (failure.text or "")


def test_without_github_actions_there_is_no_annotation(tmp_path, capsys):
    path = _model(tmp_path, "arm", "alpha = -90", "alpha = 90", after='name = "wrist_2"')
    argv = ["check", str(path), "--samples", "4", "--against", "pinocchio-urdf", "--no-diagnose"]
    assert main(argv) == 1
    assert "::error" not in capsys.readouterr().out


#: How the Pinocchio backends compute a Jacobian (the ``how`` of ``check --jacobian``).
PINOCCHIO_JACOBIAN = "computeFrameJacobian (LOCAL_WORLD_ALIGNED | LOCAL | WORLD, loop)"


def test_a_wide_terminal_keeps_the_jacobian_method_in_its_table(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "160")
    argv = ["check", str(_model(tmp_path, "arm")), "--samples", "5", "--jacobian",
            "--against", "pinocchio-dh"]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert re.search(r"┃ how +┃", out), out
    assert re.search(rf"│ {re.escape(PINOCCHIO_JACOBIAN)} +│", out), out
    assert "how: " not in out


@pytest.mark.parametrize("wrong", [False, True])
def test_at_80_columns_no_number_breaks_across_lines(tmp_path, capsys, monkeypatch, wrong):
    # rich wrapped inside numbers at 80 columns: `5.6e-` on one line, `17 m` on the next.
    monkeypatch.setenv("COLUMNS", "80")
    path = (
        _model(tmp_path, "arm", "alpha = 90\n", "alpha = -90\n", after="wrist_1")
        if wrong
        else (_model(tmp_path, "arm"))
    )
    argv = ["check", str(path), "--samples", "5", "--jacobian",
            "--against", "pinocchio-dh,pinocchio-urdf,mujoco-urdf"]  # fmt: skip
    assert main(argv) == int(wrong)
    out = capsys.readouterr().out
    table = [line for line in out.splitlines() if line[:1] in "┏┃┡│└"]
    assert table
    assert max(len(line) for line in table) <= 80
    rows = [[cell.strip() for cell in line[1:-1].split("│")] for line in table if line[0] == "│"]
    # A number broken across lines: a cell ending in a digit, `.` or `e-`, the cell
    # below it in the same column going on with a digit, `e` or `-`.
    broken = [
        (above, below)
        for row, nxt in itertools.pairwise(rows)
        for above, below in zip(row, nxt, strict=False)
        if re.search(r"[\d.e-]$", above) and re.match(r"[\de-]", below)
    ]
    assert not broken, out
    assert re.search(r"│ \d\.\d\d s │", out), out  # whole numbers, with their units
    # The Jacobian table's text column would break its words (`computeFram` /
    # `eJacobian`): it goes, and each backend's method is a whole line below the table.
    assert (
        "how: pinocchio-dh: computeFrameJacobian (LOCAL_WORLD_ALIGNED | LOCAL | WORLD, loop)\n"
        in out
    )
    assert "     mujoco-urdf: mj_kinematics + mj_comPos + mj_jacBody at the body (loop)\n" in out
    assert "┃ how" not in out
    if wrong:  # the wrong sign's 251 mm and 180°, each number whole on its line
        # The human unit first, the SI value in parentheses (as every output).
        both = r"│ 250\.854 mm +│ 180\.000° +│.*\n.*│ \(0\.251 m\) +│ \(3\.14 rad\)"
        assert re.search(both, out), out
    else:
        assert re.search(r"│ \d(\.\d+)?e-\d\d m +│ \d\.\de-\d\d rad +│", out), out
