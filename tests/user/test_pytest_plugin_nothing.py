"""The pytest plugin on checks that compare nothing: each fails, as ``fkcheck check`` does.

* every backend skipped (the planar arm has no URDF, only URDF backends asked):
  the CLI says ``error — nothing was cross-checked``; pytest must not say "3 skipped";
* a frame pair that spans no joint (``from = to = "tcp"``, ``world`` → a frame on
  DH frame 0): its pose never moves, so agreement verifies nothing.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from fkcheck.model.read import bundled_model_paths
from tests.user.test_pytest_plugin import _env, _outcomes
from tests.user.userrepo import good_ur5_text, make_user_repo


def _pytest(repo: Path, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rA", "-v"],
        cwd=repo, env=_env(tmp_path), capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip


def test_a_model_none_of_whose_backends_answered_fails(tmp_path: Path) -> None:
    tool = (
        'models = ["robots/planar.toml"]\nsamples = 10\n'
        'against = ["pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf"]\n'
    )
    repo = make_user_repo(tmp_path / "repo", tool)
    planar = bundled_model_paths()["planar2"].read_text(encoding="utf-8")
    (repo / "robots" / "planar.toml").write_text(planar, encoding="utf-8")
    done = _pytest(repo, tmp_path)
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    assert _outcomes(out) == {
        f"robots/planar.toml::fkcheck[{name}]": "FAILED"
        for name in ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf")
    }, out
    assert re.search(r"\b3 failed\b", out), out
    assert "skipped" not in out.splitlines()[-1], out
    assert "error — no backend gave an answer: nothing was cross-checked" in out
    assert "pinocchio-urdf: skipped — model has no [urdf]" in out
    assert "no backend of this model answered, so nothing was cross-checked" in out
    assert "Traceback" not in out


def test_a_frame_pair_that_spans_no_joint_fails_every_test_of_its_model(tmp_path: Path) -> None:
    pytest.importorskip("pinocchio")
    tool = 'models = ["robots/still.toml", "robots/base.toml"]\nsamples = 10\n'
    tool += 'against = ["pinocchio-dh"]\nrequire = ["implementation"]\n'
    repo = make_user_repo(tmp_path / "repo", tool)
    head, _, _ = good_ur5_text().partition("[check]")
    for name, pair in (("still", ("tcp", "tcp")), ("base", ("world", "base"))):
        text = f'{head}[check]\nfrom = "{pair[0]}"\nto = "{pair[1]}"\n'
        (repo / "robots" / f"{name}.toml").write_text(text, encoding="utf-8")
    done = _pytest(repo, tmp_path)
    out = done.stdout
    assert done.returncode == 1, out + done.stderr
    assert _outcomes(out) == {
        f"robots/{name}.toml::fkcheck[{test}]": "FAILED"
        for name in ("base", "still")
        for test in ("pinocchio-dh", "require:implementation")
    }, out
    assert re.search(r"\b4 failed\b", out), out
    assert (
        "fkcheck ur5: the frame pair 'tcp' → 'tcp' spans no joint (a frame compared with itself)"
        in out
    )
    assert (
        "fkcheck ur5: the frame pair 'world' → 'base' spans no joint ('world' is on the world, "
        "'base' on DH frame 0;" in out
    )
    assert "so comparing it verifies none of the table" in out
    assert "Traceback" not in out
