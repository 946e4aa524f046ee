"""``fkcheck check`` names the ``pyproject.toml`` it used, and never one above the repository."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pytest

from fkcheck._version import __version__
from fkcheck.cli.main import main
from fkcheck.model.read import bundled_model_paths

PLANAR2 = str(bundled_model_paths()["planar2"])
FAST = ["--against", "rtb-dh", "--seed", "1"]


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A checkout (``.git``) inside a directory whose pyproject.toml sets samples = 5.

    The working directory is ``checkout/robots``.
    """
    (tmp_path / "pyproject.toml").write_text("[tool.fkcheck]\nsamples = 5\n")
    checkout = tmp_path / "checkout"
    (checkout / ".git").mkdir(parents=True)
    (checkout / "robots").mkdir()
    monkeypatch.chdir(checkout / "robots")
    return checkout


def test_a_pyproject_above_the_repository_is_not_used_and_none_is_named(repo, capsys):
    assert main(["check", PLANAR2, *FAST, "--json", "r.json", "--html", "r.html"]) == 0
    out = capsys.readouterr().out
    result = json.loads(Path("r.json").read_text())
    assert result["samples"] == 1000  # the default: not the 5 from above the checkout
    assert result["config"] is None
    assert "config:" not in out
    assert "<dt>configuration</dt>\n  <dd>none</dd>" in Path("r.html").read_text()


def test_the_repositorys_pyproject_is_named_by_every_output(repo, capsys):
    (repo / "pyproject.toml").write_text("[tool.fkcheck]\nsamples = 4\n")
    assert main(["check", PLANAR2, *FAST, "--json", "r.json", "--html", "r.html"]) == 0
    out = capsys.readouterr().out
    result = json.loads(Path("r.json").read_text())
    assert result["samples"] == 4
    assert result["config"] == "../pyproject.toml"
    # Not a terminal: the description opens the table, naming the file as the header does.
    assert out.splitlines()[0].endswith(f"; config: ../pyproject.toml; fkcheck {__version__}"), out
    assert "[tool.fkcheck] of ../pyproject.toml" in Path("r.html").read_text()


def test_several_models_name_it_in_each_report_and_the_index(repo, capsys):
    (repo / "pyproject.toml").write_text("[tool.fkcheck]\nsamples = 4\n")
    assert main(["check", PLANAR2, "ur5", *FAST, "--out-dir", "out"]) == 0
    capsys.readouterr()
    assert json.loads(Path("out/ur5.json").read_text())["config"] == "../pyproject.toml"
    assert "[tool.fkcheck] of ../pyproject.toml" in Path("out/index.html").read_text()


def test_the_header_names_the_file_as_pytest_names_its_configfile():
    from fkcheck.backends.registry import make_backend
    from fkcheck.cli.check_output import header
    from fkcheck.model.read import load_model

    args = argparse.Namespace(
        frame_from=None, frame_to=None, tol_pos=None, tol_rot=None, samples=9, sampler="sobol",
        seed=0, config="../pyproject.toml",
    )  # fmt: skip
    text = header(load_model("planar2"), [make_backend("rtb-dh")], args)
    assert text.endswith(f"against rtb-dh; config: ../pyproject.toml; fkcheck {__version__}")


def test_no_output_replaces_the_configuration_file(repo, capsys):
    (repo / "pyproject.toml").write_text("[tool.fkcheck]\nsamples = 4\n")
    before = (repo / "pyproject.toml").read_bytes()
    assert main(["check", PLANAR2, *FAST, "--json", "../pyproject.toml"]) == 2
    err = capsys.readouterr().err
    assert err == (
        "fkcheck: error: --json ../pyproject.toml: is the configuration file, an input of this "
        "run: write elsewhere\n"
    )
    assert (repo / "pyproject.toml").read_bytes() == before
