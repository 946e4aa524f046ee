"""One options object: every way into a check refuses a bad value alike, and its limit arrives.

The ways in are ``fkcheck check`` (flags, and so the GitHub Action, which
passes flags), ``[tool.fkcheck]``, :func:`fkcheck.check` and the pytest
plugin; each builds :class:`~fkcheck.model.options.CheckOptions`. Before it,
the 120 s timeout and the 1,000-sample default were written in four or five
places, ``[tool.fkcheck] seed`` stopped at 2**32 - 1 while ``--seed`` took
2**64 - 1, the plugin's timeout never reached the engine, ``fkcheck.check``'s
never reached a ``cmd:`` program, and ``fkcheck.check`` checked neither samples
nor seed.
"""

from __future__ import annotations

import inspect
import json
import math
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

import fkcheck
import fkcheck.api
from fkcheck.backends.registry import BackendOptions
from fkcheck.cli.main import main
from fkcheck.engine.request import CheckRequest
from fkcheck.engine.runner import run_check
from fkcheck.errors import OptionError
from fkcheck.model.options import (
    DEFAULT_SAMPLER,
    DEFAULT_SAMPLES,
    DEFAULT_SEED,
    DEFAULT_TIMEOUT_S,
    FLAGS,
    MAX_SAMPLES,
    MAX_SEED,
    MAX_TIMEOUT_S,
    OPTIONS,
    PROJECT_KEYS,
    CheckOptions,
    OptionName,
    jacobian_for,
    option_problem,
    resolve_options,
)
from fkcheck.model.project import ProjectError, load_project
from fkcheck.model.read import bundled_model_paths, load_model
from tests.user.test_pytest_plugin import _env

PLANAR2 = str(bundled_model_paths()["planar2"])

#: Out of range wherever they come in: (option, value, as TOML and as a flag's text).
BAD: list[tuple[OptionName, object, str]] = [
    ("samples", -1, "-1"),
    ("samples", MAX_SAMPLES + 1, str(MAX_SAMPLES + 1)),
    ("seed", -1, "-1"),
    ("seed", MAX_SEED + 1, str(MAX_SEED + 1)),
    ("timeout_s", 0.0, "0.0"),
    ("timeout_s", 2 * MAX_TIMEOUT_S, f"{2 * MAX_TIMEOUT_S:.1f}"),
    ("timeout_s", math.nan, "nan"),
    ("processes", 0, "0"),
]
IDS = [f"{name}={text}" for name, _, text in BAD]


def _project(root: Path, table: str) -> Path:
    (root / ".git").mkdir(parents=True, exist_ok=True)  # the repository's root: none above
    (root / "pyproject.toml").write_text(f"[tool.fkcheck]\n{table}\n", encoding="utf-8")
    return root / "pyproject.toml"


def test_the_defaults_are_written_once():
    options = CheckOptions()
    assert (options.samples, options.seed, options.sampler, options.timeout_s) == (
        DEFAULT_SAMPLES,
        DEFAULT_SEED,
        DEFAULT_SAMPLER,
        DEFAULT_TIMEOUT_S,
    )
    assert BackendOptions().timeout_s == DEFAULT_TIMEOUT_S
    # The engine restates none of them: a request's options are CheckOptions' own.
    assert not set(OPTIONS) & set(inspect.signature(run_check).parameters)
    assert CheckRequest(load_model(PLANAR2), ()).options == options
    assert resolve_options() == options
    assert set(FLAGS) == set(OPTIONS)
    assert set(PROJECT_KEYS) == set(OPTIONS) - {"frame_from", "frame_to"}


@pytest.mark.parametrize(("name", "value", "text"), BAD, ids=IDS)
def test_a_bad_value_is_refused_alike_by_the_api_the_flag_and_the_project_file(
    tmp_path, monkeypatch, capsys, name, value, text
):
    problem = option_problem(name, value)
    assert problem is not None
    assert problem.startswith("must be ")
    assert ", got " in problem
    # fkcheck.check: an OptionError (a ValueError) naming the argument, before any work.
    with pytest.raises(OptionError) as api:
        fkcheck.check(PLANAR2, against=["rtb-dh"], **{name: value})
    assert str(api.value) == f"{name}: {problem}"
    assert isinstance(api.value, ValueError)
    # CheckOptions itself, and the engine called directly.
    with pytest.raises(OptionError, match=f"^{name}: "):
        CheckOptions(**{name: value})  # type: ignore[arg-type]
    with pytest.raises(OptionError, match=f"^{name}: "):
        run_check(load_model(PLANAR2), [], **{name: value})
    # fkcheck check: exit 2, one line naming the flag.
    monkeypatch.chdir(tmp_path)
    assert main(["check", PLANAR2, "--against", "rtb-dh", FLAGS[name], text]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines() == [f"fkcheck: error: {FLAGS[name]}: {problem}"]
    # [tool.fkcheck]: the same phrase, naming the key and the file; exit 2 from the CLI.
    key = PROJECT_KEYS[name]
    path = _project(tmp_path / "repo", f"{key} = {text}")
    with pytest.raises(ProjectError) as read:
        load_project(path.parent)
    assert (read.value.field, read.value.problem) == (f"tool.fkcheck.{key}", problem)
    monkeypatch.chdir(path.parent)
    assert main(["check", PLANAR2, "--against", "rtb-dh"]) == 2
    assert (
        capsys.readouterr().err.strip() == f"fkcheck: error: {path}: tool.fkcheck.{key}: {problem}"
    )


def test_the_pytest_plugin_refuses_a_bad_value_with_the_same_line(tmp_path):
    name, value, text = BAD[2]  # seed = -1
    problem = option_problem(name, value)
    repo = tmp_path / "repo"
    _project(repo, f'models = ["robots/*.toml"]\nseed = {text}')
    (repo / "robots").mkdir()
    (repo / "robots" / "planar.toml").write_text(Path(PLANAR2).read_text(encoding="utf-8"))
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q"],
        cwd=repo,
        env=_env(tmp_path),
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 4, done.stdout + done.stderr  # a usage error: nothing ran
    assert f"tool.fkcheck.seed: {problem}" in done.stderr


def test_one_seed_range_for_the_flag_the_argument_and_the_project_file(tmp_path):
    # [tool.fkcheck] seed stopped at 2**32 - 1 while --seed took 2**64 - 1.
    path = _project(tmp_path, f"seed = {MAX_SEED}")
    project = load_project(path.parent)
    assert project is not None
    assert project.options.get("seed") == MAX_SEED
    assert resolve_options(project=project.options).seed == MAX_SEED
    assert resolve_options({"seed": MAX_SEED}, labels=FLAGS).seed == MAX_SEED
    assert CheckOptions(seed=MAX_SEED).seed == MAX_SEED


def test_flag_wins_over_project_which_wins_over_the_default_and_each_says_where(tmp_path):
    path = _project(tmp_path, "samples = 7\nseed = 3\ntimeout = 30\ntol_pos_m = 1e-5")
    project = load_project(path.parent)
    options = resolve_options({"seed": 9, "tol_pos_m": None}, labels=FLAGS, project=project.options)
    assert (options.samples, options.seed, options.timeout_s, options.tol_pos_m) == (7, 9, 30, 1e-5)
    assert options.sampler == DEFAULT_SAMPLER
    assert options.tol_rot_rad is None  # the model's [check]
    assert options.sources["seed"] == "--seed"
    assert options.sources["samples"] == f"[tool.fkcheck] samples in {path}"
    assert options.tolerance_source == (f"[tool.fkcheck] tol_pos_m in {path}", "")
    assert "sampler" not in options.sources  # a default
    # An argument over options already resolved: it wins, and is the caller's.
    again = resolve_options({"samples": 2}, base=options)
    assert (again.samples, again.seed) == (2, 9)
    assert "samples" not in again.sources
    assert again.sources["seed"] == "--seed"


def _recording(monkeypatch: pytest.MonkeyPatch) -> dict[str, Any]:
    """Replace the engine behind ``fkcheck.check`` by one that records what reaches it."""
    seen: dict[str, Any] = {}

    def fake_run_request(request: CheckRequest, **kwargs: Any) -> object:
        options = request.options
        seen.update({name: getattr(options, name) for name in OPTIONS}, backends=request.backends)
        seen["tolerance_source"] = options.tolerance_source
        return SimpleNamespace()

    monkeypatch.setattr(fkcheck.api, "run_request", fake_run_request)
    return seen


def test_the_apis_timeout_reaches_the_engine_and_every_backend_it_names(monkeypatch):
    seen = _recording(monkeypatch)
    fkcheck.check(PLANAR2, against=["cmd:sleep 30", "rtb-dh"], timeout_s=1.5, diagnose=False)
    assert seen["timeout_s"] == 1.5
    assert [b.timeout_s for b in seen["backends"] if hasattr(b, "timeout_s")] == [1.5]
    seen.clear()
    fkcheck.check(PLANAR2, timeout_s=2.5, samples=3, seed=4, diagnose=False)  # the default set
    assert (seen["timeout_s"], seen["samples"], seen["seed"]) == (2.5, 3, 4)


def test_the_pytest_plugins_timeout_and_samples_reach_the_engine(tmp_path, monkeypatch):
    from fkcheck.pytest_plugin import ModelFile

    seen = _recording(monkeypatch)
    monkeypatch.setattr(fkcheck.api, "diagnose_failures", lambda *a: ())
    path = _project(
        tmp_path, 'models = ["*.toml"]\nagainst = ["cmd:sleep 30"]\ntimeout = 3\nsamples = 5'
    )
    project = load_project(path.parent)
    ModelFile._run(SimpleNamespace(project=project, path=Path(PLANAR2), _error=None))  # type: ignore[arg-type]
    assert (seen["timeout_s"], seen["samples"]) == (3.0, 5)
    assert [b.timeout_s for b in seen["backends"]] == [3.0]
    assert seen["tolerance_source"] == ("", "")  # none set: the model's [check]


def test_a_cmd_program_that_hangs_ends_at_the_apis_limit():
    hang = f"cmd:{sys.executable} -c 'import time; time.sleep(60)'"
    start = time.monotonic()
    outcome = fkcheck.check(PLANAR2, against=[hang], timeout_s=1, samples=0, diagnose=False)
    assert time.monotonic() - start < 15
    (result,) = outcome.backends
    assert result.status == "error"
    assert "timed out after 1 s" in result.message


def test_a_cmd_program_that_hangs_ends_at_the_flags_limit(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    hang = f"cmd:{sys.executable} -c 'import time; time.sleep(60)'"
    start = time.monotonic()
    argv = ["check", PLANAR2, "--against", hang, "--timeout", "1", "--samples", "0"]
    assert main([*argv, "--no-diagnose", "-q", "--json", "r.json"]) == 1
    assert time.monotonic() - start < 15
    capsys.readouterr()
    (result,) = json.loads(Path("r.json").read_text(encoding="utf-8"))["backends"]
    assert result["status"] == "error"
    assert "timed out after 1 s" in result["message"]


def test_the_models_check_is_the_last_layer_for_the_jacobian():
    model = load_model(PLANAR2)
    assert not model.check.jacobian
    assert jacobian_for(CheckOptions(), model) is None
    asked = resolve_options({"jacobian": True, "tol_jacobian": 1e-4}, labels=FLAGS)
    assert jacobian_for(asked, model) == (model.check.jacobian_reference, 1e-4)
    local = CheckOptions(jacobian=True, jacobian_reference="local")
    assert jacobian_for(local, model) == ("local", model.check.tol_jacobian)
