"""The batched Jacobian's numba kernel against the NumPy path (``geometric_jacobian``).

Entry by entry to FAST_CORE (the kernel has its own sin/cos and fused
multiply-adds; observed ≤ 2e-15 on the bundled arms), on every bundled model,
named frame and reference frame; random tables (revolute and prismatic, standard
and modified, base and tool, flipped joints); the paths it falls back to; out=.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fkcheck import JointInputError, load_model
from fkcheck.core import dh
from fkcheck.core import jacobian as core_jacobian
from fkcheck.core.tolerances import FAST_CORE
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.model.frames import frame_jacobian
from fkcheck.model.read import model_from_dict
from fkcheck.model.types import resolve_frame
from tests.helpers import BUNDLED, random_q
from tests.strategies import dh_models

numba = pytest.importorskip("numba")


@pytest.fixture(scope="module")
def kernel():
    assert core_jacobian.load_kernel(), core_jacobian.kernel_status()
    from fkcheck.core import _jacobian_kernels

    return _jacobian_kernels


@pytest.fixture
def jit_batches(kernel, monkeypatch):
    """Every batch, however small, goes to the kernel."""
    monkeypatch.setattr(dh, "JIT_MIN_POSES", 2)
    return kernel


def frame_args(model, frame):
    """``(moving, target)`` of a named frame, as ``frame_jacobian`` passes them."""
    spec = resolve_frame(model, frame)
    if spec.dh == "world":
        return 0, spec.offset.matrix
    if spec.dh == "tcp":
        return model.dof, model.chain.flange_T_tool @ spec.offset.matrix
    return spec.dh, spec.offset.matrix


def both_paths(model, q, frame, reference):
    moving, target = frame_args(model, frame)
    kw = {"moving": moving, "target": target, "reference": reference}
    fast = core_jacobian.jacobian(model.chain, q, **kw)
    slow = core_jacobian.jacobian_numpy(model.chain, q, **kw)
    return fast, slow


def assert_close(actual, expected, tol=FAST_CORE):
    assert actual.shape == expected.shape
    assert np.isfinite(actual).all()
    err = np.abs(actual - expected).max(initial=0.0)
    assert err <= tol, f"max entry error {err:.3g} > {tol:g}"


@pytest.mark.parametrize("name", BUNDLED)
@pytest.mark.parametrize("reference", JACOBIAN_REFERENCES)
def test_kernel_matches_numpy_on_every_bundled_model_frame_and_reference(
    jit_batches, name, reference, rng
):
    model = load_model(name)
    # Several blocks, a partial block and a tail shorter than one 8-pose transpose.
    q = random_q(model, rng, 2 * jit_batches.BLOCK + 13)
    for frame in model.frames:
        fast, slow = both_paths(model, q, frame, reference)
        assert_close(fast, slow)
        # Joints after the frame's DH frame do not move it: exact zeros, both paths.
        moving, _ = frame_args(model, frame)
        assert not fast[:, :, moving:].any(), frame


def test_the_bundled_models_cover_prismatic_modified_flipped_base_and_tool():
    """What the test above relies on to cover every branch of the kernel."""
    models = [load_model(name) for name in BUNDLED]
    assert any(m.chain.prismatic.any() for m in models)  # stanford
    assert any(m.convention == "modified" for m in models)  # panda
    assert any(not np.array_equal(m.chain.flange_T_tool, np.eye(4)) for m in models)


@settings(max_examples=max(1, settings().max_examples // 2), deadline=None)
@given(model=dh_models(max_joints=9), seed=st.integers(0, 2**32 - 1))
def test_kernel_matches_numpy_on_random_tables(model, seed):
    assert core_jacobian.load_kernel()
    q = random_q(model, np.random.default_rng(seed), 37)
    scale = 1.0 + float(np.abs(dh.fk_numpy(model.chain, q)[:, :3, 3]).max())
    for reference in JACOBIAN_REFERENCES:
        for frame in model.frames:
            moving, target = frame_args(model, frame)
            if moving == 0:
                continue
            out = np.empty((q.shape[0], 6, model.dof))
            code = core_jacobian._kernel.REFERENCE_CODES[reference]
            modified = model.convention == "modified"
            assert core_jacobian._kernel.jacobian_batch(
                q, model.chain.program, modified, moving, np.ascontiguousarray(target), code, out, 1
            )
            slow = core_jacobian.jacobian_numpy(
                model.chain, q, moving=moving, target=target, reference=reference
            )
            assert_close(out, slow, FAST_CORE * scale)


def test_model_jacobian_takes_the_kernel_for_large_batches_only(kernel, rng):
    """The path follows N (as fk's), and both give the NumPy path's numbers."""
    model = load_model("ur5")
    small = random_q(model, rng, 50)
    large = random_q(model, rng, dh.JIT_MIN_POSES)
    expected = core_jacobian.jacobian_numpy(
        model.chain, small, moving=6, target=model.chain.flange_T_tool
    )
    np.testing.assert_array_equal(model.jacobian(small), expected)  # NumPy: same bits
    fast = model.jacobian(large)
    slow = core_jacobian.jacobian_numpy(
        model.chain, large, moving=6, target=model.chain.flange_T_tool
    )
    assert_close(fast, slow)
    assert not np.array_equal(fast, slow)  # the kernel's own last bits: it did run


def test_threads_share_blocks_without_changing_a_bit(kernel, rng):
    """Worker counts given to the kernel itself: the parallel loop runs on any machine."""
    model = load_model("puma560")
    q = random_q(model, rng, kernel.PARALLEL_MIN_BLOCKS * kernel.BLOCK + 100)
    target = model.chain.flange_T_tool
    results = []
    for workers in (1, 2, 3, 64):
        out = np.empty((q.shape[0], 6, model.dof))
        code = kernel.REFERENCE_CODES["local"]
        assert kernel.jacobian_batch(q, model.chain.program, False, 6, target, code, out, workers)
        results.append(out)
    assert_close(results[0], core_jacobian.jacobian_numpy(
        model.chain, q, moving=6, target=target, reference="local"))  # fmt: skip
    for out in results[1:]:
        np.testing.assert_array_equal(out, results[0])


def test_an_overflowing_row_in_any_block_is_reported_by_the_parallel_loop(kernel):
    model = model_from_dict(
        {"name": "offset", "convention": "standard",
         "joint": [{"a": 0.5, "alpha": 0.3, "d": 0.1, "theta": 1e308}] * 2}
    )  # fmt: skip
    n = kernel.PARALLEL_MIN_BLOCKS * kernel.BLOCK + 5
    for row in (0, n // 2, n - 1):
        q = np.zeros((n, 2))
        q[row, 1] = 1e308  # finite, but q + θ overflows: the NumPy path must take over
        out = np.empty((n, 6, 2))
        with np.errstate(over="ignore", invalid="ignore"):
            assert not kernel.jacobian_batch(q, model.chain.program, False, 2, np.eye(4), 0, out, 2)


def test_angles_beyond_the_polynomial_range_take_libm(jit_batches, rng):
    model = load_model("ur5")
    q = random_q(model, rng, 40)
    q[7, 2] = 3e6  # beyond CODY_WAITE_LIMIT (~1.6e6 rad): that block is redone with libm
    q[30, 0] = -1e9
    fast, slow = both_paths(model, q, "tcp", "world")
    assert_close(fast, slow)


def test_an_overflowing_angle_gives_the_numpy_paths_nans(jit_batches):
    """s·q + θ overflows for a finite q: the kernel refuses, the NumPy path decides."""
    model = model_from_dict(
        {"name": "offset", "convention": "standard",
         "joint": [{"a": 0.5, "alpha": 0.3, "d": 0.1, "theta": 1e308}] * 2}
    )  # fmt: skip
    q = np.zeros((20, 2))
    q[7, 1] = 1e308  # finite, but q + θ0 overflows to inf
    with np.errstate(over="ignore", invalid="ignore"):
        fast, slow = both_paths(model, q, "tcp", "world-aligned")
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(slow))
    assert np.isnan(fast[7]).any()
    assert_close(np.delete(fast, 7, axis=0), np.delete(slow, 7, axis=0))


def test_without_numba_every_batch_takes_numpy(kernel, monkeypatch, rng):
    monkeypatch.setattr(core_jacobian, "_kernel", None)
    monkeypatch.setattr(core_jacobian, "_kernel_error", "ImportError: forced by the test")
    assert not core_jacobian.load_kernel()
    assert core_jacobian.kernel_status() == "unavailable: ImportError: forced by the test"
    model = load_model("stanford")
    q = random_q(model, rng, dh.JIT_MIN_POSES)
    for reference in JACOBIAN_REFERENCES:
        fast, slow = both_paths(model, q, "tcp", reference)
        np.testing.assert_array_equal(fast, slow)


def test_out_is_written_and_checked(jit_batches, rng):
    model = load_model("panda")
    q = random_q(model, rng, 20)
    out = np.full((20, 6, 7), np.nan)
    got = core_jacobian.jacobian(model.chain, q, moving=3, target=np.eye(4), out=out)
    assert got is out
    assert_close(out, core_jacobian.jacobian_numpy(model.chain, q, moving=3, target=np.eye(4)))
    with pytest.raises(ValueError, match=r"out must be a C-contiguous float64 array of shape"):
        core_jacobian.jacobian(model.chain, q, moving=7, target=np.eye(4), out=np.empty((20, 7, 6)))


def test_read_only_q_and_a_frame_fixed_to_the_base(jit_batches, rng):
    model = load_model("ur5")
    q = random_q(model, rng, 30)
    q.flags.writeable = False
    assert_close(*both_paths(model, q, "tool0", "local"))
    target = np.eye(4)
    target.flags.writeable = False  # a new numba type: it would be compiled again (seconds)
    big = random_q(model, rng, dh.JIT_MIN_POSES)
    kernel = core_jacobian._kernel
    assert kernel is not None
    compiled = len(kernel.jacobian_batch.signatures)
    core_jacobian.jacobian(model.chain, big, moving=6, target=target)
    assert len(kernel.jacobian_batch.signatures) == compiled
    zero = core_jacobian.jacobian(model.chain, q, moving=0, target=np.eye(4))
    np.testing.assert_array_equal(zero, np.zeros((30, 6, 6)))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"moving": 7}, r"moving must be between 0 and 6 \(the joints\), got 7"),
        ({"moving": -1}, r"moving must be between 0 and 6"),
        ({"target": np.eye(3)}, r"target must be a 4×4 transform, got shape \(3, 3\)"),
        ({"reference": "base"}, r"unknown reference 'base'; references are: world, local"),
    ],
)
def test_bad_arguments_are_refused(kwargs, message):
    model = load_model("ur5")
    args = {"moving": 6, "target": np.eye(4), **kwargs}
    with pytest.raises(ValueError, match=message):
        core_jacobian.jacobian(model.chain, np.zeros((2, 6)), **args)


def test_bad_joint_values_are_refused_on_both_paths(jit_batches):
    model = load_model("ur5")
    q = np.zeros((3, 6))
    q[1, 4] = np.inf
    for run in (core_jacobian.jacobian, core_jacobian.jacobian_numpy):
        with pytest.raises(JointInputError):
            run(model.chain, q, moving=6, target=np.eye(4))


def test_frame_jacobian_passes_the_frames_offset_and_the_tool(jit_batches, rng):
    """Through Model.jacobian: a named frame with an offset, and the TCP with the tool."""
    model = load_model("ur5")
    q = random_q(model, rng, 25)
    for frame in model.frames:
        moving, target = frame_args(model, frame)
        expected = core_jacobian.jacobian_numpy(model.chain, q, moving=moving, target=target)
        assert_close(frame_jacobian(model, q, frame), expected)
