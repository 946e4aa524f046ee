r"""Text from input, made safe for each place fkcheck shows it: terminal, XML, HTML, Markdown.

Model, frame and joint names, unknown keys, plugin exception messages and a
program's stderr all come from input, and input is hostile until proven
otherwise. Shown raw, an escape sequence retitles or clears the terminal, a
newline in a name prints a fake ``verdict: pass`` line, ``[/x]`` crashes
rich's markup parser, a NUL makes XML ill-formed. Every writer passes such
text through one function here:

* :func:`terminal_text` — one line for a terminal or log: every control
  character is written as a visible escape (``\x1b``, ``\n``, ``\u202e``);
* :func:`terminal_markup` — the same, with rich markup escaped too, for text
  that goes into a rich ``print`` or table cell (``[bold]`` prints literally);
* :func:`terminal_lines` — several lines of fkcheck's own making with input
  inside: newlines kept, every other control character escaped;
* :func:`document_text` — text for XML and HTML: tab, newline and carriage
  return kept (they are whitespace there), every other control character
  escaped, so XML 1.0 can carry it and a page shows it; the markup itself is
  escaped by the serialiser (ElementTree, Jinja2's autoescape);
* :func:`xml_safe_tree` — :func:`document_text` over every attribute and text
  of an ElementTree, just before it is serialised;
* :func:`markdown_text` — one line for a Markdown table cell: whitespace
  folded, controls escaped, HTML and Markdown special characters escaped;
* :func:`operand` — a file name in a command line fkcheck suggests or records:
  never read as an option.

The control characters are the C0 set (U+0000–U+001F), DEL, the C1 set
(U+0080–U+009F, which some terminals read as escape sequences), the Unicode
line and paragraph separators, the bidirectional overrides, embeddings,
isolates and marks (which reorder what a reader sees), lone surrogates (a file
name that is not valid UTF-8) and the non-characters U+FFFE/U+FFFF.
Everything else, ``→`` and ``°`` included, passes unchanged.
"""

from __future__ import annotations

import html
import re
import xml.etree.ElementTree as ET

__all__ = [
    "document_text",
    "markdown_text",
    "operand",
    "terminal_lines",
    "terminal_markup",
    "terminal_text",
    "unsafe_xml_character",
    "visible_escape",
    "xml_safe_tree",
]

#: Every character a terminal, XML or a reader could take for something else.
_CONTROL = (
    "\x00-\x1f\x7f-\x9f"  # C0, DEL, C1
    "\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069"  # bidi marks, embeddings, overrides, isolates
    "\u2028\u2029"  # line and paragraph separators
    "\ud800-\udfff"  # lone surrogates
    "\ufffe\uffff"  # non-characters XML refuses
)
_CONTROLS = re.compile(f"[{_CONTROL}]")
_XML_WHITESPACE = "\t\n\r"
_SHORT = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}
_MARKDOWN_SPECIAL = re.compile(r"([\\`*_\[\]|#~])")
#: Put after what starts a GitHub link or mention, it breaks the pattern and shows nothing.
_NO_LINK = "\u200b"
#: ``@`` (mentions, e-mail addresses), the ``:`` of ``scheme://``, ``#`` (issue references).
_AUTOLINK = re.compile(r"@|:(?=//)|#")
#: ``www.`` (GitHub links it without a scheme).
_WWW = re.compile(r"(?i)\b(www)\.")


def visible_escape(char: str) -> str:
    r"""One character as the escape a Python string literal would use: ``\x1b``, ``\u202e``."""
    if char in _SHORT:
        return _SHORT[char]
    code = ord(char)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def _escape_controls(text: object, keep: str = "") -> str:
    """``str(text)`` with every control character not in ``keep`` written as its escape."""

    def replace(match: re.Match[str]) -> str:
        char = match.group()
        return char if char in keep else visible_escape(char)

    return _CONTROLS.sub(replace, str(text))


def operand(name: str) -> str:
    """A file name as a command-line operand: ``./`` before one that starts with ``-``.

    ``--against=cmd:x.toml`` is a file that an argument parser would take for an
    option; ``./--against=cmd:x.toml`` is the same file and never an option.
    """
    return f"./{name}" if name.startswith("-") else name


def terminal_text(text: object) -> str:
    r"""``text`` as one line with every control character visible (``\x1b``, ``\n``).

    Args:
        text: Anything; it is turned into ``str`` first.

    Returns:
        The text, safe to print on a terminal or into a log: no escape
        sequence, no line break, no bidirectional reordering.
    """
    return _escape_controls(text)


def terminal_markup(text: object) -> str:
    r""":func:`terminal_text`, then rich markup escaped: ``[/x]`` prints as ``[/x]``."""
    from rich.markup import escape

    return escape(terminal_text(text))


def terminal_lines(text: object) -> str:
    r"""Several lines for a terminal: newlines kept, every other control character visible.

    For text fkcheck lays out itself (a diagnosis, a TOML file) that may hold
    input; names inside it should have gone through :func:`terminal_text`
    already, so that a newline in a name cannot start a line of its own.
    """
    return _escape_controls(text, keep="\n")


def document_text(text: object) -> str:
    r"""Text XML 1.0 and HTML can carry: tab, newline, CR kept, other controls visible.

    The markup characters (``<``, ``&``, quotes) are left to the serialiser.
    """
    return _escape_controls(text, keep=_XML_WHITESPACE)


def unsafe_xml_character(text: str) -> str | None:
    r"""The first character of ``text`` XML 1.0 cannot carry (or should not), as an escape.

    Returns:
        ``None`` when :func:`document_text` leaves ``text`` unchanged, else the
        first offending character written as a visible escape (``\x00``).
    """
    for match in _CONTROLS.finditer(text):
        if match.group() not in _XML_WHITESPACE:
            return visible_escape(match.group())
    return None


def xml_safe_tree(root: ET.Element) -> ET.Element:
    """Apply :func:`document_text` to every tag's attributes, text and tail, in place.

    Returns:
        ``root``, for chaining.
    """
    for element in root.iter():
        for key, value in element.attrib.items():
            element.set(key, document_text(value))
        if element.text is not None:
            element.text = document_text(element.text)
        if element.tail is not None:
            element.tail = document_text(element.tail)
    return root


def markdown_text(text: object) -> str:
    """Text safe inside a Markdown table cell: one line, no markup, no HTML, no link, no mention.

    Whitespace runs (line breaks included) fold to one space; the remaining
    control characters become visible escapes; HTML special characters become
    entities and Markdown's own (``|``, backticks, brackets, emphasis marks,
    backslash) are backslash-escaped, so the text cannot break the table or
    inject markup. What GitHub would turn into a link or a notification —
    ``@user`` (and e-mail addresses), ``scheme://`` URLs, ``www.`` names, ``#123``
    — gets a zero-width space after its ``@``, ``:`` or ``#`` and before the dot
    of ``www.``: it reads the same and links nowhere (as bots such as Renovate do).
    """
    one_line = terminal_text(" ".join(str(text).split()))
    escaped = _MARKDOWN_SPECIAL.sub(r"\\\1", html.escape(one_line, quote=False))
    return _AUTOLINK.sub(lambda m: m.group() + _NO_LINK, _WWW.sub(rf"\1{_NO_LINK}.", escaped))
