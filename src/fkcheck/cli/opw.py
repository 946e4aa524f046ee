"""``fkcheck opw``: a model's OPW parameters as MoveIt's ``opw_kinematics`` YAML.

The parameters are derived from the DH table by geometry
(:func:`fkcheck.ik.opw_params.derive_opw`) and checked by comparing
py-opw-kinematics' FK with the table's on the check's configurations; the YAML's
leading comments say how far apart they were. Exit 0 when they agree within the
model's tolerances, 1 when not (the derivation or the library is wrong), 2 when the
table is not an OPW arm (the line says which condition fails) or py-opw-kinematics
is not installed.
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from fkcheck.ik.opw_params import OpwDeviation, OpwParameters
    from fkcheck.model.types import Model

__all__ = ["DEFAULT_SAMPLES", "INSTALL_IK", "ROUNDOFF", "add_parser", "opw_yaml", "run"]

#: The command that installs the IK solvers' libraries.
INSTALL_IK = "pip install 'fkcheck[ik]'"

#: Random configurations compared when nobody says (on top of the structured ones).
DEFAULT_SAMPLES = 1000


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "opw",
        help="the model's OPW parameters as MoveIt opw_kinematics YAML",
        description="Derive the OPW parameters (a1, a2, b, c1, c2, c3, c4, joint offsets "
        "and sign corrections) of a six-axis arm with an ortho-parallel basis and a "
        "spherical wrist from its DH table, check them by comparing py-opw-kinematics' "
        "FK with the table's, and print them as MoveIt's opw_kinematics YAML. Exit 2 "
        "with the failing condition when the arm is not OPW-shaped.",
    )
    p.add_argument(
        "model", metavar="MODEL", help="bundled model name (kr6r700sixx) or a .toml/.csv file"
    )
    p.add_argument(
        "--samples",
        type=int,
        default=DEFAULT_SAMPLES,
        help=f"random configurations compared (default {DEFAULT_SAMPLES}), on top of "
        "named poses, zero, mid-range and limit corners",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of the random configurations")
    p.set_defaults(run=run)


#: A printed length (m) or angle (rad) smaller than this is round-off of a zero
#: (9.9e-17 after a rotation by exact quarter turns) and is printed as 0.0.
ROUNDOFF = 1e-12


def _number(value: float) -> str:
    """A length or angle as the YAML shows it: 12 significant digits, round-off as 0.0."""
    if abs(value) < ROUNDOFF:
        return "0.0"
    text = f"{value:.12g}"
    if text in ("-0", "0"):
        return "0.0"
    return text if any(c in text for c in ".en") else f"{text}.0"


def opw_yaml(model: Model, params: OpwParameters, deviation: OpwDeviation) -> str:
    """The parameters as MoveIt ``opw_kinematics`` YAML, with comments on their provenance.

    Args:
        model: The model they were derived from.
        params: The parameters.
        deviation: The FK comparison that checked them.

    Returns:
        The YAML text, newline-terminated.
    """
    from fkcheck.core.geometry import rpy_from_matrix

    lines = [
        f"# OPW parameters of {model.name}, derived from its DH table by fkcheck opw.",
        f"# the FK of py-opw-kinematics against the table over {deviation.samples} configurations: "
        f"at most {deviation.max_position_m:.3g} m, {deviation.max_angle_rad:.3g} rad.",
    ]
    for what, matrix, ok in (
        ("base", params.world_T_base, params.base_is_world),
        ("tool", params.flange_T_tcp, params.tool_is_tcp),
    ):
        if not ok:
            xyz = ", ".join(_number(v) for v in matrix[:3, 3])
            rpy = ", ".join(_number(v) for v in rpy_from_matrix(matrix))
            where = (
                "OPW's base frame is not the model's world: world_T_opw_base"
                if what == "base"
                else "OPW's tool frame is not the model's TCP: opw_tool_T_tcp"
            )
            lines.append(f"# {where} = xyz [{xyz}] rpy [{rpy}] (rad)")
    lines.append("opw_kinematics_geometric_parameters:")
    lines += [f"  {name}: {_number(value)}" for name, value in params.lengths.items()]
    offsets = ", ".join(_number(v) for v in params.offsets)
    signs = ", ".join(str(s) for s in params.sign_corrections)
    lines.append(f"opw_kinematics_joint_offsets: [{offsets}]")
    lines.append(f"opw_kinematics_joint_sign_corrections: [{signs}]")
    return "\n".join(lines) + "\n"


def run(args: argparse.Namespace) -> int:
    """Derive, check and print; the exit code."""
    from fkcheck.ik.opw_params import derive_opw, opw_fk_deviation
    from fkcheck.io.text import terminal_text
    from fkcheck.model.options import check_option
    from fkcheck.model.read import load_model

    samples = check_option("samples", args.samples, "--samples")
    seed = check_option("seed", args.seed, "--seed")
    model = load_model(args.model)
    params = derive_opw(model)
    try:
        deviation = opw_fk_deviation(model, params, samples, seed)
    except ModuleNotFoundError as exc:
        if exc.name != "py_opw_kinematics":
            raise
        print(
            "fkcheck: error: opw: py-opw-kinematics is not installed (no module "
            f"'py_opw_kinematics'); it comes with fkcheck's 'ik' extra: {INSTALL_IK}",
            file=sys.stderr,
        )
        return 2
    for line in opw_yaml(model, params, deviation).splitlines():
        print(terminal_text(line))
    tol_pos, tol_rot = model.check.tol_pos_m, model.check.tol_rot_rad
    if deviation.max_position_m > tol_pos or deviation.max_angle_rad > tol_rot:
        print(
            f"fkcheck: opw: {model.name}: py-opw-kinematics' FK with these parameters is "
            f"{deviation.max_position_m:.3g} m, {deviation.max_angle_rad:.3g} rad from the "
            f"table's (tolerances {tol_pos:g} m, {tol_rot:g} rad): the parameters are wrong",
            file=sys.stderr,
        )
        return 1
    return 0
