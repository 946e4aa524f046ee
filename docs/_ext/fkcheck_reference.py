"""Reference tables generated from fkcheck's code, so that they cannot drift.

Directives (in MyST pages as ```{fkcheck-backends}``` blocks), each the Markdown of
:mod:`fkcheck_tables` (which tests/docs checks without Sphinx):

* ``fkcheck-backends`` — every registered backend: name, what it is, the evidence its
  agreement gives, what it reads, whether a plain check runs it.
* ``fkcheck-model-schema`` — every section of a model file and the keys its reader
  accepts, each described by the ``Attributes:`` of the type it is read into.
* ``fkcheck-project-keys`` — the keys of ``[tool.fkcheck]``.
* ``fkcheck-action`` — the GitHub Action's inputs and outputs, from ``action.yml``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import fkcheck_tables
from docutils import nodes
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective


class _Table(SphinxDirective):
    """A directive that writes a Markdown table and parses it as MyST."""

    def markdown(self) -> list[str]:
        """The table's Markdown lines."""
        raise NotImplementedError

    def run(self) -> list[nodes.Node]:
        container = nodes.container()
        text = "\n".join(self.markdown())
        self.state.nested_parse(StringList(text.splitlines(), source="fkcheck_reference"),
                                self.content_offset, container)  # fmt: skip
        return container.children


class BackendsTable(_Table):
    """``fkcheck-backends``: the registry, one row per backend."""

    def markdown(self) -> list[str]:
        """One row per registration, the plugin form last."""
        return fkcheck_tables.backends_markdown()


class ModelSchema(_Table):
    """``fkcheck-model-schema``: each section's keys, as its reader declares them."""

    def markdown(self) -> list[str]:
        """A table per section; a key without a description is an error, not a blank."""
        return fkcheck_tables.model_schema_markdown()


class ProjectKeys(_Table):
    """``fkcheck-project-keys``: ``[tool.fkcheck]``'s keys, as the project reader declares them."""

    def markdown(self) -> list[str]:
        """One row per key, in the reader's order."""
        return fkcheck_tables.project_keys_markdown()


class ActionTable(_Table):
    """``fkcheck-action``: ``action.yml``'s inputs and outputs, with their descriptions."""

    def markdown(self) -> list[str]:
        """One row per input (with its default), then one per output."""
        action_yml = Path(self.env.srcdir).parent / "action.yml"
        self.env.note_dependency(str(action_yml))
        return fkcheck_tables.action_markdown(action_yml)


def setup(app: Sphinx) -> dict[str, Any]:
    """Register the directives."""
    app.add_directive("fkcheck-backends", BackendsTable)
    app.add_directive("fkcheck-model-schema", ModelSchema)
    app.add_directive("fkcheck-project-keys", ProjectKeys)
    app.add_directive("fkcheck-action", ActionTable)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
