"""IK solvers by name: built-ins, the ``fkcheck.ik_solvers`` entry-point group, the user's function.

A throw-away distribution (a module and its ``.dist-info`` with
``entry_points.txt``, what ``pip install`` leaves in site-packages) is put on
``sys.path``, where :mod:`importlib.metadata` finds it as installed.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest

from fkcheck.ik import check_ik, make_solver
from fkcheck.ik.registry import SolverRegistration, valid_names
from fkcheck.ik.solver import SolverRefused
from fkcheck.model.read import load_model
from tests.ik import ur_ik

#: UR's ROS frames, written out here (not fkcheck's offsets): base is base_link turned
#: π about z; flange is tool0 turned by rpy(-90°, -90°, 0) = [[0,1,0],[0,0,1],[1,0,0]].
_BASE_T_BASE_LINK = np.array([[-1.0, 0, 0, 0], [0, -1.0, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]])
_FLANGE_T_TOOL0 = np.linalg.inv(
    np.array([[0.0, 1, 0, 0], [0, 0, 1, 0], [1, 0, 0, 0], [0, 0, 0, 1.0]])
)

MODULE = """
import numpy as np
import re
import sys
sys.path.insert(0, {tests!r})
from tests.ik import ur_ik


class Solver:
    name = "demo-ik"
    method = "Hawkins' closed form (fkcheck-demo-ik)"

    def solve(self, pose):
        return ur_ik.solve(pose)

    def fk(self, q):
        return ur_ik.fk(q)


def make(model):
    if model.dof != 6:
        raise ValueError("six joints only")
    return Solver()


def no_solve(model):
    return object()


def raises(model):
    raise RuntimeError("licence server unreachable")
"""


def _install(
    root: Path, monkeypatch: pytest.MonkeyPatch, entries: dict[str, str], broken: bool = False
) -> None:
    """The distribution on ``sys.path``, its module not imported yet."""
    monkeypatch.syspath_prepend(str(root))
    monkeypatch.delitem(sys.modules, "demo_ik", raising=False)
    (root / "demo_ik.py").write_text(
        "raise ImportError('a missing dependency')\n"
        if broken
        else MODULE.format(tests=str(Path(__file__).parents[2]))
    )
    info = root / "fkcheck_demo_ik-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fkcheck-demo-ik\nVersion: 1.0\n")
    lines = "".join(f"{name} = {value}\n" for name, value in entries.items())
    (info / "entry_points.txt").write_text(f"[fkcheck.ik_solvers]\n{lines}")


@pytest.fixture
def ur5e():
    return load_model("ur5e")


def test_entry_point_solver_is_named_and_checked(tmp_path, monkeypatch, ur5e):
    _install(tmp_path, monkeypatch, {"demo-ik": "demo_ik:make"})
    assert "demo-ik" in valid_names()
    solver = make_solver("demo-ik", ur5e, "base", "tool0")
    result = check_ik(ur5e, solver, frame_from="base", frame_to="tool0", samples=20, seed=0)
    assert result.verdict == "pass"
    assert result.method == "Hawkins' closed form (fkcheck-demo-ik)"


@pytest.mark.parametrize(
    ("entries", "name", "message"),
    [
        ({"demo-ik": "demo_ik:no_solve"}, "demo-ik",
         "breaks fkcheck's solver contract: it has no name or solve"),
        ({"demo-ik": "demo_ik:raises"}, "demo-ik",
         "building it for model ur5e failed: RuntimeError: licence server unreachable"),
        ({"demo-ik": "demo_ik:nowhere"}, "demo-ik", "cannot load demo_ik:nowhere"),
        ({"ur-analytic-ik": "demo_ik:make"}, "ur-analytic-ik", "the name is taken by fkcheck"),
        ({"Demo IK": "demo_ik:make"}, "Demo IK", "not a solver name"),
        ({"demo-ik": "not a target"}, "demo-ik", "is not module:factory"),
    ],
)  # fmt: skip
def test_a_broken_third_party_solver_is_one_line(tmp_path, monkeypatch, ur5e, entries, name,
                                                 message):  # fmt: skip
    _install(tmp_path, monkeypatch, entries)
    with pytest.raises(SolverRefused, match=message) as info:
        make_solver(name, ur5e, "base", "tool0")
    assert "\n" not in str(info.value)


def test_a_module_that_does_not_import_is_one_line(tmp_path, monkeypatch, ur5e):
    _install(tmp_path, monkeypatch, {"demo-ik": "demo_ik:make"}, broken=True)
    with pytest.raises(SolverRefused, match=r"cannot load demo_ik:make: ImportError: a missing"):
        make_solver("demo-ik", ur5e, "base", "tool0")


def test_a_built_in_whose_module_is_absent_is_not_available(ur5e):
    registration = SolverRegistration("later", "fkcheck.ik.not_written_yet:make")
    with pytest.raises(SolverRefused, match=r"^IK solver later is not available in this fkcheck"):
        registration.factory()


def test_a_built_in_missing_its_factory_is_not_called_absent():
    """Only the named module's absence is 'not available'; any other failure is said."""
    registration = SolverRegistration("odd", "fkcheck.ik.solver:no_such_factory")
    with pytest.raises(SolverRefused, match=re.escape("cannot load fkcheck.ik.solver:no_such_")):
        registration.factory()


def test_the_users_function_is_a_solver_by_its_spec(ur5e):
    solver = make_solver("tests.ik.ur_ik:solve", ur5e, "base", "tool0")
    assert solver.name == "tests.ik.ur_ik:solve"
    assert np.asarray(solver.solve(np.eye(4))).shape[1] == 6


def test_a_solver_declaring_its_own_frames_is_asked_in_them(ur5e):
    """A solver for base_link -> flange answers a base -> tool0 check: same DH frames."""
    from fkcheck.ik.frames import for_frames

    class BaseLinkFlange:
        name = "declares"
        frame_from, frame_to = "base_link", "flange"

        def __init__(self):
            self.asked = []

        def solve(self, pose):
            self.asked.append(pose)
            # Its own maths for its pair: tests.ik.ur_ik solves base -> tool0.
            base_T_tool0 = _BASE_T_BASE_LINK @ pose @ _FLANGE_T_TOOL0
            return ur_ik.solve(base_T_tool0)

        def fk(self, q):
            return np.linalg.inv(_BASE_T_BASE_LINK) @ ur_ik.fk(q) @ np.linalg.inv(_FLANGE_T_TOOL0)

    inner = BaseLinkFlange()
    solver = for_frames(ur5e, inner, "base", "tool0")
    result = check_ik(ur5e, solver, frame_from="base", frame_to="tool0", samples=20, seed=0)
    assert result.verdict == "pass"
    assert result.own_fk
    assert "it solves base_link -> flange" in result.method
    q = np.radians([10.0, -60.0, 80.0, -20.0, 30.0, 40.0])
    solver.solve(ur5e.fk(q, frame_from="base", frame_to="tool0"))
    assert np.allclose(inner.asked[-1], ur5e.fk(q, frame_from="base_link", frame_to="flange"))


def test_a_solver_on_other_dh_frames_is_refused(ur5e):
    from fkcheck.ik.frames import for_frames

    class World:
        name = "mid-chain"
        frame_from, frame_to = "world", "base"

        def solve(self, pose):
            return np.zeros((0, 6))

    with pytest.raises(SolverRefused, match=r"solves world -> base \(DH frames 0 -> 0\)"):
        for_frames(ur5e, World(), "base", "tool0")
