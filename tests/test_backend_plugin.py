"""The plugin backend: a user's Python callable checked against the in-house core."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import seed_ur5
from conftest import random_q
from fkcheck.backends.base import Backend, FrameUnavailable
from fkcheck.backends.plugin import PluginBackend, PluginError
from fkcheck.backends.registry import BackendOptions, make_backend
from fkcheck.errors import BackendNotFoundError, FkcheckError
from fkcheck.frames import frame_poses_from_dh
from fkcheck.model import Model, load_model
from fkcheck.tolerances import SAME_CHAIN, SIX_DECIMALS
from helpers import assert_pose_close, assert_se3

PLUGINS = Path(__file__).parent / "plugins"
UR5_FRAMES = ["world", "tcp", "base", "base_link", "tool0", "flange"]


@pytest.fixture
def plugins_importable(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.syspath_prepend(PLUGINS)


@pytest.fixture(scope="module")
def ur5() -> Model:
    return load_model("ur5")


def plugin(spec: str) -> PluginBackend:
    return PluginBackend(spec, BackendOptions())


@pytest.mark.usefixtures("plugins_importable")
def test_closed_form_plugin_agrees_with_core_on_every_ur5_frame(
    ur5: Model, rng: np.random.Generator
) -> None:
    q = random_q(ur5, rng, 500)
    poses = plugin("ur5_closed_form:forward").frame_poses(ur5, q, UR5_FRAMES)
    assert poses.shape == (len(UR5_FRAMES), 500, 4, 4)
    # The core's DH-frame path gives the same named frames independently of the TCP path.
    expected = frame_poses_from_dh(ur5, ur5.fk(q, all_frames=True), ur5.fk(q), UR5_FRAMES)
    for name, got, want in zip(UR5_FRAMES, poses, expected, strict=True):
        assert_pose_close(got, want, SAME_CHAIN, what=name)
    assert_se3(poses[1], SAME_CHAIN)


@pytest.mark.usefixtures("plugins_importable")
def test_closed_form_plugin_reproduces_seed_hand_computation(ur5: Model) -> None:
    q = np.deg2rad([seed_ur5.Q_DEG])
    (tcp,) = plugin("ur5_closed_form:forward").frame_poses(ur5, q, ["tcp"])
    np.testing.assert_allclose(tcp[0], seed_ur5.T0[6], rtol=0, atol=SIX_DECIMALS)


@pytest.mark.usefixtures("plugins_importable")
def test_registry_builds_a_plugin_backend_from_module_function() -> None:
    backend = make_backend("ur5_closed_form:forward")
    assert isinstance(backend, PluginBackend)
    assert isinstance(backend, Backend)
    assert backend.name == "ur5_closed_form:forward"
    assert backend.method == "python callable ur5_closed_form:forward"


def test_dotted_module_path_is_split_at_the_last_colon() -> None:
    backend = plugin("mypkg.fk.core:forward")
    assert (backend.module, backend.function) == ("mypkg.fk.core", "forward")


def test_construction_imports_nothing_and_is_always_available(ur5: Model) -> None:
    backend = plugin("fkcheck_no_such_module_xyz:forward")
    assert backend.unavailable_reason(ur5) is None


@pytest.mark.parametrize("spec", ["no_colon", "mod:", ":func"])
def test_malformed_spec_is_bad_input(spec: str) -> None:
    with pytest.raises(BackendNotFoundError, match="module:function"):
        plugin(spec)


FAILURES = [
    ("fkcheck_no_such_module_xyz:forward", "cannot import module 'fkcheck_no_such_module_xyz'"),
    (
        "import_fails:forward",
        "importing module 'import_fails' raised RuntimeError: plugin module is broken on purpose",
    ),
    (
        "bad_plugins:missing",
        "module 'bad_plugins' has no attribute 'missing'; its public callables are: "
        "complex_output, float32_output, identity_int, mutates_input, nan_output, "
        "ragged_output, raises, single_pose, wrong_shape",
    ),
    ("bad_plugins:NOT_CALLABLE", "bad_plugins.NOT_CALLABLE is a int, not callable"),
    ("bad_plugins:raises", "raised ZeroDivisionError: the plugin divided by zero"),
    ("bad_plugins:wrong_shape", "returned shape (5, 3, 4); expected (5, 4, 4)"),
    ("bad_plugins:single_pose", "returned shape (4, 4); expected (5, 4, 4)"),
    ("bad_plugins:ragged_output", "returned a list that is not an array"),
    ("bad_plugins:nan_output", "returned NaN or inf for 1 of 5 configurations (first at index 2"),
    ("bad_plugins:float32_output", "returned dtype float32: too coarse for a comparison"),
    ("bad_plugins:complex_output", "returned dtype complex128; expected real numbers"),
]


@pytest.mark.usefixtures("plugins_importable")
@pytest.mark.parametrize(("spec", "message"), FAILURES, ids=[s for s, _ in FAILURES])
def test_failing_plugin_raises_a_plugin_error_naming_plugin_and_problem(
    ur5: Model, spec: str, message: str
) -> None:
    q = np.zeros((5, ur5.dof))
    with pytest.raises(PluginError, match=re.escape(f"plugin {spec}: {message}")):
        plugin(spec).frame_poses(ur5, q, ["tcp"])


def test_plugin_errors_are_backend_errors_not_bad_input() -> None:
    assert issubclass(PluginError, RuntimeError)
    assert not issubclass(PluginError, FkcheckError)


@pytest.mark.usefixtures("plugins_importable")
def test_plugin_gets_a_copy_of_q(ur5: Model) -> None:
    q = np.full((3, ur5.dof), 0.25)
    plugin("bad_plugins:mutates_input").frame_poses(ur5, q, ["tcp"])
    np.testing.assert_array_equal(q, 0.25)


@pytest.mark.usefixtures("plugins_importable")
def test_integer_output_is_accepted_as_exact_floats(ur5: Model) -> None:
    (tcp,) = plugin("bad_plugins:identity_int").frame_poses(ur5, np.zeros((2, 6)), ["tcp"])
    assert tcp.dtype == np.float64
    np.testing.assert_array_equal(tcp, np.tile(np.eye(4), (2, 1, 1)))


def test_mid_chain_frame_is_unavailable_before_the_plugin_is_imported() -> None:
    panda = load_model("panda")
    backend = plugin("fkcheck_no_such_module_xyz:forward")
    with pytest.raises(FrameUnavailable, match="'panda_link3' sits at DH frame 3, mid-chain"):
        backend.frame_poses(panda, np.zeros((1, panda.dof)), ["panda_link0", "panda_link3"])


def test_q_of_the_wrong_width_is_refused(ur5: Model) -> None:
    with pytest.raises(ValueError, match=r"q must have shape \(N, 6\), got \(4, 5\)"):
        plugin("ur5_closed_form:forward").frame_poses(ur5, np.zeros((4, 5)), ["tcp"])
