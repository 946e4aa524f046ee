"""NaN or inf from any backend, wherever it sits in a pose, is a failure, never agreement.

A backend's poses that are right except for non-finite entries — in the rotation, the
translation, the bottom row, one frame of the pair or one configuration — are a wrong
answer (issue 30: "NaN poses must never read as agreement").
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from fkcheck.backends.base import BackendDefaults, validated_q
from fkcheck.backends.blackbox import frame_poses_from_tcp
from fkcheck.engine.runner import run_check
from fkcheck.model.read import load_model
from fkcheck.model.types import Model
from tests.paths import PLUGINS_DIR

Spoil = Callable[[np.ndarray], None]


def _rotation(p: np.ndarray) -> None:
    p[..., :3, :3] = np.nan


def _translation(p: np.ndarray) -> None:
    p[..., :3, 3] = np.nan


def _bottom_row(p: np.ndarray) -> None:
    p[..., 3, :] = np.nan


def _from_frame_only(p: np.ndarray) -> None:
    p[0] = np.nan


def _one_configuration(p: np.ndarray) -> None:
    p[:, 3] = np.nan


def _one_inf(p: np.ndarray) -> None:
    p[1, :, 0, 3] = np.inf


def _one_minus_inf_in_rotation(p: np.ndarray) -> None:
    p[1, 5, 0, 0] = -np.inf


class _Spoiled(BackendDefaults):
    """UR5 in closed form (a table-independent answer), then spoiled."""

    method = "UR5 in closed form, spoiled"
    evidence = "table"
    reads = "published"

    def __init__(self, spoil: Spoil) -> None:
        self.name = f"spoiled-{spoil.__name__.strip('_')}"
        self.spoil = spoil

    def unavailable_reason(self, model: Model) -> None:
        return None

    def frame_poses(self, model, q, frames):
        import sys

        sys.path.insert(0, str(PLUGINS_DIR))
        try:
            from ur5_closed_form import forward
        finally:
            sys.path.remove(str(PLUGINS_DIR))
        poses = np.array(frame_poses_from_tcp(model, forward(validated_q(model, q)), frames))
        self.spoil(poses)
        return poses


SPOILS = [_rotation, _translation, _bottom_row, _from_frame_only, _one_configuration,
          _one_inf, _one_minus_inf_in_rotation]  # fmt: skip


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")
@pytest.mark.parametrize("spoil", SPOILS, ids=lambda f: f.__name__.strip("_"))
@pytest.mark.parametrize("pair", [("base", "tool0"), ("world", "tcp")])
def test_non_finite_poses_fail(spoil, pair):
    check = run_check(
        load_model("ur5"), [_Spoiled(spoil)], samples=8, frame_from=pair[0], frame_to=pair[1]
    )
    (result,) = check.backends
    assert result.status == "fail", result.message
    assert "returned NaN or inf" in result.message
    assert not check.verdict.startswith("pass"), check.verdict
