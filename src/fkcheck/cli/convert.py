"""``fkcheck convert``: rewrite a DH table in the other convention, and prove it equivalent."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    from fkcheck.model.options import DEFAULT_SAMPLES

    p = sub.add_parser(
        "convert",
        help="convert a DH table between standard and modified (Craig) DH",
        description="Write the same robot as a DH table in the other convention (base and tool "
        "absorb the regrouped first/last link), then prove the two equivalent: every named "
        "frame and the TCP are compared on sampled configurations. Exit 0: equivalent; 1: "
        "they differ beyond the model's tolerance; 2: bad input.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5) or a .toml/.csv file")
    p.add_argument("--to", required=True, choices=("standard", "modified"), help="convention")
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="OUT",
        help="write the model file here (default: print it)",
    )
    p.add_argument("--samples", type=int, default=DEFAULT_SAMPLES,
                   help=f"random samples (default {DEFAULT_SAMPLES})")  # fmt: skip
    p.add_argument("--seed", type=int, default=0, help="seed of the samples (default 0)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Convert, verify, write."""
    import tomllib

    from fkcheck.cli._outputs import model_inputs, plan, writes
    from fkcheck.io.atomic import write_text_atomic
    from fkcheck.io.format import format_angle_console, format_length_console
    from fkcheck.io.text import operand, terminal_text
    from fkcheck.model.convert import convert_model, equivalence_error
    from fkcheck.model.options import check_option
    from fkcheck.model.read import load_model, model_from_dict
    from fkcheck.model.sampling import sample_configurations
    from fkcheck.model.write import model_to_toml, relocate_urdf_path

    check_option("samples", args.samples, "--samples")
    check_option("seed", args.seed, "--seed")
    model = load_model(args.model)
    outputs = [("-o", args.output)]
    plan(args, outputs, model_inputs(model, expand=writes(outputs)))
    converted = convert_model(model, args.to)
    if args.output is not None:
        converted = relocate_urdf_path(converted, args.output)
    header = [
        f"{model.name} as {args.to} DH, converted by fkcheck convert from "
        f"{model.path.name if model.path else model.name} ({model.convention} DH).",
        "Named frames are re-expressed on the new DH frames; base and tool absorb the",
        "first/last link's regrouped Tx(a)·Rx(α). Equivalence is checked on every named frame.",
    ]
    text = model_to_toml(converted, header=header)
    # Verify what is written, not the in-memory object: read the text back.
    written = model_from_dict(tomllib.loads(text), args.output or model.path)
    q = sample_configurations(model, args.samples, args.seed).q
    pos, rot = equivalence_error(model, written, q)
    ok = pos <= model.check.tol_pos_m and rot <= model.check.tol_rot_rad
    summary = (
        f"fkcheck convert: {terminal_text(model.name)} {model.convention} → {args.to}: "
        f"{'equivalent' if ok else 'NOT equivalent'} over {q.shape[0]} configurations and "
        f"{len(model.frames)} named frames (max position error {format_length_console(pos)}, "
        f"max rotation error {format_angle_console(rot)})"
    )
    if args.output is None:
        sys.stdout.write(text)
        print(summary, file=sys.stderr)
    else:
        write_text_atomic(args.output, text)
        print(summary)
        print(f"wrote {terminal_text(args.output)}")
        again = terminal_text(shlex.quote(operand(str(args.output))))
        if converted.urdf is not None:
            print(f"cross-check it against its URDF: fkcheck check {again}")
    return 0 if ok else 1
