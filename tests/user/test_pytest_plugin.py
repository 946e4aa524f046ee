"""The pytest plugin in a throw-away user repository: plain `pytest` and `pytest -n 2`.

The repository has a ``pyproject.toml`` with ``[tool.fkcheck]``, ``robots/good.toml``
(the bundled UR5), ``robots/bad.toml`` (α4 of the wrong sign) and
``robots/planar.toml`` (no URDF: the URDF backend does not apply, and the table
cannot be verified). pytest runs in a subprocess, as a user runs it; the plugin
is found through its ``pytest11`` entry point.
"""

from __future__ import annotations

import importlib.metadata
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from fkcheck._version import __version__
from fkcheck.model.read import bundled_model_paths
from tests.paths import REPO_ROOT
from tests.user.userrepo import WRONG_ALPHA, make_user_repo

TOOL_FKCHECK = """\
models = ["robots/*.toml"]
samples = 50
against = ["rtb-dh", "pinocchio-urdf"]
require = ["table"]
"""

#: Every test the plugin collects, and its outcome.
EXPECTED = {
    "robots/bad.toml::fkcheck[rtb-dh]": "PASSED",
    "robots/bad.toml::fkcheck[pinocchio-urdf]": "FAILED",
    "robots/bad.toml::fkcheck[require:table]": "FAILED",
    "robots/good.toml::fkcheck[rtb-dh]": "PASSED",
    "robots/good.toml::fkcheck[pinocchio-urdf]": "PASSED",
    "robots/good.toml::fkcheck[require:table]": "PASSED",
    "robots/planar.toml::fkcheck[rtb-dh]": "PASSED",
    "robots/planar.toml::fkcheck[pinocchio-urdf]": "SKIPPED",
    "robots/planar.toml::fkcheck[require:table]": "FAILED",
}


def _entry_point() -> str:
    """What pyproject.toml registers as the ``pytest11`` entry point ``fkcheck``."""
    with (REPO_ROOT / "pyproject.toml").open("rb") as f:
        project = tomllib.load(f)["project"]
    return str(project["entry-points"]["pytest11"]["fkcheck"])


def test_pyproject_registers_the_plugin() -> None:
    assert _entry_point() == "fkcheck.pytest_plugin"


def _env(tmp_path: Path) -> dict[str, str]:
    """This checkout's fkcheck, and its entry point even where the installed metadata is older.

    An editable install made before the entry point existed does not announce
    it; a ``.dist-info`` with the entry point pyproject.toml declares stands in
    for it then (pytest loads an entry point name once, so it never doubles).
    """
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTEST_", "GITHUB_"))}
    paths = [str(REPO_ROOT / "src")]
    installed = [
        ep for ep in importlib.metadata.entry_points(group="pytest11") if ep.name == "fkcheck"
    ]
    if not installed:
        shim = tmp_path / "shim"
        info = shim / "fkcheck_pytest_entry-0.dist-info"
        info.mkdir(parents=True)
        (info / "METADATA").write_text(
            "Metadata-Version: 2.1\nName: fkcheck-pytest-entry\nVersion: 0\n", encoding="utf-8"
        )
        (info / "entry_points.txt").write_text(
            f"[pytest11]\nfkcheck = {_entry_point()}\n", encoding="utf-8"
        )
        paths.append(str(shim))
    env["PYTHONPATH"] = os.pathsep.join([*paths, env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env


def _run(tmp_path: Path, *args: str) -> subprocess.CompletedProcess[str]:
    repo = make_user_repo(tmp_path / "repo", TOOL_FKCHECK)
    planar = bundled_model_paths()["planar2"].read_text(encoding="utf-8")
    (repo / "robots" / "planar.toml").write_text(planar, encoding="utf-8")
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA", *args],
        cwd=repo,
        env=_env(tmp_path),
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


def _outcomes(stdout: str) -> dict[str, str]:
    """Node id → outcome, from ``-v`` lines (with or without xdist's ``[gw0] [ 11%]``)."""
    plain = re.finditer(r"^(robots/\S+) (PASSED|FAILED|SKIPPED)", stdout, re.MULTILINE)
    xdist = re.finditer(r"^\[gw\d\] \[ *\d+%\] (PASSED|FAILED|SKIPPED) (robots/\S+)", stdout,
                        re.MULTILINE)  # fmt: skip
    return {
        **{m.group(1): m.group(2) for m in plain},
        **{m.group(2): m.group(1) for m in xdist},
    }


def _assert_report(result: subprocess.CompletedProcess[str]) -> None:
    out = result.stdout
    assert result.returncode == 1, out + result.stderr  # tests failed (not a usage error)
    assert _outcomes(out) == EXPECTED, out
    assert re.search(r"3 failed, 5 passed, 1 skipped", out), out
    # The bad model's failure names the backend, the numbers, the worst q and the diagnosis.
    section = out.split("robots/bad.toml::fkcheck[pinocchio-urdf] _", 1)[1]
    assert "fkcheck ur5: base → tool0: fail — table disagrees" in section
    assert re.search(r"pinocchio-urdf: fail — max position error 251 mm \(2\.51e-01 m\), "
                     r"max rotation error 180° \(\S+ rad\)", section)  # fmt: skip
    assert re.search(r"worst q: \[(-?\d+\.\d\d°, ){5}-?\d+\.\d\d°\]", section)
    assert f"diagnosis: {WRONG_ALPHA}" in section
    assert "Traceback" not in out
    assert "pytest_plugin.py" not in out
    # The skip is a skip with its reason, at the model file; the evidence fails by name.
    assert re.search(r"SKIPPED \[1\] robots/planar\.toml:1: pinocchio-urdf: model has no \[urdf\]",
                     out), out  # fmt: skip
    assert "required evidence 'table' not verified (not-checked): table NOT CHECKED" in out
    assert "required evidence 'table' not verified (failed): table FAILED: pinocchio-urdf" in out
    # The good UR5 is verified partly on the word of its vouched frames: the run says so.
    vouched = out.split("fkcheck: verified on a vouch's word", 1)[1]
    assert re.search(r"robots/good\.toml: θ1, α6, θ6 on the word of \[frames\.base_link\]", vouched)


@pytest.mark.slow
def test_plain_pytest_collects_a_test_per_model_and_backend(tmp_path: Path) -> None:
    pytest.importorskip("pinocchio")
    _assert_report(_run(tmp_path, "-v"))


@pytest.mark.slow
def test_pytest_xdist_spreads_the_models(tmp_path: Path) -> None:
    pytest.importorskip("pinocchio")
    pytest.importorskip("xdist")
    result = _run(tmp_path, "-n", "2", "-v")
    assert re.search(r"created: 2/2 workers", result.stdout), result.stdout
    _assert_report(result)


_SHARE_TEST = """
import os

from fkcheck.process.cpus import usable_cores
from fkcheck.process.threads import thread_limit


def test_the_worker_has_its_share():
    assert os.environ["PYTEST_XDIST_WORKER_COUNT"] == "2"
    assert thread_limit() == max(1, usable_cores() // 2)
    assert os.environ["OPENBLAS_NUM_THREADS"] == str(thread_limit())
"""


def test_xdist_workers_of_a_project_with_models_share_the_cores(tmp_path: Path) -> None:
    # Set when the plugin configures each worker: before any of its tests, the
    # project's own ones included.
    pytest.importorskip("xdist")
    repo = make_user_repo(tmp_path / "repo", TOOL_FKCHECK)
    (repo / "test_share.py").write_text(_SHARE_TEST, encoding="utf-8")
    env = _env(tmp_path)
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
        env.pop(name, None)
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", "2", "test_share.py"],
        cwd=repo, env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stdout + result.stderr
    assert re.search(r"\b1 passed", result.stdout), result.stdout


def test_the_report_header_names_the_version_and_the_models(tmp_path: Path) -> None:
    result = _run(tmp_path, "--collect-only")
    assert result.returncode == 0, result.stdout + result.stderr
    header = result.stdout.split("collected ", 1)[0]
    assert f"\nfkcheck {__version__}: 3 [tool.fkcheck] models\n" in header, header


def test_a_project_without_tool_fkcheck_collects_nothing(tmp_path: Path) -> None:
    repo = tmp_path / "plain"
    (repo / "robots").mkdir(parents=True)
    (repo / "pyproject.toml").write_text('[project]\nname = "x"\nversion = "0"\n', "utf-8")
    (repo / "robots" / "good.toml").write_text(bundled_model_paths()["ur5"].read_text("utf-8"))
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider"],
        cwd=repo, env=_env(tmp_path), capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 5, result.stdout  # pytest: no tests collected
    assert "collected 0 items" in result.stdout
    assert f"fkcheck {__version__}:" not in result.stdout  # no models: no header line


def test_a_bad_tool_fkcheck_table_is_one_usage_error(tmp_path: Path) -> None:
    repo = make_user_repo(tmp_path / "repo", 'models = ["robots/*.toml"]\nsampels = 5\n')
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider"],
        cwd=repo, env=_env(tmp_path), capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 4, result.stdout + result.stderr  # pytest: usage error
    assert "tool.fkcheck.sampels: unknown key; keys are: models," in result.stderr
    assert "Traceback" not in result.stderr


def test_a_tolerance_beyond_its_bound_in_tool_fkcheck_is_one_usage_error(tmp_path: Path) -> None:
    # `tol_pos_m = 1000` accepted any table, and still said "table verified".
    repo = make_user_repo(tmp_path / "repo", 'models = ["robots/*.toml"]\ntol_pos_m = 1000\n')
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider"],
        cwd=repo, env=_env(tmp_path), capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 4, result.stdout + result.stderr  # pytest: usage error
    assert re.search(
        r"fkcheck: .*pyproject\.toml: tool\.fkcheck\.tol_pos_m: must be > 0 and at most 0\.01 m "
        r"\(.*\), got 1000$",
        result.stderr,
        re.MULTILINE,
    ), result.stderr
    assert "Traceback" not in result.stderr


def test_a_models_tolerance_beyond_its_bound_is_its_failing_load_test(tmp_path: Path) -> None:
    repo = make_user_repo(tmp_path / "repo", 'models = ["robots/"]\nsamples = 5\n')
    (repo / "robots" / "bad.toml").unlink()
    good = repo / "robots" / "good.toml"
    good.write_text(good.read_text("utf-8") + "tol_rot_rad = 10\n", "utf-8")  # in [check]
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA"],
        cwd=repo, env=_env(tmp_path), capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 1, result.stdout
    assert "collected 1 item" in result.stdout
    assert re.search(r"^FAILED robots/good\.toml::fkcheck\[load\]", result.stdout, re.MULTILINE)
    assert re.search(
        r"good\.toml: check\.tol_rot_rad: must be > 0 and at most 0\.1 rad \(.*\), got 10",
        result.stdout,
    ), result.stdout


def test_an_unreadable_model_is_one_failing_test(tmp_path: Path) -> None:
    repo = make_user_repo(tmp_path / "repo", 'models = ["robots/"]\nsamples = 5\n')
    (repo / "robots" / "good.toml").unlink()
    (repo / "robots" / "bad.toml").write_text('name = "x"\nconvention = "sideways"\n', "utf-8")
    result = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA"],
        cwd=repo, env=_env(tmp_path), capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 1, result.stdout
    assert "collected 1 item" in result.stdout
    assert re.search(r"^FAILED robots/bad\.toml::fkcheck\[load\]", result.stdout, re.MULTILINE)
    assert "bad.toml: convention: 'sideways' is not one of: standard, modified" in result.stdout


def test_the_plugin_reads_a_bags_settings_from_tool_fkcheck(tmp_path: Path, monkeypatch) -> None:
    # In process: the options the plugin hands the backends it builds for a model.
    from types import SimpleNamespace

    from fkcheck import api, pytest_plugin
    from fkcheck.backends import registry
    from fkcheck.model.project import load_project

    (tmp_path / "pyproject.toml").write_text(
        '[tool.fkcheck]\nagainst = ["poses:rec.mcap"]\nbag_joint_states = "/ur/joint_states"\n'
        'bag_tf = "/ur/tf"\nbag_tf_static = "/ur/tf_static"\nbag_stamp_tolerance = 0.002\n',
        encoding="utf-8",
    )
    handed: list = []

    def parse_against(names, options):
        handed.append((list(names), options))
        return []

    monkeypatch.setattr(registry, "parse_against", parse_against)
    monkeypatch.setattr(api, "check_request", lambda request: "checked")
    model_file = SimpleNamespace(
        project=load_project(tmp_path), path=bundled_model_paths()["ur5"], _error=None
    )
    assert pytest_plugin.ModelFile._run(model_file) == "checked"
    ((names, options),) = handed
    assert names == ["poses:rec.mcap"]
    assert (
        options.bag_joint_states,
        options.bag_tf,
        options.bag_tf_static,
        options.bag_stamp_tolerance_s,
    ) == ("/ur/joint_states", "/ur/tf", "/ur/tf_static", 0.002)
