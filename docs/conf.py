"""Sphinx configuration of fkcheck's documentation (Sphinx + MyST, theme furo).

Built by ``nox -s docs`` with ``-W --keep-going``: every warning is an error.
The reference is generated from the code: the CLI from its argparse parser
(sphinx-argparse), the API from docstrings (autodoc + napoleon), the backends
table and the model-file schema from the registry and the model readers
(``_ext/fkcheck_reference.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(DOCS.parent / "src"))

from fkcheck import __version__  # noqa: E402

project = "fkcheck"
author = "fkcheck developers"
copyright = "fkcheck developers"
release = __version__
version = __version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinxarg.ext",
    "fkcheck_reference",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build"]
nitpicky = False
# Help text and prose name options as typed: "--all" stays two hyphens, not an en dash.
smartquotes = False

myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "show-inheritance": False}
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_ivar = True

html_theme = "furo"
html_title = f"fkcheck {version}"
