"""Shared fixtures."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

sys.path.insert(0, str(Path(__file__).parent))  # for `import helpers`

from fkcheck.model import Model, bundled_model_paths

# In CI (FKCHECK_REQUIRE_BACKENDS=1, set by .ci/run) a skipped test is a failure.
pytest_plugins = ["ci_require"]

BUNDLED = sorted(bundled_model_paths())

# Property-based tests: a bounded, reproducible run by default; `nox -s fuzz` runs
# the "fuzz" profile (10x the examples, fresh randomness each run).
settings.register_profile(
    "default",
    max_examples=60,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "fuzz", max_examples=600, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile(os.environ.get("FKCHECK_HYPOTHESIS_PROFILE", "default"))


@pytest.fixture(autouse=True)
def _no_ci_step_summary(monkeypatch: pytest.MonkeyPatch) -> None:
    """Tests never append to a real CI page's step summary."""
    monkeypatch.delenv("GITHUB_STEP_SUMMARY", raising=False)


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator: every test run draws the same numbers."""
    return np.random.default_rng(20261121)


def random_q(model: Model, rng: np.random.Generator, n: int) -> np.ndarray:
    """n configurations uniformly within limits (±π where a joint has none)."""
    lo = np.where(np.isfinite(model.limits[:, 0]), model.limits[:, 0], -np.pi)
    hi = np.where(np.isfinite(model.limits[:, 1]), model.limits[:, 1], np.pi)
    return rng.uniform(lo, hi, size=(n, model.dof))
