"""Known differences: a recorded disagreement turns a backend's failure into an expected one.

A model file may record, in ``[[known_difference]]``, that some backends whose
evidence is independent of the table (a URDF's parsers, a published table)
disagree with it, and why (what ``fkcheck diagnose`` named). On the model's
default check (its ``[check] from`` → ``to``) this module rewrites those
backends' results, like pytest's strict ``xfail``:

* it failed, within the recorded bounds → ``xfail`` (expected failure): the
  check can still pass, but the table is never counted as verified by it;
* it failed beyond a recorded bound → stays ``fail``, the message names the bound;
* it agreed → ``xpass`` (known difference no longer seen): the check fails,
  because the record in the model file is stale;
* it errored or was skipped → unchanged (nothing was compared).

A record that names several URDF readers and nothing else (``backends =
["pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf"]``, the readers of its day)
records a difference of the description, not of those parsers: it is read as
``reads = "urdf"``, so a URDF reader that joined since is expected to disagree
as they do, and a model written for an older fkcheck keeps its verdict. One
reader named alone stays that reader's (a parser's own difference).

A record with ``versions = "<=4.1.0"`` names one reader and the versions of
its library it was measured on (a bug of that library, pinocchio#2782 say): it
applies only while the installed version matches, its expected failure names
the version (``known difference (pinocchio 4.1.0, recorded for versions
<=4.1.0)``), and once the library is outside them the record does not apply
and the backend's message says so: its failure is a failure again, and its
agreement a plain pass.

Checks of another frame pair, or with other tolerances than the model's
``[check]``, are left as they are: the finding was recorded for the default
check only (a looser tolerance may rightly pass it, a tighter one fail it).
A Jacobian compared on an expected failure (``check --jacobian``) inherits it
within the same bounds, read per radian: a table whose lengths differ by δ
(m) and angles by ε (rad) has Jacobian columns that differ by about δ m/rad
and ε rad/rad, so its failing Jacobian is ``xfail`` with the same finding
while ``max_linear <= max_position_m`` and ``max_angular <= max_angle_rad``;
beyond them it stays ``fail`` (a wrong Jacobian is never excused by a pose record).
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import replace
from importlib import metadata

from fkcheck.description.registry import LANGUAGES
from fkcheck.engine.results import BackendResult
from fkcheck.io.format import format_angle_summary, format_length_summary
from fkcheck.model.lint import Finding
from fkcheck.model.types import KnownDifference, Model

__all__ = [
    "apply_known_differences",
    "known_difference_findings",
    "known_difference_for",
    "library_of",
    "of_the_description",
]


def known_difference_for(
    model: Model, backend: str, reads: str, version: str | None = None
) -> KnownDifference | None:
    """The model's recorded difference with ``backend`` (which reads ``reads``), if any.

    One naming it wins over one selecting what it reads; one naming several URDF
    readers and nothing else selects every URDF reader (:func:`of_the_description`).
    One recorded for some versions of the backend's library (``versions``) applies
    only when ``version``, the installed one, matches them.
    """
    entries = [e for e in model.known_differences if e.applies_to_version(version)]
    named = [e for e in entries if backend in e.backends]
    selected = [
        e
        for e in entries
        if e.applies_to(backend, reads) or (reads in LANGUAGES and of_the_description(e, reads))
    ]
    found = named or selected
    return found[0] if found else None


def library_of(backend: object) -> tuple[str, str] | None:
    """``("pinocchio", "4.1.0")``: a backend's library and its installed version, if it names one.

    Read from package metadata (the backend's first ``distributions``, named as
    imported: ``pin`` is ``pinocchio``), nothing imported; ``None`` for a backend
    that names no distribution or whose distribution is not installed.
    """
    dists = tuple(getattr(backend, "distributions", ()) or ())
    if not dists:
        return None
    version = _installed(dists[0])
    return None if version is None else (_LIBRARY_NAMES.get(dists[0], dists[0]), version)


@functools.cache
def _installed(distribution: str) -> str | None:
    """The installed version of ``distribution`` (read once per process), or ``None``."""
    try:
        return metadata.version(distribution)
    except metadata.PackageNotFoundError:
        return None


#: Distributions named otherwise than the library users import (``pin`` is ``pinocchio``).
_LIBRARY_NAMES = {
    "pin": "pinocchio",
    "mujoco-core": "mujoco",
    "roboticstoolbox-python": "roboticstoolbox",
    "spatialmath-python": "spatialmath",
}


def _not_this_version(model: Model, result: BackendResult, library: tuple[str, str] | None) -> str:
    """Why a record naming the backend for other versions of its library does not apply."""
    other = [e for e in model.known_differences if result.name in e.backends and e.versions]
    if not other or result.status not in ("fail", "pass"):
        return ""
    installed = f"{library[0]} {library[1]}" if library else "its library's version unknown"
    return (
        f" (the model's known difference for {result.name} is recorded for versions "
        f"{other[0].versions} only and does not apply to {installed})"
    )


def of_the_description(entry: KnownDifference, language: str = "urdf") -> bool:
    """Whether ``entry`` names several readers of ``language`` and nothing else.

    Such a record is the description's own difference, not one of its readers'.
    """
    from fkcheck.backends.registry import names  # the registry, only when a record names some

    listed = set(entry.backends)
    return entry.reads == "" and len(listed) > 1 and listed <= set(names(reads=language))


def known_difference_findings(model: Model, ignore: Iterable[str] = ()) -> list[Finding]:
    """Lint's ``known-difference`` rule: records to write as ``reads = "urdf"``.

    Args:
        model: The model.
        ignore: Rules left out, on top of the model file's ``[lint] ignore``.
    """
    if "known-difference" in {*model.lint_ignore, *ignore}:
        return []
    return [
        Finding(
            "known-difference",
            f"known_difference[{i}].backends",
            f"names the URDF readers {', '.join(entry.backends)} one by one: a difference "
            "with the URDF is the description's, and a check reads it as every URDF "
            'reader\'s, those that joined since too; write reads = "urdf" instead',
        )
        for i, entry in enumerate(model.known_differences)
        if of_the_description(entry)
    ]


def _beyond(result: BackendResult, entry: KnownDifference) -> list[str]:
    """The recorded bounds the result's errors exceed, as text."""
    over: list[str] = []
    pos, rot = result.max_position_error_m, result.max_rotation_error_rad
    if not (pos is not None and pos <= entry.max_position_m):
        shown = "NaN" if pos is None else format_length_summary(pos)
        over.append(
            f"position error {shown} > recorded {format_length_summary(entry.max_position_m)}"
        )
    if not (rot is not None and rot <= entry.max_angle_rad):
        shown = "NaN" if rot is None else format_angle_summary(rot)
        over.append(
            f"rotation error {shown} > recorded {format_angle_summary(entry.max_angle_rad)}"
        )
    return over


def _apply(
    result: BackendResult, entry: KnownDifference, library: tuple[str, str] | None = None
) -> BackendResult:
    if result.status == "pass":
        return replace(
            result,
            status="xpass",
            message=(
                "known difference no longer seen: the model file records that this backend "
                f"disagrees ({entry.finding}), but it agrees; remove or correct its "
                "[[known_difference]]"
            ),
        )
    if result.status != "fail":
        return result
    over = _beyond(result, entry)
    if over:
        return replace(
            result,
            message=(f"beyond the recorded known difference ({'; '.join(over)}): {result.message}"),
        )
    jacobian = result.jacobian
    if jacobian is not None and jacobian.status == "fail":
        lin, ang = jacobian.max_linear_error, jacobian.max_angular_error
        beyond = []
        if not (lin is not None and lin <= entry.max_position_m):
            shown = "NaN" if lin is None else f"{lin:.3g}"
            beyond.append(f"linear {shown} m/rad > recorded {entry.max_position_m:g} m")
        if not (ang is not None and ang <= entry.max_angle_rad):
            shown = "NaN" if ang is None else f"{ang:.3g}"
            beyond.append(f"angular {shown} rad/rad > recorded {entry.max_angle_rad:g} rad")
        if beyond:
            message = f"beyond the recorded known difference ({'; '.join(beyond)}): "
            jacobian = replace(jacobian, message=message + jacobian.message)
        else:
            excused = f"expected failure, known difference: {entry.finding} — "
            jacobian = replace(jacobian, status="xfail", message=excused + jacobian.message)
    said = "known difference"
    if entry.versions and library is not None:  # a reader's own, for the versions recorded
        said += f" ({library[0]} {library[1]}, recorded for versions {entry.versions})"
    return replace(
        result,
        status="xfail",
        message=f"expected failure, {said}: {entry.finding} — {result.message}",
        jacobian=jacobian,
    )


def apply_known_differences(
    model: Model,
    frame_pair: tuple[str, str],
    tol: tuple[float, float],
    results: Sequence[BackendResult],
    reads: Mapping[str, str],
    libraries: Mapping[str, tuple[str, str] | None] | None = None,
) -> tuple[BackendResult, ...]:
    """The results with the model's recorded differences applied (see the module docstring).

    Args:
        model: The model checked.
        frame_pair: The ``(from, to)`` frames the check compared.
        tol: The ``(position m, rotation rad)`` tolerances it used.
        results: One result per backend.
        reads: What each backend reads, by name (``"urdf"``…).
        libraries: Each backend's library and installed version, by name
            (:func:`library_of`), for records tied to versions (``versions``).

    Returns:
        The results, those of listed backends rewritten.
    """
    default = frame_pair == (model.check.frame_from, model.check.frame_to) and tol == (
        model.check.tol_pos_m,
        model.check.tol_rot_rad,
    )
    if not model.known_differences or not default:
        return tuple(results)
    out: list[BackendResult] = []
    libraries = libraries or {}
    for result in results:
        library = libraries.get(result.name)
        version = library[1] if library is not None else None
        entry = known_difference_for(model, result.name, reads.get(result.name, ""), version)
        if entry is None or (entry.versions == "" and result.name not in entry.backends):
            note = _not_this_version(model, result, library)
            if note:
                result = replace(result, message=(result.message + note).strip())
        out.append(result if entry is None else _apply(result, entry, library))
    return tuple(out)
