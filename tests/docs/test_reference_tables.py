"""The reference tables the docs site generates (docs/_ext/fkcheck_tables.py), read here.

The site parses them as MyST, where a docstring's reStructuredText role shows as typed
(``:func:default_frames``), and the model-file reference describes each key by the type
it is read into, which holds radians: a file's key must be said in the file's
``angle_unit``. Sphinx is not needed (``nox -s docs`` builds the site itself).
"""

from __future__ import annotations

import importlib.util
import re

import pytest

from tests.paths import REPO_ROOT

_SPEC = importlib.util.spec_from_file_location(
    "fkcheck_tables", REPO_ROOT / "docs" / "_ext" / "fkcheck_tables.py"
)
assert _SPEC is not None
assert _SPEC.loader is not None
tables = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(tables)

#: A reStructuredText role as typed in a docstring: what MyST would print as it is.
RAW_ROLE = re.compile(r":(?:py:)?(?:func|meth|class|mod|data|attr|exc|obj|const):`")


def _schema() -> dict[str, dict[str, str]]:
    """Section heading -> key -> its description, as the page shows them."""
    out: dict[str, dict[str, str]] = {}
    section = ""
    for line in tables.model_schema_markdown():
        heading = re.match(r"^\*\*(.+?)\*\* — ", line)
        if heading:
            section = heading.group(1)
            out[section] = {"": line}
        row = re.match(r"^\| `(\w+)` \| (.*) \|$", line)
        if row:
            out[section][row.group(1)] = row.group(2)
    return out


@pytest.mark.parametrize(
    "lines",
    [
        pytest.param(tables.model_schema_markdown, id="model-file"),
        pytest.param(tables.project_keys_markdown, id="project-keys"),
        pytest.param(tables.backends_markdown, id="backends"),
        pytest.param(lambda: tables.action_markdown(REPO_ROOT / "action.yml"), id="action"),
    ],
)
def test_no_table_shows_a_raw_role(lines):
    text = "\n".join(lines())
    assert not RAW_ROLE.search(text), RAW_ROLE.search(text)


def test_roles_become_myst_roles():
    assert tables.myst_text("just those, :func:`default_frames`, so") == (
        "just those, {py:func}`default_frames`, so"
    )
    assert tables.myst_text("(:data:`~fkcheck.core.tolerances.MAX_KNOWN_ANGLE_RAD`)") == (
        "({py:data}`~fkcheck.core.tolerances.MAX_KNOWN_ANGLE_RAD`)"
    )
    schema = _schema()
    assert "{py:func}`default_frames`" in schema["top level"]["frames"]


def test_angles_are_described_in_the_files_angle_unit():
    schema = _schema()
    assert set(tables.ANGLE_KEYS) <= set(schema)
    for section, keys in tables.ANGLE_KEYS.items():
        for key in keys:
            text = schema[section][key]
            assert "the file's ``angle_unit``" in text, (section, key, text)
            assert "(rad)" not in text
            assert "in rad " not in text
    joint = schema["[[joint]]"]
    assert "metres and radians" not in joint[""]
    assert "angles in the file's ``angle_unit``" in joint[""]
    unit = schema["top level"]["angle_unit"]
    assert "display" not in unit
    for key in ("alpha", "theta", "limits", "rpy", "pose"):
        assert key in unit


def test_an_angle_key_described_in_radians_fails_the_build(monkeypatch):
    # What the [[joint]] table said before: "Link twist (rad)".
    real = tables.attributes

    def radians(obj):
        found = real(obj)
        if "alpha" in found:
            found["alpha"] = "Link twist (rad); in a modified table, ``α_{i-1}``."
        return found

    monkeypatch.setattr(tables, "attributes", radians)
    with pytest.raises(ValueError, match=r"\[\[joint\]\] key 'alpha': read in the file's "):
        tables.model_schema_markdown()
