"""The fast paths of the DH core (numba kernels, scalar Python, chunked NumPy) against the
plain 4×4 chain, entry by entry, to FAST_CORE; their sin/cos; out=; chunking; fallbacks."""

from __future__ import annotations

import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fkcheck import JointInputError, load_model
from fkcheck.core import dh
from fkcheck.core.dh import fk, fk_numpy, fk_reference
from fkcheck.core.tolerances import FAST_CORE
from fkcheck.model.read import model_from_dict
from tests.helpers import BUNDLED, assert_se3, random_q
from tests.strategies import dh_models

numba = pytest.importorskip("numba")

#: One unit in the last place of 1.0: the kernels' sin/cos must be this close to libm's.
ULP_1 = float(np.spacing(1.0))


@pytest.fixture(scope="module")
def kernels():
    assert dh.load_jit(), dh.jit_status()
    from fkcheck.core import _kernels

    return _kernels


@pytest.fixture
def jit_batches(kernels, monkeypatch):
    """fk() sends every batch, however small, to the JIT kernel."""
    monkeypatch.setattr(dh, "JIT_MIN_POSES", 2)
    return kernels


@pytest.fixture
def no_jit(monkeypatch):
    """fkcheck.core.dh as on a machine without numba."""
    monkeypatch.setattr(dh, "_jit", None)
    monkeypatch.setattr(dh, "_jit_error", "ImportError: forced by the test")


def assert_entries_close(actual, expected, tol=FAST_CORE):
    actual = np.asarray(actual)
    assert actual.shape == expected.shape
    assert np.isfinite(actual).all()
    err = np.abs(actual - expected).max(initial=0.0)
    assert err <= tol, f"max entry error {err:.3g} > {tol:g}"


def wide_q(model, rng, n, scale):
    """Configurations with revolute joints anywhere in ±scale rad (prismatic within limits)."""
    q = random_q(model, rng, n)
    revolute = ~model.chain.prismatic
    q[:, revolute] = rng.uniform(-scale, scale, size=(n, int(revolute.sum())))
    return q


# --------------------------------------------------------------------------- sin/cos


@pytest.mark.parametrize(
    "x",
    [
        np.linspace(-10.0, 10.0, 100_001),
        # Right next to multiples of π/2, where the reduced angle is tiny.
        (np.arange(-4000, 4000) * (math.pi / 2))[:, None] + np.array([0.0, 1e-15, -1e-9]),
        # Multiples of π/2 near the top of the Cody–Waite range (k close to 2**20).
        np.arange(2**20 - 2000, 2**20 + 1) * (math.pi / 2),
        np.geomspace(1e-300, 1e6, 5000),
    ],
    ids=["small", "near-k-pi/2", "top-of-range", "geometric"],
)
def test_kernel_sincos_is_within_one_ulp_of_libm(kernels, x, rng):
    x = np.ascontiguousarray(np.concatenate([np.ravel(x), -np.ravel(x)]))
    s, c = np.empty_like(x), np.empty_like(x)
    kernels.sincos_array(x, s, c)
    np.testing.assert_allclose(s, [math.sin(v) for v in x], rtol=0, atol=ULP_1)
    np.testing.assert_allclose(c, [math.cos(v) for v in x], rtol=0, atol=ULP_1)


def test_kernel_sincos_large_angles_use_exact_reduction(kernels, rng):
    limit = kernels.CODY_WAITE_LIMIT
    x = np.concatenate(
        [
            rng.uniform(-limit, limit, 20_000),  # polynomial path, full range
            [limit, -limit, np.nextafter(limit, np.inf), -np.nextafter(limit, np.inf)],
            rng.uniform(1e7, 1e12, 1000) * rng.choice([-1.0, 1.0], 1000),  # libm fallback
            [1e300, -1e300, 1.7976931348623157e308, 5e-324],
        ]
    )
    s, c = np.empty_like(x), np.empty_like(x)
    kernels.sincos_array(x, s, c)
    np.testing.assert_allclose(s, [math.sin(v) for v in x], rtol=0, atol=ULP_1)
    np.testing.assert_allclose(c, [math.cos(v) for v in x], rtol=0, atol=ULP_1)


# --------------------------------------------------------------------------- batches


@pytest.mark.parametrize("name", BUNDLED)
def test_jit_batch_matches_reference_on_every_bundled_model(jit_batches, name, rng):
    model = load_model(name)
    # Several blocks, a partial block, and a tail shorter than one vector (8 poses).
    q = random_q(model, rng, 3 * jit_batches.BLOCK + 13)
    T = fk(model.chain, q)
    assert_entries_close(T, fk_reference(model.chain, q))
    assert_se3(T, FAST_CORE)


@pytest.mark.parametrize("name", BUNDLED)
@pytest.mark.parametrize("scale", [100.0, 1e6])
def test_jit_batch_matches_reference_for_large_angles(jit_batches, name, scale, rng):
    model = load_model(name)
    q = wide_q(model, rng, 2000, scale)
    assert_entries_close(fk(model.chain, q), fk_reference(model.chain, q))


@pytest.mark.parametrize("name", ["ur5", "panda", "stanford"])
def test_jit_batch_beyond_the_polynomial_range_matches_reference(jit_batches, name, rng):
    model = load_model(name)
    q = wide_q(model, rng, 600, 1.0)
    revolute = np.flatnonzero(~model.chain.prismatic)
    # A few angles beyond the Cody–Waite limit, scattered over blocks and joints.
    for k, value in enumerate([1e7, -3e9, 1e15, -1e300, jit_batches.CODY_WAITE_LIMIT * 1.5]):
        q[97 * k + 5, revolute[k % revolute.size]] = value
    assert_entries_close(fk(model.chain, q), fk_reference(model.chain, q))


@settings(max_examples=60, deadline=None)
@given(model=dh_models(), seed=st.integers(0, 2**32 - 1), n=st.integers(1, 40))
def test_jit_batch_matches_reference_on_random_tables(kernels, model, seed, n):
    rng = np.random.default_rng(seed)
    q = wide_q(model, rng, n, 50.0)
    out = np.empty((n, 4, 4))
    kernels.fk_tcp(q, model.chain.program, model.convention == "modified", out, 3)
    # Round-off grows with the size of the numbers: scale FAST_CORE (set for arms of
    # about a metre) by the arm's reach, which reaches 50 m in these random tables.
    chain = model.chain
    reach = (
        np.abs(chain.a).sum()
        + np.abs(chain.d).sum()
        + np.abs(q[:, chain.prismatic]).sum(1).max(initial=0)
    )
    reach += np.abs(chain.world_T_base[:3, 3]).sum() + np.abs(chain.flange_T_tool[:3, 3]).sum()
    assert_entries_close(out, fk_reference(chain, q), tol=FAST_CORE * max(1.0, reach))


def test_jit_batch_result_does_not_depend_on_the_threads(kernels, rng):
    model = load_model("panda")
    # Enough blocks for the parallel loop, and a partial last block.
    q = wide_q(model, rng, kernels.PARALLEL_MIN_BLOCKS * kernels.BLOCK + 77, 1e3)
    results = []
    for workers in (1, 2, 3, 64):
        out = np.empty((q.shape[0], 4, 4))
        assert kernels.fk_tcp(q, model.chain.program, True, out, workers)
        results.append(out)
    assert_entries_close(results[0], fk_reference(model.chain, q))
    for out in results[1:]:
        np.testing.assert_array_equal(out, results[0])


def test_jit_batch_reports_non_finite_values_in_any_block(kernels):
    model = load_model("ur5")
    n = kernels.PARALLEL_MIN_BLOCKS * kernels.BLOCK + 5
    for row, value in [(0, math.nan), (n - 1, math.inf), (n // 2, -math.inf)]:
        q = np.zeros((n, 6))
        q[row, row % 6] = value
        for workers in (1, 2):
            assert not kernels.fk_tcp(q, model.chain.program, False, np.empty((n, 4, 4)), workers)


def test_jit_batch_angle_overflow_gives_the_references_nans(jit_batches):
    model = model_from_dict(
        {"name": "offset", "convention": "standard",
         "joint": [{"a": 0.5, "alpha": 0.3, "d": 0.1, "theta": 1e308}] * 2}
    )  # fmt: skip
    q = np.zeros((20, 2))
    q[7, 1] = 1e308  # finite, but q + θ0 overflows to inf
    with np.errstate(over="ignore", invalid="ignore"):  # as NumPy warns for the reference
        T, ref = fk(model.chain, q), fk_reference(model.chain, q)
    # NaN where the reference has NaN (its last row too, from the matrix product: ours
    # stays 0 0 0 1), and the other poses as usual.
    np.testing.assert_array_equal(np.isnan(T[:, :3]), np.isnan(ref[:, :3]))
    assert np.isnan(T[7, :3]).all()
    assert_entries_close(np.delete(T, 7, axis=0), np.delete(ref, 7, axis=0))


@pytest.mark.parametrize("name", BUNDLED)
def test_numpy_path_matches_reference_on_every_bundled_model(name, rng):
    model = load_model(name)
    q = wide_q(model, rng, 500, 1e6)
    assert_entries_close(fk_numpy(model.chain, q), fk_reference(model.chain, q))
    frames = fk_numpy(model.chain, q, all_frames=True)
    assert_entries_close(frames, fk_reference(model.chain, q, all_frames=True))


@pytest.mark.parametrize("all_frames", [False, True])
def test_numpy_path_in_chunks_equals_one_chunk(monkeypatch, all_frames, rng):
    model = load_model("stanford")
    q = random_q(model, rng, 50)
    whole = fk_numpy(model.chain, q, all_frames=all_frames)
    monkeypatch.setattr(dh, "NUMPY_CHUNK", 7)  # 50 poses: seven full chunks and one of 1
    np.testing.assert_array_equal(fk_numpy(model.chain, q, all_frames=all_frames), whole)


# --------------------------------------------------------------------------- one pose


@pytest.mark.parametrize("name", BUNDLED)
def test_one_pose_paths_match_reference(kernels, name, rng, monkeypatch):
    model = load_model(name)
    qs = np.concatenate([random_q(model, rng, 20), wide_q(model, rng, 20, 1e6)])
    jit_T = [fk(model.chain, q) for q in qs]
    jit_list_T = [fk(model.chain, list(q)) for q in qs]
    monkeypatch.setattr(dh, "_jit", None)
    py_T = [fk(model.chain, q) for q in qs]
    py_tuple_T = [fk(model.chain, tuple(q)) for q in qs]
    ref = fk_reference(model.chain, qs)
    for T in (jit_T, jit_list_T, py_T, py_tuple_T):
        assert_entries_close(np.array(T), ref)
    assert all(T.shape == (4, 4) and T.dtype == np.float64 for T in jit_T + py_T)


@pytest.mark.parametrize("name", BUNDLED)
def test_one_pose_jit_and_python_give_the_same_bits(kernels, name, rng, monkeypatch):
    model = load_model(name)
    qs = np.concatenate([random_q(model, rng, 50), wide_q(model, rng, 50, 1e6)])
    jit_T = np.array([fk(model.chain, q) for q in qs])
    monkeypatch.setattr(dh, "_jit", None)
    np.testing.assert_array_equal(jit_T, [fk(model.chain, q) for q in qs])


def test_small_batches_do_not_depend_on_whether_the_jit_is_loaded(kernels, rng, monkeypatch):
    model = load_model("panda")
    q = wide_q(model, rng, 100, 1e3)
    loaded = fk(model.chain, q)
    monkeypatch.setattr(dh, "_jit", None)
    np.testing.assert_array_equal(fk(model.chain, q), loaded)


@pytest.mark.parametrize("path", ["jit", "python"])
def test_one_pose_odd_inputs_take_the_general_path(kernels, path, monkeypatch):
    if path == "python":
        monkeypatch.setattr(dh, "_jit", None)
    model = load_model("ur5")
    q = np.deg2rad([30.0, -60, 90, -120, -90, 45])
    expected = fk_reference(model.chain, q)
    read_only = q.copy()
    read_only.flags.writeable = False
    strided = np.repeat(q, 2)[::2]
    for odd in (read_only, strided, q.astype(np.float32), q.tolist(), [int(v) for v in q * 0]):
        ref = fk_reference(model.chain, np.asarray(odd, dtype=np.float64))
        assert_entries_close(fk(model.chain, odd), ref, tol=FAST_CORE)
    assert_entries_close(fk(model.chain, read_only), expected)


@pytest.mark.parametrize("path", ["jit", "python", "numpy"])
@pytest.mark.parametrize(
    "bad",
    [[0.0, 0, 0, 0, 0, math.nan], [math.inf, 0, 0, 0, 0, 0], [0.0] * 5, [[0.0] * 6] * 2 + [[1.0]]],
)
def test_bad_joint_values_raise_on_every_path(kernels, path, bad, monkeypatch):
    if path != "jit":
        monkeypatch.setattr(dh, "_jit", None)
    model = load_model("ur5")
    call = fk_numpy if path == "numpy" else fk
    for q in (bad, np.array(bad, dtype=object)):
        with pytest.raises(JointInputError):
            call(model.chain, q)
    with pytest.raises(JointInputError, match="finite"):
        call(model.chain, np.array([[0.0] * 6] * 3 + [[0.0] * 5 + [math.nan]]))


# --------------------------------------------------------------------------- out=


@pytest.mark.parametrize("path", ["jit", "numpy"])
@pytest.mark.parametrize("all_frames", [False, True])
@pytest.mark.parametrize("n", [None, 1, 700])
def test_out_is_filled_and_returned(jit_batches, path, all_frames, n, rng, monkeypatch):
    if path == "numpy":
        monkeypatch.setattr(dh, "_jit", None)
        monkeypatch.setattr(dh, "_jit_error", "ImportError: forced by the test")
    model = load_model("panda")
    q = random_q(model, rng, 1 if n is None else n)
    q = q[0] if n is None else q
    expected = fk_reference(model.chain, q, all_frames=all_frames)
    out = np.full(expected.shape, np.nan)
    result = fk(model.chain, q, all_frames=all_frames, out=out)
    assert result is out
    assert_entries_close(out, expected)


def test_out_is_reused_across_calls(jit_batches, rng):
    model = load_model("ur5")
    out = np.empty((300, 4, 4))
    for _ in range(3):
        q = random_q(model, rng, 300)
        fk(model.chain, q, out=out)
        assert_entries_close(out, fk_reference(model.chain, q))


@pytest.mark.parametrize(
    ("out", "problem"),
    [
        (np.empty((10, 4, 4), dtype=np.float32), "float64"),
        (np.empty((9, 4, 4)), "shape"),
        (np.empty((4, 4, 10)).transpose(2, 0, 1), "C-contiguous"),
        ([[0.0] * 4] * 4, "NumPy array"),
    ],
)
def test_out_of_the_wrong_kind_is_refused(kernels, out, problem):
    model = load_model("ur5")
    with pytest.raises(ValueError, match=problem):
        fk(model.chain, np.zeros((10, 6)), out=out)


def test_out_overlapping_q_or_read_only_is_refused(kernels):
    model = load_model("ur5")
    buf = np.zeros(10 * 16)
    with pytest.raises(ValueError, match="overlaps"):
        fk(model.chain, buf[:60].reshape(10, 6), out=buf.reshape(10, 4, 4))
    read_only = np.empty((10, 4, 4))
    read_only.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        fk(model.chain, np.zeros((10, 6)), out=read_only)


# --------------------------------------------------------------------------- fallbacks


def test_forced_fallback_gives_the_same_results(kernels, no_jit, rng):
    assert not dh.load_jit()
    assert dh.jit_status() == "unavailable: ImportError: forced by the test"
    model = load_model("panda")
    q = wide_q(model, rng, dh.JIT_MIN_POSES + 5, 1e3)  # big enough to ask for the JIT
    fallback = fk(model.chain, q)
    assert_entries_close(fallback, fk_reference(model.chain, q))
    assert_entries_close(fk(model.chain, q[0]), fk_reference(model.chain, q[0]))
    np.testing.assert_array_equal(fallback, fk_numpy(model.chain, q))


def run_python(code: str, **env: str) -> str:
    result = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
        env={**__import__("os").environ, **env},
    )
    return result.stdout.strip()


def test_without_numba_everything_still_works():
    out = run_python(
        """
        import sys
        sys.modules["numba"] = None  # as if numba were not installed
        import numpy as np
        import fkcheck
        from fkcheck.core import dh
        model = fkcheck.load_model("ur5")
        q = np.random.default_rng(0).uniform(-3, 3, (dh.JIT_MIN_POSES, 6))
        err = np.abs(model.fk(q) - dh.fk_reference(model.chain, q)).max()
        one = np.abs(model.fk(q[0]) - dh.fk_reference(model.chain, q[0])).max()
        print(dh.load_jit(), err <= 1e-14, one <= 1e-14, dh.jit_status())
        """
    )
    assert out.startswith("False True True unavailable: ModuleNotFoundError: "), out


def test_numba_disabled_falls_back_to_numpy():
    out = run_python(
        """
        from fkcheck.core import dh
        print(dh.load_jit(), dh.jit_status())
        """,
        NUMBA_DISABLE_JIT="1",
    )
    assert out == "False unavailable: ImportError: NUMBA_DISABLE_JIT is set", out


def test_no_writable_numba_cache_falls_back_to_numpy():
    out = run_python(
        """
        import numba.core.caching
        numba.core.caching.CacheImpl._locator_classes = []  # no cache directory fits
        import numpy as np
        from fkcheck import load_model
        from fkcheck.core import dh
        chain = load_model("ur5").chain
        q = np.random.default_rng(0).uniform(-3, 3, (dh.JIT_MIN_POSES, 6))
        err = np.abs(dh.fk(chain, q) - dh.fk_reference(chain, q)).max()
        print(dh.load_jit(), err <= 1e-14, dh.jit_status())
        """
    )
    assert out.startswith("False True unavailable: RuntimeError: cannot cache function"), out


def test_import_and_one_pose_and_cli_help_do_not_import_numba():
    out = run_python(
        """
        import sys
        import numpy as np
        import fkcheck
        from fkcheck.cli.main import build_parser, main
        build_parser().format_help()
        assert main(["fk", "ur5", "--q", "0,0,0,0,0,0"]) == 0
        model = fkcheck.load_model("ur5")
        model.fk(np.zeros(6))
        model.fk([0.1] * 6)
        model.fk(np.zeros((100, 6)))
        print("numba" in sys.modules)
        """
    )
    assert out.splitlines()[-1] == "False"


def test_jit_loading_reports_its_status(kernels):
    assert dh.jit_status().startswith(f"loaded (numba {numba.__version__}")
