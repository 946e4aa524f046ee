"""``fkcheck fk``: print the pose (or every DH frame) for given joint values.

``--from``/``--to`` name the check's frames (``[frames.NAME]``, ``world``,
``tcp``, ``urdf:LINK``) and print ``from_T_to``, as Robotics Toolbox's
``fkine(q, start=, end=)`` does.

Many configurations (``--q-file``) are computed and printed a chunk at a time,
so memory holds the configurations and one chunk of poses, not every pose and
its JSON record at once (a million-line file with ``--json`` peaked at 4 GB).
"""

from __future__ import annotations

import argparse
import itertools
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.io.format import format_fixed
from fkcheck.io.strict_json import strict_json

if TYPE_CHECKING:
    from fkcheck.model.types import Model

__all__ = ["add_parser", "run"]

#: Configurations computed and printed at a time (times ``n + 1`` with --all-frames).
_CHUNK = 65_536


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "fk",
        help="forward kinematics with the in-house core",
        description="Print world_T_tcp (base and tool included) for joint values; "
        "with --from/--to, the pose of one named frame in another (from_T_to); "
        "with --all-frames, every DH frame T_0_i.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5) or a .toml/.csv file")
    src = p.add_mutually_exclusive_group()
    src.add_argument("--q", help="joint values, comma-separated (radians unless --deg)")
    src.add_argument("--q-file", type=Path, help="CSV file: one configuration per line")
    src.add_argument("--pose", help="a named pose of the model (e.g. zero, worked_example)")
    p.add_argument("--deg", action="store_true", help="revolute joint values are in degrees")
    p.add_argument("--all-frames", action="store_true", help="print every DH frame T_0_i")
    p.add_argument(
        "--from",
        dest="frame_from",
        metavar="FRAME",
        help="express the pose in this frame (the check's names: base, base_link, "
        "urdf:LINK…; default: the world)",
    )
    p.add_argument(
        "--to",
        dest="frame_to",
        metavar="FRAME",
        help="the frame whose pose is printed (default: the TCP, tool included)",
    )
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


def _record(
    model_name: str,
    q: NDArray[np.float64],
    T: NDArray[np.float64],
    frames: tuple[str, str] | None = None,
) -> dict[str, Any]:
    record: dict[str, Any] = {"model": model_name, "q_rad": q.tolist()}
    if frames is not None:
        record["from"], record["to"] = frames
    if T.ndim == 3:
        record["frames"] = T.tolist()
        T = T[-1]
    record["matrix"] = T.tolist()
    record["position"] = T[:3, 3].tolist()
    record["rotation"] = T[:3, :3].tolist()
    return record


def _fk_chunks(
    model: Model, q: NDArray[np.float64], args: argparse.Namespace
) -> Iterator[tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """``(q chunk, poses)`` for ``(N, n)`` configurations, a bounded chunk at a time.

    Each pose comes out bit for bit as from one call on the whole batch: the core
    picks its path (JIT or NumPy) by batch size, so when the whole batch would take
    the JIT path, a short last chunk is merged into the one before it.
    """
    from fkcheck.core.dh import JIT_MIN_POSES

    all_frames = args.all_frames
    total = q.shape[0]
    jit = not all_frames and total >= JIT_MIN_POSES
    if all_frames:
        size = max(1, _CHUNK // (model.dof + 1))
    else:
        size = max(_CHUNK, JIT_MIN_POSES) if jit else _CHUNK
    bounds = [*range(0, total, size), total]
    if jit and bounds[-1] - bounds[-2] < JIT_MIN_POSES:
        del bounds[-2]
    for start, stop in itertools.pairwise(bounds):
        yield q[start:stop], _fk(model, q[start:stop], args)


def _write_json_array(records: Iterable[dict[str, Any]]) -> None:
    """Print ``strict_json(list(records))``, byte for byte, one record at a time."""
    separator = "["
    for record in records:
        sys.stdout.write(separator)
        sys.stdout.write(strict_json(record))
        separator = ", "
    sys.stdout.write("]\n")


def _fk(model: Model, q: NDArray[np.float64], args: argparse.Namespace) -> NDArray[np.float64]:
    return model.fk(
        q, all_frames=args.all_frames, frame_from=args.frame_from, frame_to=args.frame_to
    )


def _frame_pair(model: Model, args: argparse.Namespace) -> tuple[str, str] | None:
    """``(from, to)`` as asked with ``--from``/``--to``, frames of ``model``; ``None``: neither.

    Raises:
        FrameError: A frame the model does not name (the message lists its frames).
        OptionError: ``--all-frames`` with ``--from`` or ``--to``.
    """
    from fkcheck.errors import OptionError
    from fkcheck.model.types import resolve_frame

    if args.frame_from is None and args.frame_to is None:
        return None
    for name in (args.frame_from, args.frame_to):
        if name is not None:
            resolve_frame(model, name)
    if args.all_frames:
        flag = "--from" if args.frame_from is not None else "--to"
        raise OptionError(
            "--all-frames",
            f"prints every DH frame in the world; it does not combine with {flag} "
            "(ask for one frame at a time)",
        )
    return (args.frame_from or "world", args.frame_to or "tcp")


def _format_matrix(T: NDArray[np.float64]) -> str:
    return "\n".join(" ".join(f"{format_fixed(v, 6):>10}" for v in row) for row in T)


def run(args: argparse.Namespace) -> int:
    """Compute and print."""
    from fkcheck.errors import JointInputError
    from fkcheck.io.text import terminal_text
    from fkcheck.model.joint_input import (
        check_bounds,
        check_limits,
        parse_q,
        read_q_file,
        to_internal_units,
    )
    from fkcheck.model.read import load_model

    model = load_model(args.model)
    pair = _frame_pair(model, args)  # a wrong frame name is said before anything is read
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
        check_limits(q, model, degrees=args.deg)
    check_bounds(q, model)

    if q.ndim == 2:
        return _print_batch(model, q, args, pair)
    T = _fk(model, q, args)
    if args.format != "matrix":
        return _print_formatted(model.name, q, T, args, pair)
    if args.json:
        print(strict_json(_record(model.name, q, T, pair)))
    elif args.all_frames:
        print("\n\n".join(f"T_0_{i} =\n{_format_matrix(Ti)}" for i, Ti in enumerate(T)))
    else:
        print(_format_matrix(T))
    return 0


def _print_batch(
    model: Model,
    q: NDArray[np.float64],
    args: argparse.Namespace,
    pair: tuple[str, str] | None,
) -> int:
    """Print the poses of ``(N, n)`` configurations, a chunk at a time."""
    from fkcheck.core.pose_formats import pose_from_matrix, pose_record

    chunks = _fk_chunks(model, q, args)
    fmt = args.format
    if args.json:

        def records() -> Iterator[dict[str, Any]]:
            for q_chunk, T in chunks:
                for qi, Ti in zip(q_chunk, T, strict=True):
                    record = _record(model.name, qi, Ti, pair)
                    if fmt != "matrix":
                        record.update(pose_record(Ti[-1] if args.all_frames else Ti, fmt))
                    yield record

        _write_json_array(records())
        return 0
    for _, T in chunks:
        if fmt == "matrix":
            # One line per configuration: the row-major 4x4 (or every frame's, in order).
            rows: Iterable[Iterable[float]] = (Ti.reshape(-1) for Ti in T)
        else:
            # One line per configuration: x y z and the rotation numbers (radians).
            rows = pose_from_matrix(T[:, -1] if args.all_frames else T, fmt)
        sys.stdout.write("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in rows))
    return 0


def _print_formatted(
    model_name: str,
    q: NDArray[np.float64],
    T: NDArray[np.float64],
    args: argparse.Namespace,
    pair: tuple[str, str] | None,
) -> int:
    """Print poses in a controller's format (``--format``) instead of matrices."""
    from fkcheck.core.pose_formats import format_pose, pose_record

    fmt = args.format
    poses = T if args.all_frames else T[None]
    if args.json:
        record = _record(model_name, q, T, pair)
        record.update(pose_record(poses[-1], fmt))
        print(strict_json(record))
    else:
        lines = [format_pose(Ti, fmt, degrees=args.deg) for Ti in poses]
        if args.all_frames:
            lines = [f"T_0_{i}: {line}" for i, line in enumerate(lines)]
        print("\n".join(lines))
    return 0
