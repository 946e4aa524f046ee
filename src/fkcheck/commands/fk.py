"""``fkcheck fk``: print the pose (or every DH frame) for given joint values."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.report.strict_json import strict_json

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "fk",
        help="forward kinematics with the in-house core",
        description="Print world_T_tcp (base and tool included) for joint values; "
        "with --all-frames, every DH frame T_0_i.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5) or a .toml/.csv file")
    src = p.add_mutually_exclusive_group()
    src.add_argument("--q", help="joint values, comma-separated (radians unless --deg)")
    src.add_argument("--q-file", type=Path, help="CSV file: one configuration per line")
    src.add_argument("--pose", help="a named pose of the model (e.g. zero, article)")
    p.add_argument("--deg", action="store_true", help="revolute joint values are in degrees")
    p.add_argument("--all-frames", action="store_true", help="print every DH frame T_0_i")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.add_argument(
        "--format",
        choices=("matrix", "quat", "rpy", "rotvec", "zyx"),
        default="matrix",
        help="pose as a 4x4 matrix (default), xyz + quaternion (qx qy qz qw), xyz + URDF "
        "roll/pitch/yaw, xyz + rotation vector (UR pendant) or xyz + Z-Y'-X'' Euler A, B, C "
        "(angles in degrees with --deg)",
    )
    p.add_argument("--ignore-limits", action="store_true", help="allow values beyond joint limits")
    p.set_defaults(run=run)


def _record(model_name: str, q: NDArray[np.float64], T: NDArray[np.float64]) -> dict[str, Any]:
    record: dict[str, Any] = {"model": model_name, "q_rad": q.tolist()}
    if T.ndim == 3:
        record["frames"] = T.tolist()
        T = T[-1]
    record["matrix"] = T.tolist()
    record["position"] = T[:3, 3].tolist()
    record["rotation"] = T[:3, :3].tolist()
    return record


def _format_matrix(T: NDArray[np.float64]) -> str:
    T = np.where(np.abs(T) < 5e-7, 0.0, T)  # print -0.000000 as 0.000000
    return "\n".join(" ".join(f"{v:10.6f}" for v in row) for row in T)


def run(args: argparse.Namespace) -> int:
    """Compute and print."""
    from fkcheck.errors import JointInputError
    from fkcheck.joint_input import check_limits, parse_q, read_q_file, to_internal_units
    from fkcheck.model import load_model
    from fkcheck.safe_text import terminal_text

    model = load_model(args.model)
    for warning in model.warnings:
        print(f"fkcheck: warning: {terminal_text(warning)}", file=sys.stderr)
    if args.q_file is not None:
        q = to_internal_units(read_q_file(args.q_file, model), model, degrees=args.deg)
    elif args.pose is not None:
        if args.pose not in model.poses:
            raise JointInputError(
                f"--pose: model {model.name} has no pose {args.pose!r}; poses are: "
                f"{', '.join(model.poses) or '(none)'}"
            )
        q = np.array(model.poses[args.pose])
    elif args.q is not None:
        q = to_internal_units(parse_q(args.q, model), model, degrees=args.deg)
    else:
        raise JointInputError("give joint values with --q, --q-file or --pose")
    if not args.ignore_limits:
        check_limits(q, model)

    T = model.fk(q, all_frames=args.all_frames)
    if args.format != "matrix":
        return _print_formatted(model.name, q, T, args)
    if q.ndim == 1:
        if args.json:
            print(strict_json(_record(model.name, q, T)))
        elif args.all_frames:
            print("\n\n".join(f"T_0_{i} =\n{_format_matrix(Ti)}" for i, Ti in enumerate(T)))
        else:
            print(_format_matrix(T))
        return 0
    if args.json:
        print(strict_json([_record(model.name, qi, Ti) for qi, Ti in zip(q, T, strict=True)]))
    else:
        # One line per configuration: the row-major 4x4 (or every frame's, in order).
        lines = (" ".join(repr(float(v)) for v in Ti.reshape(-1)) for Ti in T)
        sys.stdout.write("\n".join(lines) + "\n")
    return 0


def _print_formatted(
    model_name: str, q: NDArray[np.float64], T: NDArray[np.float64], args: argparse.Namespace
) -> int:
    """Print poses in a controller's format (``--format``) instead of matrices."""
    from fkcheck.pose_formats import format_pose, pose_from_matrix, pose_record

    fmt = args.format
    if q.ndim == 1:
        poses = T if args.all_frames else T[None]
        if args.json:
            record = _record(model_name, q, T)
            record.update(pose_record(poses[-1], fmt))
            print(strict_json(record))
        else:
            lines = [format_pose(Ti, fmt, degrees=args.deg) for Ti in poses]
            if args.all_frames:
                lines = [f"T_0_{i}: {line}" for i, line in enumerate(lines)]
            print("\n".join(lines))
        return 0
    last = T[:, -1] if args.all_frames else T
    if args.json:
        records = []
        for qi, Ti, Tl in zip(q, T, last, strict=True):
            record = _record(model_name, qi, Ti)
            record.update(pose_record(Tl, fmt))
            records.append(record)
        print(strict_json(records))
    else:
        # One line per configuration: x y z and the rotation numbers (radians).
        numbers = pose_from_matrix(last, fmt)
        sys.stdout.write("\n".join(" ".join(repr(float(v)) for v in row) for row in numbers))
        sys.stdout.write("\n")
    return 0
