"""The plugin backend: a user's Python callable checked against the in-house core."""

from __future__ import annotations

import re
import time
from pathlib import Path

import numpy as np
import pytest

from fkcheck.backends.base import Backend, FrameUnavailable
from fkcheck.backends.plugin import PluginBackend, PluginError
from fkcheck.backends.registry import BackendOptions, make_backend
from fkcheck.core.tolerances import SAME_CHAIN, SIX_DECIMALS
from fkcheck.errors import BackendNotFoundError, FkcheckError, JointInputError
from fkcheck.model.frames import frame_poses_from_dh
from fkcheck.model.read import load_model
from fkcheck.model.types import Model
from fkcheck.process.supervise import TERMINATE_GRACE_S
from tests import seed_ur5
from tests.helpers import assert_pose_close, assert_se3, random_q
from tests.paths import PLUGINS_DIR
from tests.processes import LINUX_ONLY, assert_gone, wait_for_pids

PLUGINS = PLUGINS_DIR
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


@pytest.mark.usefixtures("plugins_importable")
def test_nan_from_a_plugin_is_an_answer_the_engine_fails(ur5: Model) -> None:
    """NaN is a wrong answer, not no answer: status fail, with where it happened."""
    from fkcheck.engine.runner import run_check

    check = run_check(ur5, [plugin("bad_plugins:nan_output")], samples=2, frame_from="world",
                      frame_to="tcp")  # fmt: skip
    (row,) = check.backends
    assert row.status == "fail"
    assert re.search(r"returned NaN or inf at 1 of \d+ configurations", row.message), row.message
    assert check.verdict == "fail"


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
    with pytest.raises(JointInputError, match=r"expected 6 joint values .* got shape \(4, 5\)"):
        plugin("ur5_closed_form:forward").frame_poses(ur5, np.zeros((4, 5)), ["tcp"])


def test_non_finite_q_is_refused_before_the_plugin_is_imported(ur5: Model) -> None:
    q = np.zeros((3, 6))
    q[2, 4] = np.nan
    backend = plugin("fkcheck_no_such_module_xyz:forward")  # importing it would fail
    with pytest.raises(JointInputError, match="configuration 2 joint 5 is nan"):
        backend.frame_poses(ur5, q, ["tcp"])


# ---------------------------------------------------------------- hostile plugins (issue 15)


@pytest.fixture
def hostile(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """``plugins/hostile.py`` importable; returns the pid file its plugins write."""
    monkeypatch.syspath_prepend(PLUGINS)
    monkeypatch.setenv("FKCHECK_TEST_PIDS", str(tmp_path / "pids"))
    return tmp_path / "pids"


DEATHS = [
    ("exit_zero", "its process exited with code 0 without an answer"),
    ("sys_exit", "its process exited with code 0 without an answer"),
    ("kills_itself", "its process was killed by SIGKILL without an answer: about to die"),
]


@pytest.mark.usefixtures("hostile")
@pytest.mark.parametrize(("function", "message"), DEATHS, ids=[f for f, _ in DEATHS])
def test_plugin_that_ends_its_process_is_an_error_never_a_success(
    ur5: Model, function: str, message: str
) -> None:
    with pytest.raises(PluginError) as caught:
        plugin(f"hostile:{function}").frame_poses(ur5, np.zeros((3, 6)), ["tcp"])
    assert str(caught.value) == f"plugin hostile:{function}: {message}"


@pytest.mark.usefixtures("hostile")
def test_what_a_plugin_prints_never_mixes_with_its_answer(ur5: Model) -> None:
    q = np.full((4, ur5.dof), 0.3)
    (tcp,) = plugin("hostile:prints").frame_poses(ur5, q, ["tcp"])
    assert_pose_close(tcp, ur5.fk(q), SAME_CHAIN)


@pytest.mark.usefixtures("hostile")
def test_a_huge_exception_message_is_cut_to_one_readable_line(ur5: Model) -> None:
    with pytest.raises(PluginError, match=r"raised ValueError: y{900,1000}…$") as caught:
        plugin("hostile:long_error").frame_poses(ur5, np.zeros((1, 6)), ["tcp"])
    assert len(str(caught.value)) < 1100


@pytest.mark.usefixtures("hostile")
def test_a_thread_the_plugin_leaves_running_does_not_hold_the_answer(ur5: Model) -> None:
    q = np.full((2, ur5.dof), -0.2)
    start = time.monotonic()
    (tcp,) = plugin("hostile:thread_left").frame_poses(ur5, q, ["tcp"])
    assert time.monotonic() - start < 20.0  # the thread sleeps 600 s
    assert_pose_close(tcp, ur5.fk(q), SAME_CHAIN)


@LINUX_ONLY
def test_a_process_the_plugin_leaves_in_its_own_session_is_killed(
    ur5: Model, hostile: Path
) -> None:
    q = np.full((2, ur5.dof), 0.1)
    (tcp,) = plugin("hostile:session_left").frame_poses(ur5, q, ["tcp"])
    assert_pose_close(tcp, ur5.fk(q), SAME_CHAIN)
    pids = [int(p) for p in hostile.read_text().split()]
    assert len(pids) == 2
    assert_gone(pids, within_s=1.0)  # killed before the answer was handed over


@LINUX_ONLY
@pytest.mark.parametrize("function", ["holds_gil", "sleeps"])
def test_plugin_that_never_returns_is_killed_at_its_time_limit(
    ur5: Model, hostile: Path, function: str
) -> None:
    backend = PluginBackend(f"hostile:{function}", BackendOptions(timeout_s=2.0))
    start = time.monotonic()
    with pytest.raises(PluginError) as caught:
        backend.frame_poses(ur5, np.zeros((1, 6)), ["tcp"])
    elapsed = time.monotonic() - start
    assert str(caught.value) == (
        f"plugin hostile:{function}: timed out after 2 s (its process was killed)"
    )
    assert 2.0 <= elapsed < 2.0 + TERMINATE_GRACE_S + 1.0
    assert_gone(wait_for_pids(hostile, 1.0), within_s=1.0)


@pytest.mark.usefixtures("plugins_importable")
@pytest.mark.parametrize(
    ("function", "problem"),
    [
        ("wrong_shape", r"wrong_shape_jacobian returned shape \(7, 6, 5\); expected \(7, 6, 6\)"),
        ("float32", r"float32_jacobian returned dtype float32: too coarse"),
        ("complex_out", r"complex_out_jacobian returned dtype complex128; expected real numbers"),
        ("strings", r"strings_jacobian returned dtype <U\d+; expected real numbers"),
        ("raises", r"raises_jacobian raised ValueError: no Jacobian here"),
        ("not_callable", r"ur5_jacobians\.not_callable_jacobian is a int, not callable"),
    ],
)
def test_a_plugins_jacobian_is_checked_like_its_poses(ur5: Model, function, problem) -> None:
    q = random_q(ur5, np.random.default_rng(0), 7)
    with pytest.raises(PluginError, match=problem):
        plugin(f"ur5_jacobians:{function}").frame_jacobian(ur5, q, "tcp", "world-aligned")


@pytest.mark.usefixtures("plugins_importable")
def test_a_plugins_jacobian_is_its_own_at_every_frame_posed_as_the_tcp(ur5: Model) -> None:
    q = random_q(ur5, np.random.default_rng(1), 5)
    backend = plugin("ur5_jacobians:correct")
    for frame in ("tcp", "tool0"):  # tool0: DH frame 6 with the (zero) tool's offset
        jac = backend.frame_jacobian(ur5, q, frame, "world-aligned")
        assert jac is not None
        assert jac.shape == (5, 6, 6)
    assert backend.frame_jacobian(ur5, q, "flange", "world-aligned") is None  # turned: not the TCP
    assert backend.frame_jacobian(ur5, q, "tcp", "local") is None  # the engine asks world-aligned
    assert plugin("ur5_closed_form:forward").frame_jacobian(ur5, q, "tcp", "world-aligned") is None
