"""The pre-commit hooks, for real: ``pre-commit try-repo`` on a throw-away user repository.

``try-repo`` clones this repository at HEAD (plus uncommitted changes to tracked
files) and pip-installs it into a fresh virtualenv under ``PRE_COMMIT_HOME``
(here in tmp_path, so ~/.cache stays clean): it needs PyPI, and takes minutes
the first time on a cold pip cache.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import yaml

from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths
from tests.paths import REPO_ROOT

#: Reference libraries (and their heavy helpers) the lint hook must not import.
REFERENCES = ("pinocchio", "roboticstoolbox", "spatialmath", "yourdfpy", "example_robot_data")


def test_hooks_file_declares_a_fast_lint_and_an_opt_in_check():
    hooks = {h["id"]: h for h in yaml.safe_load((REPO_ROOT / ".pre-commit-hooks.yaml").read_text())}
    assert set(hooks) == {"fkcheck-lint", "fkcheck-check", "fkcheck-lint-system"}
    for hook in hooks.values():
        assert hook["files"] == r"\.(toml|csv)$"
        assert hook["exclude"] == r"(^|/)pyproject\.toml$"
        assert hook["pass_filenames"] is True
    assert hooks["fkcheck-lint"]["language"] == "python"
    assert hooks["fkcheck-check"]["language"] == "python"
    # The light variant: the fkcheck on PATH, no environment of its own. `system`, not
    # `unsupported` (pre-commit 4.4's new name): a pre-commit before 4.4 rejects the
    # whole file for one hook it does not know, the python hooks with it.
    system = hooks.pop("fkcheck-lint-system")
    assert system["language"] == "system"
    assert {k: v for k, v in system.items() if k not in ("id", "language", "description")} == {
        k: v for k, v in hooks["fkcheck-lint"].items() if k not in ("id", "language", "description")
    }
    # Every changed .toml/.csv is handed over: the hooks pick the model files by content,
    # and the names come after "--" (a file named like an option is a file).
    assert hooks["fkcheck-lint"]["entry"] == "fkcheck lint --only-models --"
    assert "stages" not in hooks["fkcheck-lint"]  # every commit
    assert hooks["fkcheck-check"]["entry"] == "fkcheck check --only-models --"
    assert hooks["fkcheck-check"]["stages"] == ["manual"]  # opt-in
    project = tomllib.loads((REPO_ROOT / "pyproject.toml").read_text())["project"]
    assert project["scripts"]["fkcheck"] == "fkcheck.cli.main:main"
    # Lint installs fkcheck alone (light); the check adds the reference extra, word for word.
    assert "additional_dependencies" not in hooks["fkcheck-lint"]
    assert (
        hooks["fkcheck-check"]["additional_dependencies"]
        == (project["optional-dependencies"]["reference"])
    )


def _entry(hook_id):
    hooks = {h["id"]: h for h in yaml.safe_load((REPO_ROOT / ".pre-commit-hooks.yaml").read_text())}
    words = hooks[hook_id]["entry"].split()
    assert words[0] == "fkcheck"
    return words[1:]


@pytest.mark.parametrize(
    ("other", "text"),
    [
        ("Cargo.toml", '[package]\nname = "x"\nversion = "0.1.0"\n'),
        ("pyproject.toml", "[project]\nname = 'x'\n\n[tool.fkcheck]\nsamples = 3\n"),
        ("config/settings.toml", "[joint_limits]\nmax = 3\n"),
        ("poses.csv", "q1,q2,x,y,z,qx,qy,qz,qw\n0,0,1.8,0,0,0,0,0,1\n"),
        ("--against=cmd:x.toml", 'title = "a file named like an option"\n'),
    ],
)
def test_the_lint_hook_lints_the_robot_files_and_passes_over_the_others(
    tmp_path, monkeypatch, capsys, other, text
):
    """What pre-commit runs for a commit touching a robot file and another TOML/CSV file."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "robots").mkdir()
    shutil.copyfile(bundled_model_paths()["ur5"], tmp_path / "robots" / "arm.toml")
    (tmp_path / other).parent.mkdir(parents=True, exist_ok=True)
    (tmp_path / other).write_text(text)
    assert main([*_entry("fkcheck-lint"), other, "robots/arm.toml"]) == 0
    out, err = capsys.readouterr()
    assert out == "robots/arm.toml: clean (6 joints, standard DH)\n"
    assert err == f"fkcheck lint: not robot model files, passed over: {other}\n"
    # Alone, it is nothing to lint or check: exit 0, said once.
    assert main([*_entry("fkcheck-lint"), other]) == 0
    assert capsys.readouterr().err.endswith("no robot model file among the files named\n")
    assert main([*_entry("fkcheck-check"), other]) == 0
    assert capsys.readouterr().err.endswith("no robot model file among the files named\n")


def test_the_hooks_still_lint_a_broken_model_file(tmp_path, monkeypatch, capsys):
    """A file with [[joint]] tables is a model file even when it is wrong: exit 2, one line."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "arm.toml").write_text('name = "arm"\n[[joint]]\na = "x"\n')
    assert main([*_entry("fkcheck-lint"), "arm.toml"]) == 2
    assert capsys.readouterr().err.startswith("fkcheck: error: arm.toml: ")
    assert main([*_entry("fkcheck-check"), "arm.toml"]) == 2
    assert capsys.readouterr().err.startswith("fkcheck: error: arm.toml: ")


def test_lint_imports_no_reference_library():
    code = (
        "import sys\n"
        "from fkcheck.cli.main import main\n"
        f"rc = main(['lint', *{sorted(str(p) for p in bundled_model_paths().values())!r}])\n"
        f"print('imported:', sorted(m for m in {REFERENCES!r} if m in sys.modules))\n"
        "sys.exit(rc)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "imported: []"


def _user_repo(root):
    """robots/good.toml (the bundled UR5), bad.toml (α4 of the wrong sign), rounded.toml."""
    robots = root / "robots"
    robots.mkdir(parents=True)
    text = bundled_model_paths()["ur5"].read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    wrist_1 = lines.index('name = "wrist_1"\n')
    assert lines[wrist_1 + 2] == "alpha = 90\n"
    (robots / "good.toml").write_text(text, encoding="utf-8")
    lines[wrist_1 + 2] = "alpha = -90\n"
    (robots / "bad.toml").write_text("".join(lines), encoding="utf-8")
    lines[wrist_1 + 2] = "alpha = 89.9999\n"  # 90° rounded: lint's rounded-angle
    (robots / "rounded.toml").write_text("".join(lines), encoding="utf-8")
    git = ["git", "-c", "user.name=fkcheck", "-c", "user.email=fkcheck@example.invalid"]
    subprocess.run([*git, "init", "-q"], cwd=root, check=True)
    subprocess.run([*git, "add", "-A"], cwd=root, check=True)
    subprocess.run([*git, "commit", "-q", "-m", "robots"], cwd=root, check=True)


#: pre-commit's status line of a hook: ``fkcheck lint......Failed``.
STATUS = re.compile(r"^fkcheck (lint|check)\.{3,}")


def _section(output, hook_name):
    """The lines pre-commit printed for one hook (from its status line to the next)."""
    lines = output.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(hook_name + "..."))
    end = next((i for i in range(start + 1, len(lines)) if STATUS.match(lines[i])), len(lines))
    return "\n".join(lines[start:end])


@pytest.mark.slow
def test_pre_commit_try_repo_runs_both_hooks_on_a_user_repository(tmp_path):
    assert shutil.which("git"), "git is needed by pre-commit"
    assert (REPO_ROOT / ".git").exists(), "pre-commit try-repo needs this repository's git checkout"
    user = tmp_path / "user"
    _user_repo(user)
    env = {**os.environ, "PRE_COMMIT_HOME": str(tmp_path / "pre-commit-home")}
    env.pop("PYTHONPATH", None)  # the hooks run the copy pre-commit installs, not this one
    env.pop("GITHUB_STEP_SUMMARY", None)
    env["SKIP"] = "fkcheck-lint-system"  # the fkcheck on PATH: its own test below
    # One try-repo (one install, minutes): the manual stage runs both hooks.
    done = subprocess.run(
        [sys.executable, "-m", "pre_commit", "try-repo", str(REPO_ROOT), "--all-files",
         "--hook-stage", "manual", "--verbose", "--color", "never"],
        cwd=user, env=env, capture_output=True, text=True, timeout=1200, check=False,
    )  # fmt: skip
    output = done.stdout + done.stderr
    assert done.returncode == 1, output
    lint = _section(output, "fkcheck lint")
    assert "Failed" in lint.splitlines()[0], output
    assert "robots/good.toml: clean (6 joints, standard DH)" in lint
    assert "robots/bad.toml: clean (6 joints, standard DH)" in lint  # a sign is no lint matter
    assert "robots/rounded.toml: joint[3].alpha (wrist_1): warning [rounded-angle]" in lint
    assert "fkcheck lint: 3 models, 2 clean, 1 with warnings" in lint
    check = _section(output, "fkcheck check")
    assert "Failed" in check.splitlines()[0], output
    rows = {line.split("│")[1].strip(): line.split("│")[2].strip()
            for line in check.splitlines() if line.startswith("│ robots/")}  # fmt: skip
    assert rows["robots/good.toml"] == "pass"
    assert rows["robots/bad.toml"] == "fail"
    assert "robots/bad.toml: pinocchio-urdf: " in check


#: The lint hook's environment at most (issue 32: "the default lint hook <= 200 MB").
LINT_HOOK_BYTES = 200 * 10**6


@pytest.mark.slow
def test_the_lint_hooks_own_environment_has_no_reference_library_and_is_small(tmp_path):
    """``pre-commit install-hooks`` of fkcheck-lint at this checkout's HEAD, as a user's repo does.

    (``try-repo`` above keeps its environments in a directory it deletes.)
    """
    assert (REPO_ROOT / ".git").exists(), "pre-commit needs this repository's git checkout"
    user = tmp_path / "user"
    _user_repo(user)
    rev = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=REPO_ROOT, capture_output=True, text=True, check=True
    ).stdout.strip()
    (user / ".pre-commit-config.yaml").write_text(
        f"repos:\n  - repo: {REPO_ROOT}\n    rev: {rev}\n    hooks:\n      - id: fkcheck-lint\n",
        encoding="utf-8",
    )
    home = tmp_path / "pre-commit-home"
    env = {**os.environ, "PRE_COMMIT_HOME": str(home)}
    env.pop("PYTHONPATH", None)  # the hook's own environment, not this checkout
    done = subprocess.run(
        [sys.executable, "-m", "pre_commit", "install-hooks"],
        cwd=user, env=env, capture_output=True, text=True, timeout=1200, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    (hook_env,) = home.glob("repo*/py_env-*")
    assert not list(hook_env.glob("lib/python3*/site-packages/scipy"))
    assert not list(hook_env.glob("lib/python3*/site-packages/pin-*"))
    assert 0 < _size(hook_env) <= LINT_HOOK_BYTES, _size(hook_env)


def _size(root: Path) -> int:
    """Bytes of the files under ``root`` (as ``du`` counts them, links not followed)."""
    return sum(p.lstat().st_size for p in root.rglob("*") if p.is_file() and not p.is_symlink())


def _try_system_lint(user, path):
    """``pre-commit try-repo`` of fkcheck-lint-system in ``user`` with ``path`` as PATH."""
    env = {**os.environ, "PATH": path, "PRE_COMMIT_HOME": str(user.parent / "pre-commit-home")}
    env.pop("GITHUB_STEP_SUMMARY", None)
    done = subprocess.run(
        [sys.executable, "-m", "pre_commit", "try-repo", str(REPO_ROOT), "fkcheck-lint-system",
         "--all-files", "--verbose", "--color", "never"],
        cwd=user, env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    return done.returncode, done.stdout + done.stderr


def test_pre_commit_runs_the_system_lint_hook_with_the_fkcheck_on_path(tmp_path):
    """fkcheck-lint-system through the real pre-commit: no environment, the fkcheck on PATH."""
    assert shutil.which("git"), "git is needed by pre-commit"
    assert (REPO_ROOT / ".git").exists(), "pre-commit try-repo needs this repository's git checkout"
    user = tmp_path / "user"
    _user_repo(user)
    # PATH: an fkcheck that runs this checkout's source (the project's own fkcheck), then
    # the test's PATH without any other fkcheck (git and its helpers are needed).
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    dirs = os.environ["PATH"].split(os.pathsep)
    others = [d for d in dirs if d and not Path(d, "fkcheck").exists()]
    path = os.pathsep.join([str(bin_dir), *others])
    fkcheck = bin_dir / "fkcheck"
    fkcheck.write_text(
        f'#!/bin/sh\nPYTHONPATH={REPO_ROOT / "src"} exec {sys.executable} -m fkcheck "$@"\n',
        encoding="utf-8",
    )
    fkcheck.chmod(0o755)
    rc, output = _try_system_lint(user, path)
    assert rc == 1, output
    lint = _section(output, "fkcheck lint")
    assert "Failed" in lint.splitlines()[0], output
    assert "- hook id: fkcheck-lint-system" in lint
    assert "robots/good.toml: clean (6 joints, standard DH)" in lint
    assert "robots/rounded.toml: joint[3].alpha (wrist_1): warning [rounded-angle]" in lint
    assert "fkcheck lint: 3 models, 2 clean, 1 with warnings" in lint
    # No environment was built: pre-commit's home holds its clone of the hooks repository.
    home = tmp_path / "pre-commit-home"
    assert not list(home.glob("*/py_env-*")), sorted(p.name for p in home.rglob("py_env-*"))
    # The rounded angle corrected: every table passes.
    for name in ("bad.toml", "rounded.toml"):
        (user / "robots" / name).unlink()
    subprocess.run(["git", "add", "-A"], cwd=user, check=True)
    rc, output = _try_system_lint(user, path)
    assert rc == 0, output
    lint = _section(output, "fkcheck lint")
    assert "Passed" in lint.splitlines()[0], output
    assert "robots/good.toml: clean (6 joints, standard DH)" in lint
    # Without an fkcheck on PATH: pre-commit's one line, exit 1.
    fkcheck.unlink()
    (user / "robots" / "good.toml").write_text(
        (user / "robots" / "good.toml").read_text(encoding="utf-8") + "\n", encoding="utf-8"
    )
    rc, output = _try_system_lint(user, path)
    assert rc == 1, output
    lint = _section(output, "fkcheck lint")
    assert "Failed" in lint.splitlines()[0], output
    assert "Executable `fkcheck` not found" in lint.splitlines(), output
