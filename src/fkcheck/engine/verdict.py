"""What a check proved: the evidence by kind, the requirements, and the verdict.

A cross-check answers two questions, and they are kept apart:

* **implementation** — *is the in-house core right, given the table?* Answered
  by backends that run the model's own table (``rtb-dh``, ``pinocchio-dh``,
  plugins, ``cmd:`` programs). Their agreement proves the arithmetic, not the
  numbers: a wrong d1 is wrong in every one of them.
* **table** — *is the table right, for the robot?* Answered only by evidence that
  does not come from the table: the robot's URDF read by its parsers, measured
  or pendant poses, a table published elsewhere (``rtb-model:``).

Each kind gets a status: ``verified`` (a backend of that kind answered and
agreed, none disagreed — and, for the table, every number of the table is
verified by the compared frame pair: :mod:`fkcheck.model.coverage`),
``partly-verified`` (the table's backends agree, but the pair leaves numbers of
the table not identifiable or not covered: said which), ``failed`` (one answered
and disagreed, or one the model records as disagreeing agrees: a stale
``[[known_difference]]``),
``expected-failure`` (those that disagree do so as the model's
``[[known_difference]]`` records; never read as verified) or ``not-checked``
(none answered). ``require`` (``--require``, ``[check] require``)
names kinds that must be ``verified``; when one is not, the verdict is
``unverified`` (exit 1) even though nothing disagreed.

A reader of a description that disagrees while another reader of the same
description agrees with the table is a *reader finding*
(:mod:`fkcheck.engine.readers`): it is named with its library's version in the
table's sentence and the headline, never counted as the table disagreeing, and
the verdict is still ``fail`` (the reader disagrees: no silent pass) until a
``[[known_difference]]`` records it for that reader's versions.

Verdicts: ``pass`` — every backend that ran agrees (or disagrees as recorded,
``xfail``) and every required kind is verified; ``fail`` — a backend answered
wrongly, or agreed where the model records a difference (``xpass``); ``error`` — a backend could
not answer, or none ran at all; ``unverified`` — nothing disagreed, but a
required kind of evidence is missing.

A backend that compared a subset of the configurations (the check's plan,
:mod:`fkcheck.engine.plan`) is named with its count wherever a sentence names
it — ``yourdfpy-urdf (95 081 of 1 000 081 configurations)`` — and the headline
ends with the subsets.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Literal, Protocol

from fkcheck.core.tolerances import DEFAULT_TOL_POS_M, DEFAULT_TOL_ROT_RAD
from fkcheck.engine.plan import count_text
from fkcheck.model.require import KINDS, Kind

if TYPE_CHECKING:
    from fkcheck.model.coverage import Coverage, NumberEvidence

__all__ = [
    "KINDS",
    "EvidenceKind",
    "EvidenceSummary",
    "Kind",
    "KindStatus",
    "Verdict",
    "evidence_sentences",
    "headline",
    "number_status",
    "numbers_line",
    "subset_text",
    "summarize",
    "tolerance_note",
    "verdict_of",
]

KindStatus = Literal["verified", "partly-verified", "not-checked", "failed", "expected-failure"]
Verdict = Literal["pass", "fail", "error", "unverified"]


class _Outcome(Protocol):
    """What :func:`summarize` needs of a backend's result."""

    @property
    def name(self) -> str: ...
    @property
    def status(self) -> str: ...
    @property
    def evidence(self) -> str: ...
    @property
    def ran(self) -> bool: ...
    @property
    def subset(self) -> tuple[int, int] | None: ...
    @property
    def reader_finding(self) -> str: ...


@dataclass(frozen=True)
class EvidenceKind:
    """The evidence of one kind.

    Attributes:
        kind: ``implementation`` or ``table``.
        status: ``verified``, ``partly-verified`` (table only), ``failed``,
            ``expected-failure`` or ``not-checked``.
        agreed: Backends of this kind that answered and agreed.
        disagreed: Backends of this kind that answered wrongly.
        unanswered: Backends of this kind that were asked but could not answer
            (error) or did not apply (skipped).
        expected: Backends that disagree as the model records (``xfail``).
        stale: Backends the model records as disagreeing that agree (``xpass``).
        gaps: For ``partly-verified``: the numbers of the table the frame pair
            leaves unverified, one clause (:meth:`fkcheck.model.coverage.Coverage.gaps`).
        readers: Readers that disagree while another reader of the same
            description agrees with the table (:mod:`fkcheck.engine.readers`):
            not counted in ``disagreed``, and the check still fails.
        reader_findings: Their sentences, in the same order.
    """

    kind: Kind
    status: KindStatus
    agreed: tuple[str, ...] = ()
    disagreed: tuple[str, ...] = ()
    unanswered: tuple[str, ...] = ()
    expected: tuple[str, ...] = ()
    stale: tuple[str, ...] = ()
    gaps: str = ""
    readers: tuple[str, ...] = ()
    reader_findings: tuple[str, ...] = ()


@dataclass(frozen=True)
class EvidenceSummary:
    """Both kinds of evidence and what was required.

    Attributes:
        implementation: Evidence that the core computes the table right.
        table: Evidence, independent of the table, that the table is right.
        required: Kinds that must be ``verified``.
        unmet: Required kinds that are not.
        numbers: What the compared frame pair can verify, number by number
            (``None`` when not analysed).
        loose: When a tolerance is looser than the default: which, and where it
            came from (``--tol-pos``, the model's ``[check]``, a ``pyproject.toml``);
            every headline ends with it.
        subsets: The backends that compared a subset of the configurations, as
            ``(name, compared, total)`` (:mod:`fkcheck.engine.plan`).
    """

    implementation: EvidenceKind
    table: EvidenceKind
    required: tuple[Kind, ...] = ()
    unmet: tuple[Kind, ...] = ()
    numbers: Coverage | None = None
    loose: str = ""
    subsets: tuple[tuple[str, int, int], ...] = ()

    def of(self, kind: Kind) -> EvidenceKind:
        """The evidence of one kind."""
        return self.implementation if kind == "implementation" else self.table


def _group(result: _Outcome) -> str:
    """Its status, or ``reader`` for a reader finding (:mod:`fkcheck.engine.readers`)."""
    if result.status == "fail" and result.reader_finding:
        return "reader"
    return "unanswered" if result.status in ("error", "skipped") else result.status


def _kind(kind: Kind, results: Sequence[_Outcome]) -> EvidenceKind:
    groups: dict[str, list[_Outcome]] = {}
    for r in results:
        if r.evidence == kind:
            groups.setdefault(_group(r), []).append(r)

    def names(group: str) -> tuple[str, ...]:
        return tuple(r.name for r in groups.get(group, ()))

    agreed, disagreed, expected, stale = (
        names("pass"),
        names("fail"),
        names("xfail"),
        names("xpass"),
    )
    status: KindStatus = (
        "failed"
        if disagreed or stale
        else "expected-failure"
        if expected
        else "verified"
        if agreed
        else "not-checked"
    )
    return EvidenceKind(
        kind,
        status,
        agreed,
        disagreed,
        names("unanswered"),
        expected,
        stale,
        readers=names("reader"),
        reader_findings=tuple(r.reader_finding for r in groups.get("reader", ())),
    )


def summarize(
    results: Sequence[_Outcome],
    required: Sequence[Kind] = (),
    numbers: Coverage | None = None,
    loose: str = "",
) -> EvidenceSummary:
    """Sort backend results into the two kinds of evidence.

    With ``numbers``, agreeing table evidence is ``verified`` only when every
    number of the table is; otherwise ``partly-verified``, naming the rest.
    """
    implementation = _kind("implementation", results)
    table = _kind("table", results)
    if table.status == "verified" and numbers is not None and not numbers.complete:
        table = replace(table, status="partly-verified", gaps=numbers.gaps())
    by_kind = {"implementation": implementation, "table": table}
    unmet = tuple(k for k in required if by_kind[k].status != "verified")
    subsets = tuple((r.name, *r.subset) for r in results if r.subset is not None)
    return EvidenceSummary(implementation, table, tuple(required), unmet, numbers, loose, subsets)


def tolerance_note(tol_pos_m: float, tol_rot_rad: float, sources: tuple[str, str]) -> str:
    """``tolerance looser than the default: 0.001 m (default 1e-06 m) from --tol-pos``.

    Each looser tolerance with where it came from (``sources``: position's,
    rotation's); empty when neither is looser than the default.
    """
    looser = []
    for value, default, unit, source in (
        (tol_pos_m, DEFAULT_TOL_POS_M, "m", sources[0]),
        (tol_rot_rad, DEFAULT_TOL_ROT_RAD, "rad", sources[1]),
    ):
        if value > default:
            where = f" from {source}" if source else ""
            looser.append(f"{value:g} {unit} (default {default:g} {unit}){where}")
    if not looser:
        return ""
    return f"tolerance looser than the default: {' and '.join(looser)}"


def verdict_of(results: Sequence[_Outcome], evidence: EvidenceSummary) -> Verdict:
    """The verdict of one check (see the module docstring)."""
    if not any(r.ran for r in results):
        return "error"
    if any(r.status in ("fail", "xpass") for r in results):
        return "fail"
    if any(r.status == "error" for r in results):
        return "error"
    if evidence.unmet:
        return "unverified"
    return "pass"


def _names(names: Sequence[str], subsets: Iterable[tuple[str, int, int]] = ()) -> str:
    """The names, each with its count when it compared a subset of the configurations."""
    counts = {name: f" ({subset_text(compared, total)})" for name, compared, total in subsets}
    return ", ".join(f"{name}{counts.get(name, '')}" for name in names)


def subset_text(compared: int, total: int) -> str:
    """``95 081 of 1 000 081 configurations``: what a backend on a subset compared."""
    return f"{count_text(compared)} of {count_text(total)} configurations"


def _agree(names: Sequence[str], prefix: str = "") -> str:
    """``agrees`` for one backend, ``agree`` for several."""
    return f"{prefix}agrees" if len(names) == 1 else f"{prefix}agree"


def _stale(kind: EvidenceKind) -> str:
    """The clause naming backends whose recorded difference is no longer seen."""
    if not kind.stale:
        return ""
    return (
        f" known difference no longer seen: {_names(kind.stale)} {_agree(kind.stale)}, "
        "though the model's [[known_difference]] records a disagreement (stale record)"
    )


def evidence_sentences(evidence: EvidenceSummary) -> tuple[str, str]:
    """One plain sentence per kind, the same in every output format.

    Returns:
        ``(implementation sentence, table sentence)``.
    """
    imp, tab = evidence.implementation, evidence.table
    sub = evidence.subsets  # a backend on a subset is named with its count
    if imp.status == "verified":
        imp_text = (
            f"implementation verified: {_names(imp.agreed, sub)} {_agree(imp.agreed)} with the "
            "in-house core (same table, independent code)"
        )
    elif imp.status == "failed":
        imp_text = (
            f"implementation FAILED: {_names(imp.disagreed, sub)} {_agree(imp.disagreed, 'dis')} "
            "with the in-house core"
        )
        imp_text += _stale(imp)
    else:
        imp_text = "implementation not checked: no other implementation of this table answered"
    if tab.status == "verified":
        tab_text = (
            f"table verified: {_names(tab.agreed, sub)} {_agree(tab.agreed)} "
            "(evidence independent of the table)"
        )
    elif tab.status == "partly-verified":
        partly = (
            "table PARTLY verified"
            if evidence.numbers is None or evidence.numbers.verifies_any
            else "table NOT verified"
        )
        tab_text = (
            f"{partly}: {_names(tab.agreed, sub)} {_agree(tab.agreed)} "
            f"(evidence independent of the table), but {tab.gaps}"
        )
    elif tab.status == "failed":
        tab_text = (
            f"table FAILED: {_names(tab.disagreed, sub)} {_agree(tab.disagreed, 'dis')} "
            "(evidence independent of the table)"
            if tab.disagreed
            else "table FAILED:"
        )
        tab_text += _stale(tab)
    elif tab.status == "expected-failure":
        tab_text = (
            f"table NOT VERIFIED, expected failure: {_names(tab.expected, sub)} "
            f"{_agree(tab.expected, 'dis')} as the model's [[known_difference]] records "
            "(evidence independent of the table)"
        )
        if tab.agreed:
            tab_text += f"; {_names(tab.agreed, sub)} {_agree(tab.agreed)}"
    else:
        tab_text = (
            "table NOT CHECKED: nothing independent of it (URDF, measured poses, published "
            "table) answered; agreement proves the arithmetic, not the numbers"
        )
    if tab.reader_findings:
        tab_text += "; " + "; ".join(tab.reader_findings)
    if "table" in evidence.unmet:
        tab_text += " — required (require = table)"
    if "implementation" in evidence.unmet:
        imp_text += " — required (require = implementation)"
    return imp_text, tab_text


def headline(verdict: Verdict, evidence: EvidenceSummary, n_ran: int) -> str:
    """The verdict with what it proved, one line: ``pass — implementation only; …``.

    A pass that never checked the table says so in the verdict itself, so it
    cannot be read as "the table is right" wherever only the verdict is shown;
    a tolerance looser than the default is named at its end, with its source.
    """
    line = _headline(verdict, evidence, n_ran)
    if evidence.subsets:
        line += "; on a subset: " + ", ".join(
            f"{name} {subset_text(compared, total)}" for name, compared, total in evidence.subsets
        )
    return f"{line} [{evidence.loose}]" if evidence.loose else line


def _headline(verdict: Verdict, evidence: EvidenceSummary, n_ran: int) -> str:
    if verdict == "pass":
        if evidence.table.status == "expected-failure":
            tail = (
                "implementation agrees"
                if evidence.implementation.status == "verified"
                else "no second implementation ran"
            )
            return (
                "pass — expected failure: the table differs from "
                f"{_names(evidence.table.expected)} as the model records (known difference; "
                f"table NOT verified), {tail}"
            )
        if evidence.table.status == "verified":
            # A number verified only because a frame is vouched for rests on that word.
            word = evidence.numbers.on_word() if evidence.numbers is not None else ""
            said = f", {word};" if word else ","
            if evidence.implementation.status == "verified":
                return f"pass — table verified independently{said} implementation agrees"
            said = said.rstrip(",;")
            return f"pass — table verified independently{said}; no second implementation ran"
        if evidence.table.status == "partly-verified" and evidence.numbers is not None:
            tail = (
                "implementation agrees"
                if evidence.implementation.status == "verified"
                else "no second implementation ran"
            )
            return f"pass — {evidence.numbers.summary()}; {tail}"
        if evidence.implementation.status == "verified":
            return "pass — implementation only; table not checked against anything independent"
        return "pass"
    if verdict == "unverified":
        return "unverified — nothing disagreed, but required evidence is missing: " + ", ".join(
            evidence.unmet
        )
    if verdict == "fail":
        parts = [part for k in KINDS for part in _failing(k, evidence.of(k))]
        if not parts:  # only a Jacobian can fail while every pose agrees
            return "fail — the poses agree, a Jacobian disagrees"
        return "fail — " + " and ".join(parts)
    if n_ran == 0:
        return "error — no backend gave an answer: nothing was cross-checked"
    return "error — a backend could not answer (see its message)"


def _failing(k: Kind, kind: EvidenceKind) -> list[str]:
    """What of one kind fails the check, as the headline says it."""
    parts = []
    if kind.disagreed:
        parts.append(f"{k} disagrees")
    if kind.stale:
        parts.append(f"{k}: known difference no longer seen (stale record)")
    if kind.readers:
        parts.append(
            "a reader disagrees where another reader of the same description agrees with the "
            f"table: {', '.join(kind.readers)} (a finding about the reader, not the table)"
        )
    return parts


NumberStatus = Literal[
    "verified", "not-identifiable", "not-covered", "vouched", "failed", "not-checked"
]


def number_status(status: str, table: KindStatus) -> NumberStatus:
    """A number's status after the check: what the pair can verify, and what the table showed.

    A number the pair could verify is ``verified`` only when the table's evidence
    agreed, ``failed`` when it disagreed (or disagrees as recorded), and
    ``not-checked`` when nothing independent answered.
    """
    if status != "verified":
        return status  # type: ignore[return-value]
    if table in ("verified", "partly-verified"):
        return "verified"
    if table in ("failed", "expected-failure"):
        return "failed"
    return "not-checked"


def numbers_line(numbers: Coverage, table: KindStatus, *, derived: bool = False) -> str:
    """The model's numbers in one line, the same in every output format.

    ``numbers (base → tool0): 24 in the table: 24 verified; only as a combination: d2 + d3 + d4``

    Args:
        numbers: What the compared frame pair can verify, number by number.
        table: The table's evidence.
        derived: The table is one fkcheck derived (``check --source``): there is
            no model file for ``fkcheck diagnose``, the check's own diagnosis
            names the numbers that differ.
    """
    total = len(numbers.table_numbers)
    counts: dict[str, int] = {}
    for n in numbers.table_numbers:
        s = number_status(n.status, table)
        counts[s] = counts.get(s, 0) + 1
    order = ("verified", "failed", "not-checked", "not-identifiable", "not-covered")
    words = {
        "failed": "compared, and the table differs as the model's [[known_difference]] records"
        if table == "expected-failure"
        else "compared in a failing check "
        + ("(the check's diagnosis names which)" if derived else "(fkcheck diagnose names which)")
    }
    shown = [f"{counts[s]} {words.get(s, s.replace('-', ' '))}" for s in order if counts.get(s)]
    text = f"numbers ({numbers.frame_from} → {numbers.frame_to}): {total} in the table: "
    text += ", ".join(shown) if shown else "none"
    groups = _trade_groups(numbers)
    if groups and counts.get("verified"):
        text += "; only as a combination: " + ", ".join(groups)
    vouched = _unique_groups(n for n in numbers.numbers if n.status == "vouched")
    if vouched:
        text += "; vouched for by the model's source: " + ", ".join(vouched)
    resting = [n for n in numbers.table_numbers if n.status == "verified" and n.on_word_of]
    if resting:
        text += "; on the word of a vouched frame: " + ", ".join(
            f"{n.name} ({', '.join(n.on_word_of)})" for n in resting
        )
    return text


def _trade_groups(numbers: Coverage) -> list[str]:
    seen: list[str] = []
    for n in numbers.table_numbers:
        if n.trades_with and n.status == "verified":
            group = " + ".join([n.name, *n.trades_with])
            key = "+".join(sorted([n.name, *n.trades_with]))
            if key not in [("+".join(sorted(g.split(" + ")))) for g in seen]:
                seen.append(group)
    return seen


def _unique_groups(items: Iterable[NumberEvidence]) -> list[str]:
    out: list[str] = []
    for n in items:
        if n.group not in out:
            out.append(n.group)
    return out
