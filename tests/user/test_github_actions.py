"""The reusable action (action.yml), the CI and release workflows: interface and scripts.

actionlint (``nox -s actionlint``, in .ci/run) lints the workflow, and through its
``uses: ./`` step the action's inputs. Here the action's metadata is read as YAML,
and its ``fkcheck check`` step's script is run by bash against a stand-in
``fkcheck`` that records its arguments and exits with a chosen code: the
interface is ``fkcheck check --out-dir=DIR --summary=PATH -- FILE...``, exit 0/1/2
(no input can become an option); once with the real fkcheck behind it. Its install:
the venv step's script (which Python, the cache key) with this interpreter, the
install step's with a stand-in interpreter that logs what it is asked (a warm venv
asks nothing). The release workflow (release.yml) runs on tags, publishes by
trusted publishing from one job, and its tag check is run here against a wheel of
a known version.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path
from typing import Any

import pytest

from fkcheck._version import __version__
from fkcheck.model.read import bundled_model_paths
from tests.paths import REPO_ROOT

yaml = pytest.importorskip("yaml")  # PyYAML: installed with fkcheck (xacrodoc needs it)

ACTION = REPO_ROOT / "action.yml"
WORKFLOW = REPO_ROOT / ".github" / "workflows" / "ci.yml"
RELEASE = REPO_ROOT / ".github" / "workflows" / "release.yml"


def _load(path: Path) -> dict[str, Any]:
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    return data


def test_action_inputs_and_outputs() -> None:
    action = _load(ACTION)
    assert set(action["inputs"]) == {
        "models", "samples", "require", "out-dir", "python-version", "artifact-name",
    }  # fmt: skip
    assert all(not spec["required"] for spec in action["inputs"].values())
    assert action["outputs"]["verdict"]["value"] == "${{ steps.check.outputs.verdict }}"
    assert action["runs"]["using"] == "composite"
    steps = action["runs"]["steps"]
    assert [s.get("id") for s in steps].count("check") == 1
    assert all(s.get("shell") == "bash" for s in steps if "run" in s)  # composite needs it
    upload = next(s for s in steps if str(s.get("uses", "")).startswith("actions/upload-artifact"))
    assert upload["if"] == "always()"
    assert upload["with"]["path"] == "${{ inputs.out-dir }}"


def test_workflow_runs_the_nox_sessions_and_uploads_reports() -> None:
    workflow = _load(WORKFLOW)
    runs = "\n".join(
        str(step.get("run", "")) for job in workflow["jobs"].values() for step in job["steps"]
    )
    sessions = {s for m in re.finditer(r"nox -s ([\w ]+)", runs) for s in m.group(1).split()}
    assert sessions == {"tests", "slow", "lint", "typecheck", "crossval", "bounded", "actionlint"}
    uploads = [
        step["with"]["path"]
        for job in workflow["jobs"].values()
        for step in job["steps"]
        if str(step.get("uses", "")).startswith("actions/upload-artifact")
    ]
    assert "reports/" in uploads
    assert "reports/junit/" in uploads
    assert "GITHUB_STEP_SUMMARY" in runs
    action_job = workflow["jobs"]["action"]["steps"]
    assert any(step.get("uses") == "./" for step in action_job)


def _check_script() -> str:
    step = next(s for s in _load(ACTION)["runs"]["steps"] if s.get("id") == "check")
    return str(step["run"])


def _run_check_step(
    tmp_path: Path, exit_code: int, **inputs: str
) -> tuple[dict[str, str], list[str], str]:
    """Run the step's script; returns its outputs, the stand-in's argv and the step summary."""
    if shutil.which("bash") is None:
        pytest.skip("bash is not installed")
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    argv_file = tmp_path / "argv.json"
    stub = bin_dir / "fkcheck"
    stub.write_text(
        "#!/usr/bin/env python3\nimport json, sys\n"
        f"json.dump(sys.argv[1:], open({str(argv_file)!r}, 'w'))\nsys.exit({exit_code})\n",
        encoding="utf-8",
    )
    stub.chmod(0o755)
    output, summary = tmp_path / "output", tmp_path / "summary"
    output.touch()
    summary.touch()
    env = {
        "PATH": os.environ["PATH"],
        "FKCHECK_BIN": str(bin_dir),  # the venv's bin: the step puts it first on its PATH
        "GITHUB_OUTPUT": str(output),
        "GITHUB_STEP_SUMMARY": str(summary),
        "MODELS": inputs.get("models", ""),
        "SAMPLES": inputs.get("samples", ""),
        "REQUIRE": inputs.get("require", ""),
        "OUT_DIR": "fkcheck-reports",
    }
    result = subprocess.run(
        ["bash", "-e", "-c", _check_script()], cwd=tmp_path, env=env,
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr  # the step itself never fails; "Verdict" does
    outputs = dict(line.split("=", 1) for line in output.read_text("utf-8").splitlines())
    return outputs, json.loads(argv_file.read_text("utf-8")), summary.read_text("utf-8")


def test_action_passes_models_samples_require_and_out_dir(tmp_path: Path) -> None:
    outputs, argv, _ = _run_check_step(
        tmp_path, 0, models="robots/good.toml\n  robots/*.toml calib/", samples="50",
        require="table",
    )  # fmt: skip
    assert outputs == {"verdict": "pass", "status": "0"}
    assert argv == [
        "check", "--out-dir=fkcheck-reports", "--summary=fkcheck-reports/summary.md",
        "--samples=50", "--require=table", "--", "robots/good.toml", "robots/*.toml", "calib/",
    ]  # fmt: skip
    # The glob reaches fkcheck unexpanded: it expands globs inside the project.


def test_action_without_inputs_leaves_the_models_to_tool_fkcheck(tmp_path: Path) -> None:
    outputs, argv, _ = _run_check_step(tmp_path, 1)
    assert outputs == {"verdict": "fail", "status": "1"}
    assert argv == ["check", "--out-dir=fkcheck-reports", "--summary=fkcheck-reports/summary.md",
                    "--"]  # fmt: skip


@pytest.mark.parametrize(
    ("inputs", "where"),
    [
        ({"models": "--against=cmd:./x.sh robots/a.toml"}, "models"),
        ({"models": "robots/a.toml", "samples": "--against=cmd:./x.sh"}, "--samples="),
        ({"models": "robots/a.toml", "require": "--against=cmd:./x.sh"}, "--require="),
    ],
)
def test_action_inputs_are_never_options(tmp_path: Path, inputs, where) -> None:
    """Each input reaches fkcheck as data: a value joined to its option, models after ``--``."""
    _, argv, _ = _run_check_step(tmp_path, 2, **inputs)
    hostile = "--against=cmd:./x.sh"
    if where == "models":
        assert argv[argv.index("--") + 1] == hostile
    else:
        assert f"{where}{hostile}" in argv
    assert hostile not in argv[: argv.index("--")]


def test_action_with_a_hostile_model_name_runs_no_program(tmp_path: Path) -> None:
    """The real fkcheck behind the step: ``--against=cmd:./x.sh`` is a file that is not there."""
    if shutil.which("bash") is None:
        pytest.skip("bash is not installed")
    marker = tmp_path / "ran"
    program = tmp_path / "x.sh"
    program.write_text(f"#!/bin/sh\ntouch {marker}\n", encoding="utf-8")
    program.chmod(0o755)
    (tmp_path / "robots").mkdir()
    shutil.copyfile(bundled_model_paths()["planar2"], tmp_path / "robots" / "a.toml")
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    wrapper = bin_dir / "fkcheck"
    wrapper.write_text(f'#!/bin/sh\nexec {sys.executable} -m fkcheck "$@"\n', encoding="utf-8")
    wrapper.chmod(0o755)
    output, summary = tmp_path / "output", tmp_path / "summary"
    env = {
        "PATH": os.environ["PATH"],
        "FKCHECK_BIN": str(bin_dir),
        "PYTHONPATH": str(REPO_ROOT / "src"),
        "GITHUB_OUTPUT": str(output),
        "GITHUB_STEP_SUMMARY": str(summary),
        "MODELS": "--against=cmd:./x.sh robots/a.toml",
        "SAMPLES": "3",
        "REQUIRE": "",
        "OUT_DIR": "fkcheck-reports",
    }
    result = subprocess.run(
        ["bash", "-e", "-c", _check_script()], cwd=tmp_path, env=env,
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert "status=2" in output.read_text("utf-8")
    assert result.stderr == "fkcheck: error: --against=cmd:./x.sh: no such file\n"
    assert not marker.exists()


def test_action_bad_input_is_its_own_verdict_in_the_summary(tmp_path: Path) -> None:
    outputs, _, summary = _run_check_step(tmp_path, 2, models="nope.toml")
    assert outputs == {"verdict": "bad-input", "status": "2"}
    assert summary == "fkcheck: bad input (exit 2): see the step's log\n"


def test_action_samples_take_the_flags_path_and_its_one_rule(tmp_path: Path, monkeypatch, capsys):
    # The action has no options of its own: its samples are --samples, resolved and
    # refused by fkcheck.model.options as on the command line (same line, exit 2).
    from fkcheck.cli.main import main
    from fkcheck.model.options import DEFAULT_SAMPLES, FLAGS, option_problem

    samples = _load(ACTION)["inputs"]["samples"]["description"]
    assert f"else {DEFAULT_SAMPLES})" in samples
    planar = str(bundled_model_paths()["planar2"])
    _, argv, _ = _run_check_step(tmp_path, 2, models=planar, samples="-1")
    assert f"{FLAGS['samples']}=-1" in argv
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    problem = option_problem("samples", -1)
    assert capsys.readouterr().err == f"fkcheck: error: --samples: {problem}\n"


def _step(step_id: str) -> dict[str, Any]:
    step = next(s for s in _load(ACTION)["runs"]["steps"] if s.get("id") == step_id)
    assert isinstance(step, dict)
    return step


def test_action_leaves_the_callers_python_and_path_alone() -> None:
    """setup-python only when python-version is given, and then off the caller's PATH."""
    action = _load(ACTION)
    assert action["inputs"]["python-version"]["default"] == ""
    steps = action["runs"]["steps"]
    setups = [s for s in steps if str(s.get("uses", "")).startswith("actions/setup-python")]
    assert setups == [_step("setup-python")]
    assert setups[0]["if"] == "inputs.python-version != ''"  # empty: the step does not run
    assert setups[0]["with"] == {
        "python-version": "${{ inputs.python-version }}",
        "update-environment": False,
    }
    assert _step("venv")["env"] == {"SETUP_PYTHON": "${{ steps.setup-python.outputs.python-path }}"}
    scripts = "\n".join(str(s.get("run", "")) for s in steps)
    assert "GITHUB_PATH" not in scripts  # nothing reaches the caller's later steps
    assert "GITHUB_ENV" not in scripts
    assert "pip install" in _step("install")["run"]
    assert "--user" not in _step("install")["run"]
    # The venv is cached under the key the venv step computes; saved once installed.
    restore, save = (
        next(s for s in steps if s.get("uses") == f"actions/cache/{what}@v4")
        for what in ("restore", "save")
    )
    cache = {"path": "${{ steps.venv.outputs.path }}", "key": "${{ steps.venv.outputs.key }}"}
    assert restore["with"] == cache
    assert save["with"] == cache
    assert save["if"] == "steps.install.outputs.installed == 'true'"
    assert _step("check")["env"]["FKCHECK_BIN"] == "${{ steps.venv.outputs.bin }}"
    order = [s.get("id") for s in steps]
    assert order[:4] == ["setup-python", "venv", "restore", "install"]


def _action_copy(root: Path) -> Path:
    """What the action's key hashes, copied: pyproject.toml, README.md, src/, models/."""
    for name in ("pyproject.toml", "README.md"):
        root.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(REPO_ROOT / name, root / name)
    for top in ("src", "models"):
        shutil.copytree(REPO_ROOT / top, root / top, ignore=shutil.ignore_patterns("__pycache__"))
    return root


def _run_venv_step(
    tmp_path: Path, action: Path, path: str, setup_python: str = ""
) -> tuple[subprocess.CompletedProcess[str], dict[str, str]]:
    output = tmp_path / "venv-output"
    output.write_text("", encoding="utf-8")
    env = {
        "PATH": path,
        "SETUP_PYTHON": setup_python,
        "GITHUB_ACTION_PATH": str(action),
        "GITHUB_OUTPUT": str(output),
        "RUNNER_TEMP": str(tmp_path / "runner-temp"),
        "RUNNER_OS": "Linux",
        "RUNNER_ARCH": "X64",
    }
    result = subprocess.run(
        ["bash", "-e", "-c", _step("venv")["run"]], env=env, capture_output=True, text=True,
        timeout=60, check=False,
    )  # fmt: skip
    outputs = dict(line.split("=", 1) for line in output.read_text("utf-8").splitlines())
    return result, outputs


def _python3_dir(tmp_path: Path, name: str) -> Path:
    """A directory whose python3 is this interpreter (a symlink), first on a PATH."""
    bin_dir = tmp_path / name
    bin_dir.mkdir()
    (bin_dir / "python3").symlink_to(sys.executable)
    return bin_dir


def test_action_venv_key_follows_python_and_the_action_source(tmp_path: Path) -> None:
    assert shutil.which("bash"), "bash runs the action's steps"
    action = _action_copy(tmp_path / "action")
    first = _python3_dir(tmp_path, "py-a")
    path = f"{first}{os.pathsep}{os.environ['PATH']}"
    result, outputs = _run_venv_step(tmp_path, action, path)
    assert result.returncode == 0, result.stderr
    # No python-version: the runner's python3 as found on PATH, no setup-python.
    assert outputs["python"] == str(first / "python3")
    version = ".".join(map(str, sys.version_info[:3]))
    key = outputs["key"]
    assert re.fullmatch(rf"fkcheck-venv-v1-Linux-X64-py{re.escape(version)}-[0-9a-f]{{64}}", key)
    venv = Path(outputs["path"])
    assert venv.parent == tmp_path / "runner-temp"
    assert venv.name == "fkcheck-venv-" + key[-64:][:12]
    assert outputs["bin"] == str(venv / "bin")
    # Same source, same Python: same key (bytecode caches are not the source).
    (action / "src" / "fkcheck" / "__pycache__").mkdir(exist_ok=True)
    (action / "src" / "fkcheck" / "__pycache__" / "cli.cpython-311.pyc").write_bytes(b"\0")
    assert _run_venv_step(tmp_path, action, path)[1] == outputs
    # A changed source file, a changed pyproject.toml: another key and venv.
    source = action / "src" / "fkcheck" / "model" / "lint.py"
    source.write_text(source.read_text(encoding="utf-8") + "\n# changed\n", encoding="utf-8")
    changed = _run_venv_step(tmp_path, action, path)[1]
    assert changed["key"] != key
    assert changed["path"] != outputs["path"]
    pyproject = action / "pyproject.toml"
    pyproject.write_text(pyproject.read_text(encoding="utf-8") + "\n", encoding="utf-8")
    assert _run_venv_step(tmp_path, action, path)[1]["key"] not in {key, changed["key"]}
    # Another Python (another path, e.g. setup-python's): another key.
    other = _run_venv_step(tmp_path, action, path, setup_python=sys.executable)[1]
    assert other["python"] == sys.executable
    assert other["key"] != _run_venv_step(tmp_path, action, path)[1]["key"]


def test_action_refuses_a_python_older_than_3_11_in_one_line(tmp_path: Path) -> None:
    assert shutil.which("bash"), "bash runs the action's steps"
    bin_dir = tmp_path / "old"
    bin_dir.mkdir()
    old = bin_dir / "python3"
    old.write_text("#!/bin/sh\necho 3.10\n", encoding="utf-8")  # what 3.10 prints for the check
    old.chmod(0o755)
    path = f"{bin_dir}{os.pathsep}{os.environ['PATH']}"
    result, outputs = _run_venv_step(tmp_path, _action_copy(tmp_path / "action"), path)
    assert result.returncode == 1
    assert result.stdout == (
        f"::error::fkcheck needs Python 3.11 or newer; {old} is 3.10;"
        " set the action's python-version input\n"
    )
    assert outputs == {}


#: A stand-in interpreter: logs its arguments; `-m venv DIR` makes DIR/bin/python (this
#: stand-in again) and `-m pip install ...` makes bin/fkcheck next to it.
STAND_IN_PYTHON = """#!{python}
import os, shutil, sys
from pathlib import Path
with open({log!r}, "a") as log:
    log.write(" ".join(sys.argv[1:]) + "\\n")
if sys.argv[1:3] == ["-m", "venv"]:
    (Path(sys.argv[3]) / "bin").mkdir(parents=True)
    shutil.copy(__file__, Path(sys.argv[3]) / "bin" / "python")
elif sys.argv[1:4] == ["-m", "pip", "install"]:
    fkcheck = Path(__file__).parent / "fkcheck"
    fkcheck.write_text("#!/bin/sh\\necho fkcheck 0.1.0\\n")
    fkcheck.chmod(0o755)
"""


def _run_install_step(
    tmp_path: Path, venv: Path
) -> tuple[subprocess.CompletedProcess[str], dict[str, str], list[str]]:
    """The install step's script with a stand-in interpreter; returns what it ran."""
    log = tmp_path / "python.log"
    log.write_text("", encoding="utf-8")
    python = tmp_path / "python3"
    python.write_text(STAND_IN_PYTHON.format(python=sys.executable, log=str(log)), "utf-8")
    python.chmod(0o755)
    output = tmp_path / "install-output"
    output.write_text("", encoding="utf-8")
    env = {
        "PATH": os.environ["PATH"],
        "PYTHON": str(python),
        "VENV": str(venv),
        "VENV_BIN": str(venv / "bin"),
        "GITHUB_ACTION_PATH": "/the/action",
        "GITHUB_OUTPUT": str(output),
    }
    result = subprocess.run(
        ["bash", "-e", "-c", _step("install")["run"]], env=env, capture_output=True, text=True,
        timeout=60, check=False,
    )  # fmt: skip
    outputs = dict(line.split("=", 1) for line in output.read_text("utf-8").splitlines())
    return result, outputs, log.read_text("utf-8").splitlines()


def test_action_install_cold_makes_the_venv_and_asks_for_a_save(tmp_path: Path) -> None:
    assert shutil.which("bash"), "bash runs the action's steps"
    venv = tmp_path / "runner-temp" / "fkcheck-venv-0123456789ab"
    result, outputs, ran = _run_install_step(tmp_path, venv)
    assert result.returncode == 0, result.stderr
    assert ran == [
        f"-m venv {venv}",
        "-m pip install --quiet --disable-pip-version-check /the/action[reference]",
    ]
    assert result.stdout == f"fkcheck: fkcheck 0.1.0, installed in {venv}\n"
    assert outputs == {"installed": "true"}


def test_action_install_warm_cache_skips_pip(tmp_path: Path) -> None:
    """A venv restored from the cache that runs ``fkcheck --version``: nothing installed."""
    assert shutil.which("bash"), "bash runs the action's steps"
    venv = tmp_path / "runner-temp" / "fkcheck-venv-0123456789ab"
    _run_install_step(tmp_path, venv)  # cold: the venv as the cache would restore it
    result, outputs, ran = _run_install_step(tmp_path, venv)
    assert result.returncode == 0, result.stderr
    assert ran == []  # neither venv nor pip
    assert result.stdout == f"fkcheck: fkcheck 0.1.0, from the cached venv {venv}\n"
    assert outputs == {}  # no save: the key is in the cache


def test_action_install_replaces_a_cached_venv_that_does_not_run(tmp_path: Path) -> None:
    assert shutil.which("bash"), "bash runs the action's steps"
    venv = tmp_path / "runner-temp" / "fkcheck-venv-0123456789ab"
    (venv / "bin").mkdir(parents=True)
    broken = venv / "bin" / "fkcheck"
    broken.write_text("#!/bin/sh\necho 'No module named fkcheck' >&2\nexit 1\n", encoding="utf-8")
    broken.chmod(0o755)
    (venv / "stale").write_text("from an older interpreter", encoding="utf-8")
    result, outputs, ran = _run_install_step(tmp_path, venv)
    assert result.returncode == 0, result.stderr
    assert ran == [
        f"-m venv {venv}",
        "-m pip install --quiet --disable-pip-version-check /the/action[reference]",
    ]
    assert result.stdout == (
        f"fkcheck: the cached venv {venv} does not run fkcheck; reinstalling\n"
        f"fkcheck: fkcheck 0.1.0, installed in {venv}\n"
    )
    assert not (venv / "stale").exists()
    assert outputs == {"installed": "true"}


def _on(workflow: dict[str, Any]) -> Any:
    """The workflow's ``on:`` (YAML 1.1 reads the bare key ``on`` as True)."""
    return workflow["on"] if "on" in workflow else workflow[True]


def test_release_runs_on_version_tags_and_builds_checks_and_uploads() -> None:
    release = _load(RELEASE)
    assert _on(release) == {"push": {"tags": ["v*"]}}
    assert release["permissions"] == {"contents": "read"}
    assert set(release["jobs"]) == {"build", "publish"}
    build = release["jobs"]["build"]
    assert "permissions" not in build  # contents: read, from the workflow
    runs = [str(s.get("run", "")) for s in build["steps"]]
    assert "python -m build" in runs
    assert "python -m twine check --strict dist/*" in runs
    uses = [str(s.get("uses", "")) for s in build["steps"]]
    assert uses[:2] == ["actions/checkout@v4", "actions/setup-python@v5"]
    assert build["steps"][1]["with"]["python-version"] == "3.11"
    # The tag is checked after the build and before the upload.
    names = [s.get("name") for s in build["steps"]]
    check = names.index("The tag is the built version")
    assert runs.index("python -m build") < check < uses.index("actions/upload-artifact@v4")
    upload = build["steps"][uses.index("actions/upload-artifact@v4")]["with"]
    assert (upload["name"], upload["path"], upload["if-no-files-found"]) == (
        "dist", "dist/", "error",
    )  # fmt: skip


def test_release_publishes_by_trusted_publishing_from_one_job() -> None:
    release = _load(RELEASE)
    publish = release["jobs"]["publish"]
    assert publish["needs"] == "build"
    assert publish["environment"]["name"] == "pypi"
    assert publish["permissions"] == {"id-token": "write"}
    others = [j for name, j in release["jobs"].items() if name != "publish"]
    assert all("id-token" not in (j.get("permissions") or {}) for j in others)
    download, upload = publish["steps"]
    assert download["uses"] == "actions/download-artifact@v4"
    assert download["with"] == {"name": "dist", "path": "dist/"}
    assert upload == {"uses": "pypa/gh-action-pypi-publish@release/v1"}  # no token, no inputs
    assert "secrets." not in RELEASE.read_text(encoding="utf-8")


def _run_tag_check(tmp_path: Path, tag: str, version: str) -> subprocess.CompletedProcess[str]:
    """The tag check step's script, run as ``shell: python`` runs it, beside a wheel."""
    step = next(
        s for s in _load(RELEASE)["jobs"]["build"]["steps"]
        if s.get("name") == "The tag is the built version"
    )  # fmt: skip
    assert step["shell"] == "python"
    assert step["env"] == {"TAG": "${{ github.ref_name }}"}
    dist = tmp_path / "dist"
    dist.mkdir()
    (dist / f"fkcheck-{version}.tar.gz").write_bytes(b"")
    with zipfile.ZipFile(dist / f"fkcheck-{version}-py3-none-any.whl", "w") as zf:
        zf.writestr(f"fkcheck-{version}.dist-info/METADATA",
                    f"Metadata-Version: 2.4\nName: fkcheck\nVersion: {version}\n")  # fmt: skip
    script = tmp_path / "check.py"
    script.write_text(str(step["run"]), encoding="utf-8")
    env = {**os.environ, "TAG": tag}
    return subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, env=env,
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip


def test_release_tag_check_passes_when_the_tag_is_the_version(tmp_path: Path) -> None:
    result = _run_tag_check(tmp_path, f"v{__version__}", __version__)
    assert result.returncode == 0, result.stderr
    assert result.stdout == f"tag v{__version__}: fkcheck {__version__}\n"


@pytest.mark.parametrize("tag", ["v9.9.9", "0.1.0", "v0.1.0rc1"])
def test_release_tag_check_fails_in_one_line_when_it_is_not(tmp_path: Path, tag: str) -> None:
    result = _run_tag_check(tmp_path, tag, "0.1.0")
    assert result.returncode == 1
    assert result.stdout == ""
    assert result.stderr == (f"tag {tag} is not v0.1.0, the version in src/fkcheck/_version.py\n")
