"""``fkcheck bench``: time the in-house DH core against its peers on the same poses.

``fkcheck bench --jacobian`` times the batched Jacobian instead (see
:mod:`fkcheck.bench.jacobian`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fkcheck.io.format import format_length_console, format_microseconds, format_scientific

if TYPE_CHECKING:
    from rich.table import Table

    from fkcheck.bench.ik import IkBenchResult, IkTiming

__all__ = ["add_parser", "run", "write_json"]


def _positive(text: str) -> int:
    try:
        value = int(text.replace("_", ""))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "bench",
        help="time the in-house core against Robotics Toolbox, Pinocchio, yourdfpy",
        description="Time the in-house DH core (batched, one pose, NumPy fallback, plain "
        "reference chain) and its peers (Robotics Toolbox, Pinocchio, yourdfpy) on the same "
        "seeded configurations, check that they agree, and compare with a memory-bandwidth "
        "bound. Slow peers run on the first few of the N poses (the n column says how many).",
    )
    p.add_argument(
        "model",
        metavar="MODEL",
        nargs="?",
        default="ur5",
        help="bundled model name or a .toml/.csv file (default: ur5)",
    )
    p.add_argument(
        "--n",
        type=_positive,
        default=1_000_000,
        metavar="N",
        help="configurations for the batched core (default: 1000000)",
    )
    p.add_argument(
        "--repeat",
        type=_positive,
        default=5,
        metavar="R",
        help="timed runs per contender, median reported (default: 5)",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of the configurations (default: 0)")
    p.add_argument("--json", type=Path, metavar="PATH", help="also write the numbers as JSON")
    p.add_argument(
        "--jacobian",
        action="store_true",
        help="time the TCP's world-aligned Jacobian instead of the pose: the in-house batch "
        "against Robotics Toolbox's ETS.jacob0 and Pinocchio's computeFrameJacobian, one "
        "thread and one preallocated output for all (numba's threads as an extra row)",
    )
    p.add_argument(
        "--ik",
        metavar="NAME[,NAME]",
        help="time inverse-kinematics solvers instead (fkcheck ik's --solver names) on the "
        "same poses: solves/s per solver, the library's bare call where there is one, and "
        "fkcheck ik's checking of the answers (the harness's cost); at most 2000 poses",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run the benchmark, print the table, write the JSON; 1 if a peer disagrees or fails."""
    from fkcheck.bench.harness import run_bench
    from fkcheck.bench.jacobian import run_jacobian_bench
    from fkcheck.cli._console import console
    from fkcheck.cli._outputs import model_inputs, plan, writes
    from fkcheck.io.text import terminal_markup, terminal_text
    from fkcheck.model.options import check_option
    from fkcheck.model.read import load_model

    check_option("seed", args.seed, "--seed")  # the one seed range of every command
    model = load_model(args.model)
    outputs = [("--json", args.json)]
    plan(args, outputs, model_inputs(model, expand=writes(outputs)))
    if args.ik is not None:
        return _run_ik(args, model)
    bench = run_jacobian_bench if args.jacobian else run_bench
    with console(stderr=True).status("timing…") as status:
        result = bench(
            model,
            args.n,
            args.repeat,
            seed=args.seed,
            progress=lambda name: status.update(f"timing {terminal_markup(name)}…"),
        )
    if args.jacobian:
        tol, unit = model.check.tol_jacobian, "m/rad or rad/rad"
        errors = [(t.name, t.max_jac_err) for t in result.timings]
        console().print(_jacobian_table(result, tol))
    else:
        tol, unit = model.check.tol_pos_m, "m"
        errors = [(t.name, t.max_pos_err_m) for t in result.timings]
        console().print(_table(result, tol))
    disagree = [name for name, err in errors if err is not None and not err <= tol]
    failed = [f"{t.name} ({t.error})" for t in [*result.timings, *result.recordings] if t.error]
    if args.json is not None:
        write_json(
            args.json,
            {
                **result.to_dict(),
                ("tol_jacobian" if args.jacobian else "tol_pos_m"): tol,
                "disagree": disagree,
                "failed": failed,
            },
        )
    if failed:
        print(f"fkcheck bench: peers failed: {terminal_text('; '.join(failed))}", file=sys.stderr)
        return 1
    if disagree:
        print(
            f"fkcheck bench: disagree with the in-house core by more than {tol:g} {unit}: "
            f"{terminal_text(', '.join(disagree))}",
            file=sys.stderr,
        )
        return 1
    return 0


def _table(result: Any, tol: float) -> Any:
    """The rich table: one row per contender, then notes and the facts to read it by."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from fkcheck.io.text import terminal_markup, terminal_text

    best = result.fastest_peer
    table = Table(
        title=f"fkcheck bench {terminal_markup(result.model)}: N = {result.n:,}, median of "
        f"{result.repeat} runs"
    )
    table.add_column("implementation", no_wrap=True)
    table.add_column("n", justify="right")
    table.add_column("mode", no_wrap=True)
    table.add_column("µs/pose", justify="right")
    table.add_column("poses/s", justify="right")
    table.add_column("× peer", justify="right")
    table.add_column("max |Δp|", justify="right")
    notes = []
    for t in result.timings:
        name = terminal_markup(t.name)  # a contender's name is text, never markup
        notes.append(terminal_text(f"{t.name}: {f'skipped, {t.skipped}' if t.skipped else t.note}"))
        if t.skipped:
            table.add_row(name, f"{t.n:,}", "", "skipped", "", "", "", style="dim")
            continue
        if t.error:
            table.add_row(name, f"{t.n:,}", "", "[bold red]FAILED[/]", "", "", "")
            notes[-1] = terminal_text(f"{t.name}: FAILED, {t.error}")
            continue
        speedup = result.speedup(t)
        err = "" if t.max_pos_err_m is None else format_length_console(t.max_pos_err_m)
        if t.max_pos_err_m is not None and not t.max_pos_err_m <= tol:
            err = f"[bold red]{err}[/]"
        table.add_row(
            name,
            f"{t.n:,}",
            terminal_markup(t.mode),
            format_microseconds(t.us_per_pose),
            f"{t.poses_per_s:,.0f}",
            "" if speedup is None else f"{speedup:,.1f}" if speedup >= 1 else f"{speedup:.2g}",
            err,
        )
    load = ", ".join(f"{v:.2f}" for v in result.machine.get("load_average") or [])
    headline = result.headline
    facts = [
        (
            f"Headline, like for like ({headline[0].mode}, N = {headline[0].n:,}): "
            f"{headline[0].name} {format_microseconds(headline[0].us_per_pose or 0)} µs/pose vs "
            f"{headline[1].name} {format_microseconds(headline[1].us_per_pose or 0)} µs/pose: "
            f"{headline[2]:,.1f}× as fast."
            if headline
            else "Headline: no like-for-like pair ran (needs numba and Robotics Toolbox)."
        ),
        "Rows whose mode starts with 'extra:' use what the peers do not (threads, a reused "
        "buffer): they are not like for like.",
        f"Configurations: seeded (seed {result.seed}), uniform within the joint limits; "
        "a smaller n runs on the first n of them.",
        "× peer: per-pose time of the fastest other library"
        + (f" ({best.name})" if best else " (none ran)")
        + " divided by this row's.",
        f"max |Δp|: largest position difference from the in-house batch on the same "
        f"poses (the model's tolerance is {tol:g} m).",
        f"JIT {result.jit}; numba threads: {result.threads}.",
        f"Machine: {result.machine.get('cpu')}, {result.machine.get('cpus')} CPUs, "
        f"load average {load}.",
    ]
    return Group(table, Text("\n".join([*notes, "", *facts])), *_recordings_table(result))


def _recordings_table(result: Any) -> list[Any]:
    """Reading one RTDE recording: rows/s and MB/s, fkcheck's against pandas'."""
    from rich.table import Table
    from rich.text import Text

    from fkcheck.io.text import terminal_markup, terminal_text

    rows = result.recordings
    if not rows:
        return []
    first = rows[0]
    table = Table(
        title=f"reading an RTDE recording: {first.rows:,} rows, {first.bytes / 1e6:,.1f} MB, "
        f"median of {result.repeat} runs"
    )
    for name, right in (("reader", False), ("rows/s", True), ("MB/s", True),
                        ("× pandas", True), ("max |Δ|", True)):  # fmt: skip
        table.add_column(name, justify="right" if right else "left", no_wrap=not right)
    peer = next((r for r in rows if r.kind == "peer" and r.seconds), None)
    notes = []
    for r in rows:
        name = terminal_markup(r.name)
        why = f"skipped, {r.skipped}" if r.skipped else f"FAILED, {r.error}" if r.error else r.note
        notes.append(terminal_text(f"{r.name}: {why}"))
        if r.seconds is None:
            table.add_row(name, "skipped" if r.skipped else "[bold red]FAILED[/]", "", "", "")
            continue
        ratio = "" if peer is None else f"{peer.seconds / r.seconds:.2g}"
        diff = "" if r.max_diff is None else f"{r.max_diff:.1g}"
        table.add_row(name, f"{r.rows_per_s:,.0f}", f"{r.mb_per_s:,.1f}", ratio, diff)
    notes.append(
        "× pandas: pandas.read_csv's time divided by this row's (above 1: faster). max |Δ|: "
        "largest difference of the joint (fkcheck) or all 12 (pandas) numbers from those "
        "written."
    )
    return [Text(""), table, Text("\n".join(notes))]


def _jacobian_table(result: Any, tol: float) -> Any:
    """The ``--jacobian`` table: ns per Jacobian, the ratio to each peer, the agreement."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from fkcheck.io.text import terminal_markup, terminal_text

    peers = [t for t in result.timings if t.kind == "peer" and t.seconds is not None]
    table = Table(
        title=f"fkcheck bench --jacobian {terminal_markup(result.model)}: {result.reference} "
        f"Jacobian of the TCP, N = {result.n:,}, median of {result.repeat} runs"
    )
    for header, justify in (("implementation", "left"), ("n", "right"), ("mode", "left"),
                            ("ns/config", "right")):  # fmt: skip
        table.add_column(header, justify=justify, no_wrap=True)  # type: ignore[arg-type]
    for peer in peers:
        table.add_column(f"× {terminal_markup(peer.name.split()[0])}", justify="right",
                         no_wrap=True)  # fmt: skip
    table.add_column("max |ΔJ|", justify="right", no_wrap=True)
    notes = []
    for t in result.timings:
        name = terminal_markup(t.name)
        blank = [""] * len(peers)
        if t.skipped:
            notes.append(terminal_text(f"{t.name}: skipped, {t.skipped}"))
            table.add_row(name, f"{t.n:,}", "", "skipped", *blank, "", style="dim")
            continue
        err = "" if t.max_jac_err is None else format_scientific(t.max_jac_err, "").strip()
        if t.max_jac_err is not None and not t.max_jac_err <= tol:
            err = f"[bold red]{err}[/]"
        if t.error or t.seconds is None:
            notes.append(terminal_text(f"{t.name}: FAILED, {t.error}" if t.error else
                                       f"{t.name}: {t.note}"))  # fmt: skip
            status = "[bold red]FAILED[/]" if t.error else "[bold red]not timed[/]"
            table.add_row(name, f"{t.n:,}", terminal_markup(t.mode), status, *blank, err)
            continue
        notes.append(terminal_text(f"{t.name}: {t.note}"))
        ratios = result.ratios(t)
        table.add_row(
            name,
            f"{t.n:,}",
            terminal_markup(t.mode),
            f"{t.us_per_pose * 1e3:,.1f}",
            *(f"{ratios[p.name]:,.2f}" if p is not t else "1" for p in peers),
            err,
        )
    headline = result.headline
    load = ", ".join(f"{v:.2f}" for v in result.machine.get("load_average") or [])
    facts = [
        (
            f"Headline, like for like ({headline[0].mode}, n = {headline[0].n:,}): "
            f"{headline[0].name} {headline[0].us_per_pose * 1e3:,.1f} ns vs {headline[1].name} "
            f"{headline[1].us_per_pose * 1e3:,.1f} ns per Jacobian: {headline[2]:,.1f}× as fast."
            if headline
            else "Headline: no like-for-like pair ran (needs Pinocchio)."
        ),
        *_jacobian_over_fk(result),
        "× PEER: that peer's time per configuration divided by this row's (above 1: this "
        "row is faster). Rows whose mode starts with 'extra:' use what the peers do not "
        "(threads, a larger N) or time poses, for scale: they are not like for like.",
        f"max |ΔJ|: largest difference of a column's linear or angular 3-vector from the "
        "in-house batch on the same "
        f"configurations (the model's Jacobian tolerance is {tol:g}); a peer beyond it is "
        "not timed.",
        f"Configurations: seeded (seed {result.seed}), uniform within the joint limits; "
        "a smaller n runs on the first n of them.",
        f"Jacobian kernel {result.jit}; numba threads: {result.threads}.",
        f"Machine: {result.machine.get('cpu')}, {result.machine.get('cpus')} CPUs, "
        f"load average {load}.",
    ]
    return Group(table, Text("\n".join([*notes, "", *facts])))


def _jacobian_over_fk(result: Any) -> list[str]:
    """One line: the Jacobian's time per configuration over the FK's, per thread count."""
    if not result.jacobian_over_fk:
        return []
    found = ", ".join(f"{ratio:.1f}× ({label})" for label, ratio in result.jacobian_over_fk.items())
    return [f"Jacobian vs pose: the batched Jacobian takes {found} the FK's time "
            "per configuration, same N and out=."]  # fmt: skip


def _run_ik(args: argparse.Namespace, model: Any) -> int:
    """``--ik``: time the solvers, print their table, write the JSON; 1 if one fails."""
    from fkcheck.bench.ik import run_ik_bench
    from fkcheck.cli._console import console
    from fkcheck.io.text import terminal_markup, terminal_text

    names = [n.strip() for n in args.ik.split(",") if n.strip()]
    with console(stderr=True).status("timing…") as status:
        result = run_ik_bench(
            model,
            names,
            args.n,
            args.repeat,
            seed=args.seed,
            progress=lambda name: status.update(f"timing {terminal_markup(name)}…"),
        )
    tol = model.check.tol_pos_m
    console().print(_ik_table(result, tol))
    failed = [f"{t.solver} ({t.error})" for t in result.timings if t.error]
    unsound = [
        t.solver
        for t in result.timings
        if t.max_position_error_m is not None and not t.max_position_error_m <= tol
    ]
    if args.json is not None:
        write_json(
            args.json, {**result.to_dict(), "tol_pos_m": tol, "failed": failed, "unsound": unsound}
        )
    if failed:
        print(f"fkcheck bench: solvers failed: {terminal_text('; '.join(failed))}", file=sys.stderr)
        return 1
    if unsound:
        print(
            f"fkcheck bench: solutions off their pose by more than {tol:g} m: "
            f"{terminal_text(', '.join(unsound))} (fkcheck ik says more)",
            file=sys.stderr,
        )
        return 1
    return 0


def _ik_table(result: IkBenchResult, tol: float) -> Table:
    """``--ik``'s table: one row per solver and part, an error beyond ``tol`` (m) in red."""
    from rich.table import Table

    from fkcheck.io.text import terminal_markup

    table = Table(
        title=f"fkcheck bench {terminal_markup(result.model)} --ik: {result.n:,} poses, median "
        f"of {result.repeat} runs (the check: one run)"
    )
    for column in ("solver", "part", "µs/solve", "solves/s", "× solve", "max |Δp|", "note"):
        table.add_column(
            column, justify="left" if column in ("solver", "part", "note") else "right"
        )
    solve_us = {t.solver: t.us_per_solve for t in result.timings if t.part == "solve"}
    for t in result.timings:
        table.add_row(*_ik_row(t, solve_us.get(t.solver), tol))
    return table


def _ik_row(t: IkTiming, base: float | None, tol: float) -> tuple[str, ...]:
    """One timing's cells (``base``: its solver's µs per solve, for the ``× solve`` column)."""
    from fkcheck.io.text import terminal_markup

    if t.error:
        return (terminal_markup(t.solver), t.part, "[bold red]FAILED[/]", "", "", "",
                terminal_markup(t.error))  # fmt: skip
    ratio = "" if base is None or t.us_per_solve is None else f"{t.us_per_solve / base:.2g}"
    err = "" if t.max_position_error_m is None else f"{t.max_position_error_m:.2g}"
    if t.max_position_error_m is not None and not t.max_position_error_m <= tol:
        err = f"[bold red]{err}[/]"
    return (
        terminal_markup(t.solver),
        t.part,
        "" if t.us_per_solve is None else format_microseconds(t.us_per_solve),
        f"{t.solves_per_s:,.0f}" if t.solves_per_s else "",
        ratio,
        err,
        terminal_markup(t.note),
    )


def write_json(path: Path, data: dict[str, Any]) -> None:
    """Write ``data`` as indented strict JSON (:mod:`fkcheck.io.strict_json`), atomically.

    Raises:
        TypeError: ``data`` holds something JSON cannot encode (nothing is written).
    """
    from fkcheck.io.atomic import write_text_atomic
    from fkcheck.io.strict_json import strict_json

    write_text_atomic(path, strict_json(data, indent=2) + "\n")
