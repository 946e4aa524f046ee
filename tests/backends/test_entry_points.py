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
from pathlib import Path

import pytest

from tests.paths import PLUGINS_DIR, REPO_ROOT

#: A third party's backend: UR5 written out in closed form, a table published elsewhere.
PACKAGE = '''
"""A third-party fkcheck backend (a test fixture): UR5 in closed form."""

import sys
from pathlib import Path

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
'''


def _install(site: Path, entry_points: dict[str, str]) -> None:
    """Write the distribution ``fkcheck-demo-backend`` 0.1 into ``site``."""
    package = site / "fkcheck_demo_backend"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text(PACKAGE.format(plugins=str(PLUGINS_DIR)))
    info = site / "fkcheck_demo_backend-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        "Metadata-Version: 2.1\nName: fkcheck-demo-backend\nVersion: 0.1\n"
    )
    lines = [f"{name} = {target}" for name, target in entry_points.items()]
    (info / "entry_points.txt").write_text("[fkcheck.backends]\n" + "\n".join(lines) + "\n")
    (info / "RECORD").write_text("")


def _run(site: Path, *argv: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(REPO_ROOT)])}
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
