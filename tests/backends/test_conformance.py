"""The conformance suite: every registered backend, built-in or third-party, through the same tests.

The backends come from the registry (:func:`fkcheck.backends.registry.registrations`),
so a backend added there — or installed by another distribution through the
``fkcheck.backends`` entry-point group — is tested here without a line changing.
A prefix (``cmd:``, ``poses:``…) takes an argument: the built-in ones are given
one below; a third-party prefix is held to the contract only, since nothing
here knows what its argument means.

What every backend must do (each test says what would be wrong if it passed
while the backend were broken):

* keep the contract (:func:`fkcheck.backends.base.contract_problems`), with
  evidence that matches what it reads;
* agree with the in-house core through the engine (on UR5, or the table its
  argument names), on the model's default pair (a backend that skips or errors does not conform);
* refuse joint values of the wrong shape as bad input;
* give its own Jacobian in every reference it declares, agreeing with the core;
* follow exactly what it reads: a backend computing from the model's table
  follows a changed table; every other one disagrees with it; a URDF reader
  disagrees with a URDF changed by 0.1 mm, and never opens a mesh.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fkcheck.backends import registry
from fkcheck.backends.base import Backend, contract_problems
from fkcheck.core.tolerances import ROUNDED_URDF, SAME_CHAIN
from fkcheck.engine.runner import run_check
from fkcheck.errors import FkcheckError
from fkcheck.model.read import load_model
from tests.backend_cases import (
    ARM3_TOML,
    ARM3_URDF,
    URDF_MODELS,
    assert_every_pair_agrees,
    edited_bundled_model,
    mapped_frames,
)
from tests.helpers import assert_se3, random_q
from tests.paths import DATA_DIR, PLUGINS_DIR

#: The argument each built-in prefix is tested with (UR5 in each form, but Robotics
#: Toolbox's UR5 has its own d1: its Puma 560 is the bundled table number for number).
PREFIX_CASES = {
    "rtb-model:": "Puma560",
    "cmd:": f"{sys.executable} {PLUGINS_DIR / 'fk_stdio.py'} ok",
    "poses:": str(DATA_DIR / "ur5_pendant.csv"),
}
#: The plugin form (``module:function``): a user's closed-form UR5 with its own Jacobian.
PLUGIN = "ur5_jacobians:correct"
#: Few configurations: the suite checks behaviour; accuracy is the property tests' job.
SAMPLES = 24
#: The model each case is checked on (UR5 unless named here), and a change of its d1
#: by 0.1 mm (10² tolerances) that every table-independent backend must see. The MJCF
#: readers' is the Panda's table on Menagerie's MJCF (tests/data/panda_mjcf.toml).
PANDA_MJCF = str(DATA_DIR / "panda_mjcf.toml")
MODELS = {"rtb-model:Puma560": "puma560", "mujoco-mjcf": PANDA_MJCF, "pinocchio-mjcf": PANDA_MJCF}
CHANGES = {
    "ur5": ("d = 0.089159", "d = 0.089259"),
    "puma560": ("d = 0.67183", "d = 0.67193"),
    PANDA_MJCF: ("d = 0.333", "d = 0.3331"),
}


def _specs() -> list[pytest.param]:
    """One case per registered backend: its name as ``--against`` gives it (or ``None``)."""
    params = []
    for r in registry.registrations():
        if not r.prefixed:
            params.append(pytest.param(r, r.name, id=r.name))
        else:
            arg = PREFIX_CASES.get(r.name) if r.origin == "fkcheck" else None
            params.append(pytest.param(r, None if arg is None else r.name + arg, id=r.name))
    params.append(pytest.param(None, PLUGIN, id="module:function"))
    return params


SPECS = _specs()
RUNNABLE = [p for p in SPECS if p.values[1] is not None]


@pytest.fixture(autouse=True)
def _plugins_importable(monkeypatch):
    monkeypatch.syspath_prepend(str(PLUGINS_DIR))


def _backend(spec: str) -> Backend:
    return registry.make_backend(spec)


def _model_of(spec: str) -> str:
    return MODELS.get(spec, "ur5")


@pytest.mark.parametrize(("registration", "spec"), SPECS)
def test_keeps_the_contract(registration, spec):
    if spec is None:  # a third-party prefix: what its class declares
        cls = registration.factory()
        for member in ("reads", "evidence"):
            assert isinstance(getattr(cls, member, None), str), f"{cls} declares no {member}"
        return
    backend = _backend(spec)
    assert contract_problems(backend) == []
    assert isinstance(backend, Backend)
    if registration is not None and not registration.prefixed:
        assert backend.name == registration.name
    inputs = backend.inputs(load_model(_model_of(spec)))
    assert isinstance(inputs, tuple)
    assert all(isinstance(p, Path) for p in inputs)


#: Built in a fresh process: which of a backend's ``imports`` appear in ``sys.modules``
#: when it is built, asked whether it can run and for its inputs (none may).
_IMPORTS_PROBE = """
import json, sys
from fkcheck.backends.registry import make_backend
from fkcheck.model.read import load_model
model = load_model(sys.argv[2])
before = set(sys.modules)
backend = make_backend(sys.argv[1])
reason, inputs = backend.unavailable_reason(model), backend.inputs(model)
names = {m for m in backend.imports} | {m.split(".")[0] for m in backend.imports}
loaded = sorted(n for n in names if n in sys.modules and n not in before)
print(json.dumps([reason, [str(p) for p in inputs], loaded]))
"""


PLAIN = [p for p in SPECS if p.values[0] is not None and not p.values[0].prefixed]


@pytest.mark.parametrize(("registration", "spec"), PLAIN)
def test_is_built_and_probed_without_importing_its_library(registration, spec):
    # Listing backends, --against's help and reports build every registered backend:
    # a library imported then would cost every fkcheck command its import time.
    done = subprocess.run(
        [sys.executable, "-c", _IMPORTS_PROBE, spec, _model_of(spec)],
        capture_output=True, text=True, check=True, timeout=120,
    )  # fmt: skip
    reason, inputs, loaded = json.loads(done.stdout)
    assert (reason, loaded) == (None, [])
    if registration.declared("reads") == "urdf":  # the model's URDF file, resolved
        assert [Path(p).name for p in inputs] == ["ur.urdf.xacro"]  # UR's ROS 2, bundled
    if registration.declared("reads") == "mjcf":  # the model's MJCF file, resolved
        assert [Path(p).name for p in inputs] == ["panda_nohand.xml"]  # Menagerie's, bundled


@pytest.mark.parametrize(("registration", "spec"), RUNNABLE)
def test_agrees_with_the_core(registration, spec):
    backend = _backend(spec)
    check = run_check(load_model(_model_of(spec)), [backend], samples=SAMPLES)
    (result,) = check.backends
    assert (result.status, result.message) == ("pass", "")
    assert result.evidence == backend.evidence
    assert result.max_position_error_m is not None
    assert result.max_position_error_m <= check.tol_pos_m


@pytest.mark.parametrize(("registration", "spec"), RUNNABLE)
def test_refuses_joint_values_of_the_wrong_shape(registration, spec):
    backend = _backend(spec)
    model = load_model(_model_of(spec))
    pair = [model.check.frame_from, model.check.frame_to]
    with pytest.raises(FkcheckError, match=r"joint|shape|column|value"):
        backend.frame_poses(model, np.zeros((2, model.dof - 1)), pair)


def _has_own_jacobian(spec: str) -> bool:
    sys.path.insert(0, str(PLUGINS_DIR))  # at collection: building imports no plugin, but
    try:  # the registry is asked as the test will ask it
        return registry.make_backend(spec).jacobian_method is not None
    finally:
        sys.path.remove(str(PLUGINS_DIR))


JACOBIAN_CASES = [
    pytest.param(*p.values, reference, id=f"{p.id}-{reference}")
    for p in RUNNABLE
    if _has_own_jacobian(p.values[1])
    for reference in ("world-aligned", "local", "world")
]


@pytest.mark.parametrize(("registration", "spec", "reference"), JACOBIAN_CASES)
def test_its_own_jacobian_agrees_in_every_reference_it_declares(registration, spec, reference):
    backend = _backend(spec)
    # Outside what it declares, the engine asks for world-aligned and re-expresses.
    asked = reference if reference in backend.jacobian_references else "world-aligned"
    model = load_model(_model_of(spec))
    q = np.random.default_rng(7).uniform(-3, 3, (4, model.dof))
    own = backend.frame_jacobian(model, q, model.check.frame_to, asked)
    assert own is not None
    assert own.shape == (4, 6, model.dof)
    check = run_check(
        model,
        [backend],
        samples=SAMPLES,
        jacobian=True,
        jacobian_reference=reference,
        tol_jacobian=1e-9,
    )
    (result,) = check.backends
    assert result.jacobian is not None
    assert result.jacobian.status == "pass", result.jacobian.message
    assert "differences" not in result.jacobian.method  # its own, not finite differences


@pytest.mark.parametrize(("registration", "spec"), RUNNABLE)
def test_follows_exactly_what_it_reads(tmp_path, registration, spec):
    backend = _backend(spec)
    name = _model_of(spec)
    changed = edited_bundled_model(tmp_path, name, *CHANGES[name])
    (result,) = run_check(changed, [backend], samples=SAMPLES).backends
    if backend.reads == "dh":  # computes from the table: follows it
        assert result.status == "pass"
    else:  # independent of the table: sees the change
        assert result.status == "fail"
        assert result.max_position_error_m is not None
        assert result.max_position_error_m >= 0.5e-4


URDF_READERS = [
    p for p in RUNNABLE if p.values[0] is not None and p.values[0].declared("reads") == "urdf"
]


@pytest.mark.parametrize("name", URDF_MODELS)
@pytest.mark.parametrize(("registration", "spec"), URDF_READERS)
def test_a_urdf_reader_gives_every_mapped_frame_pair_as_the_core(registration, spec, name):
    # Every pair, not only the check's: a reader must place every link a frame names.
    model = load_model(name)
    q = random_q(model, np.random.default_rng(11), 100)
    frames = mapped_frames(model)
    assert len(frames) >= 4
    poses = _backend(spec).frame_poses(model, q, frames)
    assert poses.shape == (len(frames), 100, 4, 4)
    assert_se3(poses, SAME_CHAIN)
    assert_every_pair_agrees(model, q, frames, poses, ROUNDED_URDF)


@pytest.mark.parametrize(("registration", "spec"), URDF_READERS)
def test_a_urdf_reader_sees_a_changed_urdf_and_never_opens_a_mesh(tmp_path, registration, spec):
    # arm3: a continuous joint, one turning about -z, a prismatic one, and a mesh
    # under package:// that does not exist (opening it would be an error).
    (tmp_path / "arm3.toml").write_text(ARM3_TOML)
    (tmp_path / "arm3.urdf").write_text(ARM3_URDF)
    backend = _backend(spec)
    pair = {"frame_from": "base", "frame_to": "tip"}
    (good,) = run_check(
        load_model(tmp_path / "arm3.toml"), [backend], samples=SAMPLES, **pair
    ).backends
    # (Its joints are what fkcheck's export of this table writes: the message may say its
    # agreement counts as implementation evidence; the reader's answer is what is tested.)
    assert good.status == "pass"
    (tmp_path / "arm3.urdf").write_text(ARM3_URDF.replace('xyz="0.4 0 0"', 'xyz="0.4001 0 0"'))
    (bad,) = run_check(
        load_model(tmp_path / "arm3.toml"), [backend], samples=SAMPLES, **pair
    ).backends
    assert bad.status == "fail"
    assert bad.max_position_error_m is not None
    assert bad.max_position_error_m >= 0.5e-4


def test_the_suite_covers_every_registration():
    covered = {p.values[0].name for p in SPECS if p.values[0] is not None}
    assert covered == {r.name for r in registry.registrations()}
    assert {"rtb-dh", "pinocchio-urdf", "cmd:", "poses:"} <= covered
