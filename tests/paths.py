"""Where the tests' files are: one place, for every test package."""

from pathlib import Path

__all__ = ["DATA_DIR", "GOLDEN_DIR", "PLUGINS_DIR", "REPO_ROOT", "TESTS_DIR"]

TESTS_DIR = Path(__file__).resolve().parent
REPO_ROOT = TESTS_DIR.parent
DATA_DIR = TESTS_DIR / "data"
GOLDEN_DIR = TESTS_DIR / "golden"
PLUGINS_DIR = TESTS_DIR / "plugins"
