"""Every name a module's ``__all__`` lists exists (a hand-kept ``__all__`` drifts)."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

import fkcheck

MODULES = sorted(
    info.name
    for info in pkgutil.walk_packages(fkcheck.__path__, "fkcheck.")
    if info.name != "fkcheck.__main__"
)


def test_every_subpackage_module_is_listed():
    assert "fkcheck.core.dh" in MODULES
    assert "fkcheck.backends.registry" in MODULES


@pytest.mark.parametrize("module_name", ["fkcheck", *MODULES])
def test_all_names_exist(module_name):
    module = importlib.import_module(module_name)
    names = getattr(module, "__all__", None)
    if names is None:  # only a package whose __init__ is a docstring may leave it out
        public = [
            name
            for name, value in vars(module).items()
            if not name.startswith("_") and name != "annotations" and not inspect.ismodule(value)
        ]
        assert hasattr(module, "__path__"), f"{module_name} has no __all__"
        assert not public, f"{module_name} defines {public} but has no __all__"
        return
    assert len(set(names)) == len(names), f"{module_name}.__all__ repeats a name"
    missing = [name for name in names if not hasattr(module, name)]
    assert not missing, f"{module_name}.__all__ names what it does not define: {missing}"
