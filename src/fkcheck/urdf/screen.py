"""The one screening every URDF goes through before any parser sees it (stdlib only).

A URDF is read from anywhere, so it is hostile until proven otherwise. This
module reads the file itself and parses it once, with expat, as the XML
declares (UTF-8, UTF-16 with or without a byte-order mark, ISO-8859-1 and the
other single-byte encodings expat and Python's codecs know). It refuses, with
one :class:`~fkcheck.errors.UrdfError` naming the file, the line and the problem:

* a path that is not a regular file (a directory, a FIFO, a device): it is
  looked at before it is opened, and opened non-blocking, so a FIFO never
  blocks (:func:`fkcheck.io.files.read_bytes`, whose words these messages use);
* a file over :data:`MAX_URDF_BYTES`;
* any DTD — ``<!DOCTYPE``, hence any entity declaration — seen by expat's
  handlers, whatever the encoding: a URDF never needs one, and it is how entity
  expansion ("billion laughs") and external entities (``SYSTEM "file:///…"``)
  get in;
* any xacro substitution, ``${…}`` or ``$(…)``, in the *decoded* text of the
  document: element text, text after a closing tag (tails), CDATA sections,
  attribute names and values (character references such as ``&#36;`` are
  decoded first, so they cannot hide one). xacro itself evaluates ``${…}`` as
  Python and ``$(…)`` as substitution arguments that read files and environment;
  a model opts in to xacro with ``xacro = true``, a command with
  ``--allow-xacro``: :mod:`fkcheck.urdf.xacro` then expands it in a child
  process, with fkcheck's own evaluator of expressions, and this screen sees
  the result (each refusal says how, :data:`XACRO_OPT_IN`);
* any element or attribute in a xacro namespace (``xacro:include``,
  ``xacro:macro``, ``xacro:if`` …) or in the XInclude namespace
  (``xi:include``), and any element named ``include``: a plain URDF has none;
* more than :data:`MAX_XML_ELEMENTS` elements or nesting deeper than
  :data:`MAX_XML_DEPTH` (both far beyond any robot description; they bound the
  memory and recursion the parsers downstream would spend).

Comments and processing instructions are dropped, not screened: published
URDFs keep xacro source in comments (example-robot-data's TALOS and Go1 do),
and since no parser ever receives them they can do nothing. Every URDF parser
fkcheck runs (urdfdom through Pinocchio, yourdfpy, Robotics Toolbox's reader)
gets only :func:`screen_urdf`'s result re-serialised — never the file's path,
never its bytes — so none of them can apply pre-processing of its own to
something this screen did not see.
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
import xml.parsers.expat as expat
from dataclasses import dataclass
from pathlib import Path

from fkcheck.errors import UrdfError, XacroRefused
from fkcheck.io.files import InputFileError, check_regular_file, read_bytes

__all__ = [
    "MAX_URDF_BYTES",
    "MAX_XML_DEPTH",
    "MAX_XML_ELEMENTS",
    "XACRO_OPT_IN",
    "ScreenedUrdf",
    "check_urdf_path",
    "read_urdf_bytes",
    "screen_urdf",
]

#: A robot description is kilobytes to a few megabytes; refuse anything larger.
MAX_URDF_BYTES = 32 * 1024 * 1024
#: Elements in one document. A 4,096-link robot with inertials, visuals,
#: collisions, joints and transmissions has about 120,000.
MAX_XML_ELEMENTS = 250_000
#: Element nesting. URDF needs 6 levels (robot/link/visual/geometry/mesh), Gazebo
#: extensions a few more.
MAX_XML_DEPTH = 64

#: xacro's substitutions: ``${expression}`` (Python) and ``$(arg|find|env|eval …)``.
_XACRO = re.compile(r"\$[{(]")
_XINCLUDE_NS = ("http://www.w3.org/2001/XInclude", "http://www.w3.org/2003/XInclude")


@dataclass(frozen=True, eq=False)
class ScreenedUrdf:
    """A URDF document that passed the screen.

    Attributes:
        root: The parsed tree: elements, attributes and text only (comments,
            processing instructions and the XML declaration are gone). Tags and
            attribute names in a namespace are ``{uri}name``.
        lines: The line each element starts on, by ``id(element)`` (for messages).
    """

    root: ET.Element
    lines: dict[int, int]

    def line(self, element: ET.Element) -> int | None:
        """The line ``element`` starts on in the file, if it is from this document."""
        return self.lines.get(id(element))

    def text(self) -> str:
        """The document re-serialised: what every URDF parser is given."""
        return ET.tostring(self.root, encoding="unicode")


def check_urdf_path(path: Path, shown: Path | str | None = None) -> os.stat_result:
    """Look at ``path`` without opening it: it must be an existing regular file.

    Args:
        path: The file (symbolic links are followed).
        shown: How messages name it (default: ``path``), e.g. the spec as the
            model file writes it; the message then names ``path`` too.

    Returns:
        Its ``os.stat`` result.

    Raises:
        UrdfError: Missing, cannot be looked at, not a regular file (a
            directory, a FIFO, a device, a socket), or larger than
            :data:`MAX_URDF_BYTES`.
    """
    name = path if shown is None else shown
    try:
        return check_regular_file(path, MAX_URDF_BYTES)
    except InputFileError as exc:
        where = f" ({path})" if str(path) != str(name) else ""
        raise UrdfError(name, f"{exc.problem}{where}") from None


def read_urdf_bytes(path: Path) -> bytes:
    """The bytes of a URDF file, read without ever blocking on it.

    The path is looked at first (:func:`check_urdf_path`), then opened with
    ``O_NONBLOCK`` and checked again on the open descriptor, so a path swapped
    for a FIFO in between cannot block either (:func:`fkcheck.io.files.read_bytes`).
    At most :data:`MAX_URDF_BYTES` + 1 bytes are read.

    Raises:
        UrdfError: As :func:`check_urdf_path`, or the file cannot be read.
    """
    try:
        return read_bytes(path, MAX_URDF_BYTES)
    except InputFileError as exc:
        raise UrdfError(path, exc.problem) from None


class _Refused(Exception):
    """Raised inside expat's handlers to stop parsing with a message.

    Attributes:
        line: The line the problem is on (``None``: where expat stopped).
        xacro: Whether what was refused is xacro (an opt-in would expand it).
    """

    def __init__(self, message: str, line: int | None = None, *, xacro: bool = False) -> None:
        super().__init__(message)
        self.line = line
        self.xacro = xacro


def _clark(name: str) -> str:
    """Turn expat's ``uri}local`` (namespace separator ``}``) into ElementTree's ``{uri}local``."""
    return "{" + name if "}" in name else name


def _namespace(name: str) -> str:
    return name[1:].partition("}")[0] if name.startswith("{") else ""


def _local(name: str) -> str:
    return name.rpartition("}")[2]


def _snippet(text: str, found: re.Match[str]) -> str:
    """A few characters of ``text`` around ``found``, quoted (``repr``: one line, escapes shown)."""
    start, end = max(0, found.start() - 10), found.start() + 40
    piece = ("…" if start > 0 else "") + text[start:end] + ("…" if end < len(text) else "")
    return repr(piece)


def _forbidden_namespace(name: str) -> str | None:
    uri = _namespace(name)
    if "xacro" in uri.lower():
        return "xacro"
    if uri in _XINCLUDE_NS:
        return "XInclude"
    return None


class _Screen:
    """expat handlers that build the tree and stop at the first forbidden thing."""

    def __init__(self) -> None:
        self.builder = ET.TreeBuilder()
        self.parser = expat.ParserCreate(namespace_separator="}")
        self.lines: dict[int, int] = {}
        self.depth = 0
        self.count = 0
        self.tag = ""  # the element last opened or closed, for messages
        self.closed = False  # whether it was closed (text after it is its tail)
        self.run: list[str] = []  # the text since it, in the pieces expat gave
        self.run_line = 0
        p = self.parser
        p.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
        p.StartDoctypeDeclHandler = self._doctype
        p.EntityDeclHandler = self._entity
        p.UnparsedEntityDeclHandler = self._entity
        p.NotationDeclHandler = self._entity
        p.ExternalEntityRefHandler = self._external
        p.SkippedEntityHandler = self._entity
        p.StartElementHandler = self._start
        p.EndElementHandler = self._end
        p.CharacterDataHandler = self._data
        # No comment or processing-instruction handler: expat skips both.

    def _doctype(self, *_: object) -> None:
        raise _Refused(
            "has a DTD (<!DOCTYPE …>): entity declarations are not allowed in a URDF "
            "(they are how entity expansion and external files get in)"
        )

    def _entity(self, *_: object) -> None:
        raise _Refused("declares or references an entity: not allowed in a URDF")

    def _external(self, *_: str | None) -> int:
        raise _Refused("references an external entity: not allowed in a URDF")

    def _data(self, text: str) -> None:
        if not self.run:
            self.run_line = self.parser.CurrentLineNumber
        self.run.append(text)

    def _flush(self) -> None:
        """Screen the text since the last tag as one string, then hand it to the tree.

        Screened whole: expat may hand one text over in pieces (``$&#123;`` arrives
        as ``$`` and ``{``, a CDATA section separately from the text around it).
        """
        if not self.run:
            return
        text = "".join(self.run)
        self.run.clear()
        found = _XACRO.search(text)
        if found:
            where = f"the text after </{self.tag}>" if self.closed else f"the text of <{self.tag}>"
            line = self.run_line + text.count("\n", 0, found.start())
            raise _Refused(_xacro_message(where, text, found), line, xacro=True)
        self.builder.data(text)

    def _start(self, name: str, attrs: dict[str, str]) -> None:
        self._flush()
        self.count += 1
        self.depth += 1
        if self.count > MAX_XML_ELEMENTS:
            raise _Refused(f"has more than {MAX_XML_ELEMENTS} elements (the limit for a URDF)")
        if self.depth > MAX_XML_DEPTH:
            raise _Refused(f"nests elements deeper than {MAX_XML_DEPTH} levels (the limit)")
        tag = _clark(name)
        kind = _forbidden_namespace(tag)
        if kind is not None:
            raise _Refused(
                f"has a {kind} element <{_local(tag)}> ({_namespace(tag)}): fkcheck reads "
                f"plain URDF only{_opt_in(kind)}",
                xacro=kind == "xacro",
            )
        if _local(tag) == "include":
            raise _Refused(
                f"has an <{_local(tag)}> element: a URDF includes no other file; "
                "expand it to a plain URDF first"
            )
        attrib = {}
        for key, value in attrs.items():
            attr = _clark(key)
            kind = _forbidden_namespace(attr)
            if kind is not None:
                raise _Refused(
                    f"has a {kind} attribute {_local(attr)}= on <{_local(tag)}>: fkcheck "
                    f"reads plain URDF only{_opt_in(kind)}",
                    xacro=kind == "xacro",
                )
            for text, what in ((attr, "an attribute name"), (value, f"attribute {_local(attr)}=")):
                found = _XACRO.search(text)
                if found:
                    raise _Refused(
                        _xacro_message(f"{what} of <{_local(tag)}>", text, found), xacro=True
                    )
            attrib[attr] = value
        element = self.builder.start(tag, attrib)
        self.lines[id(element)] = self.parser.CurrentLineNumber
        self.tag, self.closed = _local(tag), False

    def _end(self, name: str) -> None:
        self._flush()
        self.depth -= 1
        self.builder.end(_clark(name))
        self.tag, self.closed = _local(_clark(name)), True


def _xacro_message(where: str, text: str, found: re.Match[str]) -> str:
    closer = "}" if found.group() == "${" else ")"
    return (
        f"contains a xacro expression {found.group()}…{closer} in {where}: "
        f"{_snippet(text, found)}; fkcheck runs xacro only when asked{_opt_in('xacro')}"
    )


#: How to opt in to xacro, the end of every message refusing xacro.
XACRO_OPT_IN = (
    ": to expand it, set xacro = true in the model's [urdf] table or pass --allow-xacro "
    "(or write a plain URDF with fkcheck expand)"
)


def _opt_in(kind: str) -> str:
    """The end of a message refusing ``kind``: how to opt in to xacro, or to expand first."""
    return XACRO_OPT_IN if kind == "xacro" else "; expand it to a plain URDF first"


def screen_urdf(path: Path | str, data: bytes) -> ScreenedUrdf:
    """Parse and screen a URDF document (see the module docstring for what is refused).

    Args:
        path: The file, for messages.
        data: Its bytes, in the encoding its XML declaration names (UTF-8 by
            default; UTF-16 is recognised by its byte-order mark or its first
            characters).

    Returns:
        The screened tree.

    Raises:
        XacroRefused: It is xacro (a xacro element, attribute or substitution).
        UrdfError: Not well-formed XML, or anything else the screen refuses.
    """
    screen = _Screen()
    try:
        screen.parser.Parse(data, True)
        screen._flush()
    except _Refused as exc:
        line = exc.line or screen.parser.CurrentLineNumber
        error = XacroRefused if exc.xacro else UrdfError
        raise error(path, f"line {line}: {exc}") from None
    except expat.ExpatError as exc:
        raise UrdfError(path, f"not valid XML: {exc}") from None
    except (ValueError, LookupError) as exc:  # an encoding expat and Python cannot decode
        raise UrdfError(path, f"not valid XML: {exc}") from None
    return ScreenedUrdf(screen.builder.close(), screen.lines)
