"""One version, from src/fkcheck/_version.py: `fkcheck --version`, every report, the metadata.

A check of two bundled models writes every format (JSON, HTML, JUnit, index.html,
the Markdown summary); each names the version, as does the terminal's first line.
"""

from __future__ import annotations

import importlib.metadata
import json
import re
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

import fkcheck
from fkcheck._version import __version__
from fkcheck.cli.main import main
from tests.paths import REPO_ROOT


def test_version_is_single_sourced_in_version_py() -> None:
    with (REPO_ROOT / "pyproject.toml").open("rb") as f:
        pyproject = tomllib.load(f)
    assert "version" not in pyproject["project"]
    assert pyproject["project"]["dynamic"] == ["version"]
    path = pyproject["tool"]["hatch"]["version"]["path"]
    assert path == "src/fkcheck/_version.py"
    # What hatchling's regex source reads: the one `__version__ = "..."` line.
    found = re.findall(
        r'^__version__ = "([^"]+)"$', (REPO_ROOT / path).read_text("utf-8"), re.MULTILINE
    )
    assert found == [fkcheck.__version__]
    assert fkcheck.__version__ == __version__


def test_installed_metadata_has_the_same_version() -> None:
    assert importlib.metadata.version("fkcheck") == fkcheck.__version__


def test_version_flag_prints_it(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"fkcheck {__version__}\n"


def test_every_report_names_the_version(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "reports"
    summary = out / "summary.md"
    argv = ["check", "planar2", "planar3", "--samples", "3", "--against", "rtb-dh",
            "--out-dir", str(out), "--summary", str(summary)]  # fmt: skip
    assert main(argv) == 0
    terminal = capsys.readouterr().out.splitlines()
    headers = [line for line in terminal if line.startswith("fkcheck planar")]
    assert len(headers) == 2
    assert all(line.endswith(f"; fkcheck {__version__}") for line in headers), headers
    written = f'Written by <span data-volatile="version">fkcheck {__version__}</span>.'
    for model in ("planar2", "planar3"):
        doc = json.loads((out / f"{model}.json").read_text("utf-8"))
        assert doc["fkcheck_version"] == __version__
        assert written in (out / f"{model}.html").read_text("utf-8")
        suite = ET.parse(out / f"{model}.junit.xml").getroot().find("testsuite")
        assert suite is not None
        assert suite[0].tag == "properties"  # first in the suite, as the schema orders it
        props = {p.get("name"): p.get("value") for p in suite[0].iter("property")}
        assert props == {"fkcheck_version": __version__}
    assert written in (out / "index.html").read_text("utf-8")
    assert summary.read_text("utf-8").splitlines()[-1] == f"<sub>fkcheck {__version__}</sub>"
