"""The reference tables' Markdown, generated from fkcheck's code (no Sphinx needed).

:mod:`fkcheck_reference` turns each into a directive; tests/docs reads them here, so
that what the site shows is checked where Sphinx is not installed:

* :func:`backends_markdown` — every registered backend (:data:`fkcheck.backends.registry.BUILTIN`
  and installed entry points): name, what it is (its class docstring's first line),
  the evidence its agreement gives, what it reads (and which description formats),
  whether a plain check runs it.
* :func:`model_schema_markdown` — every section of a model file and the keys its reader
  accepts (the ``*_KEYS`` each reader in :mod:`fkcheck.model.sections` declares), each
  described by the ``Attributes:`` of the type it is read into.
* :func:`project_keys_markdown` — the keys of ``[tool.fkcheck]``
  (:mod:`fkcheck.model.project`), described by :class:`~fkcheck.model.project.ProjectConfig`
  and, for a check option, by :class:`~fkcheck.model.options.CheckOptions`.
* :func:`action_markdown` — the GitHub Action's inputs and outputs, from ``action.yml``.

Docstrings are reStructuredText; the tables are parsed as MyST Markdown, so each
text goes through :func:`myst_text` (``:func:`x``` becomes ``{func}`x```).
"""

from __future__ import annotations

import importlib
import inspect
import re
from pathlib import Path
from typing import Any

__all__ = [
    "ANGLE_KEYS",
    "SECTIONS",
    "action_markdown",
    "attributes",
    "backends_markdown",
    "model_schema_markdown",
    "myst_text",
    "project_keys_markdown",
]

#: Model-file sections: (heading, reader module, its keys' name, the type read into,
#: key -> attribute where the two differ). ``None`` keys: the top-level table.
SECTIONS: tuple[tuple[str, str, str, str, dict[str, str]], ...] = (
    ("top level", "fkcheck.model.read", "_TOP_KEYS", "fkcheck.model.types:Model",
     {"joint": "joints", "known_difference": "known_differences", "lint": "lint_ignore"}),
    ("[[joint]]", "fkcheck.model.sections.joints", "JOINT_KEYS", "fkcheck.model.types:Joint", {}),
    ("[base], [tool]", "fkcheck.model.sections.offsets", "OFFSET_KEYS",
     "fkcheck.model.types:Offset", {}),
    ("[urdf]", "fkcheck.model.sections.urdf", "URDF_KEYS", "fkcheck.model.types:UrdfSpec", {}),
    ("[mjcf]", "fkcheck.model.sections.mjcf", "MJCF_KEYS", "fkcheck.model.types:MjcfSpec", {}),
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

#: Keys whose angles the reader reads in the file's ``angle_unit`` (times ``to_rad``),
#: by section: their description must say so, or the table would claim radians.
ANGLE_KEYS: dict[str, frozenset[str]] = {
    "top level": frozenset({"poses"}),
    "[[joint]]": frozenset({"alpha", "theta", "limits"}),
    "[base], [tool]": frozenset({"rpy"}),
    "[frames.NAME]": frozenset({"rpy"}),
}

#: What an ``Offset``'s two fields are (a one-line docstring, no ``Attributes:``).
_OFFSET = {
    "xyz": "Translation ``[x, y, z]`` in metres.",
    "rpy": "URDF-style fixed-axis roll, pitch, yaw, in the file's ``angle_unit``.",
}

#: A reStructuredText role (``:func:`~fkcheck.x.f```), as Sphinx's Python domain writes them.
_ROLE = re.compile(r":(?:py:)?(func|meth|class|mod|data|attr|exc|obj|const):`([^`]+)`")


def myst_text(text: str) -> str:
    """A docstring's text as MyST: each role ``:func:`x``` as MyST's ``{func}`x```.

    Left as it is, a role shows in the page as typed (``:func:default_frames``).
    """
    return _ROLE.sub(lambda m: f"{{py:{m.group(1)}}}`{m.group(2)}`", text)


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


def _cell(text: str) -> str:
    return myst_text(text).replace("|", "\\|").replace("\n", " ")


def backends_markdown() -> list[str]:
    """The registry, one row per registration, the plugin form last."""
    from fkcheck.backends import registry
    from fkcheck.backends.registration import PLUGIN

    rows = [
        "| name | what it is | evidence | reads | formats | runs |",
        "|---|---|---|---|---|---|",
    ]
    for reg in (*registry.registrations(), PLUGIN):
        cls = reg.factory()
        evidence = reg.declared("evidence") if reg is not PLUGIN else cls.evidence
        reads = reg.declared("reads") if reg is not PLUGIN else cls.reads
        found = reg.declared("formats") if reg is not PLUGIN else cls.formats
        formats = ", ".join(found or ()) or "-"
        runs = "by default" if reg.default else f"`--against {reg.name}…`"
        if not reg.prefixed and not reg.default and reg is not PLUGIN:
            runs = f"`--against {reg.name}`"
        if reg is PLUGIN:
            runs = "`--against mypkg.fk:forward`"
        name = f"`{reg.shown}`"
        what = _cell(_first_line(cls))
        rows.append(f"| {name} | {what} | {evidence} | {reads} | {formats} | {runs} |")
    return rows


def model_schema_markdown() -> list[str]:
    """A table per model-file section, each key described by the type it is read into.

    Raises:
        ValueError: A key without a description, or an angle key whose description
            does not say it is read in the file's ``angle_unit`` (an error, not a
            blank or a claim of radians).
    """
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
            if key in ANGLE_KEYS.get(heading, ()) and "``angle_unit``" not in text:
                raise ValueError(
                    f"{heading} key {key!r}: read in the file's angle_unit, which its "
                    f"description in {type_target} does not say"
                )
            out.append(f"| `{key}` | {_cell(text)} |")
        out.append("")
    return out


def project_keys_markdown() -> list[str]:
    """``[tool.fkcheck]``'s keys, one row per key, in the reader's order."""
    from fkcheck.model import options, project

    described = attributes(project.ProjectConfig)
    # A check option's key is described by the CheckOptions attribute it sets.
    option_of = {key: name for name, key in options.PROJECT_KEYS.items()}
    described_option = attributes(options.CheckOptions)
    rows = ["| key | meaning |", "|---|---|"]
    for key in project._KEYS:
        text = described_option.get(option_of[key]) if key in option_of else described.get(key)
        if not text:
            raise ValueError(
                f"[tool.fkcheck] key {key!r}: not in ProjectConfig's or CheckOptions' Attributes"
            )
        rows.append(f"| `{key}` | {_cell(text)} |")
    return rows


def action_markdown(action_yml: Path) -> list[str]:
    """``action.yml``'s inputs (with their defaults), then its outputs, one row each."""
    import yaml

    action = yaml.safe_load(action_yml.read_text(encoding="utf-8"))
    rows = ["| | name | default | meaning |", "|---|---|---|---|"]
    for name, spec in action["inputs"].items():
        default = spec.get("default", "")
        shown = f"`{default}`" if default else "(empty)"
        rows.append(f"| input | `{name}` | {shown} | {_cell(spec['description'])} |")
    for name, spec in action.get("outputs", {}).items():
        rows.append(f"| output | `{name}` | | {_cell(spec['description'])} |")
    return rows
