"""The reusable action (action.yml), the CI and release workflows: interface and scripts.

actionlint (``nox -s actionlint``, in .ci/run) lints the workflow, and through its
``uses: ./`` step the action's inputs. Here the action's metadata is read as YAML,
and its ``fkcheck check`` step's script is run by bash against a stand-in
``fkcheck`` that records its arguments and exits with a chosen code: the
interface is ``fkcheck check --out-dir=DIR --summary=PATH -- FILE...``, exit 0/1/2
(no input can become an option); once with the real fkcheck behind it. The
release workflow (release.yml) runs on tags, publishes by trusted publishing from
one job, and its tag check is run here against a wheel of a known version.
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
    assert sessions == {"tests", "lint", "typecheck", "crossval", "bounded", "actionlint"}
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
        "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}",
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
        "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}",
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
