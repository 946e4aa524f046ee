"""``fkcheck ik``: check an inverse-kinematics solver against the table's FK.

``fkcheck ik MODEL --solver NAME``: poses from the in-house FK at seeded,
singular and near-singular configurations; the solver's every answer is held
to the table (:mod:`fkcheck.ik.check`). Exit 0 when every returned solution is
right, no configuration is missed, nothing is NaN/inf and the solver's own FK
(if any) agrees; 1 when not; 2 on bad input (an unknown solver, one that does
not fit the model, an unknown frame, a bad option).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "ik",
        help="check an IK solver: every solution right, none missing",
        description="Ask an inverse-kinematics solver for every solution of poses the "
        "in-house FK computes (seeded configurations within the limits, plus singular and "
        "near-singular ones) and check that each solution reproduces its pose, that the "
        "configuration the pose came from is among them (the missed branch named), that "
        "nothing is NaN/inf, and that the solver's own FK agrees with the table.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5e) or a .toml/.csv file")
    p.add_argument(
        "--solver",
        required=True,
        metavar="NAME",
        help="ur-analytic-ik (or ur-analytic-ik:ROBOT), opw, a solver an installed package "
        "registers (entry-point group fkcheck.ik_solvers), or your function module:function "
        "(importable from the working directory): f(pose (4, 4)) -> (k, n) radians",
    )
    p.add_argument("--samples", type=int, default=1000, help="random configurations (default 1000)")
    p.add_argument("--seed", type=int, default=0, help="their seed (default 0)")
    p.add_argument(
        "--from",
        dest="frame_from",
        metavar="FRAME",
        help="the frame the solver's pose is expressed in (default: the model's [check] from)",
    )
    p.add_argument(
        "--to",
        dest="frame_to",
        metavar="FRAME",
        help="the frame whose pose it inverts (default: the model's [check] to)",
    )
    p.add_argument(
        "--tol-pos", type=float, help="soundness tolerance, metres (default: the model's)"
    )
    p.add_argument(
        "--tol-rot", type=float, help="soundness tolerance, radians (default: the model's)"
    )
    p.add_argument("--timeout", type=float, default=None, help="time limit of a module:function "
                   "solver's run, seconds (default 120)")  # fmt: skip
    p.add_argument("--json", type=Path, metavar="OUT", help="write the result as JSON")
    p.add_argument("--markdown", type=Path, metavar="OUT", help="write the result as Markdown")
    p.add_argument("--junit", type=Path, metavar="OUT", help="write the result as JUnit XML")
    p.add_argument("--html", type=Path, metavar="OUT", help="write the result as an HTML page")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Build the solver, check it, print and write the result."""
    from fkcheck.cli._outputs import model_inputs, plan, writes
    from fkcheck.ik import check_ik, make_solver
    from fkcheck.ik.output import format_html, format_markdown, format_text, junit_xml, to_dict
    from fkcheck.ik.python_solver import PythonIkSolver
    from fkcheck.io.atomic import write_bytes_atomic, write_text_atomic
    from fkcheck.io.strict_json import strict_json
    from fkcheck.io.text import terminal_lines, terminal_text
    from fkcheck.model.options import DEFAULT_TIMEOUT_S, check_option
    from fkcheck.model.read import load_model
    from fkcheck.model.types import resolve_frame

    check_option("samples", args.samples, "--samples", lowest=0)
    check_option("seed", args.seed, "--seed")
    if args.tol_pos is not None:
        check_option("tol_pos_m", args.tol_pos, "--tol-pos")
    if args.tol_rot is not None:
        check_option("tol_rot_rad", args.tol_rot, "--tol-rot")
    timeout = DEFAULT_TIMEOUT_S if args.timeout is None else args.timeout
    check_option("timeout_s", timeout, "--timeout")
    model = load_model(args.model)
    for warning in model.warnings:
        print(f"fkcheck: warning: {terminal_text(warning)}", file=sys.stderr)
    frame_from = args.frame_from or model.check.frame_from
    frame_to = args.frame_to or model.check.frame_to
    for name in (frame_from, frame_to):
        resolve_frame(model, name)
    solver = make_solver(args.solver, model, frame_from, frame_to, timeout_s=timeout)
    outputs = [
        ("--json", args.json),
        ("--markdown", args.markdown),
        ("--junit", args.junit),
        ("--html", args.html),
    ]
    inputs = list(model_inputs(model, expand=False))
    if isinstance(solver, PythonIkSolver):
        from fkcheck.backends.plugin import module_file

        found = module_file(solver.module)
        if found is not None:
            inputs.append((f"the module of IK solver {solver.name}", found))
    plan(args, outputs, inputs if writes(outputs) else [])
    result = check_ik(
        model,
        solver,
        frame_from=frame_from,
        frame_to=frame_to,
        samples=args.samples,
        seed=args.seed,
        tol_pos_m=args.tol_pos,
        tol_rot_rad=args.tol_rot,
    )
    sys.stdout.write(terminal_lines(format_text(result)))
    if args.json is not None:
        write_text_atomic(args.json, strict_json(to_dict(result), indent=2) + "\n")
    if args.markdown is not None:
        write_text_atomic(args.markdown, format_markdown(result))
    if args.junit is not None:
        write_bytes_atomic(args.junit, junit_xml(result))
    if args.html is not None:
        write_text_atomic(args.html, format_html(result))
    return 0 if result.passed else 1
