"""An IK check's result as JSON, text and Markdown (formatting only; no kinematics).

The JSON (``fkcheck ik --json OUT``), ``"schema": "fkcheck-ik/1"``:

* ``verdict``: ``"pass"`` or ``"fail"``; ``model``, ``solver``, ``method``,
  ``frame_from``, ``frame_to``, ``seed``, ``samples``;
* ``tolerances``: ``position_m``, ``rotation_rad`` (soundness),
  ``same_configuration_rad`` and ``singular_sigma`` (:mod:`fkcheck.ik.check`);
* integers ``poses``, ``singular_poses``, ``solutions``, ``wrong_solutions``,
  ``missed``, ``garbage``, ``raised``, ``own_fk_disagreements``;
* ``own_fk``: whether the solver's own FK was checked; ``completeness_checked``:
  ``false`` for an arm of more than six joints (a continuum of configurations);
* ``counts``: poses per number of solutions (``{"8": 1603, …}``);
* ``missed_by_branch``, ``wrong_by_branch``: counts by branch name;
* ``worst``: failing poses, each with ``kind``, ``index``, ``origin``, ``q``
  (radians), ``q_deg``, ``branch``, ``returned``, ``returned_branches``,
  ``solution``, ``position_error_m``, ``rotation_error_rad``, ``explanation``;
* ``explanation``: lines; ``messages``: what the solver printed, by kind, with
  counts; ``timing``: ``solve_s``, ``check_s``, ``solves_per_s``; ``error``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from typing import Any

from fkcheck._version import __version__
from fkcheck.ik.check import SAME_CONFIGURATION_RAD, SINGULAR_SIGMA, IkCase, IkResult
from fkcheck.io.text import xml_safe_tree

__all__ = ["SCHEMA", "format_html", "format_markdown", "format_text", "junit_xml", "to_dict"]

#: The JSON's schema name and version.
SCHEMA = "fkcheck-ik/1"


def _number(value: float) -> float | None:
    """A finite float, or ``None`` (JSON has no inf)."""
    return value if math.isfinite(value) else None


def _case(case: IkCase) -> dict[str, Any]:
    return {
        "kind": case.kind,
        "index": case.index,
        "origin": case.origin,
        "q": list(case.q),
        "q_deg": [math.degrees(v) for v in case.q],
        "branch": case.branch,
        "returned": [[_number(v) for v in row] for row in case.returned],
        "returned_branches": list(case.returned_branches),
        "solution": None if case.solution is None else list(case.solution),
        "position_error_m": _number(case.position_error_m),
        "rotation_error_rad": _number(case.rotation_error_rad),
        "explanation": case.explanation,
    }


def to_dict(result: IkResult) -> dict[str, Any]:
    """The result as JSON-ready data (the fields above)."""
    return {
        "schema": SCHEMA,
        "verdict": result.verdict,
        "model": result.model,
        "solver": result.solver,
        "method": result.method,
        "frame_from": result.frame_from,
        "frame_to": result.frame_to,
        "seed": result.seed,
        "samples": result.samples,
        "tolerances": {
            "position_m": result.tol_pos_m,
            "rotation_rad": result.tol_rot_rad,
            "same_configuration_rad": SAME_CONFIGURATION_RAD,
            "singular_sigma": SINGULAR_SIGMA,
        },
        "poses": result.poses,
        "singular_poses": result.singular_poses,
        "solutions": result.solutions,
        "counts": {str(k): v for k, v in result.counts.items()},
        "wrong_solutions": result.wrong_solutions,
        "missed": result.missed,
        "garbage": result.garbage,
        "raised": result.raised,
        "completeness_checked": result.completeness_checked,
        "own_fk": result.own_fk,
        "own_fk_disagreements": result.own_fk_disagreements,
        "missed_by_branch": result.missed_by_branch,
        "wrong_by_branch": result.wrong_by_branch,
        "worst": [_case(c) for c in result.worst],
        "explanation": list(result.explanation),
        "messages": result.messages,
        "timing": {
            "solve_s": result.solve_s,
            "check_s": result.check_s,
            "solves_per_s": result.poses / result.solve_s if result.solve_s > 0 else None,
        },
        "error": result.error,
    }


def _summary(result: IkResult) -> list[str]:
    counts = ", ".join(f"{k}: {v}" for k, v in result.counts.items())
    rate = f"{result.poses / result.solve_s:,.0f} solves/s" if result.solve_s > 0 else "-"
    missed = result.missed if result.completeness_checked else "not checked (redundant arm)"
    own = (
        f"{result.own_fk_disagreements} disagreements with the table"
        if result.own_fk
        else "none (the solver has no fk)"
    )
    return [
        f"model {result.model}, solver {result.solver} ({result.method})",
        f"pose {result.frame_from} -> {result.frame_to}; tolerances "
        f"{result.tol_pos_m:g} m, {result.tol_rot_rad:g} rad",
        f"poses: {result.poses} ({result.singular_poses} singular), seed {result.seed}; "
        f"solutions per pose: {counts}",
        f"wrong solutions: {result.wrong_solutions}; missed: {missed}; "
        f"garbage (NaN/inf): {result.garbage}; raised: {result.raised}",
        f"own FK: {own}",
        f"solver time: {result.solve_s:.3g} s ({rate}); checking: {result.check_s:.3g} s",
    ]


def _case_line(case: IkCase) -> str:
    q_deg = ", ".join(f"{math.degrees(v):.6g}" for v in case.q)
    return f"{case.kind} at q = [{q_deg}]° ({case.origin}): {case.explanation}"


def format_text(result: IkResult) -> str:
    """What ``fkcheck ik`` prints."""
    lines = [f"IK {result.verdict.upper()}", *_summary(result)]
    for text, count in result.messages.items():
        lines.append(f"the solver printed {count}×: {text}")
    if result.explanation:
        lines.append("why:")
        lines.extend(f"  {line}" for line in result.explanation)
    if result.worst:
        lines.append("worst cases:")
        lines.extend(f"  {_case_line(c)}" for c in result.worst)
    return "\n".join(lines) + "\n"


def format_markdown(result: IkResult) -> str:
    """The result as a Markdown section (``--markdown OUT``, a CI job summary)."""
    mark = "✅" if result.passed else "❌"
    lines = [f"### {mark} IK {result.verdict}: {result.model} / {result.solver}", ""]
    lines.extend(f"- {line}" for line in _summary(result))
    if result.explanation:
        lines += ["", "**Why:**", ""]
        lines.extend(f"- {line.strip()}" for line in result.explanation)
    if result.worst:
        lines += ["", "| kind | origin | q (°) | branch | explanation |", "|---|---|---|---|---|"]
        for c in result.worst:
            q_deg = ", ".join(f"{math.degrees(v):.4g}" for v in c.q)
            text = c.explanation.replace("|", "\\|")
            lines.append(f"| {c.kind} | {c.origin} | {q_deg} | {c.branch} | {text} |")
    return "\n".join(lines) + "\n"


def junit_xml(result: IkResult) -> bytes:
    """The result as JUnit XML (``--junit OUT``): one suite, a case per property.

    ``soundness`` (wrong solutions), ``completeness`` (missed configurations),
    ``singular behaviour`` (NaN/inf answers, raises) and ``own FK`` (skipped when
    the solver has none) each fail with their count and the explanation; a run
    that failed as a whole is an ``<error>``.
    """
    name = f"fkcheck.ik.{result.model}.{result.solver}"
    suite = ET.Element("testsuite", name=name, time=f"{result.solve_s + result.check_s:.3f}")
    properties = ET.SubElement(suite, "properties")
    ET.SubElement(properties, "property", name="fkcheck_version", value=__version__)
    why = "\n".join(result.explanation)
    cases = [
        ("soundness", result.wrong_solutions, "wrong solutions"),
        ("completeness", result.missed, "poses missed their configuration"),
        ("singular behaviour", result.garbage + result.raised, "poses answered NaN/inf or raised"),
        ("own FK", result.own_fk_disagreements, "configurations where its FK disagrees"),
    ]
    counts = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    for title, count, what in cases:
        case = ET.SubElement(suite, "testcase", classname=name, name=title)
        counts["tests"] += 1
        if result.error:
            ET.SubElement(case, "error", message=result.error, type="error").text = result.error
            counts["errors"] += 1
        elif title == "own FK" and not result.own_fk:
            ET.SubElement(case, "skipped", message="the solver has no fk")
            counts["skipped"] += 1
        elif count:
            message = f"{count} {what} ({result.poses} poses)"
            ET.SubElement(case, "failure", message=message, type="ik").text = why
            counts["failures"] += 1
        else:
            ET.SubElement(case, "system-out").text = f"0 {what} ({result.poses} poses)"
    for key, value in counts.items():
        suite.set(key, str(value))
    suites = ET.Element("testsuites")
    suites.append(suite)
    xml_safe_tree(suites)
    ET.indent(suites)
    data: bytes = ET.tostring(suites, encoding="utf-8", xml_declaration=True)
    return data


#: The page ``--html OUT`` writes: self-contained, every value autoescaped.
_HTML = """<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<title>fkcheck ik {{ r.model }} / {{ r.solver }}: {{ r.verdict }}</title>
<style>
body { font: 14px/1.45 system-ui, sans-serif; margin: 2em auto; max-width: 72em; padding: 0 1em; }
h1 .pass { color: #1a7f37; } h1 .fail { color: #cf222e; }
table { border-collapse: collapse; } td, th { border: 1px solid #ccc; padding: .2em .5em;
  text-align: left; vertical-align: top; } code { font-size: 95%; }
</style></head><body>
<h1>IK <span class="{{ r.verdict }}">{{ r.verdict }}</span>: {{ r.model }} / {{ r.solver }}</h1>
<ul>{% for line in summary %}<li>{{ line }}</li>{% endfor %}
{% for text, count in r.messages.items() %}<li>the solver printed {{ count }}×: {{ text }}</li>
{% endfor %}</ul>
{% if r.explanation %}<h2>Why</h2><ul>{% for line in r.explanation %}<li>{{ line }}</li>
{% endfor %}</ul>{% endif %}
{% if r.worst %}<h2>Worst cases</h2><table><tr><th>kind</th><th>origin</th><th>q (°)</th>
<th>branch</th><th>explanation</th></tr>
{% for c in worst %}<tr><td>{{ c.kind }}</td><td>{{ c.origin }}</td><td><code>{{ c.q }}</code></td>
<td>{{ c.branch }}</td><td>{{ c.explanation }}</td></tr>
{% endfor %}</table>{% endif %}
<p>fkcheck {{ version }}</p>
</body></html>
"""


def format_html(result: IkResult) -> str:
    """The result as one self-contained HTML page (``--html OUT``); every value escaped."""
    import jinja2

    template = jinja2.Environment(autoescape=True).from_string(_HTML)
    worst = [
        {
            "kind": c.kind,
            "origin": c.origin,
            "q": ", ".join(f"{math.degrees(v):.6g}" for v in c.q),
            "branch": c.branch,
            "explanation": c.explanation,
        }
        for c in result.worst
    ]
    return template.render(r=result, summary=_summary(result), worst=worst, version=__version__)
