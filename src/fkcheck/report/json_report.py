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
from fkcheck.engine.results import REFERENCE_NAME, CheckResult
from fkcheck.engine.verdict import number_status
from fkcheck.io.atomic import write_text_atomic
from fkcheck.io.strict_json import strict_json
from fkcheck.report.record import BackendRecord, CheckRecord, JacobianRecord, check_record

__all__ = ["TIME_FIELDS", "result_to_dict", "write_json"]

#: Fields whose values name times; everything else is reproducible.
TIME_FIELDS = ("created", "duration_s")


def _backend(record: BackendRecord) -> dict[str, Any]:
    return {
        "name": record.name,
        "status": record.status,
        "max_position_error_m": record.max_position_m,
        "max_rotation_error_rad": record.max_rotation_rad,
        "p99_position_error_m": record.p99_position_m,
        "p99_rotation_error_rad": record.p99_rotation_rad,
        "median_position_error_m": record.median_position_m,
        "median_rotation_error_rad": record.median_rotation_rad,
        "worst_q": None if record.worst_q is None else list(record.worst_q),
        "evidence": record.evidence,
        "message": record.message,
        "method": record.method,
        "duration_s": round(record.duration_s, 6),
        "configurations": record.configurations,
        "subset": record.subset or None,
        "reader_finding": record.reader_finding or None,
        **({"jacobian": _jacobian(record.jacobian)} if record.jacobian is not None else {}),
    }


def _jacobian(j: JacobianRecord) -> dict[str, Any]:
    """A backend's Jacobian comparison: errors overall and per joint column."""
    columns = None
    if j.columns:
        columns = [
            {"joint": c.joint, "max_linear": c.linear, "max_angular": c.angular} for c in j.columns
        ]
    return {
        "status": j.status,
        "message": j.message,
        "method": j.method,
        "tolerance": j.tolerance,
        "max_linear": j.max_linear,
        "max_angular": j.max_angular,
        "worst_q": None if j.worst_q is None else list(j.worst_q),
        "first_disagreeing_joint": j.first_joint,
        "columns": columns,
        "diagnosis": j.diagnosis,
        "diagnosis_details": list(j.diagnosis_details),
    }


def _evidence(check: CheckResult, record: CheckRecord) -> dict[str, Any]:
    evidence = check.evidence
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
    for kind in record.evidence:
        kinds[kind.kind]["summary"] = kind.sentence
    return {
        **kinds,
        "required": list(evidence.required),
        "unmet": list(evidence.unmet),
    }


def _numbers(check: CheckResult, record: CheckRecord) -> dict[str, Any] | None:
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
            "competing": list(n.competing),
            "on_word_of": list(n.on_word_of),
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
        "line": record.numbers_line,
        "counts": counts,
        "vouches": [{"frame": frame, "source": source} for frame, source in numbers.vouches],
        "numbers": rows,
    }


def _calibration(record: CheckRecord) -> dict[str, Any] | None:
    """What a calibrated model's calibration changes (``None`` for other models)."""
    effect = record.calibration
    if effect is None:
        return None
    return {
        "nominal": effect.nominal,
        "calibration": effect.identity,
        "from": effect.frame_from,
        "to": effect.frame_to,
        "configurations": effect.configurations,
        "position_m": {
            "max": effect.max_position_m,
            "median": effect.median_position_m,
            "p95": effect.p95_position_m,
        },
        "rotation_rad": {
            "max": effect.max_rotation_rad,
            "median": effect.median_rotation_rad,
            "p95": effect.p95_rotation_rad,
        },
        "worst_index": effect.worst_index,
        "worst_q": list(effect.worst_q),
        "provenance": effect.provenance.state if effect.provenance is not None else None,
        "line": record.calibration_line,
    }


def _derived(check: CheckResult) -> dict[str, str] | None:
    """A table fkcheck derived (``check --source``): which file it came from, which was checked."""
    derived = check.model.derived
    if derived is None:
        return None
    return {
        "source": derived.source,
        "checked": derived.checked,
        "checked_from": derived.checked_from,
        "checked_to": derived.checked_to,
        "line": derived.line,
    }


def _jacobian_spec(check: CheckResult) -> dict[str, Any]:
    """``{"jacobian": …}`` when the check compared Jacobians, else nothing."""
    if check.jacobian is None:
        return {}
    units = {"linear": "m/rad (m/m for a prismatic joint)", "angular": "rad/rad"}
    spec = {"reference": check.jacobian.reference, "tolerance": check.jacobian.tol}
    return {"jacobian": {**spec, "units": units}}


def result_to_dict(check: CheckResult) -> dict[str, Any]:
    """The JSON document as a dict: the check's record (:mod:`fkcheck.report.record`)."""
    record = check_record(check)
    return {
        "model": check.model.name,
        "samples": check.options.samples,
        "seed": check.options.seed,
        "sampler": check.options.sampler,
        "timeout_s": check.options.timeout_s,
        "configurations": int(check.q.shape[0]),
        "from": check.frame_from,
        "to": check.frame_to,
        "tolerance": {"position_m": check.tol_pos_m, "rotation_rad": check.tol_rot_rad},
        "reference": REFERENCE_NAME,
        **_jacobian_spec(check),
        "backends": [_backend(b) for b in record.backends],
        "verdict": record.verdict,
        "headline": record.headline,
        "evidence": _evidence(check, record),
        "numbers": _numbers(check, record),
        "calibration": _calibration(record),
        "derived": _derived(check),
        "lint": list(check.lint),
        "cross_checked": record.answered,
        "fkcheck_version": __version__,
        "command": check.command,
        "config": check.config,
        "created": check.created,
        "duration_s": round(check.duration_s, 6),
    }


def write_json(check: CheckResult, path: Path | str) -> Path:
    """Write the result as JSON, atomically."""
    return write_text_atomic(path, strict_json(result_to_dict(check), indent=2) + "\n")
