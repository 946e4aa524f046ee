"""What the wheel and the sdist ship, as pyproject.toml's hatch config says (no build here).

``nox -s dist`` builds both, installs each into a fresh venv and runs the main job;
these fast checks guard the config that makes that work: the bundled models go
into the wheel where :func:`fkcheck.model.read.bundled_models_dir` looks once
installed, the sdist carries them (a wheel built from it needs them) and its
source tree by name, never reports/ or a CI venv, and the licences are declared.
"""

from __future__ import annotations

import ast
import inspect
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

from fkcheck.model.read import bundled_model_paths, bundled_models_dir
from tests.paths import REPO_ROOT


def _pyproject() -> dict[str, Any]:
    with (REPO_ROOT / "pyproject.toml").open("rb") as f:
        return tomllib.load(f)


def _hatch_build() -> dict[str, Any]:
    build: dict[str, Any] = _pyproject()["tool"]["hatch"]["build"]
    return build


def test_the_wheel_ships_the_models_where_fkcheck_looks_for_them() -> None:
    wheel = _hatch_build()["targets"]["wheel"]
    assert wheel["packages"] == ["src/fkcheck"]
    assert wheel["force-include"] == {"models": "fkcheck/_bundled_models"}
    # Installed, read.py sits in fkcheck/model/: its first candidate is fkcheck/_bundled_models.
    assert 'package / "_bundled_models"' in inspect.getsource(bundled_models_dir)
    assert (REPO_ROOT / "src" / "fkcheck" / "py.typed").is_file()


def test_the_models_directory_holds_every_bundled_model_and_the_ur_description() -> None:
    models = REPO_ROOT / "models"
    assert {p.stem for p in models.glob("*.toml")} == set(bundled_model_paths())
    assert {"ur5", "panda", "planar2"} <= set(bundled_model_paths())
    ur = models / "ur_description"
    for name in ("LICENSE", "SOURCE.md", "package.xml", "urdf/ur.urdf.xacro"):
        assert (ur / name).is_file(), name


def test_the_sdist_ships_the_source_tree_by_name() -> None:
    only = _hatch_build()["targets"]["sdist"]["only-include"]
    # What the wheel (built from the sdist) and the tests need.
    assert {"src", "models", "tests", "README.md", "LICENSE", "noxfile.py"} <= set(only)
    # Only names, each at the top of the checkout; never the run's outputs or a venv.
    assert all("/" not in name and "*" not in name for name in only)
    assert not {"reports", ".ci-venv", ".nox", "dist", "build"} & set(only)
    # Every entry at the top of the checkout that git tracks is shipped, or is reports/.
    shipped = set(only) | {"pyproject.toml", ".gitignore", "reports"}
    assert _top_level_tracked() <= shipped, _top_level_tracked() - shipped


def _top_level_tracked() -> set[str]:
    """The names at the top of the checkout that git tracks (an unpacked sdist: all of them)."""
    if not (REPO_ROOT / ".git").exists():
        return {p.name for p in REPO_ROOT.iterdir()} - {"PKG-INFO"}
    listed = subprocess.run(
        ["git", "ls-files", "-z"], cwd=REPO_ROOT, capture_output=True, text=True, check=True
    ).stdout
    return {path.split("/", 1)[0] for path in listed.split("\0") if path}


def test_the_licences_are_declared_and_present() -> None:
    project = _pyproject()["project"]
    assert project["license"] == "MIT"
    menagerie = "models/mujoco_menagerie"
    assert project["license-files"] == [
        "LICENSE",
        "models/ur_description/LICENSE",
        f"{menagerie}/universal_robots_ur5e/LICENSE",
        f"{menagerie}/universal_robots_ur10e/LICENSE.md",
        f"{menagerie}/franka_emika_panda/LICENSE",
        f"{menagerie}/ufactory_xarm7/LICENSE",
    ]
    for name in project["license-files"]:
        assert (REPO_ROOT / name).is_file(), name
    for name in project["license-files"][2:]:
        text = (REPO_ROOT / name).read_text("utf-8")
        assert "Redistribution and use" in text or "Apache License" in text, name
    assert (REPO_ROOT / "LICENSE").read_text("utf-8").startswith("MIT License\n")
    assert "Redistribution and use in source and binary forms" in (
        REPO_ROOT / "models" / "ur_description" / "LICENSE"
    ).read_text("utf-8")


def test_the_entry_points_a_user_needs_are_declared() -> None:
    project = _pyproject()["project"]
    assert project["scripts"] == {"fkcheck": "fkcheck.cli.main:main"}
    assert project["entry-points"]["pytest11"] == {"fkcheck": "fkcheck.pytest_plugin"}
    assert Path(REPO_ROOT / "src" / "fkcheck" / "pytest_plugin.py").is_file()


def test_ci_runs_the_dist_session_and_the_noxfile_defines_it() -> None:
    ci = (REPO_ROOT / ".ci" / "run").read_text("utf-8").splitlines()
    assert "python3 -m nox -s dist" in ci
    assert ci.index("python3 -m nox -s dist") > ci.index("python3 -m nox -s crossval")
    noxfile = (REPO_ROOT / "noxfile.py").read_text("utf-8")
    assert "@nox.session(default=False)\ndef dist(session: nox.Session) -> None:" in noxfile
    assert '"twine", "check", "--strict"' in noxfile


def test_the_readme_first_command_installs_the_reference_extra_and_runs_the_main_job() -> None:
    readme = (REPO_ROOT / "README.md").read_text("utf-8")
    quick = readme.split("## Quick start", 1)[1].split("```sh\n", 1)[1].split("\n```", 1)[0]
    assert quick == (
        "python3 -m venv .venv && . .venv/bin/activate && pip install '.[reference]' && fkcheck"
    )
    extras = _pyproject()["project"]["optional-dependencies"]
    assert "reference" in extras
    assert "pip install 'fkcheck[reference]'" in readme  # what a check without it says


def test_dist_installs_the_extra_for_the_main_job_and_the_wheel_alone_for_lint() -> None:
    noxfile = (REPO_ROOT / "noxfile.py").read_text("utf-8")
    assert '"--disable-pip-version-check", f"{artefact}[reference]"' in noxfile
    assert "_run_light(session, wheel, work)" in noxfile
    # The light install lints and must not have pulled a reference library in.
    light = noxfile.split("def _run_light(", 1)[1]
    assert '"lint", "ur5"' in light
    assert "_REFERENCE_PROBE" in light
    assert "pip install 'fkcheck[reference]'" in light


def test_the_tests_session_leaves_the_slow_tests_to_a_session_ci_runs_too() -> None:
    noxfile = (REPO_ROOT / "noxfile.py").read_text("utf-8")
    tests_run = 'bin_dir / "pytest", *PARALLEL, "-m", "not slow", *session.posargs, external=True'
    slow_run = 'bin_dir / "pytest", *SLOW_PARALLEL, "-m", "slow", *session.posargs, external=True'
    assert tests_run in noxfile.split("def tests(", 1)[1].split("\n@nox.session", 1)[0]
    assert slow_run in noxfile.split("def slow(", 1)[1].split("\n@nox.session", 1)[0]
    assert '"-n", "auto"' in noxfile
    markers = _pyproject()["tool"]["pytest"]["ini_options"]["markers"]
    assert any(m.startswith("slow: ") for m in markers)
    # CI: the README's test command, then the slow session, each with its own JUnit file
    # (both counted for skips), so no test is dropped from CI.
    ci = (REPO_ROOT / ".ci" / "run").read_text("utf-8").splitlines()
    tests = ci.index(
        "python3 -m pip install 'nox[uv]' && python3 -m nox -s tests || tests_status=$?"
    )
    slow = ci.index("python3 -m nox -s slow || tests_status=$?")
    assert ci[tests - 1] == 'export PYTEST_ADDOPTS="--junitxml=${tests_junit}"'
    assert ci[slow - 1] == 'export PYTEST_ADDOPTS="--junitxml=${slow_junit}"'
    assert tests < slow < ci.index('[ "$tests_status" -eq 0 ] || exit "$tests_status"')
    assert 'python3 - "$tests_junit" "$slow_junit" <<\'PY\'' in ci


def test_the_sessions_needing_the_reference_extra_share_one_environment() -> None:
    # One install of the ~1.8 GB instead of one per session (CI ran five of them): each
    # of these sessions makes or updates .nox/reference and runs its programs from there;
    # the light ones (lint, docs) keep their own small environments.
    tree = ast.parse((REPO_ROOT / "noxfile.py").read_text("utf-8"))
    sessions = {
        f.name: f
        for f in tree.body
        if isinstance(f, ast.FunctionDef)
        and any("session" in ast.unparse(d) for d in f.decorator_list)
    }
    shared = {"tests", "slow", "bounded", "typecheck", "crossval", "fuzz", "wall", "campaign"}
    for name in shared:
        (decorator,) = sessions[name].decorator_list
        assert 'venv_backend="none"' in ast.unparse(decorator).replace("'", '"'), name
        assert "_reference_env(session)" in ast.unparse(sessions[name]), name
    for name in ("lint", "docs"):
        assert "_reference_env" not in ast.unparse(sessions[name]), name
    # The hostile-input suites under the memory limit run in parallel too.
    assert "*PARALLEL" in ast.unparse(sessions["bounded"])


def test_ci_counts_the_tests_and_skips_of_both_junit_files(tmp_path: Path) -> None:
    script = (REPO_ROOT / ".ci" / "run").read_text("utf-8").split("<<'PY'\n", 1)[1]
    script = script.split("\nPY\n", 1)[0]
    tests = tmp_path / "tests.xml"
    tests.write_text(
        '<testsuites><testsuite><testcase name="a"/>'
        '<testcase name="b"><skipped message="no chromium"/></testcase></testsuite></testsuites>',
        encoding="utf-8",
    )
    slow = tmp_path / "slow.xml"
    slow.write_text(
        '<testsuites><testsuite><testcase name="c"><failure message="skipped, but '
        'FKCHECK_REQUIRE_BACKENDS=1 forbids skips: no cmake"/></testcase>'
        "</testsuite></testsuites>",
        encoding="utf-8",
    )
    done = subprocess.run(
        [sys.executable, "-", str(tests), str(slow), str(tmp_path / "absent.xml")],
        input=script, capture_output=True, text=True, check=True, timeout=60,
    )  # fmt: skip
    assert done.stdout.splitlines() == [
        "tests: 3 ran, 2 skipped (a skip fails in CI)",
        "  skipped 1x: no chromium",
        "  skipped 1x: skipped, but FKCHECK_REQUIRE_BACKENDS=1 forbids skips: no cmake",
    ]
