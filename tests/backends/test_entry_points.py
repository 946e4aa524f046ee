"""Third-party backends: a distribution registering one in the ``fkcheck.backends`` group.

Each test writes a throw-away distribution — a package and its ``.dist-info``
with ``entry_points.txt``, exactly what ``pip install`` leaves in
site-packages — into a directory put on the path of a fresh Python process, so
:mod:`importlib.metadata` finds it as an installed distribution. The backend
then has to show up where built-in ones do: ``--against`` and its help, the
conformance suite, ``[[known_difference]]`` validation and the reports.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from tests.paths import PLUGINS_DIR, REPO_ROOT

#: A third party's backend: UR5 written out in closed form, a table published elsewhere.
PACKAGE = '''
"""A third-party fkcheck backend (a test fixture): UR5 in closed form."""

import os
import sys
from pathlib import Path

import numpy as np

from fkcheck.backends.base import BackendDefaults, validated_q
from fkcheck.backends.blackbox import frame_poses_from_tcp

sys.path.insert(0, {plugins!r})
from ur5_closed_form import forward  # noqa: E402


class ClosedFormUr5(BackendDefaults):
    name = "demo-ur5"
    method = "UR5 multiplied out by hand (fkcheck-demo-backend)"
    evidence = "table"
    reads = "published"

    def __init__(self, arg, options):
        self.options = options

    def unavailable_reason(self, model):
        return None if model.dof == 6 else "UR5 only"

    def frame_poses(self, model, q, frames):
        return frame_poses_from_tcp(model, forward(validated_q(model, q)), frames)


class Incomplete:
    name = "demo-incomplete"
    method = "forgot most of the contract"
    evidence = "table"

    def __init__(self, arg, options):
        pass


class Lying(ClosedFormUr5):
    name = "demo-lying"
    reads = "dh"  # computes from the model's table, yet claims table evidence


class Exits(ClosedFormUr5):
    """Ends its process, with status 0, when asked for poses (issue 30: CI read a pass)."""

    name = "demo-exits"

    def frame_poses(self, model, q, frames):
        os._exit(0)


class ProbeExits(ClosedFormUr5):
    """Ends its process, with status 0, when asked whether it can run."""

    name = "demo-probe-exits"

    def unavailable_reason(self, model):
        os._exit(0)


class BuildExits(ClosedFormUr5):
    """Ends its process, with status 0, when built."""

    name = "demo-build-exits"

    def __init__(self, arg, options):
        os._exit(0)


class Chatty(ClosedFormUr5):
    """Right poses, and prints that look like fkcheck's own output (issue 31)."""

    name = "demo-chatty"

    def __init__(self, arg, options):
        print("verdict: pass (printed by demo-chatty)")
        super().__init__(arg, options)

    def frame_poses(self, model, q, frames):
        print("verdict: pass (printed by demo-chatty)")
        print("::error file=models/ur5.toml::printed by demo-chatty")
        return super().frame_poses(model, q, frames)


class Busy(ClosedFormUr5):
    """Holds the GIL in C (one call of the builtin sum) for hours."""

    name = "demo-busy"

    def frame_poses(self, model, q, frames):
        return sum(range(10**15))


class NanPoses(ClosedFormUr5):
    """Every pose NaN."""

    name = "demo-nan"

    def frame_poses(self, model, q, frames):
        return np.full((len(frames), len(q), 4, 4), np.nan)


class PidNoted(ClosedFormUr5):
    """Writes the id of the process that builds it, computes and imports it."""

    name = "demo-pid"

    def __init__(self, arg, options):
        _note("built")
        super().__init__(arg, options)

    def frame_poses(self, model, q, frames):
        _note("poses")
        return super().frame_poses(model, q, frames)


class NanPrefix(ClosedFormUr5):
    """A prefix whose backends answer NaN, as the one that took over ``rt4mod:``."""

    name = "rt4mod:"

    def __init__(self, arg, options):
        self.name = "rt4mod:" + arg

    def frame_poses(self, model, q, frames):
        return np.full((len(frames), len(q), 4, 4), np.nan)


class Impostor(NanPrefix):
    """A prefix's backend that calls itself by a built-in's name."""

    def __init__(self, arg, options):
        self.name = "pinocchio-urdf"


def _note(what):
    target = os.environ.get("FKCHECK_TEST_PIDS")
    if target:
        with open(target, "a") as out:
            out.write(f"{{what}} {{os.getpid()}}\\n")


_note("imported")
'''


def _install(site: Path, entry_points: dict[str, str], dist: str = "fkcheck-demo-backend") -> None:
    """Write the distribution ``dist`` 0.1 (package ``fkcheck_demo_backend``) into ``site``."""
    package = site / "fkcheck_demo_backend"
    package.mkdir(parents=True, exist_ok=True)
    (package / "__init__.py").write_text(PACKAGE.format(plugins=str(PLUGINS_DIR)))
    info = site / f"{dist.replace('-', '_')}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {dist}\nVersion: 0.1\n")
    lines = [f"{name} = {target}" for name, target in entry_points.items()]
    (info / "entry_points.txt").write_text("[fkcheck.backends]\n" + "\n".join(lines) + "\n")
    (info / "RECORD").write_text("")


def _run(
    site: Path, *argv: str, cwd: Path, env: dict[str, str] | None = None
) -> subprocess.CompletedProcess[str]:
    paths = [str(site), str(REPO_ROOT), os.environ.get("PYTHONPATH", "")]
    env = {**os.environ, **(env or {}), "PYTHONPATH": os.pathsep.join(p for p in paths if p)}
    return subprocess.run(
        [sys.executable, *argv], cwd=cwd, env=env, capture_output=True, text=True, timeout=600
    )


@pytest.fixture
def site(tmp_path: Path) -> Path:
    site = tmp_path / "site"
    _install(site, {"demo-ur5": "fkcheck_demo_backend:ClosedFormUr5"})
    return site


def test_an_installed_backend_is_named_with_against_and_reported(site, tmp_path):
    out = tmp_path / "r.json"
    done = _run(
        site, "-m", "fkcheck", "check", "ur5", "--samples", "16", "--against", "demo-ur5,rtb-dh",
        "--json", str(out), cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    doc = json.loads(out.read_text())
    (demo,) = [b for b in doc["backends"] if b["name"] == "demo-ur5"]
    assert (demo["status"], demo["evidence"]) == ("pass", "table")
    assert "fkcheck-demo-backend" in json.dumps(doc)  # its version among the libraries
    helped = _run(site, "-m", "fkcheck", "check", "--help", cwd=tmp_path)
    # argparse wraps help at the terminal's width, breaking after hyphens ("demo-" / "ur5").
    assert "demo-ur5," in "".join(helped.stdout.split())


def test_an_installed_backend_passes_the_conformance_suite(site, tmp_path):
    done = _run(
        site, "-m", "pytest", str(REPO_ROOT / "tests/backends/test_conformance.py"),
        "-k", "demo-ur5", "-q", "-p", "no:cacheprovider", "--rootdir", str(REPO_ROOT),
        cwd=REPO_ROOT,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    # Contract, built without its library, agreement, wrong shape, a changed table seen.
    assert "5 passed" in done.stdout, done.stdout


def test_an_installed_table_backend_may_be_named_as_a_known_difference(site, tmp_path):
    text = (REPO_ROOT / "models" / "ur5.toml").read_text()
    model = tmp_path / "ur5_known.toml"
    model.write_text(
        text.replace("d = 0.089159", "d = 0.089459", 1)
        + textwrap.dedent("""
            [[known_difference]]
            backends = ["demo-ur5"]
            finding = "d1 is RTB's 0.089459, not UR's 0.089159"
            max_position_m = 0.0004
            max_angle_rad = 1e-6
        """)
    )  # the URDF of ur5 is relative to the bundled model: none here, so no URDF backends
    done = _run(
        site, "-m", "fkcheck", "check", str(model), "--samples", "16", "--against", "demo-ur5",
        cwd=tmp_path,
    )  # fmt: skip
    assert "xfail" in done.stdout, done.stdout + done.stderr
    without = _run(
        tmp_path / "nothing", "-m", "fkcheck", "lint", str(model), cwd=tmp_path
    )  # not installed: the name is unknown, one line, exit 2
    assert without.returncode == 2
    assert without.stderr.count("\n") == 1, without.stderr
    assert "known_difference[0].backends[0]: 'demo-ur5' is not a backend" in without.stderr


@pytest.mark.parametrize(
    ("entry_points", "message"),
    [
        (
            {"demo-incomplete": "fkcheck_demo_backend:Incomplete"},
            r"backend demo-incomplete \(fkcheck-demo-backend 0\.1, fkcheck_demo_backend:"
            r"Incomplete\) breaks fkcheck's backend contract: no 'reads'; no 'isolated'",
        ),
        (
            {"demo-lying": "fkcheck_demo_backend:Lying"},
            r"claims 'table' evidence but reads 'dh', which proves implementation only",
        ),
        ({"rtb-dh": "fkcheck_demo_backend:ClosedFormUr5"}, r"the name is taken by fkcheck"),
        ({"Demo UR5": "fkcheck_demo_backend:ClosedFormUr5"}, r"not a backend name"),
        ({"demo-missing": "fkcheck_demo_backend:Nowhere"}, r"cannot load fkcheck_demo_backend"),
    ],
)
def test_a_broken_registration_is_one_line_and_exit_2(tmp_path, entry_points, message):
    site = tmp_path / "site"
    _install(site, entry_points)
    name = next(iter(entry_points))
    done = _run(
        site, "-m", "fkcheck", "check", "ur5", "--samples", "4", "--against", name, cwd=tmp_path
    )
    assert done.returncode == 2, done.stdout + done.stderr
    assert "Traceback" not in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert re.search(message, done.stderr), done.stderr


# --- Third-party backends run isolated (issues 30 and 31) ---------------------------------


def _one_backend(site: Path, tmp_path: Path, name: str, *extra: str, env=None):
    """``check ur5 --against NAME`` with a JSON report: (process, the backend's row or None)."""
    out = tmp_path / "r.json"
    done = _run(
        site, "-m", "fkcheck", "check", "ur5", "--samples", "8", "--against", name,
        "--json", str(out), *extra, cwd=tmp_path, env=env,
    )  # fmt: skip
    if not out.exists():
        return done, None
    (row,) = [b for b in json.loads(out.read_text())["backends"] if b["name"] == name]
    return done, row


def test_a_backend_that_calls_os_exit_0_is_its_error_not_a_pass(tmp_path):
    # In fkcheck's process, os._exit(0) ended the run: exit 0, no verdict, no JSON.
    site = tmp_path / "site"
    _install(site, {"demo-exits": "fkcheck_demo_backend:Exits"})
    done, row = _one_backend(site, tmp_path, "demo-exits")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "verdict: error" in done.stdout
    assert row is not None
    assert row["status"] == "error"
    assert "exited with code 0 without an answer" in row["message"], row["message"]


def test_a_backend_s_prints_never_reach_fkcheck_s_output(tmp_path):
    site = tmp_path / "site"
    _install(site, {"demo-chatty": "fkcheck_demo_backend:Chatty"})
    done, row = _one_backend(site, tmp_path, "demo-chatty")
    assert done.returncode == 0, done.stdout + done.stderr
    assert row is not None
    assert row["status"] == "pass"
    for stream in (done.stdout, done.stderr):
        assert "printed by demo-chatty" not in stream
        assert "::error" not in stream
    verdicts = [line for line in done.stdout.splitlines() if line.startswith("verdict:")]
    assert len(verdicts) == 1
    assert verdicts[0].startswith("verdict: pass — table verified"), verdicts


def test_a_backend_runs_only_in_processes_of_its_own(tmp_path):
    # Importing, building and computing: none of it in fkcheck's process (whose pid the
    # JSON report does not give, so: every pid noted differs from the check's own child).
    site = tmp_path / "site"
    _install(site, {"demo-pid": "fkcheck_demo_backend:PidNoted"})
    notes = tmp_path / "pids.txt"
    probe = (
        "import os, sys; from fkcheck.cli.main import main; "
        "open(sys.argv[1], 'a').write(f'fkcheck {os.getpid()}\\n'); "
        "sys.exit(main(sys.argv[2:]))"
    )
    done = _run(
        site, "-c", probe, str(notes), "check", "ur5", "--samples", "8", "--against",
        "demo-pid", cwd=tmp_path, env={"FKCHECK_TEST_PIDS": str(notes)},
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    lines = [line.split() for line in notes.read_text().splitlines()]
    (own,) = [pid for what, pid in lines if what == "fkcheck"]
    seen = {what for what, _ in lines}
    assert {"imported", "built", "poses"} <= seen, lines
    assert all(pid != own for what, pid in lines if what != "fkcheck"), lines


def test_a_backend_holding_the_gil_is_stopped_at_the_time_limit(tmp_path):
    site = tmp_path / "site"
    _install(site, {"demo-busy": "fkcheck_demo_backend:Busy"})
    start = time.monotonic()
    done, row = _one_backend(site, tmp_path, "demo-busy", "--timeout", "4")
    took = time.monotonic() - start
    assert done.returncode == 1, done.stdout + done.stderr
    assert row is not None
    assert row["status"] == "error"
    assert "timed out after 4 s" in row["message"], row["message"]
    # Building and probing take a process start each (≈0.5 s here), poses the limit;
    # a sum that held fkcheck's own GIL would take hours.
    assert took < 60, took


def test_nan_poses_from_a_backend_are_a_failure_never_agreement(tmp_path):
    site = tmp_path / "site"
    _install(site, {"demo-nan": "fkcheck_demo_backend:NanPoses"})
    done, row = _one_backend(site, tmp_path, "demo-nan")
    assert done.returncode == 1, done.stdout + done.stderr
    assert row is not None
    assert row["status"] == "fail"
    assert "NaN or inf" in row["message"], row["message"]
    assert "table verified" not in done.stdout


def test_a_prefix_that_is_also_the_user_s_plugin_module_is_ambiguous(tmp_path):
    # A distribution registering rt4mod: took over the user's --against rt4mod:fk
    # (its NaN poses read "pass — table verified"): both named, one line, exit 2.
    site = tmp_path / "site"
    _install(site, {"rt4mod:": "fkcheck_demo_backend:NanPrefix"})
    work = tmp_path / "work"
    work.mkdir()
    (work / "rt4mod.py").write_text(
        f"import sys\nsys.path.insert(0, {str(PLUGINS_DIR)!r})\n"
        "from ur5_closed_form import forward as fk\n"
    )
    done = _run(site, "-m", "fkcheck", "check", "ur5", "--against", "rt4mod:fk", cwd=work)
    assert done.returncode == 2, done.stdout + done.stderr
    assert done.stdout == ""
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert re.search(
        r"backend 'rt4mod:fk' is ambiguous: the prefix rt4mod: of fkcheck-demo-backend 0\.1 "
        r"and the Python module rt4mod \(.*rt4mod\.py\) both answer to it",
        done.stderr,
    ), done.stderr
    (work / "rt4mod.py").unlink()  # without the module, the prefix is the only answer
    done = _run(site, "-m", "fkcheck", "check", "ur5", "--samples", "8", "--against",
                "rt4mod:fk", cwd=work)  # fmt: skip
    assert done.returncode == 1, done.stdout + done.stderr
    assert "NaN or inf" in done.stdout


def test_a_prefixed_backend_may_not_take_another_backend_s_name(tmp_path):
    site = tmp_path / "site"
    _install(site, {"impostor:": "fkcheck_demo_backend:Impostor"})
    done = _run(site, "-m", "fkcheck", "check", "ur5", "--against", "impostor:x", cwd=tmp_path)
    assert done.returncode == 2, done.stdout + done.stderr
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert "calls itself 'pinocchio-urdf', which does not start with its prefix 'impostor:'" in (
        done.stderr
    )


def test_a_name_two_distributions_register_is_refused_naming_both(tmp_path):
    site = tmp_path / "site"
    _install(site, {"demo-ur5": "fkcheck_demo_backend:ClosedFormUr5"})
    _install(site, {"demo-ur5": "fkcheck_demo_backend:NanPoses"}, dist="other-demo")
    done = _run(site, "-m", "fkcheck", "check", "ur5", "--against", "demo-ur5", cwd=tmp_path)
    assert done.returncode == 2, done.stdout + done.stderr
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert "fkcheck-demo-backend 0.1" in done.stderr
    assert "other-demo 0.1" in done.stderr
    # Another backend's check does not depend on it.
    other = _run(site, "-m", "fkcheck", "check", "ur5", "--samples", "8", "--against",
                 "rtb-dh", cwd=tmp_path)  # fmt: skip
    assert other.returncode == 0, other.stdout + other.stderr


def test_a_broken_backend_the_check_does_not_use_does_not_end_it(tmp_path):
    # A [[known_difference]] made fkcheck build every registered backend: a broken entry
    # point ended a check that only asked for pinocchio-urdf (issue 31).
    text = (REPO_ROOT / "models" / "ur5.toml").read_text()
    model = tmp_path / "ur5_known.toml"
    model.write_text(
        text.replace("d = 0.089159", "d = 0.089459", 1)
        + textwrap.dedent("""
            [[known_difference]]
            backends = ["pinocchio-urdf"]
            finding = "d1 is RTB's 0.089459, not UR's 0.089159"
            max_position_m = 0.0004
            max_angle_rad = 1e-6
        """)
    )
    argv = ("-m", "fkcheck", "check", str(model), "--samples", "8", "--against", "pinocchio-urdf")
    clean = _run(tmp_path / "nothing", *argv, cwd=tmp_path)
    site = tmp_path / "site"
    _install(site, {"demo-missing": "fkcheck_demo_backend:Nowhere", "demo-exits":
                    "fkcheck_demo_backend:Exits"})  # fmt: skip
    broken = _run(site, *argv, cwd=tmp_path)
    assert "xfail" in clean.stdout, clean.stdout + clean.stderr
    verdict = [line for line in clean.stdout.splitlines() if line.startswith("verdict:")]
    assert verdict == [line for line in broken.stdout.splitlines() if line.startswith("verdict:")]
    assert broken.returncode == clean.returncode, broken.stderr
    assert "demo-missing" not in broken.stderr


def test_a_backend_that_ends_its_process_anywhere_never_ends_fkcheck_s(tmp_path):
    site = tmp_path / "site"
    _install(site, {"demo-probe-exits": "fkcheck_demo_backend:ProbeExits",
                    "demo-build-exits": "fkcheck_demo_backend:BuildExits"})  # fmt: skip
    done, row = _one_backend(site, tmp_path, "demo-probe-exits")  # asked whether it can run
    assert done.returncode == 1, done.stdout + done.stderr
    assert "Traceback" not in done.stderr
    assert row is not None
    assert row["status"] == "error"
    assert "exited with code 0 without an answer" in row["message"], row["message"]
    diagnosed = _run(site, "-m", "fkcheck", "diagnose", "ur5", "--against", "demo-probe-exits",
                     cwd=tmp_path)  # fmt: skip
    assert diagnosed.returncode == 2, diagnosed.stdout + diagnosed.stderr
    assert diagnosed.stderr.startswith(
        "fkcheck: error: cannot diagnose against demo-probe-exits: it failed: asking it about "
        "the model: its process exited with code 0 without an answer"
    ), diagnosed.stderr
    assert len(diagnosed.stderr.splitlines()) == 1
    # Built before anything runs: a backend that cannot be built is bad input.
    built = _run(site, "-m", "fkcheck", "check", "ur5", "--against", "demo-build-exits",
                 cwd=tmp_path)  # fmt: skip
    assert built.returncode == 2, built.stdout + built.stderr
    assert built.stderr == (
        "fkcheck: error: backend demo-build-exits (fkcheck-demo-backend 0.1): building it: its "
        "process exited with code 0 without an answer\n"
    )
