"""Shared fixtures."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

from fkcheck.process.threads import one_blas_thread

# In CI (FKCHECK_REQUIRE_BACKENDS=1, set by .ci/run) a skipped test is a failure.
pytest_plugins = ["tests.ci_require"]

# Property-based tests: a bounded, reproducible run by default; `nox -s fuzz` runs
# the "fuzz" profile (10x the examples, fresh randomness each run).
settings.register_profile(
    "default",
    max_examples=60,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
# derandomize=False said outright: a profile registered without it inherited the
# default profile's True, and --hypothesis-seed then changed nothing.
settings.register_profile(
    "fuzz",
    max_examples=600,
    derandomize=False,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("FKCHECK_HYPOTHESIS_PROFILE", "default"))

# The suite is fkcheck's own small linear algebra, as the program's: BLAS on one thread
# (fkcheck.process.threads.one_blas_thread; children started by the tests inherit it).
one_blas_thread()


@pytest.fixture(autouse=True)
def _no_ci_step_summary(monkeypatch: pytest.MonkeyPatch) -> None:
    """Tests never append to a real CI page's step summary."""
    monkeypatch.delenv("GITHUB_STEP_SUMMARY", raising=False)


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator: every test run draws the same numbers."""
    return np.random.default_rng(20261121)
