"""``[[known_difference]]``: disagreements with independent references, recorded with bounds."""

from __future__ import annotations

from typing import Any

from fkcheck.core.tolerances import LimitKind
from fkcheck.io.numbers import show_text
from fkcheck.model.sections.reader import Reader, kind
from fkcheck.model.types import KnownDifference

__all__ = [
    "KNOWN_DIFFERENCE_BACKENDS",
    "KNOWN_DIFFERENCE_KEYS",
    "KNOWN_DIFFERENCE_PREFIXES",
    "read_known_differences",
]

KNOWN_DIFFERENCE_KEYS = {"backends", "finding", "max_position_m", "max_angle_rad"}
#: The bound keys and the range each must be within (:mod:`fkcheck.core.tolerances`).
KNOWN_DIFFERENCE_LIMITS: dict[str, LimitKind] = {
    "max_position_m": "known_position", "max_angle_rad": "known_angle",
}  # fmt: skip
#: Backends a ``[[known_difference]]`` may name: those whose evidence is
#: independent of the table (the URDF parsers) and the prefixed ones that are
#: (a published table, measured poses). ``rtb-dh``, ``pinocchio-dh``, plugins and
#: ``cmd:`` programs run the model's own table: their disagreement is a bug, never
#: a known difference. (tests/model/test_known_difference.py keeps this in step
#: with the backend registry.)
KNOWN_DIFFERENCE_BACKENDS = ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf")
KNOWN_DIFFERENCE_PREFIXES = ("rtb-model:", "poses:")


def _known_difference_backend_ok(name: str) -> bool:
    """Whether a known difference may name backend ``name`` (one independent of the table).

    The one place that decides it, from the hand-kept lists above; the model layer
    cannot import the backend registry, which is what should say it.
    """
    return name in KNOWN_DIFFERENCE_BACKENDS or any(
        name.startswith(p) and len(name) > len(p) for p in KNOWN_DIFFERENCE_PREFIXES
    )


def _allowed() -> str:
    """The backends a known difference may name, for messages."""
    return ", ".join((*KNOWN_DIFFERENCE_BACKENDS, *(p + "…" for p in KNOWN_DIFFERENCE_PREFIXES)))


def read_known_differences(r: Reader, raw: Any) -> tuple[KnownDifference, ...]:
    """The ``[[known_difference]]`` entries, validated (see :class:`KnownDifference`).

    A backend is named by one entry at most.
    """
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise r.fail(
            "known_difference",
            f"expected an array of tables [[known_difference]], got {kind(raw)}",
        )
    listed: dict[str, int] = {}
    return tuple(_read_entry(r, item, i, listed) for i, item in enumerate(raw))


def _read_entry(r: Reader, item: Any, i: int, listed: dict[str, int]) -> KnownDifference:
    """Entry ``i``; its backends are recorded in ``listed`` (backend → entry)."""
    where = f"known_difference[{i}]"
    tbl = r.table(item, where, KNOWN_DIFFERENCE_KEYS)
    for required in ("backends", "finding"):
        if required not in tbl:
            raise r.fail(f"{where}.{required}", "missing (required)")
    names = _backends(r, tbl["backends"], where, i, listed)
    finding = r.string(tbl["finding"], f"{where}.finding")
    if not finding.strip():
        raise r.fail(f"{where}.finding", "must not be empty: say what fkcheck diagnose names")
    bounds: dict[str, float] = {}
    for key, limit_kind in KNOWN_DIFFERENCE_LIMITS.items():
        if key not in tbl:
            raise r.fail(
                f"{where}.{key}",
                "missing (required: the largest error the recorded difference shows, "
                "so that a larger one still fails)",
            )
        bounds[key] = r.limit(tbl[key], f"{where}.{key}", limit_kind)
    return KnownDifference(names, finding, **bounds)


def _backends(r: Reader, names: Any, where: str, i: int, listed: dict[str, int]) -> tuple[str, ...]:
    """``backends``: a non-empty list of backends independent of the table, none listed before."""
    if not isinstance(names, list) or not names or not all(isinstance(x, str) for x in names):
        raise r.fail(
            f"{where}.backends", f"expected a non-empty list of backend names: {_allowed()}"
        )
    for k, backend in enumerate(names):
        if not _known_difference_backend_ok(backend):
            raise r.fail(
                f"{where}.backends[{k}]",
                f"{show_text(backend)} is not a backend whose evidence is independent of the "
                f"table; known differences may name: {_allowed()}",
            )
        if backend in listed:
            raise r.fail(
                f"{where}.backends[{k}]",
                f"{show_text(backend)} is listed already, in known_difference[{listed[backend]}]",
            )
        listed[backend] = i
    return tuple(names)
