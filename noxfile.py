"""Sessions: `nox` runs the default ones (tests, lint); CI calls the others by name."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import nox

nox.needs_version = ">=2025.2.9"
nox.options.default_venv_backend = "venv"
nox.options.reuse_existing_virtualenvs = True

PYPROJECT = nox.project.load_toml("pyproject.toml")


def _install(session: nox.Session, *groups: str, reference: bool = True) -> None:
    """fkcheck (editable) and the dependency groups; with the reference and ik extras unless not.

    ``reference=False``: fkcheck's own dependencies only (lint, convert, fk; what
    the docs build imports), without the reference libraries' ~1.7 GB. The ``ik``
    extra (the analytic IK solvers, a few MB) comes with ``reference``: the IK tests
    and the typecheck need it.
    """
    deps = [d for g in groups for d in nox.project.dependency_groups(PYPROJECT, g)]
    session.install("-e", ".[reference,ik]" if reference else ".", *deps)


#: The one environment of the sessions that need the reference extra (tests, slow,
#: bounded, typecheck, crossval, fuzz, wall, campaign), in nox's envdir: ``.nox/reference``.
REFERENCE_ENV = "reference"

#: What it holds besides fkcheck[reference,ik]: every group those sessions use.
_REFERENCE_GROUPS = ("test", "typecheck")


def _uv() -> str | None:
    """uv's program, from nox's environment (``nox[uv]``) or the PATH; ``None``: pip."""
    try:
        from uv import find_uv_bin  # the uv package's own locator

        return str(find_uv_bin())
    except (ImportError, FileNotFoundError):
        return shutil.which("uv")


def _reference_env(session: nox.Session) -> Path:
    """The shared environment's ``bin/``: created if missing, brought up to date.

    The sessions that need the ~1.8 GB of reference libraries (:data:`REFERENCE_ENV`'s)
    install them once into one venv, ``.nox/reference``, instead of once each (a
    fresh venv per session was five installs in CI, about 4 of its minutes, and 9 GB
    on disk). A session installs when the venv is missing or was installed from
    another ``pyproject.toml`` (a stamp in it says which; fkcheck is installed
    editable, so its sources need none), so a session run alone, on a clean clone,
    installs everything itself. With uv (``pip install 'nox[uv]'``, or ``uv`` on
    the PATH) it installs with uv — from uv's cache, seconds instead of pip's
    minute — into a venv seeded with pip (tests install into venvs of their own);
    else with pip. They are ``venv_backend="none"`` sessions that run
    the venv's programs by path. Two of them started at once in one checkout share
    it: let the first finish installing before starting the second.
    """
    venv = session.cache_dir.parent / REFERENCE_ENV  # cache_dir is <envdir>/.cache
    bin_dir = venv / "bin"
    uv = _uv()
    if not (bin_dir / "python").is_file():
        if uv:
            session.run(uv, "venv", "--quiet", "--seed", "--python", sys.executable, str(venv),
                        external=True)  # fmt: skip
        else:
            session.run(sys.executable, "-m", "venv", str(venv), external=True)
    groups = (nox.project.dependency_groups(PYPROJECT, g) for g in _REFERENCE_GROUPS)
    deps = list(dict.fromkeys(d for group in groups for d in group))  # each once
    # What was installed: pyproject.toml (fkcheck's dependencies, extras, entry points)
    # and the groups. The install is editable, so a change to the sources needs none.
    stamp = venv / ".fkcheck-installed"
    wanted = hashlib.sha256(Path("pyproject.toml").read_bytes() + repr(deps).encode()).hexdigest()
    if stamp.is_file() and stamp.read_text(encoding="utf-8") == wanted:
        session.log(f"{venv}: installed from this pyproject.toml (delete it to reinstall)")
    else:
        stamp.unlink(missing_ok=True)
        installer = (
            # Byte-compiled at install, as pip does: a module compiled at its first
            # import under the tests' warnings-as-errors fails on a library's
            # SyntaxWarning (spatialmath's "\m"), and the suite's first imports wait.
            [uv, "pip", "install", "--compile-bytecode", "--python", str(bin_dir / "python")]
            if uv
            else [str(bin_dir / "python"), "-m", "pip", "install"]
        )
        session.run(*installer, "-e", ".[reference,ik]", *deps, external=True, silent=True)
        stamp.write_text(wanted, encoding="utf-8")
    session.env["VIRTUAL_ENV"] = str(venv)
    session.env["PATH"] = os.pathsep.join([str(bin_dir), os.environ.get("PATH", "")])
    return bin_dir


#: pytest-xdist's workers: one per CPU (2 on two cores), each given whole test files
#: (`loadfile`: a module-scoped fixture, often a check, is computed once). A test that
#: shares a file, a port or the environment with another is a bug under it (CONTRIBUTING.md).
PARALLEL = ("-n", "auto", "--dist", "loadfile")

#: The slow tests' workers take single tests (`worksteal`): one file's three property
#: runs (tests/urdf/test_map_link_choice_property.py) are almost half the session's time,
#: and whole files kept them on one worker. No slow test shares a module-scoped fixture.
SLOW_PARALLEL = ("-n", "auto", "--dist", "worksteal")


@nox.session(venv_backend="none")
def tests(session: nox.Session) -> None:
    """Run the test suite in parallel, without the tests marked ``slow``.

    Bounded property-based examples. The long runs (marker ``slow``: the stress
    run, the long property run of map, the tests that build an environment, run
    the pytest plugin in a project or check every bundled model) are ``nox -s
    slow``'s; CI runs both. In the shared environment (``.nox/reference``).
    """
    bin_dir = _reference_env(session)
    session.run(bin_dir / "pytest", *PARALLEL, "-m", "not slow", *session.posargs, external=True)


@nox.session(default=False, venv_backend="none")
def slow(session: nox.Session) -> None:
    """Run the tests marked ``slow`` (``nox -s tests`` leaves them out), in parallel."""
    bin_dir = _reference_env(session)
    session.run(bin_dir / "pytest", *SLOW_PARALLEL, "-m", "slow", *session.posargs, external=True)


@nox.session
def lint(session: nox.Session) -> None:
    """Ruff lint, and the import contract (reference backends never import fkcheck's maths).

    Neither reads fkcheck's dependencies (import-linter parses the sources and
    only needs the package found), so they are not installed: 1.8 GB less on disk.
    """
    session.install("--no-deps", "-e", ".")
    session.install(*nox.project.dependency_groups(PYPROJECT, "lint"))
    session.run("ruff", "check", "src", "tests", "noxfile.py")
    session.run("lint-imports")


@nox.session(default=False)
def actionlint(session: nox.Session) -> None:
    """actionlint on .github/workflows (which checks action.yml's inputs through `uses: ./`)."""
    session.install(*nox.project.dependency_groups(PYPROJECT, "actionlint"))  # not fkcheck
    session.run("actionlint")


@nox.session(default=False, venv_backend="none")
def typecheck(session: nox.Session) -> None:
    """Mypy (strict) on src/, in the shared environment (``.nox/reference``)."""
    session.run(_reference_env(session) / "mypy", external=True)


@nox.session(default=False, venv_backend="none")
def fuzz(session: nox.Session) -> None:
    """Property-based tests with 10x the examples of the default session."""
    bin_dir = _reference_env(session)
    session.env["FKCHECK_HYPOTHESIS_PROFILE"] = "fuzz"
    session.run(
        bin_dir / "pytest", "-k", "property", "--hypothesis-show-statistics", *session.posargs,
        external=True,
    )  # fmt: skip


#: Address-space limit of `nox -s bounded` (what `ulimit -v` sets), bytes.
BOUNDED_AS_BYTES = 2 << 30

_BOUNDED_PYTEST = (
    "import resource, sys, pytest; "
    "limit = int(sys.argv[1]); "
    "resource.setrlimit(resource.RLIMIT_AS, (limit, limit)); "
    "sys.exit(pytest.main(sys.argv[2:]))"
)


@nox.session(default=False, venv_backend="none")
def bounded(session: nox.Session) -> None:
    """The hostile-input suites and the big-input test under a 2 GiB address-space limit.

    `ulimit -v` for the test process and every fkcheck it starts: a reader that
    loads a whole hostile file, or a report built all at once, runs out of memory
    here instead of passing. In parallel (each pytest-xdist worker starts under the
    limit too), in the shared environment (``.nox/reference``).
    """
    bin_dir = _reference_env(session)
    session.run(
        bin_dir / "python", "-c", _BOUNDED_PYTEST, str(BOUNDED_AS_BYTES), "-p", "no:cacheprovider",
        *PARALLEL,
        "tests/hostile/test_hostile_inputs.py", "tests/hostile/test_hostile_urdf.py",
        "tests/hostile/test_hostile_xacro.py", "tests/hostile/test_hostile_outputs.py",
        "tests/hostile/test_hostile_processes.py", "tests/hostile/test_bounded_memory.py",
        "tests/hostile/test_hostile_calibration.py", "tests/hostile/test_property_calibration.py",
        "tests/hostile/test_bounded_work.py", "tests/hostile/test_hostile_readers.py",
        "tests/backends/test_bag.py",
        *session.posargs, external=True,
    )  # fmt: skip


@nox.session(default=False, venv_backend="none")
def crossval(session: nox.Session) -> None:
    """Check every bundled model against every default backend; fail when any disagrees.

    Writes reports/: per model <model>.json, <model>.html and <model>.junit.xml,
    plus index.html (every model x backend) and summary.md (also appended to
    $GITHUB_STEP_SUMMARY on GitHub Actions). Extra arguments go to
    `fkcheck check --all`, e.g. `nox -s crossval -- --samples 10000`.
    """
    session.run(
        _reference_env(session) / "fkcheck", "check", "--all", "--out-dir", "reports",
        "--summary", "reports/summary.md", *session.posargs, external=True,
    )  # fmt: skip


@nox.session(default=False)
def bench(session: nox.Session) -> None:
    """Time the in-house core against its peers: reports/bench.json and reports/bench.png.

    Runs `fkcheck bench ur5 --n 1000000` (the table is printed; exit 1 if a peer
    disagrees) and plots the JSON; then times Jacobians the same way,
    `fkcheck bench ur5 --jacobian --n 1000000` (reports/bench-jacobian.json).
    Extra arguments go to both `fkcheck bench` runs, e.g.
    `nox -s bench -- --repeat 9`. The pytest-benchmark suite is separate:
    `python -m pytest benchmarks`.
    """
    _install(session, "bench")
    session.run(
        "fkcheck", "bench", "ur5", "--n", "1000000", "--json", "reports/bench.json",
        *session.posargs,
    )  # fmt: skip
    session.run("python", "benchmarks/plot_bench.py", "reports/bench.json", "reports/bench.png")
    session.run(
        "fkcheck", "bench", "ur5", "--jacobian", "--n", "1000000",
        "--json", "reports/bench-jacobian.json", *session.posargs,
    )  # fmt: skip


@nox.session(default=False, venv_backend="none")
def wall(session: nox.Session) -> None:
    """Wall time of whole checks (benchmarks/check_wall.py): reports/check-wall.json.

    ``check ur5 --samples 10000`` with every default backend, median of 7 fresh
    runs, against ``--against rtb-dh`` alone in the same session; ``nox -s wall
    -- --big`` adds the 10⁶-sample and 3·10⁵-sample Jacobian checks.
    """
    session.run(
        _reference_env(session) / "python", "benchmarks/check_wall.py",
        "--json", "reports/check-wall.json", *session.posargs, external=True,
    )  # fmt: skip


@nox.session(default=False, venv_backend="none")
def campaign(session: nox.Session) -> None:
    """Verdict campaign (benchmarks/verdict_campaign.py): reports/verdict-campaign.json.

    Three vendors' published DH tables (UR5e, Franka Panda, ABB IRB 120), each mapped
    onto an independent URDF with ``fkcheck map`` and checked with ``--require table``,
    as published and with every single number wrong in turn: a table of caught, not
    identifiable, not covered and false green per arm; exit 1 on a false green or a
    published table refused. About 200 map → check runs.
    """
    session.run(
        _reference_env(session) / "python", "benchmarks/verdict_campaign.py",
        "--json", "reports/verdict-campaign.json", *session.posargs, external=True,
    )  # fmt: skip


@nox.session(default=False)
def docs(session: nox.Session) -> None:
    """Build the docs site (warnings are errors), with fkcheck's own dependencies only.

    `sphinx-build -W --keep-going` into docs/_build/html: the CLI, API, backends and
    model-file reference are generated from the code, so a docstring autodoc cannot
    read or a key without a description fails the build. It imports no reference
    library, so none is installed (no `reference` extra). The pages' examples run
    checks: tests/docs and the walkthrough and notebook tests (tests/user/test_docs_*)
    run them, in `nox -s tests`.
    """
    _install(session, "docs", reference=False)
    session.run(
        "sphinx-build", "-W", "--keep-going", "-b", "html", "docs", "docs/_build/html",
    )  # fmt: skip


def _built_version(wheel: Path) -> str:
    """The ``Version:`` of a wheel's METADATA."""
    with zipfile.ZipFile(wheel) as zf:
        name = next(n for n in zf.namelist() if n.endswith(".dist-info/METADATA"))
        for line in zf.read(name).decode("utf-8").splitlines():
            if line.startswith("Version: "):
                return line.removeprefix("Version: ")
    raise ValueError(f"{wheel.name}: no Version in its METADATA")


@nox.session(default=False)
def dist(session: nox.Session) -> None:
    """Build the sdist and wheel, `twine check --strict` them, and run each installed.

    Each of the two goes into a fresh venv of its own with the `reference` extra (the
    sdist through pip's build of it), which runs the main job (bare `fkcheck` in an
    empty directory: exit 0, reports/ur5.json and reports/ur5.html, the JSON's
    fkcheck_version the built version) and `fkcheck --version`; the venv is then
    removed. The wheel alone (no extra, as pre-commit's fkcheck-lint hook installs
    it) must lint a bundled model, must not have installed a reference library, and
    its main job must end in one line naming the extra (exit 2). Nothing is published.
    """
    session.install("build", "twine")
    work = Path(tempfile.mkdtemp(prefix="fkcheck-dist-"))
    try:
        out = work / "dist"
        session.run("python", "-m", "build", "--outdir", str(out), ".")
        (wheel,) = out.glob("fkcheck-*.whl")
        (sdist,) = out.glob("fkcheck-*.tar.gz")
        session.run("twine", "check", "--strict", str(wheel), str(sdist))
        version = _built_version(wheel)
        if sdist.name != f"fkcheck-{version}.tar.gz":
            session.error(f"sdist {sdist.name} is not version {version} (the wheel's)")
        for artefact in (wheel, sdist):
            _run_installed(session, artefact, version, work)
        _run_light(session, wheel, work)
        session.log(f"dist: {wheel.name} and {sdist.name} install and run the main job")
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _run_installed(session: nox.Session, artefact: Path, version: str, work: Path) -> None:
    """Install one artefact into a fresh venv; run the main job and --version there."""
    venv = work / "venv"
    run_dir = work / "run"
    bin_dir = venv / "bin"
    # Only the fresh venv: no PYTHONPATH reaching a checkout's src/; and no second
    # ur5 summary in a GitHub job's step summary.
    env: dict[str, str | None] = {
        "PYTHONPATH": None, "VIRTUAL_ENV": str(venv), "GITHUB_STEP_SUMMARY": None,
    }  # fmt: skip
    try:
        session.run("python", "-m", "venv", str(venv))
        session.run(
            str(bin_dir / "python"), "-m", "pip", "install", "--quiet",
            "--disable-pip-version-check", f"{artefact}[reference]", external=True, env=env,
        )  # fmt: skip
        run_dir.mkdir()
        with session.chdir(run_dir):
            session.run(str(bin_dir / "fkcheck"), external=True, env=env)  # the main job
        json_report = run_dir / "reports" / "ur5.json"
        html_report = run_dir / "reports" / "ur5.html"
        for report in (json_report, html_report):
            if not report.is_file():
                session.error(f"{artefact.name}: the main job wrote no {report.name}")
        reported = json.loads(json_report.read_text(encoding="utf-8"))["fkcheck_version"]
        if reported != version:
            session.error(f"{artefact.name}: ur5.json has fkcheck_version {reported!r}")
        shown = session.run(
            str(bin_dir / "fkcheck"), "--version", external=True, env=env, silent=True
        )
        if not isinstance(shown, str) or shown.strip() != f"fkcheck {version}":
            session.error(f"{artefact.name}: fkcheck --version printed {shown!r}")
        session.log(f"{artefact.name}: main job and `fkcheck --version` ({version}): ok")
    finally:
        shutil.rmtree(venv, ignore_errors=True)
        shutil.rmtree(run_dir, ignore_errors=True)


#: A reference library (the `reference` extra's), absent from a light install.
_REFERENCE_PROBE = (
    "import importlib.util, sys; "
    "found = [m for m in ('scipy', 'pinocchio', 'roboticstoolbox', 'numba', 'matplotlib', "
    "'rosbags') "
    "if importlib.util.find_spec(m)]; "
    "sys.exit(f'installed without the extra, yet present: {found}' if found else 0)"
)


def _run_light(session: nox.Session, wheel: Path, work: Path) -> None:
    """The wheel without its extra: lint runs, the main job names the extra in one line."""
    venv = work / "venv-light"
    run_dir = work / "run-light"
    bin_dir = venv / "bin"
    env: dict[str, str | None] = {
        "PYTHONPATH": None, "VIRTUAL_ENV": str(venv), "GITHUB_STEP_SUMMARY": None,
    }  # fmt: skip
    try:
        session.run("python", "-m", "venv", str(venv))
        session.run(
            str(bin_dir / "python"), "-m", "pip", "install", "--quiet",
            "--disable-pip-version-check", str(wheel), external=True, env=env,
        )  # fmt: skip
        session.run(str(bin_dir / "python"), "-c", _REFERENCE_PROBE, external=True, env=env)
        run_dir.mkdir()
        with session.chdir(run_dir):
            session.run(str(bin_dir / "fkcheck"), "lint", "ur5", external=True, env=env)
            done = subprocess.run(
                [str(bin_dir / "fkcheck")], capture_output=True, text=True, check=False,
                env={k: v for k, v in {**os.environ, **env}.items() if v is not None},
            )  # fmt: skip
        said = done.stderr.strip().splitlines()
        wanted = "pip install 'fkcheck[reference]'"
        if done.returncode != 2 or len(said) != 1 or wanted not in said[0]:
            session.error(
                f"{wheel.name} without the extra: the main job exited {done.returncode} "
                f"and said {done.stderr!r}, not one line naming {wanted!r} (exit 2)"
            )
        session.log(f"{wheel.name} without the extra: lint runs; the main job names the extra")
    finally:
        shutil.rmtree(venv, ignore_errors=True)
        shutil.rmtree(run_dir, ignore_errors=True)
