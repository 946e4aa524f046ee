r"""The one JSON writer: strict JSON that jq, browsers' ``JSON.parse`` and every other parser read.

Python's :func:`json.dumps` writes ``NaN``, ``Infinity`` and ``-Infinity`` by
default, which are not JSON. Every JSON fkcheck prints or writes goes through
:func:`strict_json` instead: a non-finite number becomes ``null``, and the
object that held it gets a ``"non_finite"`` member saying what was there, keyed
by the member's name (``"max_position_error_m"``) or its path below that object
(``"matrix[0][3]"``):

.. code-block:: json

    {"max_position_error_m": null, "non_finite": {"max_position_error_m": "Infinity"}}

A reader that only wants numbers sees ``null``; one that wants to know why
reads ``non_finite``. (A non-finite number directly inside a top-level array,
with no object around it, becomes ``null`` with no reason: fkcheck writes no
such document.) NumPy scalars and arrays are written as the numbers and lists
they hold. Strings are written with ``\u`` escapes for every non-ASCII or
control character, so the bytes are plain ASCII.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

__all__ = ["NON_FINITE_KEY", "jsonable", "strict_json"]

#: The member naming the non-finite numbers an object held.
NON_FINITE_KEY = "non_finite"


def _non_finite_name(value: float) -> str:
    if math.isnan(value):
        return "NaN"
    return "Infinity" if value > 0 else "-Infinity"


def _clean(value: Any, path: str, found: dict[str, str]) -> Any:
    """``value`` with non-finite floats as ``None``, recorded in ``found`` under ``path``."""
    if isinstance(value, dict):
        inner: dict[str, str] = {}
        out = {key: _clean(item, str(key), inner) for key, item in value.items()}
        if inner:
            if NON_FINITE_KEY in out:
                raise ValueError(f"cannot write JSON: the object has a {NON_FINITE_KEY!r} member")
            out[NON_FINITE_KEY] = inner
        return out
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, list | tuple):
        return [_clean(item, f"{path}[{i}]", found) for i, item in enumerate(value)]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        found[path] = _non_finite_name(value)
        return None
    return value


def jsonable(value: Any) -> Any:
    """``value`` with every non-finite number replaced by ``None`` and a ``non_finite`` reason.

    Dicts, lists, tuples, NumPy arrays and scalars are walked; everything else
    is returned as it is (so :func:`json.dumps` still refuses what JSON cannot
    hold).

    Raises:
        ValueError: An object holding a non-finite number already has a
            ``non_finite`` member.
    """
    return _clean(value, "", {})


def strict_json(value: Any, *, indent: int | None = None) -> str:
    """``value`` as strict JSON text (no ``NaN``/``Infinity``), without a trailing newline.

    Args:
        value: A JSON-like document (dicts, lists, strings, numbers, NumPy values).
        indent: As :func:`json.dumps`'s.

    Raises:
        TypeError: ``value`` holds something JSON cannot encode.
        ValueError: See :func:`jsonable`.
    """
    try:  # the common case: nothing to replace, no extra pass over the data
        return json.dumps(value, indent=indent, allow_nan=False)
    except (ValueError, TypeError):
        return json.dumps(jsonable(value), indent=indent, allow_nan=False)
