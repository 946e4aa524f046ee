"""``fkcheck map``: propose a model's ``[urdf]`` and ``[frames.*]`` block from a URDF.

Exit codes: 0 when the proposed block, pasted into the model, is a mapping
``fkcheck check`` (as the summary prints it) can pass on (the table moves like a
chain of the URDF, with every axis the same way round, and links sit at constant
offsets from DH frame 0 and from the last DH frame); 1 when it is not (a joint
turns the other way, or the chain moves like the table only with rows changed —
a vendor's zeros a quarter turn apart, a sign, one number — each said as the
``[[joint]]`` edit; no chain moves like the table even so, or no link matches
one end: the block then says how near the nearest came); 2 for bad input.
"""

from __future__ import annotations

import argparse
import shlex
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from fkcheck.description.types import Description
    from fkcheck.model.types import Model
    from fkcheck.urdf.mapping import MapResult

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    from fkcheck.cli.expand import add_xacro_options

    p = sub.add_parser(
        "map",
        help="find which URDF joints and links a DH model's joints and frames are",
        description="Propose the [urdf] and [frames.*] block of MODEL for URDF: which URDF "
        "joints are the DH joints (found by how they move over sampled configurations, not "
        "by name, with each axis' direction), and every URDF link at a constant offset from "
        "DH frame 0 and from the last DH frame (or the TCP), with that offset; frames the "
        "model declares keep their names. Computed with fkcheck's own DH core and URDF "
        "geometry: prove the result with fkcheck check, against the independent URDF "
        "parsers. Exit 0: the block can pass as pasted; 1: it cannot (it says why, and how "
        "near the nearest link came); 2: bad input.",
    )
    p.add_argument("model", metavar="MODEL", help="a bundled model name or a model file")
    p.add_argument(
        "urdf",
        metavar="URDF",
        nargs="?",
        help="a URDF file or example-robot-data:<subpath> (default: the model's [urdf] path)",
    )
    p.add_argument("--samples", type=int, default=64, help="random configurations (default 64)")
    p.add_argument("--seed", type=int, default=0, help="seed of the samples (default 0)")
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="FILE",
        help="write the block here (default: print it)",
    )
    add_xacro_options(p)  # --allow-xacro (for the model's [urdf] or URDF), --arg, --package
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Read, map, write the block, summarise."""
    from fkcheck.cli._outputs import Input, description_inputs, plan
    from fkcheck.cli.expand import xacro_inputs
    from fkcheck.description.registry import format_named
    from fkcheck.io.atomic import write_text_atomic
    from fkcheck.io.text import terminal_text
    from fkcheck.model.options import check_option
    from fkcheck.model.read import load_model
    from fkcheck.urdf.mapping import map_model, proposal_toml
    from fkcheck.urdf.source import allow_xacro

    check_option("samples", args.samples, "--samples")
    check_option("seed", args.seed, "--seed")
    model = load_model(args.model)
    values, packages = xacro_inputs(args)
    if args.allow_xacro:
        model = allow_xacro(model)
    described, spec, xacro_args, declared = _description(args, model, values, packages)
    path, kin = described.path, described.tree
    inputs: list[Input] = [("the model", model.path), *description_inputs(described, "the URDF")]
    plan(args, [("-o", args.output)], inputs)
    fmt = format_named(described.format)  # the block is in its section, frames by its key
    # The solver reads each declared frame's twin in this format (in its ``urdf`` field);
    # the block keeps the frame's twins in the other formats as the model has them.
    urdf_twins = {name: spec.urdf for name, spec in model.frames.items()}
    twins = {name: replace(s, urdf=fmt.frame(s)) for name, s in model.frames.items()}
    result = map_model(
        replace(model, frames=twins), kin, spec, samples=args.samples, seed=args.seed,
        xacro_args=xacro_args, packages=declared,
    )  # fmt: skip
    text = proposal_toml(
        result,
        fmt.section,
        lambda s: fmt.with_frame(replace(s, urdf=urdf_twins.get(s.name)), s.urdf),
    )
    if result.complete:
        summary = _complete_summary(args.model, model, path, result)
    else:
        summary = [f"fkcheck map: {model.name} onto {path.name}: {_why_not(result)}"]
    if args.output is None:
        sys.stdout.write(text)
        for line in summary:
            print(terminal_text(line), file=sys.stderr)
    else:
        write_text_atomic(args.output, text)
        for line in summary:
            print(terminal_text(line))
        print(f"wrote {terminal_text(args.output)}")
    return 0 if result.complete else 1


def _description(
    args: argparse.Namespace,
    model: Model,
    values: dict[str, str],
    packages: dict[str, Path],
) -> tuple[Description, str, dict[str, str] | None, dict[str, str]]:
    """The URDF to map onto: the one named, else the model's own.

    Returns:
        ``(described, spec, xacro_args, packages)``: the description read, the
        block's path to it, and the xacro arguments and packages the block opts
        in to (``None`` and empty when the URDF is not xacro).
    """
    from fkcheck.description.registry import (
        load_description,
        model_format,
        read_description_file,
    )
    from fkcheck.errors import FkcheckError, XacroRefused
    from fkcheck.urdf.locate import path_for, urdf_spec_for

    # The block opts in to xacro (with its arguments and packages) when the URDF is xacro.
    xacro_args: dict[str, str] | None = None
    declared: dict[str, str] = {}
    if args.urdf is not None:
        try:
            described = read_description_file(args.urdf)
        except XacroRefused:
            if not args.allow_xacro:
                raise
            described = read_description_file(args.urdf, args=values, packages=packages)
            xacro_args = values
            declared = {name: path_for(where, model.path) for name, where in packages.items()}
        spec = urdf_spec_for(described.path, model.path)  # relative to the model file it goes in
    elif (declared_fmt := model_format(model)) is not None:
        # screened; expanded first when xacro = true
        described = load_description(model, mapping=False, language=declared_fmt.language)
        spec = declared_fmt.written(model)
        if declared_fmt.executes and model.urdf is not None:
            xacro_args, declared = dict(model.urdf.xacro_args), dict(model.urdf.packages)
    else:
        raise FkcheckError(
            f"model {model.name} has no [urdf]: give the URDF to map it onto "
            "(fkcheck map MODEL URDF, a file or example-robot-data:<subpath>)"
        )
    return described, spec, xacro_args, declared


def _complete_summary(named: str, model: Model, path: Path, result: MapResult) -> list[str]:
    """The summary lines of a block that can pass as pasted (``named``: the MODEL argument)."""
    linked = [f.spec.name for f in result.frames if f.fit is not None]
    command = shlex.join(["fkcheck", "check", named, *result.check_flags])
    summary = [
        f"fkcheck map: {model.name} onto {path.name}: {model.dof} joints, "
        f"{len(linked)} frames ({', '.join(linked)}); check it: {command}"
    ]
    if result.check_flags:
        own = model.check
        summary.append(
            f"fkcheck map: the model's own [check] compares {own.frame_from} → "
            f"{own.frame_to}, and no URDF link sits exactly on "
            f"{' or '.join(result.unmapped_ends)}: give --from/--to as "
            "above, or set from and to in its [check] (the block's last lines)"
        )
    if result.numbers is not None and result.pair is not None:
        summary.append(
            f"fkcheck map: the proposed check {result.pair[0]} → {result.pair[1]} can verify "
            f"{result.numbers.scope()}"
        )
    hiding = [name for name in result.absorbs if result.pair and name in result.pair]
    if hiding:
        summary.append(
            f"fkcheck map: {', '.join(hiding)} "
            f"{'carries an offset' if len(hiding) == 1 else 'carry offsets'} that a table "
            "error would also produce, or sit beside links that could be the DH frame "
            "instead: either the URDF defines it so, or the table is off "
            "— fkcheck cannot tell (see the NOT IDENTIFIABLE comments)"
        )
    return summary


def _why_not(result: Any) -> str:
    """Why the block cannot pass as pasted, in one line."""
    from fkcheck.io.format import format_deg, format_mm

    if not result.joints_fit:
        return (
            "no chain of the URDF moves like the table (the nearest leaves the last DH frame "
            f"{format_mm(result.fit_m)} / {format_deg(result.fit_rad)} off)"
        )
    flipped = [j.dh for j in result.joints if j.flipped]
    edits = []
    if flipped:
        edits.append(
            f"joints {', '.join(flipped)} turn the other way in the URDF: toggle their flip"
        )
    moved = [
        line
        for line in result.edits.lines(result.model)
        if not line.endswith(("= true", "= false"))
    ]
    if moved:
        edits.append(
            "the chain moves like the table only with these rows changed (the block's comments "
            "say so too): " + "; ".join(moved)
        )
    if edits:
        return "; ".join(edits)
    parts = [
        f"no link at a constant offset from DH frame {n.anchor} (nearest: {n.link}, "
        f"{format_mm(n.spread_m)} / {format_deg(n.spread_rad)})"
        for n in result.nearest
    ]
    return "; ".join(parts) or "no link at a constant offset from DH frame 0"
