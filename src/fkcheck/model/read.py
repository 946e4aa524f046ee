"""Reading model files: the TOML schema and the plain DH CSV, validated into a ``Model``.

Files are read by :mod:`fkcheck.io.files` (a regular file of at most 1 MiB,
UTF-8, a leading byte-order mark skipped), the CSV's numbers by
:func:`fkcheck.io.numbers.parse_number` (plain ASCII decimals only). Every bad
field raises :class:`~fkcheck.errors.ModelError` naming the file, the field and
the problem; the bounds are those of :mod:`fkcheck.model.types`, and of
:mod:`fkcheck.core.tolerances` for ``[check]`` tolerances and known differences.
"""

from __future__ import annotations

import re
import sys
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from fkcheck.errors import ModelError
from fkcheck.io.files import MAX_MODEL_FILE_BYTES, InputFileError, read_text
from fkcheck.io.numbers import NumberError, parse_number, split_fields
from fkcheck.model.sections.calibration import read_calibration
from fkcheck.model.sections.check import read_check
from fkcheck.model.sections.frames import read_frames
from fkcheck.model.sections.header import read_free_text, read_header
from fkcheck.model.sections.joints import read_joints
from fkcheck.model.sections.known_difference import read_known_differences
from fkcheck.model.sections.lint import read_lint
from fkcheck.model.sections.mjcf import read_mjcf
from fkcheck.model.sections.offsets import read_offset
from fkcheck.model.sections.poses import read_poses
from fkcheck.model.sections.reader import Reader
from fkcheck.model.sections.urdf import read_urdf
from fkcheck.model.types import CheckSpec, Model, Offset

__all__ = [
    "bundled_model_paths",
    "bundled_models_dir",
    "is_model_file",
    "load_model",
    "model_from_dict",
]

_TOP_KEYS = {
    "name", "description", "source", "convention", "angle_unit",
    "joint", "base", "tool", "poses", "urdf", "mjcf", "frames", "check", "lint", "known_difference",
    "calibration",
}  # fmt: skip
_INT_DIGITS = sys.get_int_max_str_digits()
_CSV_COLUMNS = ("a", "alpha", "d", "theta_offset")


def bundled_models_dir() -> Path:
    """The directory holding the bundled model files."""
    package = Path(__file__).resolve().parents[1]  # src/fkcheck, or site-packages/fkcheck
    for candidate in (package / "_bundled_models", package.parents[1] / "models"):
        if candidate.is_dir():
            return candidate
    raise ModelError(None, "", "bundled models not found: the installation is incomplete")


def bundled_model_paths() -> dict[str, Path]:
    """Bundled model names and their files, sorted by name."""
    return {p.stem: p for p in sorted(bundled_models_dir().glob("*.toml"))}


def load_model(name_or_path: str | Path) -> Model:
    """Load a model: a bundled name (``"ur5"``), a ``.toml`` file or a DH ``.csv`` file.

    Raises:
        ModelError: The file is missing or invalid, or the name is unknown.
    """
    text = str(name_or_path)
    path = Path(name_or_path)
    if not path.exists() and "/" not in text and "\\" not in text and path.suffix == "":
        bundled = bundled_model_paths()
        if text not in bundled:
            raise ModelError(
                None,
                "",
                f"no model file {text!r} and no bundled model of that name; "
                f"bundled models are: {', '.join(bundled)}",
            )
        path = bundled[text]
    try:
        content = read_text(path, MAX_MODEL_FILE_BYTES)
    except InputFileError as exc:
        raise ModelError(path, "", exc.problem) from None
    if path.suffix.lower() == ".csv":
        return _model_from_csv(content, path)
    try:
        data = tomllib.loads(content)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(path, "", f"not valid TOML: {exc}") from None
    except ValueError:  # tomllib's int() of more than sys.get_int_max_str_digits() digits
        raise ModelError(
            path, "", f"number too large: an integer of more than {_INT_DIGITS} digits"
        ) from None
    except RecursionError:  # arrays or inline tables nested thousands deep
        raise ModelError(path, "", "not valid TOML: arrays or tables nested too deeply") from None
    return model_from_dict(data, path)


#: A ``[[joint]]`` table header: what makes a TOML file a model file.
_JOINT_TABLE = re.compile(r"^[ \t]*\[\[[ \t]*joint[ \t]*\]\]", re.MULTILINE)


def is_model_file(path: Path) -> bool:
    """Whether a file found by a glob or in a directory is a robot model file.

    A ``.toml`` file is one when it has a ``[[joint]]`` table (or a top-level
    ``joint`` array), a ``.csv`` file when its first row is a DH row (five fields,
    the last four numbers): ``pyproject.toml``, ``Cargo.toml`` or a poses CSV
    are not. A file that cannot be read counts as one, so that its reader says
    what is wrong with it instead of the file going unnoticed.
    """
    try:
        content = read_text(path, MAX_MODEL_FILE_BYTES)
    except InputFileError:
        return True
    if path.suffix.lower() == ".csv":
        for line in content.splitlines():
            if line.strip() and not line.strip().startswith("#"):
                fields = split_fields(line)
                try:
                    for _, text in fields[1:]:
                        parse_number(text)
                except NumberError:
                    return False
                return len(fields) == 5
        return False
    if _JOINT_TABLE.search(content):
        return True
    try:
        return "joint" in tomllib.loads(content)
    except (tomllib.TOMLDecodeError, ValueError, RecursionError):
        return False


def _model_from_csv(content: str, path: Path) -> Model:
    """Read a plain DH CSV: ``name,a,alpha,d,theta_offset`` per joint, standard DH, radians.

    The layout of the DH file the robot-model article (Part 3) of a series on a
    C++/Eigen arm controller reads (its ``parseDhCsv``).
    """
    joints = []
    for lineno, line in enumerate(content.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        fields = split_fields(line)
        where = f"line {lineno}"
        if len(fields) != 5:
            raise ModelError(
                path,
                where,
                "expected 5 comma-separated fields (name,a,alpha,d,theta_offset), "
                f"got {len(fields)}",
            )
        values = []
        for label, (column, text) in zip(_CSV_COLUMNS, fields[1:], strict=True):
            try:
                values.append(parse_number(text))
            except NumberError as exc:
                raise ModelError(path, f"{where}.{label} (column {column})", exc.problem) from None
        joints.append({"name": fields[0][1].strip(), "a": values[0], "alpha": values[1],
                       "d": values[2], "theta": values[3]})  # fmt: skip
    data: dict[str, Any] = {"name": path.stem, "convention": "standard", "joint": joints,
                            "source": f"DH CSV {path.name}"}  # fmt: skip
    return model_from_dict(data, path)


def model_from_dict(data: Mapping[str, Any], path: Path | None = None) -> Model:
    """Validate a parsed model file (the TOML schema) into a :class:`Model`.

    Each section has its reader in :mod:`fkcheck.model.sections`; they run in
    this order, so that a file with several faults is told the first one.

    Args:
        data: The parsed TOML document.
        path: The file it came from, for messages and relative URDF paths.

    Raises:
        ModelError: Anything missing, mistyped, unknown, non-finite or inconsistent.
    """
    r = Reader(path)
    top = r.table(dict(data), "", _TOP_KEYS)
    if not top:
        raise r.fail("", "empty model file (needs name, convention and [[joint]] rows)")
    header = read_header(r, top)
    to_rad = header.to_rad
    calibration = read_calibration(r, top["calibration"]) if "calibration" in top else None
    linearised = calibration is not None and calibration.status == 2
    joints, warnings = read_joints(r, top, header, linearised=linearised)
    n = len(joints)
    base = read_offset(r, top["base"], "base", to_rad) if "base" in top else Offset()
    tool = read_offset(r, top["tool"], "tool", to_rad) if "tool" in top else Offset()
    poses = read_poses(r, top["poses"], joints, to_rad) if "poses" in top else {}
    urdf = read_urdf(r, top["urdf"], n) if "urdf" in top else None
    mjcf = read_mjcf(r, top["mjcf"], n) if "mjcf" in top else None
    frames = read_frames(r, top, n, to_rad)
    check = read_check(r, top["check"], frames) if "check" in top else CheckSpec()
    lint_ignore = read_lint(r, top["lint"]) if "lint" in top else ()
    known = read_known_differences(r, top.get("known_difference"))
    return Model(
        name=header.name,
        convention=header.convention,
        joints=joints,
        description=read_free_text(r, top, "description"),
        source=read_free_text(r, top, "source"),
        base=base,
        tool=tool,
        poses=poses,
        urdf=urdf,
        mjcf=mjcf,
        frames=frames,
        check=check,
        angle_unit=header.angle_unit,
        path=path,
        warnings=warnings,
        lint_ignore=lint_ignore,
        known_differences=known,
        calibration=calibration,
    )
