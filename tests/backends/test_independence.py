"""Independence is the product: references never share fkcheck's maths, and prove it.

Two kinds of test:

* **Static**: no module of :mod:`fkcheck.backends` reaches fkcheck's kinematics
  through a :class:`~fkcheck.model.Model` (``.matrix`` of an offset, ``model.chain``,
  ``model.fk``); the import contract (``lint-imports``, in ``nox -s lint``) covers
  direct imports.
* **Mutation**: fkcheck's own rpy → matrix, its named-frame offset and its DH
  link matrix are each broken on purpose; the check must then fail against every
  reference that covers what was broken. A reference that borrowed the broken
  code would stay green and fail this test. (yourdfpy computes its poses in a
  child process, which imports an unbroken fkcheck; the reference and the
  comparison stay in this process, where the break is.)
"""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest

import fkcheck.backends
import fkcheck.core.dh
import fkcheck.core.geometry
import fkcheck.engine.runner
import fkcheck.model.frames
from fkcheck.backends import registry
from fkcheck.backends.registry import make_backend
from fkcheck.engine.runner import run_check
from fkcheck.model.read import load_model, model_from_dict
from tests.paths import PLUGINS_DIR

BACKENDS_DIR = Path(fkcheck.backends.__file__).parent
PLUGINS = PLUGINS_DIR
#: Every default reference (the registry's); all read the UR5's named frames (its URDF
#: frames are UR's ROS 2 description's: ``flange``, not ROS 1's ``ee_link``).
UR5_REFERENCES = list(registry.default_names())


# --------------------------------------------------------------------------- static


def _doors_into_the_core(path: Path) -> list[str]:
    """``x.matrix``, ``model.chain`` and ``model.fk`` uses in one backend module."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if not isinstance(node, ast.Attribute):
            continue
        on_model = isinstance(node.value, ast.Name) and node.value.id == "model"
        if node.attr == "matrix" or (on_model and node.attr in ("chain", "fk", "limits")):
            found.append(f"{path.name}:{node.lineno}: .{node.attr}")
    return found


@pytest.mark.parametrize("path", sorted(BACKENDS_DIR.glob("*.py")), ids=lambda p: p.name)
def test_no_backend_reaches_the_core_through_the_model(path):
    assert _doors_into_the_core(path) == []


def test_the_static_check_sees_a_door_when_there_is_one(tmp_path):
    bad = tmp_path / "bad_backend.py"
    bad.write_text("def f(model):\n    return model.base.matrix @ model.fk(q)\n")
    assert sorted(_doors_into_the_core(bad)) == [
        "bad_backend.py:2: .fk",
        "bad_backend.py:2: .matrix",
    ]


# --------------------------------------------------------------------------- mutations


def _statuses(model, names, pair, samples=8):
    check = run_check(model, [make_backend(n) for n in names], samples=samples,
                      frame_from=pair[0], frame_to=pair[1])  # fmt: skip
    return {r.name: r.status for r in check.backends}, check


def _swapped_roll_and_yaw(original):
    """Roll and yaw exchanged: changes base_link's Rz(π) into Rx(π)."""

    def broken(rpy):
        r, p, y = np.asarray(rpy, dtype=np.float64).reshape(3)
        return original((y, p, r))

    return broken


def _reversed_order(original):
    """``Rx(r)·Ry(p)·Rz(y)`` instead of URDF's ``Rz(y)·Ry(p)·Rx(r)`` (intrinsic/extrinsic mix-up).

    At flange's pitch of -90°, swapping roll and yaw changes nothing (gimbal
    lock); the order does.
    """

    def broken(rpy):
        r, p, y = np.asarray(rpy, dtype=np.float64).reshape(3)
        return original((r, 0, 0)) @ original((0, p, 0)) @ original((0, 0, y))

    return broken


def test_control_every_reference_passes_unbroken():
    statuses, _ = _statuses(load_model("ur5"), UR5_REFERENCES, ("base_link", "flange"))
    assert statuses == dict.fromkeys(UR5_REFERENCES, "pass")


@pytest.mark.parametrize(
    ("pair", "mutation"),
    [(("base_link", "tool0"), _swapped_roll_and_yaw), (("tool0", "flange"), _reversed_order)],
    ids=["base_link-swapped-roll-yaw", "flange-reversed-order"],
)
def test_broken_rpy_to_matrix_turns_every_reference_red(monkeypatch, pair, mutation):
    """fkcheck's rpy → matrix broken: the named frames' offsets come out wrong."""
    monkeypatch.setattr(
        fkcheck.core.geometry, "matrix_from_rpy", mutation(fkcheck.core.geometry.matrix_from_rpy)
    )
    statuses, check = _statuses(load_model("ur5"), UR5_REFERENCES, pair)
    assert statuses == dict.fromkeys(UR5_REFERENCES, "fail"), check.backends
    assert check.verdict == "fail"


def test_broken_rpy_to_matrix_in_base_and_tool_turns_dh_and_black_box_references_red(
    monkeypatch,
):
    """A table with a rotated base and tool, checked world → tcp (no URDF involved)."""
    data = {
        "name": "rotated-3r",
        "convention": "standard",
        "joint": [{"a": 0.4, "alpha": 0.3, "d": 0.1}, {"a": 0.3, "alpha": -0.7, "d": 0.0},
                  {"a": 0.2, "alpha": 0.0, "d": 0.05}],
        "base": {"xyz": [0.1, 0.2, 0.3], "rpy": [0.4, 0.1, -1.2]},
        "tool": {"xyz": [0.0, 0.0, 0.1], "rpy": [0.2, -0.5, 0.9]},
    }  # fmt: skip
    honest = model_from_dict(data)
    q = np.random.default_rng(5).uniform(-3, 3, size=(1, 3))
    honest_world_T_tcp = honest.fk(q)  # computed before the break
    monkeypatch.setattr(
        fkcheck.core.geometry,
        "matrix_from_rpy",
        _swapped_roll_and_yaw(fkcheck.core.geometry.matrix_from_rpy),
    )
    broken = model_from_dict(data)
    assert not np.allclose(broken.fk(q), honest_world_T_tcp)  # the break reaches the core
    statuses, _ = _statuses(broken, ["rtb-dh", "pinocchio-dh"], ("world", "tcp"))
    assert statuses == {"rtb-dh": "fail", "pinocchio-dh": "fail"}


def test_broken_frame_offset_turns_every_reference_red(monkeypatch):
    """The core forgets a named frame's offset (places it at its DH frame)."""
    original = fkcheck.model.frames.frame_poses_from_dh

    def broken(model, world_T_dh, world_T_tcp, frames):
        poses = original(model, world_T_dh, world_T_tcp, frames)
        for k, name in enumerate(frames):
            poses[k] = poses[k] @ np.linalg.inv(model.frames[name].offset.matrix)
        return poses

    monkeypatch.setattr(fkcheck.model.frames, "frame_poses_from_dh", broken)
    for pair in [("base_link", "tool0"), ("tool0", "flange")]:
        statuses, check = _statuses(load_model("ur5"), UR5_REFERENCES, pair)
        assert statuses == dict.fromkeys(UR5_REFERENCES, "fail"), (pair, check.backends)


def test_broken_dh_matrix_turns_every_reference_red(monkeypatch):
    """The core's DH link matrix with sin α of the wrong sign."""
    original = fkcheck.core.dh._fk_numpy_chunk

    def broken(chain, q2, out, all_frames):
        original(dataclasses.replace(chain, alpha=-chain.alpha), q2, out, all_frames)

    monkeypatch.setattr(fkcheck.core.dh, "_fk_numpy_chunk", broken)
    statuses, check = _statuses(load_model("ur5"), UR5_REFERENCES, ("base", "tool0"))
    assert statuses == dict.fromkeys(UR5_REFERENCES, "fail"), check.backends


def test_broken_dh_matrix_turns_black_box_references_red(monkeypatch):
    """A plugin with its own closed form, and Robotics Toolbox's published UR5 table."""
    monkeypatch.syspath_prepend(str(PLUGINS))
    original = fkcheck.core.dh._fk_numpy_chunk

    def broken(chain, q2, out, all_frames):
        original(dataclasses.replace(chain, alpha=-chain.alpha), q2, out, all_frames)

    names = ["ur5_closed_form:forward", "rtb-model:UR5"]
    statuses, _ = _statuses(load_model("ur5"), names, ("world", "tool0"))
    assert statuses["ur5_closed_form:forward"] == "pass"  # control
    monkeypatch.setattr(fkcheck.core.dh, "_fk_numpy_chunk", broken)
    statuses, _ = _statuses(load_model("ur5"), names, ("world", "tool0"))
    assert statuses == dict.fromkeys(names, "fail")
