"""Shared fixtures."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))  # for `import helpers`

from fkcheck.model import Model, bundled_model_paths

BUNDLED = sorted(bundled_model_paths())


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator: every test run draws the same numbers."""
    return np.random.default_rng(20261121)


def random_q(model: Model, rng: np.random.Generator, n: int) -> np.ndarray:
    """n configurations uniformly within limits (±π where a joint has none)."""
    lo = np.where(np.isfinite(model.limits[:, 0]), model.limits[:, 0], -np.pi)
    hi = np.where(np.isfinite(model.limits[:, 1]), model.limits[:, 1], np.pi)
    return rng.uniform(lo, hi, size=(n, model.dof))
