"""Running ``fkcheck check`` on one model or many, with progress; the files it writes."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from fkcheck.cli.progress import PLAIN_INTERVAL_S
from fkcheck.errors import FkcheckError
from fkcheck.io.text import operand, terminal_text

if TYPE_CHECKING:
    from collections.abc import Mapping, Sequence

    from fkcheck.api import Outcome
    from fkcheck.backends.base import Backend
    from fkcheck.cli._targets import Target
    from fkcheck.diagnose.failures import BackendDiagnosis
    from fkcheck.engine.plan import Plan
    from fkcheck.engine.results import CheckResult
    from fkcheck.engine.verdict import Kind
    from fkcheck.model.types import Model

from fkcheck.cli.check_output import (
    print_annotations,
    print_diagnose_hint,
    print_diagnoses,
    print_header,
    print_models_table,
    print_plan,
    print_summary,
)

__all__ = [
    "backends_from_args",
    "check_with_progress",
    "jacobian_from_args",
    "model_command",
    "require_from_args",
    "run_many",
    "run_one",
    "write_summaries",
]


def backends_from_args(args: argparse.Namespace, model: Model | None = None) -> list[Backend]:
    """The backends ``--against`` names, with the options.

    Default: the standard set, and the readers of the description formats ``model``
    declares (:func:`fkcheck.backends.registry.default_names`).
    """
    from fkcheck.backends.registry import BackendOptions, default_backends, parse_against
    from fkcheck.cli._arguments import bag_options

    options = BackendOptions(
        timeout_s=args.options.timeout_s,
        frame_from=args.options.frame_from,
        frame_to=args.options.frame_to,
        **bag_options(args),  # a ROS 2 bag's settings given (else the defaults)
    )
    return (
        parse_against(args.against, options) if args.against else default_backends(options, model)
    )


def require_from_args(args: argparse.Namespace) -> tuple[Kind, ...]:
    """``--require`` values, validated (comma-separated and repeatable)."""
    from fkcheck.model.require import parse_require

    values = [v.strip() for item in args.require or () for v in item.split(",") if v.strip()]
    try:
        return parse_require(values, "--require")
    except ValueError as exc:
        raise FkcheckError(str(exc)) from None


def jacobian_from_args(args: argparse.Namespace) -> bool | None:
    """``--jacobian``/``--no-jacobian``; ``--jacobian-reference`` or ``--tol-jacobian`` imply it."""
    if args.jacobian is not None:
        return bool(args.jacobian)
    if args.jacobian_reference is not None or args.tol_jacobian is not None:
        return True
    return None  # the model's [check] jacobian


def check_with_progress(
    args: argparse.Namespace, model: Model, backends: list[Backend], *, diagnose: bool
) -> Outcome:
    """The inputs read, the header, the plan, the core's kernels, then the check with progress.

    The check is prepared first (:func:`~fkcheck.engine.prepare.prepare`: inputs read
    and screened once), so bad input is one line with nothing on stdout; the
    header is then flushed (the first line of a CI log); each backend given
    a subset by the plan is said before it runs; loading the core's kernels, for
    a check large enough to use them, is its own phase
    (:func:`~fkcheck.cli.progress.kernels_phase`). No progress with ``--quiet``.
    """
    from fkcheck.api import check_request
    from fkcheck.cli.progress import check_progress, kernels_phase
    from fkcheck.diagnose.jacobian import explain_sample
    from fkcheck.engine.prepare import prepare
    from fkcheck.engine.request import CheckRequest

    # args.options: the flags over [tool.fkcheck], resolved once (fkcheck.cli.check)
    lint_ignore = tuple(getattr(args, "lint_ignore", ()))
    request = CheckRequest(model, tuple(backends), args.options, lint_ignore, explain_sample)
    prepared = prepare(request)  # bad input: one line, nothing on stdout
    print_header(model, backends, args)
    quiet = getattr(args, "quiet", False)

    def on_plan(plan: Plan) -> None:
        print_plan(plan.notes())
        kernels_phase(
            jacobian=prepared.jacobian is not None, configurations=plan.total, quiet=quiet
        )

    progress = check_progress(
        [b.name for b in backends],
        quiet=quiet,
        interval_s=getattr(args, "progress_interval", PLAIN_INTERVAL_S),
        limit_s=args.options.timeout_s,
    )
    with progress as on_progress:
        return check_request(prepared, diagnose=diagnose, on_progress=on_progress, on_plan=on_plan)


def write_summaries(
    args: argparse.Namespace,
    checks: list[CheckResult],
    step_summary: str | None,
    diagnoses: Mapping[str, Sequence[BackendDiagnosis]] | None = None,
    *,
    file: bool = True,
) -> None:
    """The Markdown summary: to ``--summary`` (with ``file``) and appended to ``step_summary``."""
    from fkcheck.cli._outputs import append_to_step_summary
    from fkcheck.report.markdown import markdown_summary, write_summary

    text = markdown_summary(checks, diagnoses=diagnoses)
    if file and args.summary is not None:
        write_summary(args.summary, text)
    append_to_step_summary(step_summary, text)


def model_command(args: argparse.Namespace, model: str) -> str:
    """The command line that reproduces one model's check of a run over several.

    Every option the check was given (``args.options``: flag, ``[tool.fkcheck]``)
    is written as its flag, in :data:`~fkcheck.model.options.OPTIONS`' order; the
    samples, seed, sampler and time limit always, so that no default is assumed;
    against a recording (``poses:``), a ROS 2 bag's settings given too.
    """
    from fkcheck.model.options import BAG_FLAGS, FLAGS, OPTIONS, CheckOptions

    defaults = CheckOptions()
    argv = ["check", operand(model)]
    for name in OPTIONS:
        value = getattr(args.options, name)
        if value != getattr(defaults, name) or name in _ALWAYS_WRITTEN:
            argv += _flag(FLAGS[name], value)
    for value in args.against or ():
        argv += ["--against", value]
    if any(value.startswith("poses:") for value in args.against or ()):
        for setting, flag in BAG_FLAGS.items():  # a ROS 2 bag's (flag, [tool.fkcheck])
            if (given := getattr(args, setting, None)) is not None:
                argv += [flag, str(given)]
    if getattr(args, "allow_xacro", False):
        argv.append("--allow-xacro")
    return "fkcheck " + shlex.join(argv)


#: Options a reproducing command line always writes, default or not.
_ALWAYS_WRITTEN = frozenset({"samples", "seed", "sampler", "timeout_s"})


def _flag(flag: str, value: object) -> list[str]:
    """One option as its flag's arguments: a switch, ``--no-`` for false, repeated for a list."""
    if value is None:
        return []
    if isinstance(value, bool):
        return [flag if value else "--no-" + flag.removeprefix("--")]
    if isinstance(value, tuple):
        return [arg for item in value for arg in (flag, str(item))]
    return [flag, f"{value:g}" if isinstance(value, float) else str(value)]


def run_many(args: argparse.Namespace, targets: list[Target], out_dir: Path | None) -> int:
    """Several models: each model's files and the index (with ``out_dir``), one summary."""
    import datetime as _dt
    from dataclasses import replace

    from fkcheck.cli._outputs import (
        backend_inputs,
        model_inputs,
        plan,
        step_summary_target,
        writes,
    )
    from fkcheck.cli._targets import unique_stems
    from fkcheck.io.output_paths import check_output_dir
    from fkcheck.report.html import write_index
    from fkcheck.report.index import IndexEntry, build_index_page
    from fkcheck.report.write import write_reports

    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    if out_dir is not None:
        check_output_dir("--out-dir", out_dir)
        unique_stems(targets)
    # File names come from the model file's name, never from text inside it.
    files = {t.stem: (f"{t.stem}.html", f"{t.stem}.json", f"{t.stem}.junit.xml") for t in targets}
    outputs: list[tuple[str, Path | str | None]] = []
    if out_dir is not None:
        outputs += [("--out-dir", out_dir / name) for names in files.values() for name in names]
        outputs.append(("--out-dir", out_dir / "index.html"))
    outputs.append(("--summary", args.summary))
    expand = writes(outputs)
    inputs = [item for target in targets for item in model_inputs(target.model, expand=expand)]
    inputs += [
        item for t in targets for item in backend_inputs(backends_from_args(args, t.model), t.model)
    ]
    inputs.append(("the configuration file", args.config))
    step_summary = step_summary_target(inputs, plan(args, outputs, inputs))
    entries: list[IndexEntry] = []
    checks: list[CheckResult] = []
    diagnoses: dict[str, Sequence[BackendDiagnosis]] = {}
    each: list[Sequence[BackendDiagnosis]] = []  # per target, for the terminal
    # The diagnosis (about a second per disagreement) runs for a failing model: its
    # one line is printed, and the reports, summaries and annotations show it.
    diagnose = args.diagnose
    for number, target in enumerate(targets, start=1):
        for warning in target.model.warnings:
            print(f"fkcheck: warning: {target.stem}: {terminal_text(warning)}", file=sys.stderr)
        outcome = check_with_progress(
            args, target.model, backends_from_args(args, target.model), diagnose=diagnose
        )
        check = replace(outcome.check, command=model_command(args, target.arg), config=args.config)
        if out_dir is not None:
            html, json, junit = (out_dir / name for name in files[target.stem])
            write_reports(check, outcome.diagnoses, html=html, json=json, junit=junit)
            entries.append(IndexEntry(check, *files[target.stem]))
        checks.append(check)
        diagnoses[check.model.name] = outcome.diagnoses
        each.append(outcome.diagnoses)
        print_annotations(check, outcome.diagnoses)
        print(
            f"fkcheck: [{number}/{len(targets)}] {terminal_text(target.arg)}: {check.verdict} "
            f"({check.duration_s:.1f} s)",
            flush=True,
        )
    if out_dir is not None:
        command = "fkcheck " + shlex.join(getattr(args, "argv", []))
        page = build_index_page(entries, command=command, created=created)
        write_index(page, out_dir / "index.html")
    write_summaries(args, checks, step_summary, diagnoses)
    labelled = [(t.arg, c) for t, c in zip(targets, checks, strict=True)]
    print_models_table(labelled, each)
    return _print_tally(labelled, out_dir)


#: ``--all``'s evidence lines: a table status, what it means, and whether it is said at 0.
_TALLY = (
    ("verified", "table verified independently", True),
    ("partly-verified", "table partly verified (numbers the frame pair cannot verify)", False),
    ("failed", "table FAILED against independent evidence", False),
    ("not-checked", "implementation only, table not checked", True),
    (
        "expected-failure",
        "table differs from its description (URDF, MJCF) as recorded "
        "(expected failure, not verified)",
        False,
    ),
)


def _print_tally(labelled: list[tuple[str, CheckResult]], out_dir: Path | None) -> int:
    """The last lines of ``--all``: how many pass, and what each table's evidence is."""
    failed = [label for label, c in labelled if c.verdict != "pass"]
    where = f"reports in {out_dir}/ (index.html)" if out_dir is not None else "no reports written"
    print(f"fkcheck: {len(labelled) - len(failed)} of {len(labelled)} models pass; {where}")
    for status, what, always in _TALLY:
        found = [label for label, c in labelled if c.evidence.table.status == status]
        if found:
            print(f"fkcheck: {what}: {len(found)} ({terminal_text(', '.join(found))})")
        elif always:
            print(f"fkcheck: {what}: 0")
    return 0 if not failed else 1


def run_one(args: argparse.Namespace, target: Target) -> int:
    """One model: its table, and the files asked for."""
    from dataclasses import replace

    from fkcheck.cli._outputs import (
        backend_inputs,
        model_inputs,
        plan,
        step_summary_target,
        writes,
    )
    from fkcheck.report.write import write_reports

    model = target.model
    for warning in model.warnings:
        print(f"fkcheck: warning: {terminal_text(warning)}", file=sys.stderr)
    backends = backends_from_args(args, model)
    outputs = [("--json", args.json), ("--junit", args.junit), ("--html", args.html),
               ("--summary", args.summary)]  # fmt: skip
    inputs = [*model_inputs(model, expand=writes(outputs)), *backend_inputs(backends, model)]
    inputs.append(("the configuration file", args.config))
    step_summary = step_summary_target(inputs, plan(args, outputs, inputs))
    # The diagnosis (about a second per disagreeing backend) runs for a failing check:
    # its one line is printed, and the reports show it.
    outcome = check_with_progress(args, model, backends, diagnose=args.diagnose)
    argv = getattr(args, "argv", [])
    check = replace(outcome.check, command="fkcheck " + shlex.join(argv), config=args.config)
    # Files first: a closed or full stdout must not cost the run its reports.
    # The same function as fkcheck.write_report: the same files, byte for byte.
    write_reports(check, outcome.diagnoses, json=args.json, junit=args.junit, html=args.html,
                  summary=args.summary)  # fmt: skip
    write_summaries(args, [check], step_summary, {check.model.name: outcome.diagnoses}, file=False)
    print_summary(check)
    print_diagnoses(outcome.diagnoses)
    print_annotations(check, outcome.diagnoses)
    print_diagnose_hint(target.arg, check, backends)
    return 0 if check.verdict == "pass" else 1
