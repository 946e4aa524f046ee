"""Backends by what they declare: the default set, a format's readers, a known difference's.

Every list is derived from what each registered backend declares
(:class:`~fkcheck.backends.base.Backend`, :mod:`fkcheck.backends.registration`),
and so is ``--against``'s help.
"""

from __future__ import annotations

from collections.abc import Sequence

from fkcheck.backends.base import Backend, Evidence, Reads
from fkcheck.backends.registration import (
    BUILTIN,
    PLUGIN,
    BackendOptions,
    find_registration,
    make_backend,
    registrations,
)
from fkcheck.errors import FkcheckError, ModelError
from fkcheck.io.numbers import show_text
from fkcheck.model.types import Model

__all__ = [
    "against_help",
    "check_known_differences",
    "default_backends",
    "default_names",
    "known_difference_names",
    "names",
]


def names(
    *,
    reads: Reads | str | None = None,
    evidence: Evidence | None = None,
    default: bool | None = None,
    format: str | None = None,
) -> tuple[str, ...]:
    """Registered names (prefixes as ``"cmd:"``) with the given declarations, in order.

    ``format``: only the readers of that description format (``formats`` holds it).

    Asking for declarations builds each third-party backend in its own process; one
    that cannot be built is left out (asking for it by name says why).
    """
    out = []
    for r in registrations():
        if default is not None and r.default != default:
            continue
        try:
            if reads is not None and r.declared("reads") != reads:
                continue
            if evidence is not None and r.declared("evidence") != evidence:
                continue
            if format is not None and format not in (r.declared("formats") or ()):
                continue
        except FkcheckError:
            if r.origin == "fkcheck":
                raise
            continue
        out.append(r.name)
    return tuple(out)


def default_names(model: Model | None = None) -> tuple[str, ...]:
    """The backends a check of ``model`` runs when ``--against`` is not given.

    The default set, then the readers of each description format ``model``
    declares (``default_for``: ``mujoco-mjcf`` and ``pinocchio-mjcf`` for a
    model with ``[mjcf]``); without a model, the default set alone. A model
    that declares a description leaves out the default set's readers of the
    formats it does not declare, as a model with ``[urdf]`` only never lists
    the MJCF readers: a reader of a file the model does not have is no
    skipped check of it (asked for by name, it still says why it cannot run).
    A model with no description keeps them: their ``model has no [urdf]`` says
    where table evidence would come from.
    """
    plain = names(default=True)
    if model is None:
        return plain
    from fkcheck.description.registry import model_formats

    declared = {fmt.name for fmt in model_formats(model)}
    if declared:
        plain = tuple(n for n in plain if _reads_one_of(n, declared))
    return plain + tuple(r.name for r in registrations() if r.default_for in declared)


def _reads_one_of(name: str, declared: set[str]) -> bool:
    """Whether backend ``name`` reads no description file, or one of the formats ``declared``."""
    registration, _ = find_registration(name, registrations())
    formats = () if registration is None else registration.declared("formats") or ()
    return not formats or bool(declared.intersection(formats))


def default_backends(
    options: BackendOptions | None = None, model: Model | None = None
) -> list[Backend]:
    """The backends a plain check of ``model`` runs (:func:`default_names`)."""
    return [make_backend(name, options) for name in default_names(model)]


def known_difference_names() -> tuple[str, ...]:
    """What a ``[[known_difference]]`` may name: backends whose evidence is the table's.

    Backends computing from the model's own table (``rtb-dh``, plugins, ``cmd:``)
    disagree only through a bug, never through a known difference.
    """
    return names(evidence="table")


def _known_difference_ok(name: str, used: Sequence[Backend]) -> bool:
    """Whether a ``[[known_difference]]`` may name ``name``.

    A backend this check uses says its own evidence. Otherwise the name must be
    registered: a built-in's evidence is read from it; a third party's is held
    to it only by a check that uses it (building it would run its code, and a
    broken distribution the check does not use must not end it).
    """
    for backend in used:
        if backend.name == name:
            return backend.evidence == "table"
    registration, _ = find_registration(name, registrations())
    if registration is None or registration is PLUGIN:
        return False
    if registration.origin != "fkcheck":
        return True
    return bool(registration.declared("evidence") == "table")


def _distributions(name: str, used: Sequence[Backend]) -> tuple[str, ...] | None:
    """The distributions backend ``name`` computes with (``None``: not known without running it).

    A backend this check uses says its own; a built-in's are read from it; a
    third party's only by a check that uses it (as :func:`_known_difference_ok`).
    """
    for backend in used:
        if backend.name == name:
            return tuple(backend.distributions or ())
    registration, _ = find_registration(name, registrations())
    if registration is None or registration is PLUGIN or registration.origin != "fkcheck":
        return None
    return tuple(registration.declared("distributions") or ())


def _versioned() -> str:
    """The built-ins a ``versions = …`` record may name: table evidence with a library."""
    found = [
        r.name + ("…" if r.name.endswith(":") else "")
        for r in BUILTIN
        if r.declared("evidence") == "table" and r.declared("distributions")
    ]
    return ", ".join(found) + ", or a third-party backend that names its distributions"


def check_known_differences(model: Model, used: Sequence[Backend] = ()) -> None:
    """Refuse a ``[[known_difference]]`` that can never apply.

    One naming a backend whose evidence is not the table's, or recording
    ``versions = …`` for a backend with no library whose version it could match
    (``poses:``, a backend that names no ``distributions``: the record would
    never apply, and the difference it records would fail the check unexplained).
    Builds no backend but the built-ins it names (``used``: those a check has
    built already).

    Raises:
        ModelError: The first such record, with its field, what is wrong and
            the names allowed.
    """
    if not model.known_differences:
        return
    for i, known in enumerate(model.known_differences):
        for k, name in enumerate(known.backends):
            if not _known_difference_ok(name, used):
                builtin = [r.name for r in BUILTIN if r.declared("evidence") == "table"]
                others = [r.name for r in registrations() if r.origin != "fkcheck"]
                shown = ", ".join(a + "…" if a.endswith(":") else a for a in builtin + others)
                raise ModelError(
                    model.path,
                    f"known_difference[{i}].backends[{k}]",
                    f"{show_text(name)} is not a backend whose evidence is independent of the "
                    f"table; known differences may name: {shown}",
                )
        if known.versions and _distributions(known.backends[0], used) == ():
            raise ModelError(
                model.path,
                f"known_difference[{i}].versions",
                f"{show_text(known.backends[0])} computes with no library (it names no "
                f"distributions): versions = {show_text(known.versions)} has no version to "
                f"match and the record would never apply; drop versions, or record them for: "
                f"{_versioned()}",
            )


def against_help() -> str:
    """What ``--against`` accepts, for the command line's help (from the registry)."""
    found = registrations()  # a broken registration is reported when it is asked for
    plain = [r.name for r in found if r.default]
    formats = sorted({r.default_for for r in found if r.default_for})
    per_format = [
        f"{', '.join(r.name for r in found if r.default_for == fmt)} (the default for a model "
        f"with [{fmt}]), "
        for fmt in formats
    ]
    extra = [r.name for r in found if not r.default and not r.default_for and not r.prefixed]
    return (
        f"backends, comma-separated or repeated: {', '.join(plain)} (the default set), "
        + "".join(per_format)
        + "".join(f"{name}, " for name in extra)
        + "rtb-model:NAME, poses:FILE.csv or poses:BAG (measured poses, or a ROS 2 bag: "
        "the check runs at their configurations), cmd:PROGRAM, module:function"
        + "".join(f", {r.name}ARG" for r in found if r.prefixed and r.origin != "fkcheck")
    )
