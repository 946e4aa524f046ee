"""``fkcheck check``: compare the in-house core with reference backends."""

from __future__ import annotations

import argparse
import math
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from fkcheck.check import BackendResult, CheckResult

__all__ = ["add_parser", "format_m", "format_rad", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "check",
        help="cross-check the in-house DH core against reference libraries",
        description="Compare from_T_to, pose by pose, between the in-house DH core and each "
        "reference backend. Exit 0: every backend that ran agrees; 1: a backend disagrees "
        "or errors, or none ran; 2: bad input.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5) or a .toml/.csv file")
    p.add_argument(
        "--against",
        action="append",
        metavar="LIST",
        help="backends, comma-separated or repeated: rtb-dh, pinocchio-dh, pinocchio-urdf, "
        "yourdfpy-urdf, rtb-urdf (the default set), rtb-model:NAME, cmd:PROGRAM, module:function",
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
    p.set_defaults(run=run)


def format_m(value: float | None) -> str:
    """A length in metres, with millimetres when large enough to matter."""
    if value is None:
        return "-"
    if value >= 1e-5:
        return f"{value:.3g} m ({value * 1e3:.3f} mm)"
    return f"{value:.2g} m"


def format_rad(value: float | None) -> str:
    """An angle in radians, with degrees when large enough to matter."""
    if value is None:
        return "-"
    if value >= 1e-5:
        return f"{value:.3g} rad ({math.degrees(value):.3f}°)"
    return f"{value:.2g} rad"


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


def print_summary(check: CheckResult) -> None:
    """The terminal table and verdict line."""
    from rich.console import Console
    from rich.table import Table

    console = Console(highlight=False)
    title = (
        f"fkcheck {check.model.name}: {check.frame_from} → {check.frame_to}, "
        f"{check.q.shape[0]} configurations ({check.samples} {check.sampler} samples, "
        f"seed {check.seed}), tolerance {check.tol_pos_m:g} m / {check.tol_rot_rad:g} rad"
    )
    table = Table(title=title, title_justify="left")
    for column in (
        "backend",
        "status",
        "max position error",
        "max rotation error",
        "worst q",
        "time",
    ):
        table.add_column(column, overflow="fold")
    table.add_row("fkcheck-dh", "reference", "", "", "", "")
    for r in check.backends:
        if r.ran:
            table.add_row(
                r.name, f"[{_STYLE[r.status]}]{r.status}[/]", format_m(r.max_position_error_m),
                format_rad(r.max_rotation_error_rad), _worst_q(r, check), f"{r.duration_s:.2f} s",
            )  # fmt: skip
        else:
            table.add_row(r.name, f"[{_STYLE[r.status]}]{r.status}[/]", r.message, "", "", "")
    console.print(table)
    for r in check.backends:
        if r.status == "fail":
            console.print(f"[bold red]{r.name}[/]: {r.message}")
    ran = len(check.ran)
    if not ran:
        console.print("[bold red]verdict: error[/] — no reference backend ran: nothing was "
                      "cross-checked")  # fmt: skip
    else:
        style = "bold green" if check.verdict == "pass" else "bold red"
        console.print(f"[{style}]verdict: {check.verdict}[/] ({ran} backend(s) cross-checked)")


def run(args: argparse.Namespace) -> int:
    """Run the check, print, write the requested files."""
    from dataclasses import replace

    from fkcheck.backends.registry import BackendOptions, default_backends, parse_against
    from fkcheck.check import run_check
    from fkcheck.errors import JointInputError
    from fkcheck.model import load_model
    from fkcheck.report.json_report import write_json
    from fkcheck.report.junit import write_junit

    if args.samples < 0:
        raise JointInputError(f"--samples must be 0 or more, got {args.samples}")
    for flag, value in (("--tol-pos", args.tol_pos), ("--tol-rot", args.tol_rot),
                        ("--timeout", args.timeout)):  # fmt: skip
        if value is not None and not (math.isfinite(value) and value > 0):
            raise JointInputError(f"{flag} must be a positive number, got {value}")
    model = load_model(args.model)
    for warning in model.warnings:
        print(f"fkcheck: warning: {warning}", file=sys.stderr)
    options = BackendOptions(timeout_s=args.timeout)
    backends = parse_against(args.against, options) if args.against else default_backends(options)

    check = run_check(
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
    )
    check = replace(check, command="fkcheck " + shlex.join(getattr(args, "argv", [])))
    print_summary(check)
    if args.json is not None:
        write_json(check, args.json)
    if args.junit is not None:
        write_junit(check, args.junit)
    return 0 if check.verdict == "pass" else 1
