"""What ``fkcheck check`` prints: header, tables (one model, many), hints, annotations."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from fkcheck._version import __version__
from fkcheck.io.format import format_angle_console, format_length_console, format_scientific
from fkcheck.io.text import terminal_markup, terminal_text

if TYPE_CHECKING:
    from collections.abc import Sequence

    from fkcheck.backends.base import Backend
    from fkcheck.diagnose.failures import BackendDiagnosis
    from fkcheck.engine.results import CheckResult
    from fkcheck.model.types import Model
    from fkcheck.report.record import CheckRecord

from fkcheck.io.files import InputFileError, read_text

__all__ = [
    "annotate",
    "header",
    "print_annotations",
    "print_diagnose_hint",
    "print_diagnoses",
    "print_header",
    "print_models_table",
    "print_plan",
    "print_summary",
]


_STYLE = {"pass": "green", "fail": "bold red", "error": "bold red", "skipped": "yellow",
          "xfail": "bold yellow", "xpass": "bold red"}  # fmt: skip


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
        f"{tol_rot:g} rad, against {names}{_config(getattr(args, 'config', None))}"
        f"{_VERSION}"
    )


#: The end of a check's first line: the version that ran, where a CI log shows it.
_VERSION = f"; fkcheck {__version__}"


def _config(path: str | None) -> str:
    """``; config: PATH``: the ``pyproject.toml`` that applied (as pytest's ``configfile:``)."""
    from fkcheck.urdf.locate import display_path

    return "" if path is None else f"; config: {display_path(path)}"


def print_header(model: Model, backends: Sequence[Backend], args: argparse.Namespace) -> None:
    """Print :func:`header` at the start of a check, before anything slow, and flush it.

    Flushed at once, also in a pipe or a CI log (where stdout is block-buffered):
    it is the log's first line, before the progress lines on stderr.
    """
    import sys

    from fkcheck.cli._console import console

    console(highlight=False).print(header(model, backends, args))
    sys.stdout.flush()


def print_plan(notes: Sequence[str]) -> None:
    """The check's plan, before any backend runs: each backend given a subset, and why."""
    import sys

    from fkcheck.cli._console import console

    for note in notes:
        console(highlight=False).print(f"fkcheck: plan: {terminal_markup(note)}")
    sys.stdout.flush()


def print_summary(check: CheckResult, *, title: bool = False) -> None:
    """The terminal table and verdict line.

    Args:
        check: The finished check.
        title: Open with the check's full description (model, frames,
            configurations, tolerance); without it (the header was printed at
            the start, :func:`print_header`) the table opens with the number of
            configurations only.
    """
    from fkcheck.cli._console import console as make_console
    from fkcheck.report.record import check_record

    record = check_record(check)
    console = make_console(highlight=False)
    asked = check.options
    described = (
        f"fkcheck {terminal_markup(check.model.name)}: {terminal_markup(check.frame_from)} → "
        f"{terminal_markup(check.frame_to)}, "
        f"{check.q.shape[0]} configurations ({asked.samples} {asked.sampler} samples, "
        f"seed {asked.seed}), tolerance {check.tol_pos_m:g} m / {check.tol_rot_rad:g} rad"
        f"{terminal_markup(_config(check.config))}{_VERSION}"
    )
    if title:
        console.print(described)
    else:
        console.print(f"{check.q.shape[0]} configurations compared")
    # Numbers never wrap (no `6.8e-` / `16 m` at 80 columns): their columns are no_wrap,
    # a backend that did not run says why below the table, and where the terminal is
    # narrower than the table, the evidence column goes (the evidence lines say it).
    table = _backends_table(record, evidence=True)
    if not _fits(console, table):
        table = _backends_table(record, evidence=False)
    console.print(table)
    if check.jacobian is not None:
        _print_jacobians(console, check, record)
    _print_backend_lines(console, record)
    _print_verdict(console, check, record)


def _print_jacobians(console: Any, check: CheckResult, record: CheckRecord) -> None:
    """The Jacobian table (and, where it would not fit, each backend's way as a line)."""
    # As the backends' table: where its text column would break words, it goes, and
    # each backend's way of computing the Jacobian (or why it had none) is a line below.
    jacobian = _jacobian_table(check, record, how=True)
    if not _fits(console, jacobian):
        console.print(_jacobian_table(check, record, how=False))
        for i, (name, how) in enumerate(_jacobian_how(record)):
            lead = "how: " if i == 0 else " " * len("how: ")
            console.print(f"{lead}{terminal_markup(name)}: {terminal_markup(how)}")
    else:
        console.print(jacobian)


def _print_backend_lines(console: Any, record: CheckRecord) -> None:
    """Below the table: a pass's note once, why a backend did not run or failed."""
    notes: dict[str, list[str]] = {}  # a pass's message (a URDF from this table), once each
    for r in record.backends:
        if r.status == "pass" and r.message:
            notes.setdefault(r.message, []).append(r.name)
    for message, names in notes.items():
        console.print(f"[yellow]{terminal_markup(', '.join(names))}[/]: {terminal_markup(message)}")
    for r in record.backends:
        if not r.ran:
            name, message = terminal_markup(r.name), terminal_markup(r.message)
            console.print(f"[{_STYLE[r.status]}]{name}[/] ({r.status}): {message}")
        if r.status in ("fail", "xfail", "xpass"):
            name, message = terminal_markup(r.name), terminal_markup(r.message)
            console.print(f"[{_STYLE[r.status]}]{name}[/]: {message}")
        if r.jacobian is not None and r.jacobian.status == "fail":
            name, message = terminal_markup(r.name), terminal_markup(r.jacobian.message)
            console.print(f"[bold red]{name}[/]: {message}")
            if r.jacobian.diagnosis:
                console.print(f"  diagnosis: {terminal_markup(r.jacobian.diagnosis)}")
                for line in r.jacobian.diagnosis_details:
                    console.print(f"    {terminal_markup(line)}")


def _print_verdict(console: Any, check: CheckResult, record: CheckRecord) -> None:
    """The evidence lines, the numbers' and calibration's lines, and the verdict."""
    implementation, table_text = (e.sentence for e in record.evidence)
    table_style = {"verified": "green", "failed": "bold red", "not-checked": "bold yellow",
                   "expected-failure": "bold yellow", "partly-verified": "bold yellow"}  # fmt: skip
    imp_style = table_style[record.of("implementation").status]
    tab_style = table_style[record.of("table").status]
    console.print(f"evidence: [{imp_style}]{terminal_markup(implementation)}[/]")
    console.print(f"          [{tab_style}]{terminal_markup(table_text)}[/]")
    if record.numbers_line:
        console.print(f"          [{tab_style}]{terminal_markup(record.numbers_line)}[/]")
    if record.calibration_line:
        console.print(f"{terminal_markup(record.calibration_line)}")
    line = record.headline
    style = "bold green" if check.verdict == "pass" else "bold red"
    if check.verdict == "pass" and record.of("table").status != "verified":
        style = "bold yellow"
    answered = record.answered
    count = f" ({answered} backend(s) answered)" if answered else ""
    console.print(f"[{style}]verdict: {terminal_markup(line)}[/]{count}")


def _fits(console: Any, table: Any) -> bool:
    """Whether ``table`` printed on ``console`` stays within its width (rich may overflow it)."""
    import io

    from rich.cells import cell_len
    from rich.console import Console

    out = io.StringIO()
    probe = Console(width=console.width, file=out, color_system=None, emoji=False)
    probe.print(table, crop=False)
    widest = max((cell_len(line) for line in out.getvalue().splitlines()), default=0)
    return bool(widest <= console.width)


def _number_column(table: Any, header: str, values: Sequence[str]) -> None:
    """A column that wraps between words, never inside one (``6.8e-`` / ``16 m``).

    Numbers and names alike (no ``computeFram`` / ``eJacobian``): rich folds a word
    wider than its column; the column's minimum is its longest word (rich keeps it
    when it narrows a table), its maximum its widest value.
    """
    from rich.cells import cell_len

    words = [w for v in [*values, header] for w in v.split()]
    table.add_column(
        header,
        overflow="fold",
        min_width=max((cell_len(w) for w in words), default=1),
        max_width=max((cell_len(v) for v in [*values, *header.split()]), default=1),
    )


def _backends_table(record: CheckRecord, *, evidence: bool) -> Any:
    """One row per backend: status, largest errors, worst q, time (with the evidence column)."""
    from rich.table import Table

    ran = [r for r in record.backends if r.ran]
    position = {r.name: format_length_console(r.max_position_m) for r in ran}
    rotation = {r.name: format_angle_console(r.max_rotation_rad) for r in ran}
    time = {r.name: f"{r.duration_s:.2f} s" for r in ran}
    table = Table()
    for column in ("backend", *(("evidence",) if evidence else ()), "status"):
        table.add_column(column, overflow="fold", no_wrap=True)
    _number_column(table, "max position error", list(position.values()))
    _number_column(table, "max rotation error", list(rotation.values()))
    table.add_column("worst q", overflow="fold")
    _number_column(table, "time", list(time.values()))
    kind: tuple[str, ...] = ("",) if evidence else ()
    table.add_row("fkcheck-dh", *kind, "reference", "", "", "", "")
    for r in record.backends:
        kind = (r.evidence,) if evidence else ()
        status = f"[{_STYLE[r.status]}]{r.label}[/]"
        # A backend on a subset (the check's plan) is named with its count.
        subset = r.subset.removesuffix(" configurations")
        name = terminal_markup(r.name) + (f"\n({subset})" if subset else "")
        if r.ran:
            worst_q = r.worst_q_text if r.status in ("fail", "xfail") else ""
            table.add_row(
                name, *kind, status, position[r.name], rotation[r.name],
                terminal_markup(worst_q), time[r.name],
            )  # fmt: skip
        else:  # why: a line below the table
            table.add_row(name, *kind, status, "", "", "", "")
    return table


def _jacobian_how(record: CheckRecord) -> list[tuple[str, str]]:
    """Each Jacobian backend's method, or why it was not compared (the table's ``how``)."""
    return [
        (r.name if r.jacobian.ran else f"{r.name} ({r.jacobian.status})",
         r.jacobian.method if r.jacobian.ran else r.jacobian.message)
        for r in record.backends
        if r.jacobian is not None
    ]  # fmt: skip


def _jacobian_table(check: CheckResult, record: CheckRecord, *, how: bool) -> Any:
    """The Jacobian comparison, one row per backend (``check --jacobian``).

    With ``how``, a column says how each backend computed its Jacobian (or why it
    has none); without it the caller prints that below the table
    (:func:`_jacobian_how`), for a terminal too narrow for it whole.
    """
    from rich.table import Table

    assert check.jacobian is not None
    table = Table(
        title=f"Jacobian of {terminal_markup(check.frame_to)}, {check.jacobian.reference}, "
        f"tolerance {check.jacobian.tol:g} (m/rad, rad/rad)",
        title_justify="left",
    )
    ran = [r.jacobian for r in record.backends if r.jacobian is not None and r.jacobian.ran]
    for column in ("backend", "status"):
        table.add_column(column, overflow="fold", no_wrap=True)
    linear = [format_scientific(j.max_linear, "m/rad") for j in ran]
    _number_column(table, "max linear diff", linear)
    angular = [format_scientific(j.max_angular, "rad/rad") for j in ran]
    _number_column(table, "max angular diff", angular)
    _number_column(table, "first column", [j.first_label for j in ran])
    hows = [text for _, text in _jacobian_how(record)]
    if how:
        _number_column(table, "how", hows)
    compared = [r for r in record.backends if r.jacobian is not None]
    for r, text in zip(compared, hows, strict=True):
        j = r.jacobian
        assert j is not None
        status = f"[{_STYLE[j.status]}]{j.status}[/]"
        said = (terminal_markup(text),) if how else ()
        if not j.ran:
            table.add_row(terminal_markup(r.name), status, "", "", "", *said)
            continue
        table.add_row(
            terminal_markup(r.name), status, format_scientific(j.max_linear, "m/rad"),
            format_scientific(j.max_angular, "rad/rad"), terminal_markup(j.first_label), *said,
        )  # fmt: skip
    return table


def diagnosis_lines(diagnoses: Sequence[BackendDiagnosis]) -> list[str]:
    """One line per distinct disagreement, the headline the reports carry.

    ``diagnosis (pinocchio-urdf, yourdfpy-urdf): one number differs: a2 (J2)``: the
    most likely explanation's title, or why there is none
    (:func:`fkcheck.report.diagnosis.diagnosis_headline`).
    """
    from fkcheck.report.diagnosis import diagnosis_headline

    lines = []
    for outcome in diagnoses:
        who = ", ".join(terminal_text(n) for n in (outcome.backend, *outcome.also))
        lines.append(f"diagnosis ({who}): {terminal_text(diagnosis_headline(outcome))}")
    return lines


def print_diagnoses(diagnoses: Sequence[BackendDiagnosis], prefix: str = "") -> None:
    """The diagnoses of a failed check in one line each (:func:`diagnosis_lines`)."""
    for line in diagnosis_lines(diagnoses):
        print(f"{prefix}{line}", flush=True)


def print_diagnose_hint(
    model_arg: str, check: CheckResult, backends: Sequence[Backend] = ()
) -> None:
    """Offer ``fkcheck diagnose`` for the first backend that disagrees with the table.

    A reader finding (:mod:`fkcheck.engine.readers`) is the reader's, not the
    table's: no diagnosis of the table's numbers is offered for it, but how to
    record it for the reader's versions: up to the installed release of its
    library (:func:`fkcheck.engine.expected.library_of` of its backend in
    ``backends``; ``4.1.1`` of ``4.1.1rc1``, as a record reads it), ``VERSION``
    when that is not known. The ``fkcheck diagnose`` line is the report's
    (:func:`~fkcheck.diagnose.failures.diagnose_command`, with the model as given):
    the check's seed, tolerances, time limit and ``--bag-*`` settings when not the
    defaults. Not for a table fkcheck derived (``check --source``): there is no
    model file to name.
    """
    from fkcheck.diagnose.failures import bag_arguments, diagnose_command
    from fkcheck.engine.expected import library_of
    from fkcheck.model.version_spec import release_text

    by_name = {b.name: b for b in backends}
    failed = [r for r in check.backends if r.status == "fail" and not r.reader_finding]
    readers = [r.name for r in check.backends if r.status == "fail" and r.reader_finding]
    if readers and not failed:
        library = library_of(by_name[readers[0]]) if readers[0] in by_name else None
        version = (release_text(library[1]) if library is not None else None) or "VERSION"
        print(
            f"hint: a reader's finding, not the table's: record it for the reader's version "
            f'with [[known_difference]] backends = ["{terminal_text(readers[0])}"], '
            f'versions = "<={terminal_text(version)}" (docs/reference/model-file.md)'
        )
    if failed and check.model.derived is None:
        bag = bag_arguments(by_name.get(failed[0].name))
        command = diagnose_command(check, failed[0].name, bag, model_arg)  # the report's line
        print(f"hint: explain it: {terminal_text(command)}")


def print_models_table(
    checks: list[tuple[str, CheckResult]],
    diagnoses: Sequence[Sequence[BackendDiagnosis]] = (),
) -> None:
    """The terminal table of a run over several models: one row per model.

    A model's max errors are the worst of its backends that count for the verdict:
    a recorded expected failure's (``xfail``, its known difference) are left out,
    and a line under the table says so when any row has one. Under it, each failing
    backend's message, and each failing model's diagnosis in one line
    (:func:`diagnosis_lines`).

    Args:
        checks: Each model's label (its file as given, or the bundled name) and its check.
        diagnoses: Each model's diagnoses, aligned with ``checks`` (none: no lines).
    """
    from rich.table import Table

    from fkcheck.cli._console import console as make_console
    from fkcheck.report.record import check_record

    records = [(label, check_record(check)) for label, check in checks]
    console = make_console(highlight=False)
    table = Table(title=f"fkcheck: {len(checks)} models", title_justify="left")
    for column in ("model", "verdict", "backends", "max position error", "max rotation error",
                   "table"):  # fmt: skip
        table.add_column(column, overflow="fold", no_wrap=column in ("model", "verdict"))
    for label, record in records:
        counts: dict[str, int] = {}
        for r in record.backends:
            counts[r.status] = counts.get(r.status, 0) + 1
        counted = [r for r in record.backends if r.status != "xfail"]
        pos = [r.max_position_m for r in counted if r.max_position_m is not None]
        rot = [r.max_rotation_rad for r in counted if r.max_rotation_rad is not None]
        style = "bold green" if record.verdict == "pass" else "bold red"
        table.add_row(
            terminal_markup(label),
            f"[{style}]{record.verdict}[/]",
            ", ".join(f"{n} {status}" for status, n in counts.items()),
            format_length_console(max(pos)) if pos else "",
            format_angle_console(max(rot)) if rot else "",
            record.of("table").status,
        )
    console.print(table)
    if any(r.status == "xfail" for _, record in records for r in record.backends):
        console.print(
            "max errors: of the backends that count for the verdict, not of a recorded "
            "expected failure (a row's xfail: its own check and report give their errors)"
        )
    for k, (label, record) in enumerate(records):
        for r in record.backends:
            name = terminal_markup(label)
            if r.status in ("fail", "error", "xpass"):
                message = terminal_markup(r.message)
                console.print(f"[bold red]{name}[/]: {terminal_markup(r.name)}: {message}")
            if r.jacobian is not None and r.jacobian.status in ("fail", "error"):
                message = terminal_markup(r.jacobian.message)
                console.print(f"[bold red]{name}[/]: {terminal_markup(r.name)} Jacobian: {message}")
        for line in diagnosis_lines(diagnoses[k] if k < len(diagnoses) else ()):
            console.print(f"[bold red]{terminal_markup(label)}[/]: {terminal_markup(line)}")


def annotate() -> bool:
    """Whether to print GitHub annotations (``GITHUB_ACTIONS=true``)."""
    from fkcheck.report.annotations import in_github_actions

    return in_github_actions()


def print_annotations(check: CheckResult, diagnoses: Sequence[BackendDiagnosis]) -> None:
    """On GitHub Actions: an ``::error`` line per failure, at the model file (and line)."""
    from fkcheck.report.annotations import github_annotations

    if not annotate():
        return
    source = None
    if check.model.path is not None and check.model.path.suffix == ".toml":
        try:
            source = read_text(check.model.path)  # bounded, regular files only, as at load
        except InputFileError:
            source = None  # the file-level annotation still says what failed
    for line in github_annotations(check, diagnoses, source=source):
        print(line)
