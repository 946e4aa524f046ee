"""iDynTree's bindings, imported with SWIG's import-time deprecation warnings silenced.

Importing ``idyntree.bindings`` (iDynTree 15.1, SWIG bindings) emits
``DeprecationWarning: builtin type SwigPyPacked has no __module__ attribute``
(and the same for ``SwigPyObject`` and ``swigvarlink``) while its extension
module initialises. Where warnings are errors — ``python -W error``, or pytest
with ``filterwarnings = ["error"]`` as fkcheck's own test suite and many users'
have — that warning raised inside the extension's initialisation *crashes the
process* (segmentation fault) instead of raising. Importing this module instead
silences exactly those three messages for the duration of the import.

It is imported lazily, by :mod:`fkcheck.backends.idyntree_urdf`'s methods and by
the engine (the backend's ``imports``), never at package import.
"""

from __future__ import annotations

import warnings

__all__ = ["SWIG_IMPORT_WARNING", "bindings"]

#: The message of the warnings SWIG's bindings emit while they are imported.
SWIG_IMPORT_WARNING = r"builtin type (SwigPyPacked|SwigPyObject|swigvarlink) has no __module__"

with warnings.catch_warnings():
    warnings.filterwarnings("ignore", message=SWIG_IMPORT_WARNING, category=DeprecationWarning)
    import idyntree.bindings as bindings
