"""``[[known_difference]]``: disagreements with independent references, recorded with bounds."""

from __future__ import annotations

from typing import Any

from fkcheck.core.tolerances import LimitKind
from fkcheck.io.numbers import show_text
from fkcheck.model.sections.reader import Reader, kind
from fkcheck.model.types import KnownDifference
from fkcheck.model.version_spec import parse_versions

__all__ = ["KNOWN_DIFFERENCE_KEYS", "KNOWN_DIFFERENCE_READS", "read_known_differences"]

KNOWN_DIFFERENCE_KEYS = {
    "backends", "reads", "versions", "finding", "max_position_m", "max_angle_rad",
}  # fmt: skip
#: What ``reads`` may select: every backend reading the model's URDF, or its MJCF.
#: (Backends that read the table can never differ from it; measured poses and
#: published tables are named one by one.)
KNOWN_DIFFERENCE_READS = ("urdf", "mjcf")
#: The bound keys and the range each must be within (:mod:`fkcheck.core.tolerances`).
KNOWN_DIFFERENCE_LIMITS: dict[str, LimitKind] = {
    "max_position_m": "known_position", "max_angle_rad": "known_angle",
}  # fmt: skip
#: The same for a reader's own difference (``versions = …``): up to 10 m and π rad.
READER_DIFFERENCE_LIMITS: dict[str, LimitKind] = {
    "max_position_m": "reader_position", "max_angle_rad": "reader_angle",
}  # fmt: skip


def read_known_differences(r: Reader, raw: Any) -> tuple[KnownDifference, ...]:
    """The ``[[known_difference]]`` entries, validated (see :class:`KnownDifference`).

    The form is checked here; which backend names are allowed is the backend
    registry's to say (:func:`fkcheck.backends.registry.check_known_differences`),
    since it alone knows the installed backends. A backend is named by one entry
    at most, and one entry at most selects by ``reads``.
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
    if "backends" not in tbl and "reads" not in tbl:
        raise r.fail(
            f"{where}.backends",
            'missing (required: the backends by name, or reads = "urdf" for every URDF reader)',
        )
    if "finding" not in tbl:
        raise r.fail(f"{where}.finding", "missing (required)")
    names = _backends(r, tbl["backends"], where, i, listed) if "backends" in tbl else ()
    reads = _reads(r, tbl["reads"], where, i, listed) if "reads" in tbl else ""
    finding = r.string(tbl["finding"], f"{where}.finding")
    if not finding.strip():
        raise r.fail(f"{where}.finding", "must not be empty: say what fkcheck diagnose names")
    versions = _versions(r, tbl["versions"], where, names, reads) if "versions" in tbl else ""
    limits = READER_DIFFERENCE_LIMITS if versions else KNOWN_DIFFERENCE_LIMITS
    bounds: dict[str, float] = {}
    for key, limit_kind in limits.items():
        if key not in tbl:
            raise r.fail(
                f"{where}.{key}",
                "missing (required: the largest error the recorded difference shows, "
                "so that a larger one still fails)",
            )
        bounds[key] = r.limit(tbl[key], f"{where}.{key}", limit_kind)
    return KnownDifference(names, finding, **bounds, reads=reads, versions=versions)


def _versions(r: Reader, value: Any, where: str, names: tuple[str, ...], reads: str) -> str:
    """``versions``: a valid spec (:mod:`fkcheck.model.version_spec`), for one backend named."""
    text = r.string(value, f"{where}.versions")
    if reads or len(names) != 1:
        raise r.fail(
            f"{where}.versions",
            "records one reader's library versions: name that one backend alone "
            '(backends = ["pinocchio-mjcf"]), without reads',
        )
    try:
        parse_versions(text)
    except ValueError as exc:
        raise r.fail(f"{where}.versions", str(exc)) from None
    return text


def _backends(r: Reader, names: Any, where: str, i: int, listed: dict[str, int]) -> tuple[str, ...]:
    """``backends``: a non-empty list of backend names, none listed before."""
    if not isinstance(names, list) or not names or not all(isinstance(x, str) for x in names):
        raise r.fail(f"{where}.backends", "expected a non-empty list of backend names")
    for k, backend in enumerate(names):
        if backend in listed:
            raise r.fail(
                f"{where}.backends[{k}]",
                f"{show_text(backend)} is listed already, in known_difference[{listed[backend]}]",
            )
        listed[backend] = i
    return tuple(names)


def _reads(r: Reader, value: Any, where: str, i: int, listed: dict[str, int]) -> str:
    """``reads``: one of :data:`KNOWN_DIFFERENCE_READS`, selected by one entry at most."""
    reads = r.string(value, f"{where}.reads")
    if reads not in KNOWN_DIFFERENCE_READS:
        raise r.fail(
            f"{where}.reads",
            f"{show_text(reads)} is not one of: {', '.join(KNOWN_DIFFERENCE_READS)}",
        )
    key = f"reads:{reads}"
    if key in listed:
        raise r.fail(f"{where}.reads", f"selected already, in known_difference[{listed[key]}]")
    listed[key] = i
    return reads
