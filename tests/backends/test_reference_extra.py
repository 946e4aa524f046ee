"""Without the ``reference`` extra: lint runs, each reference backend is unavailable, naming it.

fkcheck's own dependencies are what lint, fk and convert import; the reference
libraries (and SciPy, Matplotlib, numba) come with ``pip install 'fkcheck[reference]'``.
Each test runs a fresh interpreter in which every module of
:data:`fkcheck.errors.REFERENCE_LIBRARIES` is absent (``sys.modules[name] = None``:
``import`` fails, ``importlib.util.find_spec`` finds nothing), as in a venv
without the extra; ``nox -s dist`` installs the wheel without it for real.
"""

from __future__ import annotations

import subprocess
import sys
import tomllib

import pytest

from fkcheck.backends.registry import BUILTIN
from fkcheck.errors import INSTALL_REFERENCE, REFERENCE_LIBRARIES, missing_extra
from tests.paths import REPO_ROOT

#: Makes every reference library absent, then runs the rest of the script.
_ABSENT = (
    "import sys\n"
    "from fkcheck.errors import REFERENCE_LIBRARIES\n"
    "for name in REFERENCE_LIBRARIES:\n"
    "    sys.modules[name] = None\n"
)

_CLI = _ABSENT + "from fkcheck.cli.main import main\nsys.exit(main(sys.argv[1:]))\n"

#: The distribution each top-level module of REFERENCE_LIBRARIES comes from.
_DISTRIBUTION = {
    "scipy": "scipy",
    "matplotlib": "matplotlib",
    "numba": "numba",
    "llvmlite": "numba",
    "roboticstoolbox": "roboticstoolbox-python",
    "spatialmath": "roboticstoolbox-python",
    "pinocchio": "pin",
    "example_robot_data": "example-robot-data",
    "yourdfpy": "yourdfpy",
    "mujoco": "mujoco-core",
    "idyntree": "idyntree",
    "xacrodoc": "xacrodoc",
    "xacro": "xacrodoc",
    "rosbags": "rosbags",
}


def _run(script: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", script, *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def _requirement_names(requirements: list[str]) -> set[str]:
    return {r.split(">")[0].split("=")[0].split("[")[0].strip() for r in requirements}


def test_the_reference_extra_installs_every_library_fkcheck_names_as_its() -> None:
    with (REPO_ROOT / "pyproject.toml").open("rb") as f:
        project = tomllib.load(f)["project"]
    extra = _requirement_names(project["optional-dependencies"]["reference"])
    assert set(_DISTRIBUTION) == set(REFERENCE_LIBRARIES)
    assert set(_DISTRIBUTION.values()) <= extra
    # The light install has none of them: lint and the lint hook stay small.
    assert not extra & _requirement_names(project["dependencies"])
    # threadpoolctl (one pure-Python module, 82 KB) sizes the BLAS pools of xdist workers that share
    # the cores (fkcheck.process.threads); the pytest plugin may need it before any check.
    assert _requirement_names(project["dependencies"]) == {
        "numpy",
        "pyyaml",
        "jinja2",
        "rich",
        "threadpoolctl",
    }
    # fkcheck[pytest]: pytest and what its checks need, one command.
    assert project["optional-dependencies"]["pytest"] == ["fkcheck[reference]", "pytest>=8"]


@pytest.mark.parametrize("registration", [r for r in BUILTIN if r.default], ids=lambda r: r.name)
def test_each_default_backend_without_its_library_is_unavailable_naming_the_extra(
    registration,
) -> None:
    script = _ABSENT + (
        "from fkcheck.backends.registry import make_backend\n"
        "from fkcheck.model.read import load_model\n"
        "print(make_backend(sys.argv[1]).unavailable_reason(load_model('ur5')))\n"
    )
    done = _run(script, registration.name)
    assert done.returncode == 0, done.stderr
    reason = done.stdout.strip()
    assert reason.endswith(f"is not installed ({INSTALL_REFERENCE})"), reason


def test_rtb_model_without_robotics_toolbox_is_unavailable_naming_the_extra() -> None:
    script = _ABSENT + (
        "from fkcheck.backends.registry import make_backend\n"
        "from fkcheck.model.read import load_model\n"
        "print(make_backend('rtb-model:UR5').unavailable_reason(load_model('ur5')))\n"
    )
    done = _run(script)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == (
        f"Robotics Toolbox for Python (roboticstoolbox) is not installed ({INSTALL_REFERENCE})"
    )


#: The modules that import a reference library at their top: each is imported only by
#: the code that needs it (a backend, the numba kernels with their NumPy fallback, the
#: map's modules).
TOP_LEVEL_IMPORTERS = {
    "fkcheck.backends._idyntree",
    "fkcheck.core._jacobian_kernels",
    "fkcheck.core._kernels",
    "fkcheck.urdf.chain_fit",
    "fkcheck.urdf.hand_eye",
    "fkcheck.urdf.map_frames",
    "fkcheck.urdf.map_result",
    "fkcheck.urdf.mapping",
    "fkcheck.urdf.matching",
    "fkcheck.urdf.placement",
    "fkcheck.urdf.proposal",
}


def test_every_other_module_imports_without_the_reference_libraries() -> None:
    script = _ABSENT + (
        "import importlib, pkgutil, fkcheck\n"
        "for info in pkgutil.walk_packages(fkcheck.__path__, 'fkcheck.'):\n"
        "    if info.name != 'fkcheck.__main__':  # that one runs the CLI\n"
        "        try:\n"
        "            importlib.import_module(info.name)\n"
        "        except ImportError:\n"
        "            print(info.name)\n"
    )
    done = _run(script)
    assert done.returncode == 0, done.stderr
    assert set(done.stdout.split()) == TOP_LEVEL_IMPORTERS


def test_lint_and_fk_run_without_the_reference_libraries() -> None:
    lint = _run(_CLI, "lint", "ur5")
    assert (lint.returncode, lint.stderr) == (0, "")
    assert "clean (6 joints, standard DH)" in lint.stdout
    fk = _run(_CLI, "fk", "ur5", "--q", "0,0,0,0,0,0")
    assert (fk.returncode, fk.stderr) == (0, "")
    assert "-0.191450" in fk.stdout  # tool0's y at zero: -(d4 + d6)


def test_a_check_that_needs_scipy_says_so_in_one_line_and_exits_2() -> None:
    done = _run(_CLI, "check", "planar2", "--samples", "50")  # no URDF: SciPy first
    assert done.returncode == 2, done.stderr
    assert done.stderr == (
        "fkcheck: error: check: SciPy is not installed (no module 'scipy'); it comes "
        f"with fkcheck's 'reference' extra: {INSTALL_REFERENCE}\n"
    )


@pytest.mark.parametrize("argv", [["check", "ur5", "--samples", "50"], ["map", "ur5"], []])
def test_the_main_job_check_and_map_end_in_one_line_naming_the_extra(argv: list[str]) -> None:
    # The UR5's URDF is xacro (xacrodoc) and its check samples with SciPy: whichever is
    # reached first is named, with the extra that installs both.
    done = _run(_CLI, *argv)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith("fkcheck: error: "), done.stderr
    assert INSTALL_REFERENCE in done.stderr
    assert "Traceback" not in done.stdout


def test_missing_extra_names_only_the_reference_libraries() -> None:
    found = missing_extra(ModuleNotFoundError("No module named 'scipy.stats'", name="scipy.stats"))
    assert found is not None
    assert (found.module, found.library) == ("scipy", "SciPy")
    assert INSTALL_REFERENCE in str(found)
    # Any other missing module is a bug or a broken installation: not explained away.
    assert missing_extra(ModuleNotFoundError("No module named 'numpy'", name="numpy")) is None
    assert missing_extra(ModuleNotFoundError("no name")) is None
    assert missing_extra(ImportError("cannot import name 'x'", name="scipy")) is None
