"""``fkcheck check``: compare the in-house core with reference backends.

``fkcheck check MODEL`` checks one model and writes whichever of ``--json``,
``--junit``, ``--html`` and ``--summary`` it is given. ``fkcheck check A B DIR``
checks several (bundled names, ``.toml``/``.csv`` files, directories of them;
globs are the shell's business) and ``fkcheck check --all`` every bundled model:
one terminal table with a row per model, one exit code, and with ``--out-dir``
each model's ``<stem>.json``, ``<stem>.html`` and ``<stem>.junit.xml`` plus
``index.html``, the dashboard linking them (``--all`` writes into ``reports/``
unless ``--out-dir`` says otherwise). File names come from each model file's
stem; two models with one stem are refused (exit 2) rather than one
overwriting the other. With no MODEL and no ``--all``, the models listed in
``[tool.fkcheck] models`` of the nearest ``pyproject.toml`` are checked; that
table also gives defaults for ``--samples``, ``--seed``, ``--sampler``,
``--timeout``, ``--against``, ``--require``, ``--tol-pos`` and ``--tol-rot``
(a flag on the command line wins). Every model is read, and its URDF screened,
before any check runs: bad input in any of them is one line and exit 2.

Either way, when the environment variable ``GITHUB_STEP_SUMMARY`` names a file (as on
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
    from fkcheck.cli._targets import Target
    from fkcheck.diagnose.failures import BackendDiagnosis
    from fkcheck.engine.results import BackendResult, CheckResult
    from fkcheck.engine.verdict import Kind
    from fkcheck.model.project import ProjectConfig
    from fkcheck.model.types import Model

__all__ = ["DEFAULT_OUT_DIR", "add_parser", "header", "print_header", "print_summary", "run"]

#: Where ``--all`` writes its reports unless ``--out-dir`` says otherwise.
DEFAULT_OUT_DIR = Path("reports")

#: Option values when neither the command line nor ``[tool.fkcheck]`` gives one.
DEFAULTS: dict[str, Any] = {"samples": 1000, "seed": 0, "sampler": "sobol", "timeout": 120.0}


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "check",
        help="cross-check the in-house DH core against reference libraries",
        description="Compare from_T_to, pose by pose, between the in-house DH core and each "
        "reference backend, for one model or many (one table, one exit code). "
        "[tool.fkcheck] in the nearest pyproject.toml gives the models when none is named, "
        "and defaults for the options; a flag given here wins. Exit 0: every backend that "
        "ran agrees for every model; 1: a backend disagrees or errors, none ran, or "
        "required evidence is missing; 2: bad input (in any model: nothing runs).",
    )
    p.add_argument(
        "models",
        metavar="MODEL",
        nargs="*",
        help="bundled model names (ur5), .toml/.csv files or directories of them; none: "
        "[tool.fkcheck] models of the nearest pyproject.toml, or --all",
    )
    p.add_argument(
        "--all",
        action="store_true",
        help="check every bundled model; write <model>.json/.html/.junit.xml and index.html "
        f"into --out-dir (default {DEFAULT_OUT_DIR}/)",
    )
    p.add_argument(
        "--out-dir",
        type=Path,
        metavar="DIR",
        help="write each model's <stem>.json/.html/.junit.xml and index.html here "
        f"(--all: default {DEFAULT_OUT_DIR}/)",
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
    p.add_argument("--samples", type=int, help="random samples (default 1000)")
    p.add_argument("--seed", type=int, help="seed of the random samples (default 0)")
    p.add_argument("--sampler", choices=("sobol", "uniform"), help="(default sobol)")
    p.add_argument("--from", dest="frame_from", metavar="FRAME", help="frame the pose is in")
    p.add_argument("--to", dest="frame_to", metavar="FRAME", help="frame whose pose is compared")
    p.add_argument("--tol-pos", type=float, metavar="M", help="position tolerance, metres")
    p.add_argument("--tol-rot", type=float, metavar="RAD", help="rotation tolerance, radians")
    p.add_argument("--timeout", type=float, metavar="S",
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


def _apply_project(args: argparse.Namespace, project: ProjectConfig | None) -> None:
    """Fill the options not given on the command line from ``[tool.fkcheck]``, then defaults."""
    from_project: dict[str, Any] = {}
    if project is not None:
        from_project = {
            "samples": project.samples,
            "seed": project.seed,
            "sampler": project.sampler,
            "timeout": project.timeout,
            "tol_pos": project.tol_pos_m,
            "tol_rot": project.tol_rot_rad,
            "against": list(project.against) if project.against is not None else None,
            "require": list(project.require) or None,
        }
    for key, value in from_project.items():
        if getattr(args, key) is None and value is not None:
            setattr(args, key, value)
    for key, value in DEFAULTS.items():
        if getattr(args, key) is None:
            setattr(args, key, value)


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
    if args.all and args.models:
        raise FkcheckError(
            f"--all checks every bundled model: drop MODEL ({' '.join(args.models)!r})"
        )
    if args.all or args.out_dir is not None:
        per_model = "--all" if args.all else "--out-dir"
        for flag, value in (("--json", args.json), ("--junit", args.junit),
                            ("--html", args.html)):  # fmt: skip
            if value is not None:
                raise FkcheckError(
                    f"{flag} does not go with {per_model} (each model's files go to --out-dir)"
                )
    if args.all:
        for flag, value in (("--from", args.frame_from), ("--to", args.frame_to)):
            if value is not None:
                raise FkcheckError(f"{flag} does not go with --all (frames are per model)")


def _validate_many(args: argparse.Namespace) -> None:
    """Options that name one model's files do not go with several models."""
    for flag, value in (("--json", args.json), ("--junit", args.junit), ("--html", args.html)):
        if value is not None:
            raise FkcheckError(
                f"{flag} writes one model's file: with several models use --out-dir DIR "
                "(each model's .json/.html/.junit.xml and index.html)"
            )


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
    """The command line that reproduces one model's check of a run over several."""
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


def print_models_table(checks: list[tuple[str, CheckResult]]) -> None:
    """The terminal table of a run over several models: one row per model.

    Args:
        checks: Each model's label (its file as given, or the bundled name) and its check.
    """
    from rich.table import Table

    from fkcheck.cli._console import console as make_console

    console = make_console(highlight=False)
    table = Table(title=f"fkcheck: {len(checks)} models", title_justify="left")
    for column in ("model", "verdict", "backends", "max position error", "max rotation error",
                   "table"):  # fmt: skip
        table.add_column(column, overflow="fold", no_wrap=column in ("model", "verdict"))
    for label, check in checks:
        counts: dict[str, int] = {}
        for r in check.backends:
            counts[r.status] = counts.get(r.status, 0) + 1
        pos = [r.max_position_error_m for r in check.ran if r.max_position_error_m is not None]
        rot = [r.max_rotation_error_rad for r in check.ran if r.max_rotation_error_rad is not None]
        style = "bold green" if check.verdict == "pass" else "bold red"
        table.add_row(
            terminal_markup(label),
            f"[{style}]{check.verdict}[/]",
            ", ".join(f"{n} {status}" for status, n in counts.items()),
            format_length_console(max(pos)) if pos else "",
            format_angle_console(max(rot)) if rot else "",
            check.evidence.table.status,
        )
    console.print(table)
    for label, check in checks:
        for r in check.backends:
            if r.status in ("fail", "error"):
                name, message = terminal_markup(label), terminal_markup(r.message)
                console.print(f"[bold red]{name}[/]: {terminal_markup(r.name)}: {message}")


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


def _run_many(args: argparse.Namespace, targets: list[Target], out_dir: Path | None) -> int:
    """Several models: each model's files and the index (with ``out_dir``), one summary."""
    import datetime as _dt
    from dataclasses import replace

    from fkcheck.cli._outputs import backend_inputs, model_inputs, plan, step_summary_target
    from fkcheck.cli._targets import unique_stems
    from fkcheck.io.output_paths import check_output_dir
    from fkcheck.report.html import write_html, write_index
    from fkcheck.report.index import IndexEntry, build_index_page
    from fkcheck.report.json_report import write_json
    from fkcheck.report.junit import write_junit

    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    if out_dir is not None:
        check_output_dir("--out-dir", out_dir)
        unique_stems(targets)
    inputs = [item for target in targets for item in model_inputs(target.model)]
    inputs += backend_inputs(_backends(args))
    # File names come from the model file's name, never from text inside it.
    files = {t.stem: (f"{t.stem}.html", f"{t.stem}.json", f"{t.stem}.junit.xml") for t in targets}
    outputs: list[tuple[str, Path | str | None]] = []
    if out_dir is not None:
        outputs += [("--out-dir", out_dir / name) for names in files.values() for name in names]
        outputs.append(("--out-dir", out_dir / "index.html"))
    outputs.append(("--summary", args.summary))
    step_summary = step_summary_target(inputs, plan(args, outputs, inputs))
    entries: list[IndexEntry] = []
    checks: list[CheckResult] = []
    diagnoses: dict[str, Sequence[BackendDiagnosis]] = {}
    # The diagnosis (about a second per disagreement) is for the reports, summaries
    # and annotations that show it.
    wanted = out_dir is not None or args.summary is not None or step_summary is not None
    diagnose = args.diagnose and (wanted or _annotate())
    for number, target in enumerate(targets, start=1):
        for warning in target.model.warnings:
            print(f"fkcheck: warning: {target.stem}: {terminal_text(warning)}", file=sys.stderr)
        outcome = _check(args, target.model, _backends(args), diagnose=diagnose)
        check = replace(outcome.check, command=_model_command(args, target.arg))
        if out_dir is not None:
            names = files[target.stem]
            write_html(check, out_dir / names[0], diagnoses=outcome.diagnoses)
            write_json(check, out_dir / names[1])
            write_junit(check, out_dir / names[2], diagnoses=outcome.diagnoses)
            entries.append(IndexEntry(check, *names))
        checks.append(check)
        diagnoses[check.model.name] = outcome.diagnoses
        _print_annotations(check, outcome.diagnoses)
        print(
            f"fkcheck: [{number}/{len(targets)}] {terminal_text(target.arg)}: {check.verdict} "
            f"({check.duration_s:.1f} s)",
            flush=True,
        )
    if out_dir is not None:
        command = "fkcheck " + shlex.join(getattr(args, "argv", []))
        page = build_index_page(entries, command=command, created=created)
        write_index(page, out_dir / "index.html")
    _summaries(args, checks, step_summary, diagnoses)
    labelled = [(t.arg, c) for t, c in zip(targets, checks, strict=True)]
    print_models_table(labelled)
    failed = [label for label, c in labelled if c.verdict != "pass"]
    verified = [label for label, c in labelled if c.evidence.table.status == "verified"]
    unchecked = [label for label, c in labelled if c.evidence.table.status == "not-checked"]
    where = f"reports in {out_dir}/ (index.html)" if out_dir is not None else "no reports written"
    print(f"fkcheck: {len(checks) - len(failed)} of {len(checks)} models pass; {where}")
    print(
        f"fkcheck: table verified independently: {len(verified)} "
        f"({terminal_text(', '.join(verified))})"
    )
    print(
        f"fkcheck: implementation only, table not checked: {len(unchecked)} "
        f"({terminal_text(', '.join(unchecked))})"
    )
    return 0 if not failed else 1


def _targets(args: argparse.Namespace, project: ProjectConfig | None) -> list[Target]:
    """The models to check: ``--all``'s bundled ones, the arguments, or the project's."""
    from fkcheck.cli._targets import Target, load_targets
    from fkcheck.model.read import bundled_model_paths, load_model

    if args.all:
        bundled = bundled_model_paths().items()
        return [Target(stem, stem, load_model(path)) for stem, path in bundled]
    if not args.models and (project is None or not project.models):
        where = f" (none in {project.path})" if project is not None else ""
        raise FkcheckError(
            "give a MODEL (e.g. ur5) or --all, or list models in [tool.fkcheck] models = "
            f"[...] of pyproject.toml{where}"
        )
    return load_targets(args.models, project)


def run(args: argparse.Namespace) -> int:
    """Run the check, print, write the requested files."""
    from pathlib import Path as _Path

    from fkcheck.cli._targets import project_config

    project = project_config()
    _apply_project(args, project)
    _validate(args)
    _require(args)  # bad --require is exit 2 before anything runs
    targets = _targets(args, project)
    one_file = len(args.models) == 1 and not _Path(args.models[0]).is_dir()
    if args.all or args.out_dir is not None or not one_file or len(targets) != 1:
        _validate_many(args)
        out_dir = args.out_dir or (DEFAULT_OUT_DIR if args.all else None)
        return _run_many(args, targets, out_dir)
    return _run_one(args, targets[0])


def _run_one(args: argparse.Namespace, target: Target) -> int:
    """One model: its table, and the files asked for."""
    from dataclasses import replace

    from fkcheck.cli._outputs import backend_inputs, model_inputs, plan, step_summary_target
    from fkcheck.report.html import write_html
    from fkcheck.report.json_report import write_json
    from fkcheck.report.junit import write_junit

    model = target.model
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
    _print_diagnose_hint(target.arg, check)
    return 0 if check.verdict == "pass" else 1
