"""Two readers of one description that disagree: a finding about a reader, not the table.

Backends that read a description (``formats``: ``mujoco-mjcf`` and
``pinocchio-mjcf`` read the model's one MJCF, the URDF readers its one URDF)
compute the same poses from the same file when both read it right. So when,
among the readers of one format, one agrees with the table and another
disagrees, the file matches the table as the agreeing reader reads it, and the
disagreement is the other reader's: :func:`apply_reader_findings` marks its row
with that sentence (``reader_finding``), naming both libraries and their
versions. The row stays ``fail`` — the reader still disagrees, and a check is
never a silent pass — but the table's evidence does not count it against the
table (:mod:`fkcheck.engine.verdict`), and no diagnosis blames a number of the
table for it (:mod:`fkcheck.diagnose.failures`). A ``[[known_difference]]``
naming that reader with ``versions`` records it (:mod:`fkcheck.engine.expected`).

The agreeing reader must have compared the configuration where the other one is
worst (a reader on a subset that never saw it proves nothing there); an
expected failure (``xfail``) agrees with nothing, it disagrees as recorded.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

from fkcheck.engine.results import BackendResult

__all__ = ["apply_reader_findings", "reader_sentence"]


def _named(name: str, library: tuple[str, str] | None) -> str:
    return f"{name} ({library[0]} {library[1]})" if library is not None else name


def reader_sentence(
    name: str,
    agreeing: str,
    libraries: Mapping[str, tuple[str, str] | None],
) -> str:
    """``pinocchio-mjcf (pinocchio 4.1.0) disagrees with mujoco-mjcf (mujoco 3.3.7), …``."""
    return (
        f"{_named(name, libraries.get(name))} disagrees with "
        f"{_named(agreeing, libraries.get(agreeing))}, which agrees with the table: "
        "a finding about the reader, not the table"
    )


def _saw(agreeing: BackendResult, index: int | None) -> bool:
    """Whether ``agreeing`` compared configuration ``index``."""
    return agreeing.subset is None or (index is not None and index < agreeing.subset[0])


def apply_reader_findings(
    results: Sequence[BackendResult],
    formats: Mapping[str, str],
    libraries: Mapping[str, tuple[str, str] | None],
) -> tuple[BackendResult, ...]:
    """The results, each reader that disagrees where another of its format agrees marked.

    Args:
        results: One result per backend, known differences applied.
        formats: The format each description reader reads, by name (``"mjcf"``);
            backends that read no description are absent.
        libraries: Each backend's library and version, by name
            (:func:`fkcheck.engine.expected.library_of`).

    Returns:
        The results; a marked one keeps ``fail`` and its message starts with the finding.
    """
    out = list(results)
    for i, result in enumerate(results):
        fmt = formats.get(result.name)
        if fmt is None or result.status != "fail" or not result.ran:
            continue
        agreeing = next(
            (
                r
                for r in results
                if r.name != result.name
                and formats.get(r.name) == fmt
                and r.status == "pass"
                and _saw(r, result.worst_index)
            ),
            None,
        )
        if agreeing is None:
            continue
        sentence = reader_sentence(result.name, agreeing.name, libraries)
        out[i] = replace(result, reader_finding=sentence, message=f"{sentence} — {result.message}")
    return tuple(out)
