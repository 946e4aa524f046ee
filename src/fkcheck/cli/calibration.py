"""``fkcheck calibration``: a robot's own model from its nominal model and its calibration."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from fkcheck.cli._arguments import utf8_text
from fkcheck.cli._model_output import add_model_output, emit_model

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "calibration",
        help="apply a UR arm's factory calibration to its nominal model",
        description="Write the calibrated model of one Universal Robots arm: its nominal model "
        "(a bundled UR model such as ur5e, or your model file) with the robot's own DH table "
        "from the controller's calibration.conf (deltas, added) or a KinematicsInfo dump (full "
        "values, as UR's driver logs them). Give the robot's ur_calibration YAML as well and "
        "the model's [urdf] becomes UR's own description expanded with it (kinematics_params), "
        "so that `fkcheck check` compares what ROS uses with what the controller uses. "
        "Linearised tables (d2/d3 of hundreds of metres) are normal. A calibration that moves "
        "the tool more than 50 mm from the nominal one does not fit the nominal model and is "
        "refused. Prints what the calibration changes over the workspace.",
    )
    p.add_argument("nominal", metavar="NOMINAL", help="bundled model name (ur5e) or model file")
    p.add_argument(
        "files",
        nargs="+",
        type=Path,
        metavar="CALIBRATION",
        help="calibration.conf, a KinematicsInfo dump and/or ur_calibration's YAML "
        "(one table and at most one YAML)",
    )
    p.add_argument("--name", type=utf8_text, help="model name (default: NOMINAL-calibrated)")
    add_model_output(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Read, apply, write, summarise."""
    from fkcheck.calibration.apply import apply_calibration
    from fkcheck.calibration.description import calibrated_description, split_files
    from fkcheck.calibration.ur_files import CalibrationError
    from fkcheck.cli._outputs import plan
    from fkcheck.io.text import terminal_text
    from fkcheck.model.read import load_model
    from fkcheck.model.write import model_to_toml
    from fkcheck.urdf.locate import path_for

    nominal = load_model(args.nominal)
    table_file, yaml_file = split_files(args.files)  # at least one of them
    inputs = [("the calibration", f.path) for f in (table_file, yaml_file) if f is not None]
    if nominal.path is not None:
        inputs.append(("the nominal model", nominal.path))
    plan(args, [("-o", args.output)], inputs)
    nominal_ref = _nominal_ref(args, nominal)
    table = None
    if table_file is None:
        from fkcheck.calibration.description import table_from_yaml

        table = table_from_yaml(nominal, yaml_file)
    main = table_file or yaml_file
    if main is None:  # split_files refuses this; kept for the type checker
        raise CalibrationError(Path("."), "no calibration file given")
    result = apply_calibration(
        nominal,
        main,
        nominal_ref=nominal_ref,
        file_ref=path_for(main.path, args.output),
        name=args.name or "",
        table=table,
    )
    model = calibrated_description(result.model, nominal, yaml_file, args.output)
    header = _header(model.name, nominal.name, table_file, yaml_file, args.output)
    text = model_to_toml(model, header=header)
    again = emit_model(args, text, f"fkcheck calibration: {terminal_text(result.effect.line)}")
    advice = ""
    if table_file is None:
        advice = (
            "the table is derived from UR's description with the YAML, so that description "
            "cannot check it: compare it with what the controller recorded (fkcheck check "
            f"{again or 'MODEL.toml'} --against poses:RECORDING.csv), or give calibration.conf too"
        )
    elif model.urdf is None:
        advice = (
            "no description to check the table against: give the robot's ur_calibration YAML "
            "too (fkcheck calibration NOMINAL calibration.conf robot_calibration.yaml)"
        )
    if advice:
        print(advice, file=sys.stdout if again else sys.stderr)
    return 0


def _nominal_ref(args: argparse.Namespace, nominal: Any) -> str:
    """How the written model names its nominal model: a bundled name, or a file in its folder.

    A printed model is taken to be written in the current directory.

    Raises:
        CalibrationError: The nominal model file is outside the written model's
            folder (the model could not name it: ``[calibration] nominal`` is held
            to the model's folder).
    """
    from fkcheck.calibration.effect import nominal_location
    from fkcheck.calibration.ur_files import CalibrationError
    from fkcheck.errors import ModelError
    from fkcheck.urdf.locate import path_for

    if nominal.path is None or not Path(args.nominal).exists():
        return str(args.nominal)  # a bundled model's name
    target = args.output if args.output is not None else Path.cwd() / "calibrated.toml"
    ref = path_for(nominal.path, target)
    try:
        nominal_location(ref, target.parent)
    except ModelError as exc:
        raise CalibrationError(
            nominal.path,
            f"the nominal model is outside {target.parent}, where the calibrated model goes "
            f"({exc.problem}): write it beside the nominal model, or copy the nominal model "
            "to its folder",
        ) from None
    return ref


def _header(
    name: str, nominal: str, table_file: Any, yaml_file: Any, output: Path | None
) -> list[str]:
    lines = [f"{name}: {nominal}'s nominal table with this robot's factory calibration."]
    if table_file is not None:
        lines.append(
            f"Table: {table_file.form} {table_file.path.name} (sha256 {table_file.sha256[:16]}…)."
        )
    if yaml_file is not None:
        lines.append(
            f"Description: UR's ROS 2 description with kinematics_params = {yaml_file.path.name}"
            f" ({yaml_file.hash or 'no hash'})."
        )
    lines.append(
        f"Generated by fkcheck calibration; check it: fkcheck check {output or 'MODEL.toml'}"
    )
    return lines
