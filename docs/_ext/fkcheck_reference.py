"""Reference tables generated from fkcheck's code, so that they cannot drift.

Directives (in MyST pages as ```{fkcheck-backends}``` blocks):

* ``fkcheck-backends`` — every registered backend (:data:`fkcheck.backends.registry.BUILTIN`
  and installed entry points): name, what it is (its class docstring's first line),
  the evidence its agreement gives, what it reads, whether a plain check runs it.
* ``fkcheck-model-schema`` — every section of a model file and the keys its reader
  accepts (the ``*_KEYS`` each reader in :mod:`fkcheck.model.sections` declares), each
  described by the ``Attributes:`` of the type it is read into.
* ``fkcheck-project-keys`` — the keys of ``[tool.fkcheck]``
  (:mod:`fkcheck.model.project`), described by :class:`~fkcheck.model.project.ProjectConfig`.
* ``fkcheck-action`` — the GitHub Action's inputs and outputs, from ``action.yml``.
"""

from __future__ import annotations

import importlib
import inspect
import re
from pathlib import Path
from typing import Any

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective

#: Model-file sections: (heading, reader module, its keys' name, the type read into,
#: key -> attribute where the two differ). ``None`` keys: the top-level table.
SECTIONS: tuple[tuple[str, str, str, str, dict[str, str]], ...] = (
    ("top level", "fkcheck.model.read", "_TOP_KEYS", "fkcheck.model.types:Model",
     {"joint": "joints", "known_difference": "known_differences", "lint": "lint_ignore"}),
    ("[[joint]]", "fkcheck.model.sections.joints", "JOINT_KEYS", "fkcheck.model.types:Joint", {}),
    ("[base], [tool]", "fkcheck.model.sections.offsets", "OFFSET_KEYS",
     "fkcheck.model.types:Offset", {}),
    ("[urdf]", "fkcheck.model.sections.urdf", "URDF_KEYS", "fkcheck.model.types:UrdfSpec", {}),
    ("[frames.NAME]", "fkcheck.model.sections.frames", "FRAME_KEYS",
     "fkcheck.model.types:FrameSpec", {"xyz": "offset", "rpy": "offset"}),
    ("[check]", "fkcheck.model.sections.check", "CHECK_KEYS", "fkcheck.model.types:CheckSpec",
     {"from": "frame_from", "to": "frame_to"}),
    ("[lint]", "fkcheck.model.sections.lint", "LINT_KEYS", "fkcheck.model.types:Model",
     {"ignore": "lint_ignore"}),
    ("[[known_difference]]", "fkcheck.model.sections.known_difference", "KNOWN_DIFFERENCE_KEYS",
     "fkcheck.model.types:KnownDifference", {}),
    ("[calibration]", "fkcheck.model.sections.calibration", "CALIBRATION_KEYS",
     "fkcheck.model.types:CalibrationSpec", {}),
)  # fmt: skip

#: What an ``Offset``'s two fields are (a one-line docstring, no ``Attributes:``).
_OFFSET = {
    "xyz": "Translation ``[x, y, z]`` in metres.",
    "rpy": "URDF-style fixed-axis roll, pitch, yaw, in the file's ``angle_unit``.",
}


def attributes(obj: Any) -> dict[str, str]:
    """The ``Attributes:`` section of a Google-style docstring: name -> text (one line)."""
    doc = inspect.getdoc(obj) or ""
    out: dict[str, str] = {}
    lines = doc.split("Attributes:\n", 1)[1].splitlines() if "Attributes:" in doc else []
    current = ""
    for line in lines:
        if line and not line.startswith(" "):
            break  # the next section
        match = re.match(r"^ {4}(\w+): (.*)$", line)
        if match:
            current = match.group(1)
            out[current] = match.group(2)
        elif current and line.strip():
            out[current] += " " + line.strip()
    return out


def _load(target: str) -> Any:
    module, _, attribute = target.partition(":")
    return getattr(importlib.import_module(module), attribute)


def _first_line(obj: Any) -> str:
    doc = inspect.getdoc(obj) or ""
    return doc.split("\n\n", 1)[0].replace("\n", " ")


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


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


class BackendsTable(_Table):
    """``fkcheck-backends``: the registry, one row per backend."""

    def markdown(self) -> list[str]:
        """One row per registration, the plugin form last."""
        from fkcheck.backends import registry

        rows = [
            "| name | what it is | evidence | reads | runs |",
            "|---|---|---|---|---|",
        ]
        for reg in (*registry.registrations(), registry._PLUGIN):
            cls = reg.factory()
            evidence = reg.declared("evidence") if reg is not registry._PLUGIN else cls.evidence
            reads = reg.declared("reads") if reg is not registry._PLUGIN else cls.reads
            runs = "by default" if reg.default else f"`--against {reg.name}…`"
            if not reg.prefixed and not reg.default and reg is not registry._PLUGIN:
                runs = f"`--against {reg.name}`"
            if reg is registry._PLUGIN:
                runs = "`--against mypkg.fk:forward`"
            name = f"`{reg.shown}`"
            rows.append(f"| {name} | {_cell(_first_line(cls))} | {evidence} | {reads} | {runs} |")
        return rows


class ModelSchema(_Table):
    """``fkcheck-model-schema``: each section's keys, as its reader declares them."""

    def markdown(self) -> list[str]:
        """A table per section; a key without a description is an error, not a blank."""
        out: list[str] = []
        for heading, module_name, keys_name, type_target, alias in SECTIONS:
            module = importlib.import_module(module_name)
            keys = sorted(getattr(module, keys_name))
            described = attributes(_load(type_target))
            out += [f"**{heading}** — {_cell(_first_line(module))}", ""]
            out += ["| key | meaning |", "|---|---|"]
            for key in keys:
                if key in _OFFSET and (heading.startswith("[base]") or alias.get(key) == "offset"):
                    text = _OFFSET[key]
                else:
                    text = described.get(alias.get(key, key), "")
                if not text:
                    raise ValueError(f"{heading} key {key!r}: no description in {type_target}")
                out.append(f"| `{key}` | {_cell(text)} |")
            out.append("")
        return out


class ProjectKeys(_Table):
    """``fkcheck-project-keys``: ``[tool.fkcheck]``'s keys, as the project reader declares them."""

    def markdown(self) -> list[str]:
        """One row per key, in the reader's order."""
        from fkcheck.model import project

        described = attributes(project.ProjectConfig)
        rows = ["| key | meaning |", "|---|---|"]
        for key in project._KEYS:
            if key not in described:
                raise ValueError(f"[tool.fkcheck] key {key!r}: not in ProjectConfig's Attributes")
            rows.append(f"| `{key}` | {_cell(described[key])} |")
        return rows


class ActionTable(_Table):
    """``fkcheck-action``: ``action.yml``'s inputs and outputs, with their descriptions."""

    def markdown(self) -> list[str]:
        """One row per input (with its default), then one per output."""
        import yaml

        action_yml = Path(self.env.srcdir).parent / "action.yml"
        self.env.note_dependency(str(action_yml))
        action = yaml.safe_load(action_yml.read_text(encoding="utf-8"))
        rows = ["| | name | default | meaning |", "|---|---|---|---|"]
        for name, spec in action["inputs"].items():
            default = spec.get("default", "")
            shown = f"`{default}`" if default else "(empty)"
            rows.append(f"| input | `{name}` | {shown} | {_cell(spec['description'])} |")
        for name, spec in action.get("outputs", {}).items():
            rows.append(f"| output | `{name}` | | {_cell(spec['description'])} |")
        return rows


def setup(app: Sphinx) -> dict[str, Any]:
    """Register the directives."""
    app.add_directive("fkcheck-backends", BackendsTable)
    app.add_directive("fkcheck-model-schema", ModelSchema)
    app.add_directive("fkcheck-project-keys", ProjectKeys)
    app.add_directive("fkcheck-action", ActionTable)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
