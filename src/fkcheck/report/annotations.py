r"""GitHub Actions annotations: a failed check as ``::error file=…,line=…::…`` lines.

On GitHub Actions (``GITHUB_ACTIONS=true``) ``fkcheck check`` prints these to
stdout; the runner turns each into an error on the pull request, pinned to the
model file and, when the diagnosis names a parameter (``joint[4].alpha``), to
the line of that parameter in the model's TOML. The line is found by scanning
the file's text (``[[joint]]`` blocks, ``[table]`` headers, ``key =``); a file
or a field it cannot place gets a file-level annotation.

GitHub's escaping rules (the runner's ``escapeData`` and ``escapeProperty``):
in the message ``%``, ``\r`` and ``\n`` become ``%25``, ``%0D`` and ``%0A``;
in a property (``file``, ``title``) ``:`` and ``,`` also become ``%3A`` and
``%2C``. The diagnoses are passed in, already run; nothing here runs one.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from fkcheck.engine.results import CheckResult
from fkcheck.io.text import terminal_text
from fkcheck.report.record import check_record

if TYPE_CHECKING:
    from fkcheck.diagnose.failures import BackendDiagnosis

__all__ = [
    "escape_data",
    "escape_property",
    "field_line",
    "github_annotations",
    "in_github_actions",
]

_FIELD = re.compile(r"^(?P<table>[A-Za-z_][\w-]*)(?:\[(?P<index>\d+)\])?\.(?P<key>[\w-]+)")
_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]\s]+)\s*\]\]?")


def in_github_actions() -> bool:
    """Whether the environment says this runs on GitHub Actions (``GITHUB_ACTIONS=true``)."""
    return os.environ.get("GITHUB_ACTIONS") == "true"


def escape_data(text: str) -> str:
    """A message for a workflow command: ``%``, CR and LF escaped."""
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    """A property value (``file``, ``title``): :func:`escape_data`, then ``:`` and ``,``."""
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def field_line(source: str, field: str) -> int | None:
    """The 1-based line of a model-file field in a TOML text, or ``None``.

    Args:
        source: The model file's text.
        field: A diagnosis field: ``joint[4].alpha`` (the fifth ``[[joint]]``
            block's ``alpha =``) or ``base.xyz[2]`` (the ``[base]`` table's ``xyz =``).

    Returns:
        The line number, or ``None`` when the field is not written in the text
        (a default value, another file format, a field this scan does not know).
    """
    match = _FIELD.match(field)
    if match is None:
        return None
    table, key = match["table"], match["key"]
    index = int(match["index"]) if match["index"] is not None else None
    seen = -1
    inside = False
    key_line = re.compile(rf"^\s*{re.escape(key)}\s*=")
    lines = source.splitlines()
    for number, (line, in_string) in enumerate(zip(lines, _in_string(lines), strict=True), 1):
        if in_string:  # inside a multi-line string: text, not TOML (a description's lines)
            continue
        header = _HEADER.match(line)
        if header is not None:
            array = header[1] == "[["
            name = header[2]
            if array and name == table:
                seen += 1
                inside = index is not None and seen == index
            else:
                inside = not array and index is None and name == table
            continue
        if inside and key_line.match(line):
            return number
    return None


def _in_string(lines: Sequence[str]) -> list[bool]:
    """For each line, whether it starts inside a multi-line string (triple quotes).

    A scan of TOML's quoting: basic strings (backslash escapes), literal strings,
    their multi-line forms, and comments, which end the line.
    """
    starts: list[bool] = []
    open_: str | None = None  # the delimiter of the multi-line string we are in
    for line in lines:
        starts.append(open_ is not None)
        i = 0
        while i < len(line):
            if open_ is not None:
                if open_ == '"""' and line[i] == "\\":
                    i += 2
                    continue
                if line.startswith(open_, i):
                    open_, i = None, i + 3
                    continue
                i += 1
                continue
            char = line[i]
            if char == "#":
                break
            if line.startswith(('"""', "'''"), i):
                open_, i = line[i : i + 3], i + 3
                continue
            if char in "\"'":
                i += 1
                while i < len(line) and line[i] != char:
                    i += 2 if char == '"' and line[i] == "\\" else 1
            i += 1
    return starts


def _relative(path: Path) -> str:
    """``path`` relative to the working directory (the repository on a runner) when inside it."""
    try:
        return Path(os.path.relpath(path)).as_posix() if path.is_absolute() else path.as_posix()
    except ValueError:  # another drive (Windows)
        return path.as_posix()


def _command(
    file: str | None, line: int | None, title: str, message: str, level: str = "error"
) -> str:
    props = []
    if file is not None:
        props.append(f"file={escape_property(file)}")
        if line is not None:
            props.append(f"line={line}")
    props.append(f"title={escape_property(title)}")
    return f"::{level} {','.join(props)}::{escape_data(message)}"


def github_annotations(
    check: CheckResult,
    diagnoses: Sequence[BackendDiagnosis] = (),
    *,
    source: str | None = None,
) -> list[str]:
    """The ``::error`` lines for a check that did not pass; for a pass, at most a warning.

    A pass whose table is only partly verified gets one ``::warning``, naming
    the numbers the compared pair leaves unverified.

    One line per distinct disagreement (backends one diagnosis stands for share
    it): the numbers and the diagnosis headline, at the line of the first
    parameter the diagnosis would change when ``source`` has it; one per
    backend that errored; one when required evidence is missing.

    Args:
        check: The check result.
        diagnoses: Its diagnoses, as :func:`fkcheck.diagnose.failures.diagnose_failures`
            returned them.
        source: The model file's text (to find a parameter's line), if read.

    Returns:
        Workflow-command lines, without newlines (every control character of
        input is escaped).
    """
    model = check.model
    file = _relative(model.path) if model.path is not None else None
    name = terminal_text(model.name)
    record = check_record(check, diagnoses)
    if record.verdict == "pass":
        if record.of("table").status != "partly-verified":
            return []
        title = f"fkcheck {name}: table partly verified"
        sentence = terminal_text(record.of("table").sentence)
        return [_command(file, None, title, sentence, level="warning")]
    lines: list[str] = []
    done: set[str] = set()
    for r in record.backends:
        jac = r.jacobian
        if jac is not None and jac.status in ("fail", "error"):
            title = terminal_text(f"fkcheck {name}: {r.name}'s Jacobian {jac.status}s")
            cause = f"; diagnosis: {jac.diagnosis}" if jac.diagnosis else ""
            lines.append(_command(file, None, title, terminal_text(jac.message + cause)))
        if r.status == "xpass":
            title = terminal_text(f"fkcheck {name}: {r.name}: known difference no longer seen")
            lines.append(_command(file, None, title, terminal_text(r.message)))
        if r.name in done or r.status not in ("fail", "error"):
            continue
        if r.status == "error":
            title = terminal_text(f"fkcheck {name}: {r.name} errored")
            lines.append(_command(file, None, title, terminal_text(r.message)))
            continue
        line = None
        message = r.message
        if r.diagnosis:
            message = f"{message}; diagnosis: {r.diagnosis}"
            if r.diagnosis_field and source is not None:
                line = field_line(source, r.diagnosis_field)
        group = r.diagnosed_with
        done.update(group)
        verb = "disagree" if len(group) > 1 else "disagrees"
        title = f"fkcheck {name}: {', '.join(group)} {verb} with the in-house core"
        if r.reader_finding:  # the reader's, not the table's (no diagnosis stands for it)
            title = (
                f"fkcheck {name}: {r.label}: {r.name} disagrees with another reader of the same "
                "description, which agrees with the table"
            )
        lines.append(_command(file, line, terminal_text(title), terminal_text(message)))
    if record.verdict == "unverified":
        sentence = record.of("table").sentence
        lines.append(_command(file, None, f"fkcheck {name}: unverified", terminal_text(sentence)))
    return lines
