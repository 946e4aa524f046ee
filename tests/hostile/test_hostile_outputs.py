"""Hostile and odd input against fkcheck's outputs (issue 15): paths, JSON, text per format.

Families, each a parametrised test:

* output paths — an output that is an input, two outputs on one path, a device,
  a FIFO, a directory, ``/proc``, ``/sys``, names too long, ``--out-dir`` a file,
  a parent that is a file, for every command that writes files: exit 2, one line,
  nothing in the run's directory changed, and the check never started (a plugin
  that would leave a marker file is among the backends);
* ``$GITHUB_STEP_SUMMARY`` — a FIFO, a missing directory, a directory, an input
  or an output of the run: a warning line, the check's own exit code, no hang;
* an interrupted run says truly which files it wrote;
* strict JSON — non-finite numbers are ``null`` with a reason, in the writer and
  in ``check``'s and ``fk``'s JSON;
* text from input (model, frame and joint names, unknown keys, plugin messages,
  a program's stderr, the error line) in every format: terminal (escape
  sequences and rich markup shown literally, no fake lines), JSON, JUnit XML,
  Markdown, HTML; ``fkcheck urdf`` never writes ill-formed XML;
* standard output on ``/dev/full`` and in ASCII: one line or escaped text, no traceback.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from fkcheck.cli.main import main
from fkcheck.errors import FkcheckError
from fkcheck.io.strict_json import jsonable, strict_json
from fkcheck.io.text import document_text, terminal_text
from fkcheck.model.read import bundled_model_paths, load_model
from fkcheck.model.write import model_to_toml
from fkcheck.urdf.export import model_for_urdf, urdf_from_model
from tests.paths import REPO_ROOT

SRC = REPO_ROOT / "src"
PLANAR2 = bundled_model_paths()["planar2"]

#: Seconds a refused run may take: it must stop before any backend runs.
REFUSE_S = 10.0
#: Seconds a small check (planar2, a few samples, cheap backends) may take.
SMALL_RUN_S = 60.0

#: Hostile text, by what it tries.
HOSTILE = {
    "rich-close-tag": "[/x]",
    "rich-style": "[bold green]pass[/]",
    "osc-window-title": "\x1b]0;pwned\x07",
    "csi-clear-screen": "\x1b[2J\x1b[H",
    "fake-verdict-line": "x\nverdict: pass",
    "nul-backspace-cr": "a\x00b\x08c\rd",
    "c1-csi-del": "\x9b2J\x7f",
    "bidi-override": "\u202eexe.txt",
    "html-and-markdown": "<script>alert(1)</script> | `x` *y*",
}

#: Characters that must never reach a terminal raw (newline is the one allowed).
RAW_CONTROL = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069\u2028\u2029]")
#: Characters that must never reach XML or HTML raw (tab, newline, CR allowed).
RAW_DOCUMENT_CONTROL = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\u202a-\u202e\u2066-\u2069]")

PLUGIN_SOURCE = '''\
"""Test plugin: leaves a marker when called, or raises a message from the environment."""
import os
from pathlib import Path

import numpy as np


def touch(q):
    Path(os.environ["FKCHECK_TEST_MARKER"]).write_text("the check ran", encoding="utf-8")
    return np.tile(np.eye(4), (q.shape[0], 1, 1))


def raises(q):
    raise RuntimeError(Path(os.environ["FKCHECK_TEST_MESSAGE"]).read_bytes().decode("utf-8"))


def overflow(q):
    T = np.tile(np.eye(4), (q.shape[0], 1, 1))
    T[:, :3, 3] = 1e308
    return T
'''


@dataclass(frozen=True)
class Run:
    """What one fkcheck run did."""

    code: int
    out: str
    err: str
    seconds: float


def toml_string(text: str) -> str:
    """A TOML basic string (JSON's escapes are TOML's; TOML wants DEL escaped too)."""
    return json.dumps(text).replace("\x7f", "\\u007f")


def snapshot(root: Path) -> dict[str, tuple[str, int]]:
    """Every file under ``root``: content hash and modification time."""
    found = {}
    for path in sorted(root.rglob("*")):
        if path.is_file() and not path.is_symlink():
            data = path.read_bytes()
            found[str(path.relative_to(root))] = (hashlib.sha256(data).hexdigest(),
                                                  path.stat().st_mtime_ns)  # fmt: skip
    return found


def changed(before: dict[str, tuple[str, int]], after: dict[str, tuple[str, int]]) -> set[str]:
    """Files added, removed or modified."""
    return {k for k in before.keys() | after.keys() if before.get(k) != after.get(k)}


def one_error_line(err: str) -> str:
    """stderr must be exactly one ``fkcheck: error:`` line; return it."""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("fkcheck: error: "), err
    assert "Traceback" not in err
    return lines[0]


@pytest.fixture
def env(tmp_path, monkeypatch):
    """A run directory with the plugin importable and a marker path; no colour, wide tables."""
    plugin_dir = tmp_path / "plugin"
    plugin_dir.mkdir()
    (plugin_dir / "fkcheck_test_plugin.py").write_text(PLUGIN_SOURCE, encoding="utf-8")
    monkeypatch.syspath_prepend(str(plugin_dir))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(SRC), str(plugin_dir)]))
    monkeypatch.setenv("FKCHECK_TEST_MARKER", str(tmp_path / "marker"))
    monkeypatch.setenv("COLUMNS", "1000")
    monkeypatch.delenv("FORCE_COLOR", raising=False)
    monkeypatch.chdir(tmp_path)
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    return run_dir


@pytest.fixture
def keep_sigterm():
    """main() installs a SIGTERM handler; give the test process its own back."""
    previous = signal.getsignal(signal.SIGTERM)
    yield
    signal.signal(signal.SIGTERM, previous)


def run_main(argv: list[str], capsys: pytest.CaptureFixture[str]) -> Run:
    """fkcheck in this process."""
    capsys.readouterr()
    start = time.monotonic()
    code = main([str(a) for a in argv])
    seconds = time.monotonic() - start
    captured = capsys.readouterr()
    return Run(code, captured.out, captured.err, seconds)


def run_subprocess(argv: list[object], timeout: float = SMALL_RUN_S, **kwargs) -> Run:
    """fkcheck in a child process, killed at ``timeout`` (stdout captured unless given)."""
    kwargs.setdefault("stdout", subprocess.PIPE)
    start = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-m", "fkcheck.cli.main", *map(str, argv)],
        stderr=subprocess.PIPE, timeout=timeout, **kwargs,
    )  # fmt: skip
    seconds = time.monotonic() - start
    out = (proc.stdout or b"").decode("utf-8", "backslashreplace")
    return Run(proc.returncode, out, proc.stderr.decode("utf-8", "backslashreplace"), seconds)


def write_models(run_dir: Path) -> dict[str, Path]:
    """The planar2 model, the same model with a URDF, the URDF, a poses CSV, a program."""
    model_file = run_dir / "model.toml"
    shutil.copyfile(PLANAR2, model_file)
    model = load_model(model_file)
    export = urdf_from_model(model)
    urdf = run_dir / "robot.urdf"
    urdf.write_text(export.text, encoding="utf-8")
    mapped = model_for_urdf(model, export, "robot.urdf")
    with_urdf = run_dir / "with_urdf.toml"
    with_urdf.write_text(model_to_toml(mapped), encoding="utf-8")
    poses = run_dir / "poses.csv"
    poses.write_text("q1,q2,x,y,z,qx,qy,qz,qw\n0,0,1.8,0,0,0,0,0,1\n", encoding="utf-8")
    program = run_dir / "fk_program.py"
    program.write_text("import sys\nsys.exit(3)\n", encoding="utf-8")
    return {"model": model_file, "with_urdf": with_urdf, "urdf": urdf, "poses": poses,
            "program": program}  # fmt: skip


# --- output paths: refused before anything runs ------------------------------------------------

LONG_NAME = "n" * 300

#: (id, argv after the command's model, fragment of the one error line).
#: ``{model}`` etc. are replaced by the files of write_models; TOUCH is a backend that
#: leaves a marker file, so a check that started is caught.
CHECK = ["check", "{model}", "--samples", "3", "--against", "fkcheck_test_plugin:touch"]
PATH_CASES = [
    ("json-is-the-model", [*CHECK, "--json", "{model}"], "is the model file of planar2, an input"),
    ("json-is-a-symlink-to-the-model", [*CHECK, "--json", "{link}"], "is the model file"),
    ("html-is-the-models-urdf",
     ["check", "{with_urdf}", "--samples", "3", "--against", "fkcheck_test_plugin:touch",
      "--html", "{urdf}"], "is the URDF of planar2, an input"),
    ("junit-is-the-poses-csv",
     [*CHECK, "--against", "poses:{poses}", "--junit", "{poses}"], "poses:"),
    ("json-is-the-cmd-program",
     [*CHECK, "--against", "cmd:python {program}", "--json", "{program}"], "cmd:python"),
    ("json-is-the-plugin-module", [*CHECK, "--json", "{plugin}"],
     "is a file of backend fkcheck_test_plugin:touch"),
    ("json-and-html-share-a-path", [*CHECK, "--json", "{d}/r.out", "--html", "{d}/r.out"],
     "--html {d}/r.out: is also --json: two outputs cannot share a path"),
    ("summary-and-json-share-a-path-spelled-apart",
     [*CHECK, "--json", "{d}/r.out", "--summary", "{d}/sub/../r.out"], "is also --json"),
    ("json-is-dev-null", [*CHECK, "--json", "/dev/null"], "is a character device"),
    ("json-is-a-fifo", [*CHECK, "--json", "{fifo}"], "is a FIFO"),
    ("json-is-a-directory", [*CHECK, "--json", "{d}"], "is a directory"),
    ("json-parent-is-a-file", [*CHECK, "--json", "{model}/x.json"],
     "{model} is a regular file, not a directory"),
    ("json-is-a-symlink-to-a-fifo", [*CHECK, "--json", "{pipe}"],
     "--json {pipe}: is a symlink to {fifo}, which is a FIFO (named pipe); fkcheck writes only "
     "regular files or new paths"),
    ("json-in-proc", [*CHECK, "--json", "/proc/fk-test.json"], "cannot create a file in /proc"),
    ("json-in-sys", [*CHECK, "--json", "/sys/fk-test.json"], "cannot create a file in /sys"),
    ("json-name-too-long", [*CHECK, "--json", f"{{d}}/{LONG_NAME}.json"], "255 bytes"),
    ("json-directory-name-too-long", [*CHECK, "--json", f"{{d}}/{LONG_NAME}/x.json"], "255 bytes"),
    ("all-out-dir-is-a-file",
     ["check", "--all", "--samples", "1", "--against", "fkcheck_test_plugin:touch",
      "--out-dir", "{model}"], "--out-dir {model}: is a regular file, not a directory"),
    ("all-out-dir-holds-a-directory-named-like-a-report",
     ["check", "--all", "--samples", "1", "--against", "fkcheck_test_plugin:touch",
      "--out-dir", "{d}"], "ur5.json: is a directory"),
    ("all-summary-is-the-index",
     ["check", "--all", "--samples", "1", "--against", "fkcheck_test_plugin:touch",
      "--out-dir", "{d}/out", "--summary", "{d}/out/index.html"], "is also --out-dir"),
    ("urdf-o-is-the-model", ["urdf", "{model}", "-o", "{model}"], "-o {model}: is the model file"),
    ("urdf-o-is-the-models-own-urdf", ["urdf", "{with_urdf}", "-o", "{urdf}"], "is the URDF of"),
    ("urdf-o-and-write-model-share",
     ["urdf", "{model}", "-o", "{d}/x.urdf", "--write-model", "{d}/x.urdf"], "is also -o"),
    ("urdf-o-is-dev-null", ["urdf", "{model}", "-o", "/dev/null"], "is a character device"),
    ("convert-o-is-the-model",
     ["convert", "{model}", "--to", "modified", "--samples", "3", "-o", "{model}"],
     "is the model file"),
    ("table-from-o-is-the-urdf",
     ["table-from", "{urdf}", "--base", "world", "--tip", "tcp", "-o", "{urdf}"], "is the URDF"),
    ("bench-json-is-the-model",
     ["bench", "{model}", "--n", "1000000", "--json", "{model}"], "is the model file"),
    ("diagnose-json-is-the-poses-csv",
     ["diagnose", "{model}", "--against", "poses:{poses}", "--json", "{poses}"], "poses:"),
]  # fmt: skip


@pytest.mark.parametrize(("argv", "fragment"), [pytest.param(a, f, id=i) for i, a, f in PATH_CASES])
def test_a_bad_output_path_is_one_line_exit_2_before_anything_runs(env, capsys, argv, fragment):
    files = write_models(env)
    (env / "link.toml").symlink_to(files["model"])
    os.mkfifo(env / "fifo")
    (env / "pipe.json").symlink_to(env / "fifo")
    (env / "ur5.json").mkdir()
    names = {**{k: str(v) for k, v in files.items()}, "d": str(env), "link": str(env / "link.toml"),
             "fifo": str(env / "fifo"), "pipe": str(env / "pipe.json"),
             "plugin": str(env.parent / "plugin" / "fkcheck_test_plugin.py")}  # fmt: skip
    before = snapshot(env.parent)
    run = run_main([a.format(**names) for a in argv], capsys)
    line = one_error_line(run.err)
    assert run.code == 2
    assert fragment.format(**names) in line
    assert changed(before, snapshot(env.parent)) == set()  # nothing written, nothing replaced
    assert not (env.parent / "marker").exists()  # the check never started
    assert run.seconds < REFUSE_S
    assert sorted(p.name for p in env.iterdir()) == sorted(
        [*(p.name for p in files.values()), "link.toml", "fifo", "pipe.json", "ur5.json"]
    )  # no directory created, no temporary or probe file left


def test_a_new_path_in_new_directories_is_written(env, capsys):
    files = write_models(env)
    target = env / "new" / "deeper" / "r.json"
    run = run_main(["check", files["model"], "--samples", "3", "--against", "rtb-dh",
                    "--json", target], capsys)  # fmt: skip
    assert run.code == 0, run.err
    assert json.loads(target.read_text(encoding="utf-8"))["verdict"] == "pass"
    assert [p.name for p in target.parent.iterdir()] == ["r.json"]  # no probe file left


def test_a_symlink_to_a_regular_file_that_is_no_input_is_replaced_not_followed(env, capsys):
    files = write_models(env)
    elsewhere = env / "elsewhere.txt"
    elsewhere.write_text("keep me\n", encoding="utf-8")
    (env / "r.json").symlink_to(elsewhere)
    run = run_main(["check", files["model"], "--samples", "3", "--against", "rtb-dh",
                    "--json", env / "r.json"], capsys)  # fmt: skip
    assert run.code == 0, run.err
    assert elsewhere.read_text(encoding="utf-8") == "keep me\n"
    assert not (env / "r.json").is_symlink()
    assert json.loads((env / "r.json").read_text(encoding="utf-8"))["verdict"] == "pass"


# --- $GITHUB_STEP_SUMMARY: a warning, never a failed check or a hang ---------------------------

STEP_CASES = [
    ("fifo", "{d}/fifo", "is a FIFO (named pipe), not a regular file"),
    ("missing-directory", "{d}/missing/summary.md", "its directory {d}/missing does not exist"),
    ("directory", "{d}", "is a directory, not a regular file"),
    ("dev-null", "/dev/null", "is a character device, not a regular file"),
    ("the-json-output", "{d}/r.json", "is also --json, an output of this run"),
    ("the-model-file", "{model}", "is the model file of planar2, an input of this run"),
]


@pytest.mark.parametrize(
    ("target", "fragment"), [pytest.param(t, f, id=i) for i, t, f in STEP_CASES]
)
def test_a_step_summary_fkcheck_cannot_append_to_is_a_warning(env, target, fragment):
    """Run as a child: a regression here (a FIFO) hangs, and the timeout catches it."""
    files = write_models(env)
    os.mkfifo(env / "fifo")
    names = {"d": str(env), "model": str(files["model"])}
    step = target.format(**names)
    before = snapshot(env)
    argv = ["check", files["model"], "--samples", "3", "--against", "rtb-dh", "--json",
            env / "r.json"]  # fmt: skip
    run = run_subprocess(argv, env={**os.environ, "GITHUB_STEP_SUMMARY": step})
    assert run.code == 0, run.err  # the check's own verdict: pass
    assert run.err.splitlines() == [
        f"fkcheck: warning: $GITHUB_STEP_SUMMARY {step}: {fragment.format(**names)}; the "
        "summary is not appended there"
    ]
    assert "verdict: pass" in run.out
    assert changed(before, snapshot(env)) == {"r.json"}
    assert json.loads((env / "r.json").read_text(encoding="utf-8"))["verdict"] == "pass"
    assert not (env / "missing").exists()
    assert run.seconds < SMALL_RUN_S


def test_a_regular_step_summary_is_appended_to(env, capsys, monkeypatch):
    files = write_models(env)
    step = env / "step.md"
    step.write_text("earlier step\n", encoding="utf-8")
    monkeypatch.setenv("GITHUB_STEP_SUMMARY", str(step))
    run = run_main(["check", files["model"], "--samples", "3", "--against", "rtb-dh"], capsys)
    assert run.code == 0
    assert run.err == ""
    text = step.read_text(encoding="utf-8")
    assert text.startswith("earlier step\n## fkcheck planar2: ❔ PASS (implementation only)\n")


# --- an interrupted run says which files it wrote -----------------------------------------------


def _interrupt_with_sigterm(*args, **kwargs):
    os.kill(os.getpid(), signal.SIGTERM)
    time.sleep(10)  # the handler raises before this ends
    raise AssertionError("SIGTERM was not delivered")


def _interrupt_with_ctrl_c(*args, **kwargs):
    raise KeyboardInterrupt


@pytest.mark.usefixtures("keep_sigterm")
@pytest.mark.parametrize(
    ("module", "function", "interrupt", "code", "words", "written", "not_written"),
    [
        pytest.param("fkcheck.report.html", "write_html", _interrupt_with_sigterm, 143,
                     "terminated (SIGTERM)", ["r.json", "r.xml"], ["r.html"], id="sigterm-in-html"),
        pytest.param("fkcheck.report.junit", "write_junit", _interrupt_with_ctrl_c, 130,
                     "interrupted (Ctrl-C)", ["r.json"], ["r.xml", "r.html"], id="ctrl-c-in-junit"),
        pytest.param("fkcheck.report.json_report", "write_json", _interrupt_with_ctrl_c, 130,
                     "interrupted (Ctrl-C)", [], ["r.json", "r.xml", "r.html"], id="ctrl-c-first"),
    ],
)  # fmt: skip
def test_an_interrupted_run_names_what_it_wrote(
    env, capsys, monkeypatch, module, function, interrupt, code, words, written, not_written
):
    files = write_models(env)
    (env / "r.html").write_text("an older report\n", encoding="utf-8")  # kept, and not "written"
    monkeypatch.setattr(f"{module}.{function}", interrupt)
    argv = ["check", files["model"], "--samples", "3", "--against", "rtb-dh", "--json",
            env / "r.json", "--junit", env / "r.xml", "--html", env / "r.html"]  # fmt: skip
    run = run_main(argv, capsys)
    assert run.code == code
    if written:
        expected = (f"written: {', '.join(str(env / n) for n in written)}; "
                    f"not written: {', '.join(str(env / n) for n in not_written)}")  # fmt: skip
    else:
        expected = "no report written"
    assert run.err.splitlines() == [f"fkcheck: {words}: results incomplete, {expected}"]
    for name in written:
        assert (env / name).stat().st_size > 0
    assert (env / "r.html").read_text(encoding="utf-8") == "an older report\n"
    assert not [p for p in env.iterdir() if p.name.endswith(".tmp")]


# --- strict JSON ---------------------------------------------------------------------------------


def _refuse_constant(name: str) -> None:
    raise ValueError(f"not strict JSON: {name}")


def strict_loads(text: str):
    """json.loads that refuses NaN, Infinity and -Infinity, as jq and JSON.parse do."""
    return json.loads(text, parse_constant=_refuse_constant)


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        pytest.param({"a": float("nan")}, {"a": None, "non_finite": {"a": "NaN"}}, id="nan"),
        pytest.param({"a": [1.0, float("-inf")]},
                     {"a": [1.0, None], "non_finite": {"a[1]": "-Infinity"}}, id="in-a-list"),
        pytest.param({"m": [[0.0, float("inf")]], "ok": 2},
                     {"m": [[0.0, None]], "ok": 2, "non_finite": {"m[0][1]": "Infinity"}},
                     id="in-a-matrix"),
        pytest.param([{"x": float("inf")}, {"x": 1}],
                     [{"x": None, "non_finite": {"x": "Infinity"}}, {"x": 1}], id="records"),
        pytest.param({"outer": {"inner": float("nan")}},
                     {"outer": {"inner": None, "non_finite": {"inner": "NaN"}}},
                     id="the-nearest-object-holds-the-reason"),
        pytest.param({"a": 1.5, "b": "NaN"}, {"a": 1.5, "b": "NaN"}, id="finite-unchanged"),
    ],
)  # fmt: skip
def test_strict_json_writes_null_and_a_reason(value, expected):
    text = strict_json(value, indent=2)
    assert strict_loads(text) == expected
    assert "NaN" not in text.replace('"NaN"', "")
    assert "Infinity" not in text.replace('"Infinity"', "").replace('"-Infinity"', "")


def test_strict_json_writes_numpy_values_as_numbers():
    value = {"a": np.float32(0.5), "b": np.array([1.0, np.inf]), "c": np.int64(3)}
    assert strict_loads(strict_json(value)) == {
        "a": 0.5, "b": [1.0, None], "c": 3, "non_finite": {"b[1]": "Infinity"}
    }  # fmt: skip


def test_strict_json_refuses_to_hide_a_reason_behind_an_existing_member():
    with pytest.raises(ValueError, match="non_finite"):
        jsonable({"x": float("nan"), "non_finite": "mine"})


def test_a_failing_checks_json_is_strict_with_a_reason(env):
    files = write_models(env)
    run = run_subprocess(["check", files["model"], "--samples", "3", "--against",
                          "fkcheck_test_plugin:overflow", "--json", env / "r.json"])  # fmt: skip
    assert run.code == 1, run.err
    doc = strict_loads((env / "r.json").read_text(encoding="utf-8"))
    (backend,) = doc["backends"]
    assert backend["status"] != "pass"
    assert backend["max_position_error_m"] is None
    assert backend["non_finite"]["max_position_error_m"] == "Infinity"
    assert backend["message"]
    assert "Traceback" not in run.err


def test_fk_json_is_strict_when_the_pose_overflows(env):
    """a = 1e308 overflows the pose. Either the model is refused (one line, exit 2) or
    the JSON is strict with the reason: never ``Infinity`` on stdout."""
    text = PLANAR2.read_text(encoding="utf-8").replace("a = 1.0", "a = 1e308").replace(
        "a = 0.8", "a = 1e308")  # fmt: skip
    (env / "big.toml").write_text(text, encoding="utf-8")
    run = run_subprocess(["fk", env / "big.toml", "--q", "0,0", "--json"])
    assert "Traceback" not in run.err
    if run.code == 2:
        one_error_line(run.err)
        assert run.out == ""
        return
    assert run.code == 0, run.err
    doc = strict_loads(run.out)
    assert doc["position"][0] is None
    assert doc["non_finite"]["position[0]"] == "Infinity"
    assert doc["non_finite"]["matrix[0][3]"] == "Infinity"


# --- text from input in every format -------------------------------------------------------------


def hostile_model(run_dir: Path, text: str) -> tuple[Path, str]:
    """planar2 with ``text`` in its name, both joint names and a frame's name."""
    frame = f"f{text}"
    source = PLANAR2.read_text(encoding="utf-8")
    source = source.replace('name = "planar2"', f"name = {toml_string(text)}", 1)
    source = source.replace('name = "theta1"', f"name = {toml_string('j1' + text)}", 1)
    source = source.replace('name = "theta2"', f"name = {toml_string('j2' + text)}", 1)
    source = source.replace("[poses]", f"[frames.{toml_string(frame)}]\ndh = 2\n\n[poses]", 1)
    path = run_dir / "hostile.toml"
    path.write_text(source, encoding="utf-8")
    return path, frame


def assert_terminal_safe(run: Run) -> None:
    for stream in (run.out, run.err):
        assert not RAW_CONTROL.search(stream), repr(stream)
        assert "Traceback" not in stream


def assert_markdown_table_intact(text: str) -> None:
    assert not RAW_CONTROL.search(text)
    rows = [line for line in text.splitlines() if line.startswith("|")]
    assert rows
    for row in rows:  # 5 columns: 6 pipes that are not backslash-escaped
        assert len(re.findall(r"(?<!\\)\|", row)) == 6, row


def assert_documents_safe(run_dir: Path) -> dict:
    """The JSON parses strictly, the JUnit and HTML carry no raw control character."""
    doc = strict_loads((run_dir / "r.json").read_text(encoding="utf-8"))
    junit = (run_dir / "r.xml").read_text(encoding="utf-8")
    assert not RAW_DOCUMENT_CONTROL.search(junit)
    ET.fromstring(junit.encode("utf-8"))
    page = (run_dir / "r.html").read_text(encoding="utf-8")
    assert not RAW_DOCUMENT_CONTROL.search(page)
    assert "<script>alert" not in page
    assert_markdown_table_intact((run_dir / "r.md").read_text(encoding="utf-8"))
    return doc


def report_args(run_dir: Path) -> list[object]:
    return ["--json", run_dir / "r.json", "--junit", run_dir / "r.xml", "--html",
            run_dir / "r.html", "--summary", run_dir / "r.md", "--no-diagnose"]  # fmt: skip


@pytest.mark.parametrize("text", [pytest.param(t, id=i) for i, t in HOSTILE.items()])
def test_hostile_names_are_shown_literally_everywhere(env, capsys, text):
    model, frame = hostile_model(env, text)
    argv = ["check", model, "--samples", "3", "--against", "rtb-dh", "--to", frame,
            *report_args(env)]  # fmt: skip
    run = run_main(argv, capsys)
    assert_terminal_safe(run)
    assert run.seconds < SMALL_RUN_S
    if run.code == 2:  # a future rule refusing such names: one escaped line is right too
        one_error_line(run.err)
        return
    assert run.code == 0, run.err
    title = f"fkcheck {terminal_text(text)}: world → {terminal_text(frame)},"
    assert " ".join(title.split()) in " ".join(run.out.split())  # the title may wrap
    verdicts = [line for line in run.out.splitlines() if line.startswith("verdict")]
    assert verdicts == [
        "verdict: pass — implementation only; table not checked against anything independent "
        "(1 backend(s) answered)"
    ]
    doc = assert_documents_safe(env)
    assert (doc["model"], doc["to"]) == (text, frame)  # JSON keeps the text exactly
    suite = ET.parse(env / "r.xml").getroot().find("testsuite")
    assert suite is not None
    assert suite.get("name") == f"fkcheck.{document_text(text)}"


@pytest.mark.parametrize("text", [pytest.param(t, id=i) for i, t in HOSTILE.items()])
def test_a_plugins_message_is_shown_literally_everywhere(env, capsys, monkeypatch, text):
    (env.parent / "message.txt").write_bytes(f"{text} end".encode())  # bytes: CR kept
    monkeypatch.setenv("FKCHECK_TEST_MESSAGE", str(env.parent / "message.txt"))
    files = write_models(env)
    argv = ["check", files["model"], "--samples", "3", "--against",
            "fkcheck_test_plugin:raises", *report_args(env)]  # fmt: skip
    run = run_main(argv, capsys)
    assert run.code == 1, run.err
    assert_terminal_safe(run)
    assert f"{terminal_text(text)} end" in run.out  # literally, markup and escapes visible
    verdicts = [line for line in run.out.splitlines() if line.startswith("verdict")]
    assert len(verdicts) == 1
    assert verdicts[0].startswith("verdict: error")
    doc = assert_documents_safe(env)
    assert f"{text} end" in doc["backends"][0]["message"]
    error = ET.parse(env / "r.xml").getroot().find("testsuite/testcase/error")
    assert error is not None
    assert f"{document_text(text)} end" in (error.get("message") or "")
    assert run.seconds < SMALL_RUN_S


def test_a_programs_stderr_is_shown_literally(env, capsys):
    program = env / "noisy.py"
    program.write_text(
        "import sys\nsys.stderr.write('[/x] \\x1b]0;pwned\\x07\\x1b[2J verdict: pass\\n')\n"
        "sys.exit(3)\n", encoding="utf-8",
    )  # fmt: skip
    files = write_models(env)
    run = run_main(["check", files["model"], "--samples", "3", "--against",
                    f"cmd:{sys.executable} {program}"], capsys)  # fmt: skip
    assert run.code == 1, run.err
    assert_terminal_safe(run)
    assert "[/x] \\x1b]0;pwned\\x07\\x1b[2J verdict: pass" in run.out


ERROR_LINE_CASES = [
    ("unknown-key", "toml", '"\\u001b]0;pwned\\u0007[/x]" = 1\n', "\\x1b]0;pwned\\x07[/x]"),
    ("missing-file-name", "name", "\x1b[2J[/x]\nverdict: pass.toml",
     "\\x1b[2J[/x]\\nverdict: pass.toml"),
    ("argparse-unrecognized", "argv", "\x1b]0;pwned\x07", "\\x1b]0;pwned\\x07"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("kind", "payload", "shown"), [pytest.param(k, p, s, id=i) for i, k, p, s in ERROR_LINE_CASES]
)
def test_the_error_line_shows_input_literally(env, capsys, kind, payload, shown):
    if kind == "toml":
        model = env / "bad.toml"
        model.write_text(payload + PLANAR2.read_text(encoding="utf-8"), encoding="utf-8")
        argv = ["check", model]
    elif kind == "name":
        argv = ["check", str(env / payload)]
    else:
        argv = ["check", "planar2", payload]
    run = run_main(argv, capsys)
    assert run.code == 2
    assert run.err.count("\n") == 1
    assert run.err.startswith("fkcheck")
    assert not RAW_CONTROL.search(run.err)
    assert shown in run.err
    assert run.seconds < REFUSE_S


# --- fkcheck urdf: always well-formed XML -------------------------------------------------------


@pytest.mark.parametrize(
    ("joint", "fragment"),
    [
        pytest.param("j\x00", "joint[1].name: 'j\\x00' holds \\x00", id="nul"),
        pytest.param("j\x1b[2J", "joint[1].name: 'j\\x1b[2J' holds \\x1b", id="escape"),
        pytest.param("j\x7f", "holds \\x7f", id="del"),
    ],
)
def test_urdf_refuses_a_name_xml_cannot_carry(env, capsys, joint, fragment):
    source = PLANAR2.read_text(encoding="utf-8").replace(
        'name = "theta1"', f"name = {toml_string(joint)}", 1)  # fmt: skip
    (env / "m.toml").write_text(source, encoding="utf-8")
    run = run_main(["urdf", env / "m.toml", "-o", env / "m.urdf"], capsys)
    assert run.code == 2
    line = one_error_line(run.err)
    assert not RAW_CONTROL.search(run.err)
    assert not (env / "m.urdf").exists()
    try:  # models may one day refuse such names themselves; while they load, urdf names it
        load_model(env / "m.toml")
    except FkcheckError:
        return
    assert fragment in line


def test_urdf_writes_markup_and_comment_dashes_as_well_formed_xml(env, capsys):
    name = "a--b<&>'\"]]>-"
    source = PLANAR2.read_text(encoding="utf-8")
    source = source.replace('name = "planar2"', f"name = {toml_string(name)}", 1)
    source = source.replace('name = "theta1"', f"name = {toml_string('j<&>--')}", 1)
    (env / "m.toml").write_text(source, encoding="utf-8")
    run = run_main(["urdf", env / "m.toml", "-o", env / "m.urdf", "--write-model",
                    env / "mapped.toml"], capsys)  # fmt: skip
    assert run.code == 0, run.err
    root = ET.parse(env / "m.urdf").getroot()
    assert root.get("name") == name
    assert next(j.get("name") for j in root.iter("joint") if j.get("type") != "fixed") == "j<&>--"
    assert load_model(env / "mapped.toml").name == name  # the companion model reads back


def test_written_toml_stays_valid_with_control_characters_in_names(env, capsys):
    model, _frame = hostile_model(env, "x\x1b[2J\x7f\nverdict: pass")
    run = run_main(["convert", model, "--to", "modified", "--samples", "3", "-o",
                    env / "out.toml"], capsys)  # fmt: skip
    assert run.code == 0, run.err
    assert_terminal_safe(run)
    assert load_model(env / "out.toml").name == "x\x1b[2J\x7f\nverdict: pass"


# --- standard output that cannot be written, or only in ASCII ---------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        pytest.param(["check", "planar2", "--samples", "3", "--against", "rtb-dh"], id="check"),
        pytest.param(["fk", "planar2", "--q", "1,2"], id="fk-small"),
        pytest.param(["models"], id="models"),
        pytest.param(["--help"], id="help"),
    ],
)
@pytest.mark.parametrize("unbuffered", [False, True], ids=["buffered", "unbuffered"])
def test_stdout_on_dev_full_is_one_line_exit_2(env, argv, unbuffered):
    """Buffered, the write fails at the last flush; unbuffered, at the first print."""
    child_env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    if unbuffered:
        child_env["PYTHONUNBUFFERED"] = "1"
    with open("/dev/full", "wb") as full:
        run = run_subprocess(argv, stdout=full, env=child_env)
    assert run.code == 2
    assert run.err.splitlines() == [
        "fkcheck: error: cannot write standard output: No space left on device"
    ]


def test_a_large_fk_output_on_dev_full_fails_mid_run_with_one_line(env):
    (env / "q.csv").write_text("0.1,0.2\n" * 5000, encoding="utf-8")
    with open("/dev/full", "wb") as full:
        run = run_subprocess(["fk", "planar2", "--q-file", env / "q.csv"], stdout=full)
    assert run.code == 2
    assert run.err.splitlines() == [
        "fkcheck: error: cannot write standard output: No space left on device"
    ]


def _closed(*streams: int) -> None:
    """In the child, before fkcheck starts: close these descriptors (``>&-``)."""
    for fd in streams:
        os.close(fd)


#: What a run writes and exits with; the model file it reads is named {model}.
CLOSED = [
    pytest.param(["check", "planar2", "--samples", "3", "--against", "rtb-dh", "--json",
                  "{d}/r.json"], 0, "r.json", id="check-pass"),
    pytest.param(["check", "{model}", "--samples", "3", "--against",
                  "fkcheck_test_plugin:touch", "--json", "{d}/r.json"], 1, "r.json",
                 id="check-fail"),
    pytest.param(["urdf", "planar2", "-o", "{d}/r.urdf"], 0, "r.urdf", id="urdf"),
    pytest.param(["lint", "planar2"], 0, None, id="lint"),
    pytest.param(["--help"], 0, None, id="help"),
]  # fmt: skip


@pytest.mark.parametrize(("argv", "code", "written"), CLOSED)
@pytest.mark.parametrize("streams", [(1,), (0, 1), (1, 2)], ids=["stdout", "stdin+stdout",
                                                                   "stdout+stderr"])  # fmt: skip
def test_a_closed_stream_is_no_traceback_and_the_run_keeps_its_exit_code(
    env, argv, code, written, streams
):
    """``fkcheck check ur5 >&-``: the run goes on, its output going nowhere, its files written."""
    files = write_models(env)
    argv = [a.replace("{d}", str(env)).replace("{model}", str(files["model"])) for a in argv]
    run = run_subprocess(argv, stdout=None, preexec_fn=lambda: _closed(*streams))
    assert run.code == code, run.err
    assert "Traceback" not in run.err
    assert run.err == ""  # nothing to say: stderr closed, or the run had no complaint
    if written is not None:
        assert (env / written).is_file()


@pytest.mark.parametrize(
    ("argv", "shown"),
    [
        pytest.param(["check", "planar2", "--samples", "3", "--against", "rtb-dh"],
                     "world \\u2192 tcp", id="check-arrow"),
        pytest.param(["models", "--long"], "Armstrong-H\\xe9louvry", id="models-accents"),
        pytest.param(["convert", "planar2", "--to", "modified", "--samples", "3"],
                     "standard \\u2192 modified", id="convert-arrow-on-stderr"),
    ],
)  # fmt: skip
def test_an_ascii_terminal_gets_escapes_not_a_traceback(env, argv, shown):
    run = run_subprocess(argv, env={**os.environ, "PYTHONIOENCODING": "ascii"})
    assert run.code == 0, run.err
    assert "Traceback" not in run.err
    assert shown in run.out + run.err
    assert run.out.isascii()
    assert run.err.isascii()
