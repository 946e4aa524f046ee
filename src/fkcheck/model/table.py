"""A model built in code from a DH table: a notebook's way in, without a file.

:func:`model_from_table` writes the table into the TOML schema and validates
it with :func:`~fkcheck.model.read.model_from_dict`, the reader every model
file goes through: the same checks, the same :class:`~fkcheck.errors.ModelError`
lines (shown at ``<model>``, as there is no file), and the same defaults — the
named frames ``world`` and ``tcp`` and the ``[check]`` between them.

Example:
    >>> import fkcheck
    >>> model = fkcheck.model_from_table("2r", [(0.3, 0.0, 0.0, 0.0), (0.2, 0.0, 0.0, 0.0)])
    >>> model.dof, model.check.frame_from, model.check.frame_to
    (2, 'world', 'tcp')
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from fkcheck.errors import ModelError
from fkcheck.model.read import model_from_dict
from fkcheck.model.types import Model

__all__ = ["TUPLE_COLUMNS", "model_from_table"]

#: What a row given as a tuple holds, in order (lengths in metres, angles in ``angle_unit``).
TUPLE_COLUMNS = ("a", "alpha", "d", "theta")


def model_from_table(
    name: str,
    rows: Sequence[Mapping[str, Any] | Sequence[float]] | np.ndarray,
    *,
    convention: str = "standard",
    angle_unit: str = "rad",
    limits: Sequence[Sequence[float] | None] | None = None,
    description: str = "",
    source: str = "",
    base: Mapping[str, Any] | None = None,
    tool: Mapping[str, Any] | None = None,
    frames: Mapping[str, Any] | None = None,
    poses: Mapping[str, Any] | None = None,
    check: Mapping[str, Any] | None = None,
) -> Model:
    """A model from a DH table in code, validated exactly as a model file is.

    Args:
        name: The model's name (not blank).
        rows: One per joint: a ``(a, alpha, d, theta)`` tuple (or list, or a row
            of an ``(n, 4)`` array), or a dict with a model file's ``[[joint]]``
            keys (``a``, ``alpha``, ``d``, ``theta``, ``name``, ``type``,
            ``flip``, ``limits``). Lengths in metres, angles in ``angle_unit``.
        convention: ``"standard"`` or ``"modified"`` DH.
        angle_unit: ``"rad"`` or ``"deg"``: the unit of every angle given here.
        limits: Per joint, ``(lower, upper)`` or ``None`` (in ``angle_unit`` for a
            revolute joint, metres for a prismatic one); default: none.
        description: Free text, as the file's ``description``.
        source: Where the table comes from, as the file's ``source``.
        base: The ``[base]`` table (``xyz``, ``rpy``), default identity.
        tool: The ``[tool]`` table, default identity.
        frames: The ``[frames.NAME]`` tables, on top of ``world`` and ``tcp``.
        poses: The ``[poses]`` table: named configurations.
        check: The ``[check]`` table; default ``world`` → ``tcp`` at the
            default tolerances.

    Returns:
        The validated model (its ``path`` is ``None``).

    Raises:
        ModelError: A bad row or option, one line naming the field
            (``<model>: joint[1].alpha: expected a number, got a string``).
    """
    table = rows.tolist() if isinstance(rows, np.ndarray) else rows
    if isinstance(table, str | bytes | Mapping) or not isinstance(table, Sequence):
        raise ModelError(None, "joint", f"expected a sequence of rows, got {_kind(table)}")
    if limits is not None and len(limits) != len(table):
        raise ModelError(
            None, "limits", f"{len(limits)} limits for {len(table)} joints: give one per joint"
        )
    joints = [_row(i, raw, None if limits is None else limits[i]) for i, raw in enumerate(table)]
    data: dict[str, Any] = {
        "name": name,
        "convention": convention,
        "angle_unit": angle_unit,
        "joint": joints,
    }
    given = {"description": description, "source": source}
    data.update({key: value for key, value in given.items() if value})
    sections = {"base": base, "tool": tool, "frames": frames, "poses": poses, "check": check}
    data.update({key: _plain(value) for key, value in sections.items() if value is not None})
    return model_from_dict(data)


def _row(i: int, raw: Any, limit: Sequence[float] | None) -> Any:
    """Row ``i`` as a ``[[joint]]`` table (anything else is left for the reader to refuse)."""
    if isinstance(raw, np.ndarray):
        raw = raw.tolist()
    if isinstance(raw, list | tuple):
        if len(raw) != len(TUPLE_COLUMNS):
            raise ModelError(
                None,
                f"joint[{i}]",
                f"a tuple row is ({', '.join(TUPLE_COLUMNS)}), got {len(raw)} values; "
                "or give a dict with keys a, alpha, d, theta, name, type, flip, limits",
            )
        raw = dict(zip(TUPLE_COLUMNS, raw, strict=True))
    if not isinstance(raw, Mapping):
        return raw
    row = {key: _plain(value) for key, value in raw.items()}
    if limit is not None:
        if "limits" in row:
            raise ModelError(None, f"joint[{i}].limits", "given twice: in the row and in limits=")
        row["limits"] = _plain(limit)
    return row


def _plain(value: Any) -> Any:
    """NumPy scalars and arrays as Python numbers and lists, as a TOML parser gives them."""
    if isinstance(value, np.generic | np.ndarray):
        return value.tolist()
    if isinstance(value, Mapping):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(item) for item in value]
    return value


def _kind(value: Any) -> str:
    """What was given instead of rows, for the message."""
    return type(value).__name__
