r"""Command-line values that become text in what fkcheck writes: UTF-8, or refused in one line.

Python decodes the command line with surrogate escapes: a byte that is not
UTF-8 (``k=1.0\xff``) arrives as a lone surrogate (``\udcff``). A file name may
hold one (the file is found by its bytes), but a value written into a URDF, a
model file or a report — a xacro argument, a package directory ``$(find …)``
puts into the URDF, a model or robot name — cannot: :func:`utf8_text`, an
argparse ``type``, refuses it (``fkcheck …: error: argument --arg: …``, exit 2).
"""

from __future__ import annotations

import argparse

__all__ = ["utf8_text"]


def utf8_text(value: str) -> str:
    """``value`` if it is UTF-8 text; else :class:`argparse.ArgumentTypeError` naming the byte."""
    for char in value:
        if "\udc80" <= char <= "\udcff":
            byte = ord(char) - 0xDC00
            raise argparse.ArgumentTypeError(
                f"{value!r} is not UTF-8 text (byte 0x{byte:02x}): it cannot be written into a "
                "URDF, model or report"
            )
    return value
