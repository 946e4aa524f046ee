"""``fkcheck urdf``: write a kinematic URDF from a DH model (and a model that checks it)."""

from __future__ import annotations

import argparse
import os
import shlex
from pathlib import Path
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    from fkcheck.cli._arguments import utf8_text
    from fkcheck.cli.expand import add_allow_xacro

    p = sub.add_parser(
        "urdf",
        help="write a URDF from a DH model",
        description="Write a kinematic URDF (a link per DH frame, revolute/prismatic joints "
        "with limits, fixed links for the named frames such as base_link, tool0, flange, tcp) "
        "loadable by Pinocchio, yourdfpy and Robotics Toolbox. With --write-model, also "
        "write the model with [urdf] and [frames] pointing at it, so that "
        "`fkcheck check` compares the DH table with the new URDF.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5) or a .toml/.csv file")
    p.add_argument(
        "-o", "--output", type=Path, required=True, metavar="ROBOT.urdf", help="the URDF to write"
    )
    p.add_argument(
        "--write-model",
        type=Path,
        metavar="MODEL.toml",
        help="also write the model mapped onto the new URDF",
    )
    p.add_argument("--name", type=utf8_text, help="<robot name> (default: the model's name)")
    add_allow_xacro(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Write the URDF (and the companion model)."""
    from fkcheck.cli._outputs import model_inputs, plan
    from fkcheck.io.atomic import write_text_atomic
    from fkcheck.io.text import operand, terminal_text
    from fkcheck.model.read import load_model
    from fkcheck.model.write import model_to_toml
    from fkcheck.urdf.export import model_for_urdf, urdf_from_model

    model = load_model(args.model)
    if args.allow_xacro:
        from fkcheck.urdf.source import allow_xacro

        model = allow_xacro(model)
    plan(args, [("-o", args.output), ("--write-model", args.write_model)], model_inputs(model))
    export = urdf_from_model(model, args.name)
    write_text_atomic(args.output, export.text)
    shown = terminal_text(args.output)
    print(f"wrote {shown}: {model.dof} joints, {len(export.frame_links)} frames")
    if args.write_model is not None:
        relative = os.path.relpath(args.output.resolve(), args.write_model.resolve().parent)
        mapped = model_for_urdf(model, export, Path(relative).as_posix())
        header = [f"{model.name} mapped onto {args.output.name}, written by fkcheck urdf."]
        write_text_atomic(args.write_model, model_to_toml(mapped, header=header))
        written = terminal_text(args.write_model)
        again = terminal_text(shlex.quote(operand(str(args.write_model))))
        print(f"wrote {written}; check it: fkcheck check {again}")
    return 0
