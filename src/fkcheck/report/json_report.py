"""The JSON result: a contract other tools read (documented in the README).

Identical inputs and seed give identical JSON except ``created`` and the
``duration_s`` fields. The JSON is strict (:mod:`fkcheck.io.strict_json`):
a non-finite number is written as ``null``, and its object gets a
``"non_finite"`` member naming what it was.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from fkcheck._version import __version__
from fkcheck.engine.results import REFERENCE_NAME, BackendResult, CheckResult
from fkcheck.engine.verdict import evidence_sentences, headline, number_status, numbers_line
from fkcheck.io.atomic import write_text_atomic
from fkcheck.io.strict_json import strict_json

__all__ = ["TIME_FIELDS", "result_to_dict", "write_json"]

#: Fields whose values name times; everything else is reproducible.
TIME_FIELDS = ("created", "duration_s")


def _backend(result: BackendResult, check: CheckResult) -> dict[str, Any]:
    worst_q = None
    if result.worst_index is not None:
        worst_q = check.q[result.worst_index].tolist()
    return {
        "name": result.name,
        "status": result.status,
        "max_position_error_m": result.max_position_error_m,
        "max_rotation_error_rad": result.max_rotation_error_rad,
        "p99_position_error_m": result.percentile("position", 99),
        "p99_rotation_error_rad": result.percentile("rotation", 99),
        "median_position_error_m": result.percentile("position", 50),
        "median_rotation_error_rad": result.percentile("rotation", 50),
        "worst_q": worst_q,
        "evidence": result.evidence,
        "message": result.message,
        "method": result.method,
        "duration_s": round(result.duration_s, 6),
        **({"jacobian": _jacobian(result, check)} if result.jacobian is not None else {}),
    }


def _jacobian(result: BackendResult, check: CheckResult) -> dict[str, Any]:
    """A backend's Jacobian comparison: errors overall and per joint column."""
    j = result.jacobian
    assert j is not None
    columns = None
    if j.column_linear is not None and j.column_angular is not None:
        columns = [
            {"joint": joint.name, "max_linear": float(lin), "max_angular": float(ang)}
            for joint, lin, ang in zip(
                check.model.joints, j.column_linear, j.column_angular, strict=True
            )
        ]
    first = j.first_bad_column
    return {
        "status": j.status,
        "message": j.message,
        "method": j.method,
        "tolerance": j.tolerance,
        "max_linear": j.max_linear_error,
        "max_angular": j.max_angular_error,
        "worst_q": None if j.worst_index is None else check.q[j.worst_index].tolist(),
        "first_disagreeing_joint": None if first is None else check.model.joints[first].name,
        "columns": columns,
        "diagnosis": j.diagnosis,
        "diagnosis_details": list(j.diagnosis_details),
    }


def _evidence(check: CheckResult) -> dict[str, Any]:
    evidence = check.evidence
    implementation, table = evidence_sentences(evidence)
    kinds: dict[str, dict[str, Any]] = {
        kind.kind: {
            "status": kind.status,
            "agreed": list(kind.agreed),
            "disagreed": list(kind.disagreed),
            "unanswered": list(kind.unanswered),
            "gaps": kind.gaps,
        }
        for kind in (evidence.implementation, evidence.table)
    }
    kinds["implementation"]["summary"] = implementation
    kinds["table"]["summary"] = table
    return {
        **kinds,
        "required": list(evidence.required),
        "unmet": list(evidence.unmet),
    }


def _numbers(check: CheckResult) -> dict[str, Any] | None:
    """Every number of the model, with what this check verified of it."""
    numbers = check.numbers
    if numbers is None:
        return None
    table = check.evidence.table.status
    rows = [
        {
            "name": n.name,
            "group": n.group,
            "unit": n.unit,
            "table": n.table,
            "status": number_status(n.status, table),
            "pair_can": n.status,
            "resolution": n.resolution,
            "absorbed_by": n.absorbed_by,
            "trades_with": list(n.trades_with),
            "source": n.source,
        }
        for n in numbers.numbers
    ]
    counts: dict[str, int] = {}
    for n in numbers.table_numbers:
        status = number_status(n.status, table)
        counts[status] = counts.get(status, 0) + 1
    return {
        "from": numbers.frame_from,
        "to": numbers.frame_to,
        "joints_spanned": list(numbers.joints_spanned),
        "summary": numbers.summary(),
        "line": numbers_line(numbers, table),
        "counts": counts,
        "numbers": rows,
    }


def _jacobian_spec(check: CheckResult) -> dict[str, Any]:
    """``{"jacobian": …}`` when the check compared Jacobians, else nothing."""
    if check.jacobian is None:
        return {}
    units = {"linear": "m/rad (m/m for a prismatic joint)", "angular": "rad/rad"}
    spec = {"reference": check.jacobian.reference, "tolerance": check.jacobian.tol}
    return {"jacobian": {**spec, "units": units}}


def result_to_dict(check: CheckResult) -> dict[str, Any]:
    """The JSON document as a dict."""
    return {
        "model": check.model.name,
        "samples": check.samples,
        "seed": check.seed,
        "sampler": check.sampler,
        "configurations": int(check.q.shape[0]),
        "from": check.frame_from,
        "to": check.frame_to,
        "tolerance": {"position_m": check.tol_pos_m, "rotation_rad": check.tol_rot_rad},
        "reference": REFERENCE_NAME,
        **_jacobian_spec(check),
        "backends": [_backend(b, check) for b in check.backends],
        "verdict": check.verdict,
        "headline": headline(check.verdict, check.evidence, len(check.ran)),
        "evidence": _evidence(check),
        "numbers": _numbers(check),
        "cross_checked": len(check.ran),
        "fkcheck_version": __version__,
        "command": check.command,
        "config": check.config,
        "created": check.created,
        "duration_s": round(check.duration_s, 6),
    }


def write_json(check: CheckResult, path: Path | str) -> Path:
    """Write the result as JSON, atomically."""
    return write_text_atomic(path, strict_json(result_to_dict(check), indent=2) + "\n")
