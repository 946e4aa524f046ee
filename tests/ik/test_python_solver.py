"""A ``module:function`` IK solver's module is found and refused as a plugin's is.

The solver and the ``--against module:function`` plugin share one import (from
the working directory, :func:`fkcheck.backends.plugin.import_callable`): each
import failure reads the same for both.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from fkcheck.backends.plugin import PluginBackend, PluginError
from fkcheck.backends.registry import BackendOptions
from fkcheck.errors import BackendNotFoundError
from fkcheck.ik.python_solver import PythonIkSolver
from fkcheck.ik.solver import IkSolverError
from fkcheck.model.read import load_model
from tests.paths import PLUGINS_DIR

#: Solver specs whose module cannot give a callable, and what both say.
REFUSED = [
    ("fkcheck_no_such_module_xyz:solve", "cannot import module 'fkcheck_no_such_module_xyz'"),
    (
        "import_fails:solve",
        "importing module 'import_fails' raised RuntimeError: plugin module is broken on purpose",
    ),
    ("bad_plugins:missing", "module 'bad_plugins' has no attribute 'missing'; its public"),
    ("bad_plugins:NOT_CALLABLE", "bad_plugins.NOT_CALLABLE is a int, not callable"),
]


@pytest.mark.parametrize(("spec", "message"), REFUSED, ids=[s for s, _ in REFUSED])
def test_a_solver_module_is_refused_in_the_plugins_words(monkeypatch, spec, message):
    monkeypatch.syspath_prepend(PLUGINS_DIR)
    model = load_model("ur5")
    with pytest.raises(IkSolverError, match=re.escape(f"IK solver {spec}: {message}")) as solver:
        PythonIkSolver(spec, model.dof, timeout_s=60.0).solve(np.eye(4))
    with pytest.raises(PluginError) as plugin:
        PluginBackend(spec, BackendOptions(timeout_s=60.0)).frame_poses(
            model, np.zeros((1, model.dof)), ["tcp"]
        )
    assert solver.value.problem == plugin.value.problem


@pytest.mark.parametrize("spec", ["solve", ":solve", "ur_ik:", " "])
def test_a_spec_that_is_not_module_function_is_bad_input(spec):
    with pytest.raises(BackendNotFoundError, match="module:function"):
        PythonIkSolver(spec, 6)
