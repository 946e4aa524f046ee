"""``fkcheck check``: compare the in-house core with reference backends.

``fkcheck check MODEL`` checks one model and writes whichever of ``--json``,
``--junit``, ``--html`` and ``--summary`` it is given. ``fkcheck check --all``
checks every bundled model and writes, into ``--out-dir`` (default
``reports/``), each model's ``<model>.json``, ``<model>.html`` and
``<model>.junit.xml`` plus ``index.html``, the dashboard linking them. Either
way, when the environment variable ``GITHUB_STEP_SUMMARY`` names a file (as on
GitHub Actions), the Markdown summary is appended to it — if it is a regular
file, or a new one in an existing directory, and neither an input nor an output
of the run; otherwise a warning says why and the check goes on with its own
exit code (the CI page's file is not the check's business). Every output path
is checked before the check runs (:mod:`fkcheck.io.output_paths`): a path
that is an input, shared by two outputs, not a regular file, or in a directory
that cannot take it is bad input (exit 2). The HTML report of a
failing check has a Diagnosis section (``fkcheck diagnose`` run against the
disagreeing backends) unless ``--no-diagnose`` is given; the JSON is the same
with or without it. The diagnosis runs whenever a report shows it: ``--html``,
``--junit``, ``--summary``, ``$GITHUB_STEP_SUMMARY``, or the annotations —
with ``GITHUB_ACTIONS=true`` each failure is also printed as an ``::error``
line at the model file (:mod:`fkcheck.report.annotations`). On a terminal the
header prints before the backends run; their progress goes to stderr
(:mod:`fkcheck.cli.progress`; ``--quiet`` turns it off).
"""

from __future__ import annotations

import argparse
import math
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fkcheck.cli.progress import PLAIN_INTERVAL_S
from fkcheck.errors import FkcheckError
from fkcheck.io.format import format_angle_console, format_length_console
from fkcheck.io.text import terminal_markup, terminal_text

if TYPE_CHECKING:
    from collections.abc import Mapping, Sequence

    from fkcheck.api import Outcome
    from fkcheck.backends.base import Backend
    from fkcheck.diagnose.failures import BackendDiagnosis
    from fkcheck.engine.results import BackendResult, CheckResult
    from fkcheck.engine.verdict import Kind
    from fkcheck.model.types import Model

__all__ = ["DEFAULT_OUT_DIR", "add_parser", "header", "print_header", "print_summary", "run"]

#: Where ``--all`` writes its reports unless ``--out-dir`` says otherwise.
DEFAULT_OUT_DIR = Path("reports")


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "check",
        help="cross-check the in-house DH core against reference libraries",
        description="Compare from_T_to, pose by pose, between the in-house DH core and each "
        "reference backend. Exit 0: every backend that ran agrees; 1: a backend disagrees "
        "or errors, or none ran; 2: bad input.",
    )
    p.add_argument(
        "model",
        metavar="MODEL",
        nargs="?",
        help="bundled model name (ur5) or a .toml/.csv file; omit with --all",
    )
    p.add_argument(
        "--all",
        action="store_true",
        help="check every bundled model; write <model>.json/.html/.junit.xml and index.html "
        "into --out-dir",
    )
    p.add_argument(
        "--out-dir",
        type=Path,
        metavar="DIR",
        help=f"with --all: where to write the reports (default {DEFAULT_OUT_DIR}/)",
    )
    p.add_argument(
        "--against",
        action="append",
        metavar="LIST",
        help="backends, comma-separated or repeated: rtb-dh, pinocchio-dh, pinocchio-urdf, "
        "yourdfpy-urdf, rtb-urdf (the default set), rtb-model:NAME, poses:FILE.csv (measured "
        "poses: the check runs at their configurations), cmd:PROGRAM, module:function",
    )
    p.add_argument(
        "--require",
        action="append",
        metavar="KIND",
        help="evidence that must be verified, else the verdict is 'unverified' (exit 1): "
        "'table' (checked against something independent of the table: a URDF, measured "
        "poses, a published table) or 'implementation'; comma-separated or repeated; adds "
        "to the model's [check] require",
    )
    p.add_argument("--samples", type=int, default=1000, help="random samples (default 1000)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random samples (default 0)")
    p.add_argument("--sampler", choices=("sobol", "uniform"), default="sobol")
    p.add_argument("--from", dest="frame_from", metavar="FRAME", help="frame the pose is in")
    p.add_argument("--to", dest="frame_to", metavar="FRAME", help="frame whose pose is compared")
    p.add_argument("--tol-pos", type=float, metavar="M", help="position tolerance, metres")
    p.add_argument("--tol-rot", type=float, metavar="RAD", help="rotation tolerance, radians")
    p.add_argument("--timeout", type=float, default=120.0, metavar="S",
                   help="time limit per backend, seconds (default 120)")  # fmt: skip
    p.add_argument("--json", type=Path, metavar="PATH", help="write the JSON result here")
    p.add_argument("--junit", type=Path, metavar="PATH", help="write JUnit XML here")
    p.add_argument("--html", type=Path, metavar="PATH", help="write the HTML report here")
    p.add_argument(
        "--summary",
        type=Path,
        metavar="PATH",
        help="write a Markdown summary here (also appended to $GITHUB_STEP_SUMMARY when set)",
    )
    p.add_argument(
        "--no-diagnose",
        dest="diagnose",
        action="store_false",
        help="HTML report of a failing check: leave out the Diagnosis section (it runs "
        "fkcheck diagnose against each distinct disagreeing backend, about a second each)",
    )
    p.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        help="no progress on stderr (the result table and verdict still print)",
    )
    p.add_argument(
        "--progress-interval",
        type=float,
        default=PLAIN_INTERVAL_S,
        metavar="S",
        help="when stderr is not a terminal (a CI log): seconds between the plain progress "
        f"lines of each running backend (default {PLAIN_INTERVAL_S:g})",
    )
    p.set_defaults(run=run)


_STYLE = {"pass": "green", "fail": "bold red", "error": "bold red", "skipped": "yellow"}


def _worst_q(result: BackendResult, check: CheckResult) -> str:
    if result.worst_index is None or result.status != "fail":
        return ""
    q = check.q[result.worst_index]
    parts = [
        f"{math.degrees(v):.1f}°" if j.type == "revolute" else f"{v:.3f} m"
        for v, j in zip(q, check.model.joints, strict=True)
    ]
    return "[" + ", ".join(parts) + "]"


def header(
    model: Model,
    backends: Sequence[Backend],
    args: argparse.Namespace,
) -> str:
    """The line printed before the backends run: what is checked, how, against what.

    Text from input is escaped for rich (:func:`~fkcheck.io.text.terminal_markup`).
    """
    from fkcheck.backends.base import FixedConfigurations

    frame_from = args.frame_from or model.check.frame_from
    frame_to = args.frame_to or model.check.frame_to
    tol_pos = args.tol_pos or model.check.tol_pos_m
    tol_rot = args.tol_rot or model.check.tol_rot_rad
    if any(isinstance(b, FixedConfigurations) for b in backends):
        where = "at the measured poses' configurations"
    else:
        where = f"{args.samples} {args.sampler} samples (seed {args.seed})"
    names = ", ".join(b.name for b in backends) or "no backend"
    return terminal_markup(
        f"fkcheck {model.name}: {frame_from} → {frame_to}, {where}, tolerance {tol_pos:g} m / "
        f"{tol_rot:g} rad, against {names}"
    )


def print_header(model: Model, backends: Sequence[Backend], args: argparse.Namespace) -> None:
    """On a terminal, print :func:`header` at the start of a check, before any backend runs.

    Not in a pipe or a log: there stdout carries the result only (bad input
    found while the check starts leaves it empty; the description then opens
    the result table, :func:`print_summary`), and the progress lines on stderr
    say what runs.
    """
    from fkcheck.cli._console import console, is_terminal

    if is_terminal():
        console(highlight=False).print(header(model, backends, args))


def print_summary(check: CheckResult, *, title: bool | None = None) -> None:
    """The terminal table and verdict line.

    Args:
        check: The finished check.
        title: Open with the check's full description (model, frames,
            configurations, tolerance); without it (the header was printed at
            the start) the table opens with the number of configurations only.
            Default: when stdout is no terminal (see :func:`print_header`).
    """
    from rich.table import Table

    from fkcheck.cli._console import console as make_console
    from fkcheck.cli._console import is_terminal
    from fkcheck.engine.verdict import evidence_sentences, headline

    console = make_console(highlight=False)
    described = (
        f"fkcheck {terminal_markup(check.model.name)}: {terminal_markup(check.frame_from)} → "
        f"{terminal_markup(check.frame_to)}, "
        f"{check.q.shape[0]} configurations ({check.samples} {check.sampler} samples, "
        f"seed {check.seed}), tolerance {check.tol_pos_m:g} m / {check.tol_rot_rad:g} rad"
    )
    if title is None:
        title = not is_terminal()
    if title:
        console.print(described)
    else:
        console.print(f"{check.q.shape[0]} configurations compared")
    table = Table()
    for column in (
        "backend",
        "evidence",
        "status",
        "max position error",
        "max rotation error",
        "worst q",
        "time",
    ):
        # Backend names and statuses never wrap; long messages fold.
        table.add_column(
            column, overflow="fold", no_wrap=column in ("backend", "evidence", "status")
        )
    table.add_row("fkcheck-dh", "", "reference", "", "", "", "")
    for r in check.backends:
        if r.ran:
            table.add_row(
                terminal_markup(r.name), r.evidence, f"[{_STYLE[r.status]}]{r.status}[/]",
                format_length_console(r.max_position_error_m),
                format_angle_console(r.max_rotation_error_rad),
                terminal_markup(_worst_q(r, check)), f"{r.duration_s:.2f} s",
            )  # fmt: skip
        else:
            table.add_row(
                terminal_markup(r.name), r.evidence, f"[{_STYLE[r.status]}]{r.status}[/]",
                terminal_markup(r.message), "", "", "",
            )  # fmt: skip
    console.print(table)
    for r in check.backends:
        if r.status == "fail":
            name, message = terminal_markup(r.name), terminal_markup(r.message)
            console.print(f"[bold red]{name}[/]: {message}")
    evidence = check.evidence
    implementation, table_text = evidence_sentences(evidence)
    table_style = {"verified": "green", "failed": "bold red", "not-checked": "bold yellow"}
    imp_style = table_style[evidence.implementation.status]
    tab_style = table_style[evidence.table.status]
    console.print(f"evidence: [{imp_style}]{terminal_markup(implementation)}[/]")
    console.print(f"          [{tab_style}]{terminal_markup(table_text)}[/]")
    line = headline(check.verdict, evidence, len(check.ran))
    style = "bold green" if check.verdict == "pass" else "bold red"
    if check.verdict == "pass" and evidence.table.status != "verified":
        style = "bold yellow"
    answered = len(check.ran)
    count = f" ({answered} backend(s) answered)" if answered else ""
    console.print(f"[{style}]verdict: {terminal_markup(line)}[/]{count}")


def _validate(args: argparse.Namespace) -> None:
    from fkcheck.backends.registry import MAX_TIMEOUT_S
    from fkcheck.errors import JointInputError
    from fkcheck.model.sampling import check_sampling_options

    check_sampling_options(args.samples, args.seed)
    for flag, value in (("--tol-pos", args.tol_pos), ("--tol-rot", args.tol_rot),
                        ("--timeout", args.timeout)):  # fmt: skip
        if value is not None and not (math.isfinite(value) and value > 0):
            raise JointInputError(f"{flag} must be a positive number, got {value}")
    if args.timeout > MAX_TIMEOUT_S:
        raise JointInputError(
            f"--timeout must be at most {MAX_TIMEOUT_S:g} s, got {args.timeout:g}"
        )
    if args.all:
        if args.model is not None:
            raise FkcheckError(f"--all checks every bundled model: drop MODEL ({args.model!r})")
        for flag, value in (
            ("--json", args.json),
            ("--junit", args.junit),
            ("--html", args.html),
            ("--from", args.frame_from),
            ("--to", args.frame_to),
        ):
            if value is not None:
                raise FkcheckError(
                    f"{flag} does not go with --all (each model's files go to --out-dir; "
                    "frames are per model)"
                )
    else:
        if args.model is None:
            raise FkcheckError("give a MODEL (e.g. ur5) or --all")
        if args.out_dir is not None:
            raise FkcheckError("--out-dir goes with --all; for one model use --json/--html/--junit")


def _backends(args: argparse.Namespace) -> list[Backend]:
    from fkcheck.backends.registry import BackendOptions, default_backends, parse_against

    options = BackendOptions(timeout_s=args.timeout)
    return parse_against(args.against, options) if args.against else default_backends(options)


def _require(args: argparse.Namespace) -> tuple[Kind, ...]:
    """``--require`` values, validated (comma-separated and repeatable)."""
    from fkcheck.model.require import parse_require

    values = [v.strip() for item in args.require or () for v in item.split(",") if v.strip()]
    try:
        return parse_require(values, "--require")
    except ValueError as exc:
        raise FkcheckError(str(exc)) from None


def _check(
    args: argparse.Namespace, model: Model, backends: list[Backend], *, diagnose: bool
) -> Outcome:
    """The header, then the check with its progress on stderr (none with ``--quiet``)."""
    from fkcheck.api import check
    from fkcheck.cli.progress import check_progress

    print_header(model, backends, args)
    progress = check_progress(
        [b.name for b in backends],
        quiet=getattr(args, "quiet", False),
        interval_s=getattr(args, "progress_interval", PLAIN_INTERVAL_S),
    )
    with progress as on_progress:
        return check(
            model,
            backends,
            samples=args.samples,
            seed=args.seed,
            sampler=args.sampler,
            frame_from=args.frame_from,
            frame_to=args.frame_to,
            tol_pos_m=args.tol_pos,
            tol_rot_rad=args.tol_rot,
            timeout_s=args.timeout,
            require=_require(args),
            diagnose=diagnose,
            on_progress=on_progress,
        )


def _summaries(
    args: argparse.Namespace,
    checks: list[CheckResult],
    step_summary: str | None,
    diagnoses: Mapping[str, Sequence[BackendDiagnosis]] | None = None,
) -> None:
    """The Markdown summary: to ``--summary`` and appended to ``step_summary`` when given."""
    from fkcheck.cli._outputs import append_to_step_summary
    from fkcheck.report.markdown import markdown_summary, write_summary

    text = markdown_summary(checks, diagnoses=diagnoses)
    if args.summary is not None:
        write_summary(args.summary, text)
    append_to_step_summary(step_summary, text)


def _model_command(args: argparse.Namespace, model: str) -> str:
    """The command line that reproduces one model's check of an ``--all`` run."""
    argv = [
        "check",
        model,
        "--samples",
        str(args.samples),
        "--seed",
        str(args.seed),
        "--sampler",
        args.sampler,
        "--timeout",
        f"{args.timeout:g}",
    ]
    for value in args.against or ():
        argv += ["--against", value]
    if args.tol_pos is not None:
        argv += ["--tol-pos", f"{args.tol_pos:g}"]
    if args.tol_rot is not None:
        argv += ["--tol-rot", f"{args.tol_rot:g}"]
    for value in args.require or ():
        argv += ["--require", value]
    return "fkcheck " + shlex.join(argv)


def _print_diagnose_hint(model_arg: str, check: CheckResult) -> None:
    """Offer ``fkcheck diagnose`` for the first backend that disagrees."""
    failed = [r for r in check.backends if r.status == "fail"]
    if failed:
        argv = ["diagnose", model_arg, "--against", failed[0].name, "--from", check.frame_from,
                "--to", check.frame_to]  # fmt: skip
        print(f"hint: explain it: fkcheck {terminal_text(shlex.join(argv))}")


def _annotate() -> bool:
    """Whether to print GitHub annotations (``GITHUB_ACTIONS=true``)."""
    from fkcheck.report.annotations import in_github_actions

    return in_github_actions()


def _print_annotations(check: CheckResult, diagnoses: Sequence[BackendDiagnosis]) -> None:
    """On GitHub Actions: an ``::error`` line per failure, at the model file (and line)."""
    from fkcheck.report.annotations import github_annotations

    if not _annotate():
        return
    source = None
    if check.model.path is not None and check.model.path.suffix == ".toml":
        try:
            source = check.model.path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            source = None  # the file-level annotation still says what failed
    for line in github_annotations(check, diagnoses, source=source):
        print(line)


def _run_all(args: argparse.Namespace) -> int:
    """``--all``: every bundled model, each model's files, the index and the summary."""
    import datetime as _dt
    from dataclasses import replace

    from fkcheck.cli._outputs import backend_inputs, model_inputs, plan, step_summary_target
    from fkcheck.io.output_paths import check_output_dir
    from fkcheck.model.read import bundled_model_paths, load_model
    from fkcheck.report.html import write_html, write_index
    from fkcheck.report.index import IndexEntry, build_index_page
    from fkcheck.report.json_report import write_json
    from fkcheck.report.junit import write_junit

    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    out_dir: Path = args.out_dir or DEFAULT_OUT_DIR
    check_output_dir("--out-dir", out_dir)
    models = {stem: load_model(path) for stem, path in bundled_model_paths().items()}
    inputs = [item for model in models.values() for item in model_inputs(model)]
    inputs += backend_inputs(_backends(args))
    # File names come from the bundled file's name, never from text inside it.
    files = {stem: (f"{stem}.html", f"{stem}.json", f"{stem}.junit.xml") for stem in models}
    outputs = [("--out-dir", out_dir / name) for names in files.values() for name in names]
    output_plan = plan(
        args, [*outputs, ("--out-dir", out_dir / "index.html"), ("--summary", args.summary)], inputs
    )
    step_summary = step_summary_target(inputs, output_plan)
    entries: list[IndexEntry] = []
    checks: list[CheckResult] = []
    for stem, model in models.items():
        for warning in model.warnings:
            print(f"fkcheck: warning: {stem}: {terminal_text(warning)}", file=sys.stderr)
        outcome = _check(args, model, _backends(args), diagnose=args.diagnose)
        check = replace(outcome.check, command=_model_command(args, stem))
        names = files[stem]
        write_html(check, out_dir / names[0], diagnoses=outcome.diagnoses)
        write_json(check, out_dir / names[1])
        write_junit(check, out_dir / names[2])
        print_summary(check)
        entries.append(IndexEntry(check, *names))
        checks.append(check)
    command = "fkcheck " + shlex.join(getattr(args, "argv", []))
    write_index(build_index_page(entries, command=command, created=created), out_dir / "index.html")
    _summaries(args, checks, step_summary)
    failed = [c.model.name for c in checks if c.verdict != "pass"]
    verified = [c.model.name for c in checks if c.evidence.table.status == "verified"]
    unchecked = [c.model.name for c in checks if c.evidence.table.status == "not-checked"]
    print(
        f"fkcheck: {len(checks) - len(failed)} of {len(checks)} models pass; reports in "
        f"{out_dir}/ (index.html)"
    )
    print(
        f"fkcheck: table verified independently: {len(verified)} "
        f"({terminal_text(', '.join(verified))})"
    )
    print(
        f"fkcheck: implementation only, table not checked: {len(unchecked)} "
        f"({terminal_text(', '.join(unchecked))})"
    )
    return 0 if not failed else 1


def run(args: argparse.Namespace) -> int:
    """Run the check, print, write the requested files."""
    from dataclasses import replace

    from fkcheck.cli._outputs import backend_inputs, model_inputs, plan, step_summary_target
    from fkcheck.model.read import load_model
    from fkcheck.report.html import write_html
    from fkcheck.report.json_report import write_json
    from fkcheck.report.junit import write_junit

    _validate(args)
    _require(args)  # bad --require is exit 2 before anything runs
    if args.all:
        return _run_all(args)
    model = load_model(args.model)
    for warning in model.warnings:
        print(f"fkcheck: warning: {terminal_text(warning)}", file=sys.stderr)
    backends = _backends(args)
    inputs = [*model_inputs(model), *backend_inputs(backends)]
    outputs = [("--json", args.json), ("--junit", args.junit), ("--html", args.html),
               ("--summary", args.summary)]  # fmt: skip
    step_summary = step_summary_target(inputs, plan(args, outputs, inputs))
    # The diagnosis (about a second per disagreeing backend) is for the reports that show it.
    cause_shown = (args.html, args.junit, args.summary, step_summary) != (None,) * 4
    outcome = _check(args, model, backends, diagnose=args.diagnose and (cause_shown or _annotate()))
    check = replace(outcome.check, command="fkcheck " + shlex.join(getattr(args, "argv", [])))
    # Files first: a closed or full stdout must not cost the run its reports.
    if args.json is not None:
        write_json(check, args.json)
    if args.junit is not None:
        write_junit(check, args.junit, diagnoses=outcome.diagnoses)
    if args.html is not None:
        write_html(check, args.html, diagnoses=outcome.diagnoses)
    _summaries(args, [check], step_summary, {check.model.name: outcome.diagnoses})
    print_summary(check)
    _print_annotations(check, outcome.diagnoses)
    _print_diagnose_hint(args.model, check)
    return 0 if check.verdict == "pass" else 1
