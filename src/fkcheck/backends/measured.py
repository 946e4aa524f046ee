"""The ``poses:<file.csv>`` backend: measured or teach-pendant poses as the reference.

A team's real robot becomes a reference: a CSV of joint values and the pose a
controller showed (or a tracker measured) for each. The file:

.. code-block:: text

    # fkcheck poses: from=base to=tool0        (optional; default: the model's [check])
    q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,rx,ry,rz
    30,-60,90,-120,-90,45,-505.612,-417.951,178.795,2.492393,1.912480,0.000000

Columns, by header name:

* joints ``q1 … qn`` in radians / metres, or ``q1_deg …`` in degrees (revolute joints);
* position ``x, y, z`` in metres, or ``x_mm, y_mm, z_mm``;
* rotation, one of: ``qx, qy, qz, qw`` (quaternion); ``rx, ry, rz`` (rotation vector in
  radians, as a UR pendant shows it); ``roll, pitch, yaw`` (URDF rpy); ``A, B, C``
  (Z-Y'-X'' Euler) — the angles in radians, or with ``_deg`` in degrees.

The poses are ``from_T_to`` for one frame pair. They exist only at the file's
configurations, so this backend answers for exactly those: the check must run on
them (``configurations()``), and any other configuration makes it *skipped*
with that reason. Measured poses are noisy: compare them with a tolerance that
fits the measurement (``--tol-pos 1e-3``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.base import BackendUnavailable, Evidence, FrameUnavailable
from fkcheck.backends.registry import BackendOptions
from fkcheck.errors import FkcheckError
from fkcheck.model import Model

__all__ = ["MeasuredPoses", "PosesFileError", "read_poses_file"]

Float = NDArray[np.float64]

#: Joint values within this of a file row (radians / metres) are that row.
MATCH_TOL = 1e-9
_PAIR = re.compile(r"^#\s*fkcheck poses:\s*from\s*=\s*(\S+)\s+to\s*=\s*(\S+)\s*$")
_ROTATIONS: dict[str, tuple[str, ...]] = {
    "quat": ("qx", "qy", "qz", "qw"),
    "rotvec": ("rx", "ry", "rz"),
    "rpy": ("roll", "pitch", "yaw"),
    "zyx": ("A", "B", "C"),
}


class PosesFileError(FkcheckError):
    """A measured-poses file that cannot be read.

    Attributes:
        path: The file.
        problem: What is wrong (with the line number where there is one).
    """

    def __init__(self, path: Path, problem: str) -> None:
        self.path = path
        self.problem = problem
        super().__init__(f"{path}: {problem}")


def _column(header: list[str], names: Sequence[str], path: Path) -> tuple[list[int], float]:
    """Indices of ``names`` (or ``names`` + unit suffix) and the factor to SI units."""
    for suffix, factor in (("", 1.0), ("_deg", math.pi / 180), ("_mm", 1e-3)):
        wanted = [n + suffix for n in names]
        if all(w in header for w in wanted):
            return [header.index(w) for w in wanted], factor
    raise PosesFileError(
        path,
        f"header needs columns {', '.join(names)} (or with _deg/_mm); it has: {', '.join(header)}",
    )


def read_poses_file(path: Path, model: Model) -> tuple[Float, Float, tuple[str, str] | None]:
    """Read a measured-poses CSV.

    Args:
        path: The file.
        model: The model (joint count and types).

    Returns:
        ``(q, poses, pair)``: ``(N, n)`` joint values (radians / metres), ``(N, 4, 4)``
        poses ``from_T_to`` and the frame pair the file declares, if it does.

    Raises:
        PosesFileError: Unreadable, a missing column, a bad number, or no rows.
    """
    from fkcheck.pose_formats import matrix_from_pose

    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise PosesFileError(path, f"cannot read: {exc}") from None
    pair = None
    rows: list[tuple[int, list[str]]] = []
    header: list[str] | None = None
    for lineno, line in enumerate(lines, start=1):
        text = line.strip()
        match = _PAIR.match(text)
        if match:
            pair = (match.group(1), match.group(2))
            continue
        if not text or text.startswith("#"):
            continue
        cells = [c.strip() for c in text.split(",")]
        if header is None:
            header = cells
        else:
            rows.append((lineno, cells))
    if header is None or not rows:
        raise PosesFileError(path, "no header line and data rows")
    n = model.dof
    q_cols, q_factor = _column(header, [f"q{i + 1}" for i in range(n)], path)
    p_cols, p_factor = _column(header, ["x", "y", "z"], path)
    found = None
    for fmt, names in _ROTATIONS.items():
        try:
            found = fmt, *_column(header, names, path)
        except PosesFileError:
            continue
        break
    if found is None:
        raise PosesFileError(
            path,
            "header needs a rotation: qx,qy,qz,qw or rx,ry,rz or "
            f"roll,pitch,yaw or A,B,C; it has: {', '.join(header)}",
        )
    fmt, r_cols, r_factor = found
    if fmt == "quat":
        r_factor = 1.0
    q = np.empty((len(rows), n))
    values = np.empty((len(rows), 3 + len(r_cols)))
    for k, (lineno, cells) in enumerate(rows):
        try:
            numbers = [float(c) for c in cells]
        except ValueError:
            raise PosesFileError(path, f"line {lineno}: not all numbers") from None
        if len(numbers) != len(header) or not all(math.isfinite(v) for v in numbers):
            raise PosesFileError(path, f"line {lineno}: expected {len(header)} finite numbers")
        q[k] = [numbers[c] for c in q_cols]
        values[k, :3] = [numbers[c] * p_factor for c in p_cols]
        values[k, 3:] = [numbers[c] * r_factor for c in r_cols]
    if q_factor != 1.0:  # degrees apply to revolute joints only
        revolute = np.array([j.type == "revolute" for j in model.joints])
        q[:, revolute] *= q_factor
    try:
        poses = matrix_from_pose(values, fmt)  # type: ignore[arg-type]
    except ValueError as exc:
        raise PosesFileError(path, str(exc)) from None
    return q, poses, pair


class MeasuredPoses:
    """Reference poses read from a CSV file, at that file's configurations.

    Attributes:
        name: ``"poses:<path>"``.
        method: ``"measured poses (CSV)"``.
        path: The CSV file.
    """

    method = "measured poses (CSV)"
    evidence: Evidence = "table"

    def __init__(self, arg: str, options: BackendOptions | None = None) -> None:
        """Build the backend for the CSV file ``arg``."""
        self.path = Path(arg)
        self.name = f"poses:{arg}"
        self.options = options or BackendOptions()

    def unavailable_reason(self, model: Model) -> str | None:
        """``None`` when the file exists; it is read (and validated) when used."""
        return None if self.path.is_file() else f"no such file: {self.path}"

    def configurations(self, model: Model) -> Float:
        """The file's joint values, ``(N, n)``: the check must run on these."""
        return read_poses_file(self.path, model)[0]

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """``[identity, from_T_to]`` for the file's pair, at the file's configurations.

        Raises:
            PosesFileError: The file cannot be read.
            FrameUnavailable: ``frames`` is not the file's pair.
            BackendUnavailable: A configuration is not in the file.
        """
        file_q, poses, pair = read_poses_file(self.path, model)
        pair = pair or (model.check.frame_from, model.check.frame_to)
        if tuple(frames) != pair:
            raise FrameUnavailable(
                f"{self.path.name} holds poses of {pair[1]} in {pair[0]}, not "
                f"{' → '.join(frames)} (declare the pair with '# fkcheck poses: from=… to=…')"
            )
        q = np.asarray(q, dtype=np.float64)
        out = np.empty((2, q.shape[0], 4, 4))
        out[0] = np.eye(4)
        for k, row in enumerate(q):
            diff = np.abs(file_q - row).max(axis=1)
            match = int(np.argmin(diff))
            if diff[match] > MATCH_TOL:
                raise BackendUnavailable(
                    f"{self.path.name} has no pose for configuration {k} (measured poses exist "
                    "only at the file's configurations: run on them, e.g. fkcheck diagnose)"
                )
            out[1, k] = poses[match]
        return out
