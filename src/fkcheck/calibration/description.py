"""A calibrated model's description: UR's own, expanded with the robot's ``kinematics_params``.

UR's ROS description reads a robot's calibration from ``ur_calibration``'s YAML
(its ``kinematics_params`` xacro argument). A calibrated model made with the
YAML keeps the nominal model's ``[urdf]`` (UR's bundled description) and
names the YAML as that argument's file (``[urdf.xacro_files]``), so that
``fkcheck check`` compares the controller's table with what ROS computes from
the YAML. Made without it, the model has no description: the nominal one
would differ from the calibrated table by the calibration itself.

With the YAML alone, there is no controller table: :func:`table_from_yaml`
derives one from the description as UR's xacro reads the YAML (fkcheck's
exact URDF → DH extraction, :mod:`fkcheck.urdf.to_dh`). Such a table agrees
with that description by construction, so the model keeps no ``[urdf]``:
check it against what the controller recorded instead (``poses:``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from fkcheck.calibration.ur_files import (
    CalibrationError,
    DhValues,
    UrCalibration,
    read_ur_calibration,
)
from fkcheck.model.types import Model

__all__ = [
    "KINEMATICS_ARG",
    "YAML_TABLE_TOL",
    "calibrated_description",
    "screen_kinematics",
    "split_files",
    "table_from_yaml",
    "with_kinematics",
]

#: The xacro argument of UR's description that names the kinematics YAML.
KINEMATICS_ARG = "kinematics_params"
#: How closely the table derived from a YAML must reproduce the description's
#: tool pose (m and rad): the extraction is exact up to round-off.
YAML_TABLE_TOL = 1e-9


def split_files(paths: Sequence[Path]) -> tuple[UrCalibration | None, UrCalibration | None]:
    """Read the calibration files: at most one table (conf or KinematicsInfo), at most one YAML.

    Raises:
        CalibrationError: Two tables, two YAMLs, or more than two files.
        InputFileError: A file cannot be read.
    """
    table: UrCalibration | None = None
    yaml: UrCalibration | None = None
    for path in paths:
        cal = read_ur_calibration(path)
        if cal.form == "ur_calibration YAML":
            if yaml is not None:
                raise CalibrationError(path, f"a second ur_calibration YAML (first: {yaml.path})")
            yaml = cal
        else:
            if table is not None:
                raise CalibrationError(
                    path,
                    f"a second calibration table (first: {table.path}, a {table.form}); give "
                    "one of calibration.conf and KinematicsInfo",
                )
            table = cal
    if table is None and yaml is None:
        raise CalibrationError(Path("."), "no calibration file given")
    return table, yaml


def _ur_description(nominal: Model, yaml: UrCalibration) -> None:
    urdf = nominal.urdf
    if urdf is None or not urdf.xacro or "ur_type" not in urdf.xacro_args:
        raise CalibrationError(
            yaml.path,
            f"{nominal.name!r} has no UR xacro description to read a ur_calibration YAML with "
            "(its [urdf] must be UR's ur.urdf.xacro with xacro_args ur_type, as the bundled "
            "UR models have)",
        )


def screen_kinematics(model: Model) -> None:
    """Read the YAML a model's UR description expands with, as ``fkcheck calibration`` reads it.

    A calibrated model (``[calibration]``), or any model on UR's bundled
    description, that names a ``kinematics_params`` file in ``[urdf.xacro_files]``:
    that file must be a ur_calibration YAML that
    :func:`~fkcheck.calibration.ur_files.read_ur_calibration` accepts — numbers
    only, bounded, each key once — before the description is expanded with it.
    The expansion would otherwise evaluate a string such as ``"${0.5}"`` as an
    expression, which the calibration reader refuses: one screen at both places.

    Raises:
        CalibrationError: The file is not such a YAML (one line naming it).
        InputFileError: The file cannot be read.
    """
    from fkcheck.urdf.locate import FKCHECK_PREFIX, locate

    urdf = model.urdf
    if urdf is None or KINEMATICS_ARG not in urdf.xacro_files:
        return
    on_ur = urdf.path.startswith(f"{FKCHECK_PREFIX}ur_description/")
    if model.calibration is None and not on_ur:
        return
    base = Path.cwd() if model.path is None else model.path.parent
    path = locate(urdf.xacro_files[KINEMATICS_ARG], base)
    try:
        cal = read_ur_calibration(path)
    except CalibrationError as exc:
        raise CalibrationError(
            exc.path, f"{exc.problem} (the {KINEMATICS_ARG} of {model.name}'s description)"
        ) from None
    if cal.form != "ur_calibration YAML":
        raise CalibrationError(
            path,
            f"a {cal.form}, not a ur_calibration YAML (the {KINEMATICS_ARG} of "
            f"{model.name}'s description)",
        )


def with_kinematics(model: Model, yaml_path: Path, output: Path | None) -> Model:
    """``model`` whose UR description reads ``yaml_path`` as ``kinematics_params``."""
    from fkcheck.urdf.locate import path_for

    assert model.urdf is not None
    files = dict(model.urdf.xacro_files)
    files[KINEMATICS_ARG] = path_for(yaml_path, output)
    args = {k: v for k, v in model.urdf.xacro_args.items() if k != KINEMATICS_ARG}
    return replace(model, urdf=replace(model.urdf, xacro_files=files, xacro_args=args))


def calibrated_description(
    model: Model, nominal: Model, yaml: UrCalibration | None, output: Path | None
) -> Model:
    """The calibrated model's ``[urdf]``: UR's description with the YAML, or none.

    Raises:
        CalibrationError: A YAML is given but the nominal model has no UR xacro description.
    """
    if yaml is None or model.calibration is None or model.calibration.form == yaml.form:
        frames = {name: replace(spec, urdf=None) for name, spec in model.frames.items()}
        return replace(model, urdf=None, frames=frames)
    _ur_description(nominal, yaml)
    relocated = _relocated(model, nominal, output)
    return with_kinematics(relocated, yaml.path, output)


def _relocated(model: Model, nominal: Model, output: Path | None) -> Model:
    """The nominal model's ``[urdf]`` paths as the written file must name them.

    A printed model is taken to be written in the current directory.
    """
    from fkcheck.model.write import relocate_urdf_path

    target = output if output is not None else Path.cwd() / "calibrated.toml"
    moved = relocate_urdf_path(replace(model, path=nominal.path), target)
    return replace(moved, path=model.path)


def table_from_yaml(nominal: Model, yaml: UrCalibration | None) -> DhValues:
    """The standard-DH table of UR's description expanded with the YAML, ``base`` → ``tool0``.

    Raises:
        CalibrationError: The nominal model has no UR description, or the
            extraction leaves a base or tool transform (the table alone would
            not reproduce the description's ``tool0``).
    """
    from fkcheck.description.registry import load_description
    from fkcheck.urdf.to_dh import dh_from_urdf

    assert yaml is not None
    _ur_description(nominal, yaml)
    # The nominal model's own [urdf], read from where it is; the YAML by its absolute path.
    model = with_kinematics(nominal, yaml.path.resolve(), None)
    tree = load_description(model, mapping=False).tree
    extraction = dh_from_urdf(tree, "base", "tool0", "standard")
    derived = extraction.model
    for label, offset in (("base", derived.base), ("tool", derived.tool)):
        if not np.allclose(offset.matrix, np.eye(4), rtol=0.0, atol=YAML_TABLE_TOL):
            raise CalibrationError(
                yaml.path,
                f"UR's description with this YAML puts tool0 off the last joint's DH frame "
                f"({label} transform left by the extraction): it is no UR arm's calibration",
            )
    joints = derived.joints
    return DhValues(
        theta=tuple(j.theta for j in joints),
        a=tuple(j.a for j in joints),
        d=tuple(j.d for j in joints),
        alpha=tuple(j.alpha for j in joints),
    )
