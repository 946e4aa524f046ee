"""Reading model files: the TOML schema and the plain DH CSV, validated into a ``Model``.

Files are read by :mod:`fkcheck.io.files` (a regular file of at most 1 MiB,
UTF-8, a leading byte-order mark skipped), the CSV's numbers by
:func:`fkcheck.io.numbers.parse_number` (plain ASCII decimals only). Every bad
field raises :class:`~fkcheck.errors.ModelError` naming the file, the field and
the problem; the bounds are those of :mod:`fkcheck.model.types`, and of
:mod:`fkcheck.core.tolerances` for ``[check]`` tolerances and known differences.
"""

from __future__ import annotations

import math
import re
import sys
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from fkcheck.core.tolerances import LimitKind, limit_problem
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.errors import ModelError
from fkcheck.io.files import MAX_MODEL_FILE_BYTES, InputFileError, read_text
from fkcheck.io.numbers import NumberError, parse_number, show_text, split_fields
from fkcheck.model.lint_rules import LINT_RULES, parse_lint_rules
from fkcheck.model.require import parse_require
from fkcheck.model.types import (
    MAX_JOINT_RAD,
    MAX_JOINTS,
    MAX_LENGTH_M,
    PACKAGE_NAME,
    CheckSpec,
    FrameSpec,
    Joint,
    KnownDifference,
    Model,
    Offset,
    UrdfSpec,
)

__all__ = [
    "KNOWN_DIFFERENCE_BACKENDS",
    "KNOWN_DIFFERENCE_PREFIXES",
    "bundled_model_paths",
    "bundled_models_dir",
    "is_model_file",
    "load_model",
    "model_from_dict",
]

_TOP_KEYS = {
    "name", "description", "source", "convention", "angle_unit",
    "joint", "base", "tool", "poses", "urdf", "frames", "check", "lint", "known_difference",
}  # fmt: skip
_JOINT_KEYS = {"name", "type", "a", "alpha", "d", "theta", "flip", "limits"}
_OFFSET_KEYS = {"xyz", "rpy"}
_URDF_KEYS = {"path", "joints", "xacro", "xacro_args", "packages"}
_FRAME_KEYS = {"dh", "xyz", "rpy", "urdf", "source"}
_CHECK_KEYS = {
    "from", "to", "tol_pos_m", "tol_rot_rad", "require",
    "jacobian", "jacobian_reference", "tol_jacobian",
}  # fmt: skip
_LINT_KEYS = {"ignore"}
_KNOWN_DIFFERENCE_KEYS = {"backends", "finding", "max_position_m", "max_angle_rad"}
_CHECK_LIMITS: dict[str, LimitKind] = {
    "tol_pos_m": "tol_pos", "tol_rot_rad": "tol_rot", "tol_jacobian": "tol_jacobian",
}  # fmt: skip
_KNOWN_DIFFERENCE_LIMITS: dict[str, LimitKind] = {
    "max_position_m": "known_position", "max_angle_rad": "known_angle",
}  # fmt: skip
#: Backends a ``[[known_difference]]`` may name: those whose evidence is
#: independent of the table (the URDF parsers) and the prefixed ones that are
#: (a published table, measured poses). ``rtb-dh``, ``pinocchio-dh``, plugins and
#: ``cmd:`` programs run the model's own table: their disagreement is a bug, never
#: a known difference. (tests/model/test_known_difference.py keeps this in step
#: with the backend registry.)
KNOWN_DIFFERENCE_BACKENDS = ("pinocchio-urdf", "yourdfpy-urdf", "rtb-urdf", "idyntree-urdf")
KNOWN_DIFFERENCE_PREFIXES = ("rtb-model:", "poses:")
_CONVENTIONS = ("standard", "modified")
_JOINT_TYPES = ("revolute", "prismatic")
_ANGLE_UNITS = ("rad", "deg")
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


class _Reader:
    """Typed accessors that raise ModelError naming the file and field."""

    def __init__(self, path: Path | None) -> None:
        self.path = path

    def fail(self, field_: str, problem: str) -> ModelError:
        return ModelError(self.path, field_, problem)

    def table(self, value: Any, field_: str, allowed: set[str]) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise self.fail(field_, f"expected a table, got {_kind(value)}")
        unknown = sorted(set(value) - allowed)
        if unknown:
            raise self.fail(
                f"{field_}.{_key(unknown[0])}" if field_ else _key(unknown[0]),
                f"unknown key; allowed keys are: {', '.join(sorted(allowed))}",
            )
        return value

    def number(self, value: Any, field_: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(field_, f"expected a number, got {_kind(value)}")
        try:
            result = float(value)
        except OverflowError:  # a TOML integer of hundreds of digits
            digits = _digits(int(value))
            raise self.fail(field_, f"number too large: an integer of {digits} digits") from None
        if not math.isfinite(result):
            raise self.fail(field_, f"must be a finite number, got {value}")
        return result

    def bounded(self, value: float, field_: str, bound: float, unit: str) -> float:
        if abs(value) > bound:
            raise self.fail(
                field_, f"{value:g} {unit} is beyond ±{bound:g} {unit}, more than any arm needs"
            )
        return value

    def limit(self, value: Any, field_: str, kind: LimitKind) -> float:
        number = self.number(value, field_)
        problem = limit_problem(number, kind)
        if problem is not None:
            raise self.fail(field_, problem)
        return number

    def length(self, value: Any, field_: str) -> float:
        return self.bounded(self.number(value, field_), field_, MAX_LENGTH_M, "m")

    def string(self, value: Any, field_: str) -> str:
        if not isinstance(value, str):
            raise self.fail(field_, f"expected a string, got {_kind(value)}")
        return value

    def choice(self, value: Any, field_: str, choices: tuple[str, ...]) -> str:
        text = self.string(value, field_)
        if text not in choices:
            raise self.fail(field_, f"{show_text(text)} is not one of: {', '.join(choices)}")
        return text

    def numbers(self, value: Any, field_: str, length: int | None) -> list[float]:
        if not isinstance(value, list):
            raise self.fail(field_, f"expected a list of numbers, got {_kind(value)}")
        if length is not None and len(value) != length:
            raise self.fail(field_, f"expected {length} numbers, got {len(value)}")
        return [self.number(v, f"{field_}[{i}]") for i, v in enumerate(value)]


def _text_table(r: _Reader, value: Any, field_: str, what: str) -> dict[str, str]:
    """An inline table of strings (``{ ur_type = "ur5e" }``), each naming ``what``."""
    if not isinstance(value, dict):
        raise r.fail(field_, f'expected a table such as {{ name = "…" }}, got {_kind(value)}')
    for key, item in value.items():
        if not isinstance(item, str):
            raise r.fail(
                f"{field_}.{_key(key)}", f"expected a string ({what}, as text), got {_kind(item)}"
            )
    return dict(value)


def _key(name: str) -> str:
    """A key or name from the file as it goes into a message: as is when short and printable."""
    return name if name.isprintable() and len(name) <= 64 else show_text(name)


def _value(value: Any) -> str:
    """A scalar from the file as it goes into a message (short, one line); else its kind."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 64:
        return f"an integer of {_digits(value)} digits"
    if isinstance(value, str):
        return show_text(value)
    return repr(value) if isinstance(value, int | float) else _kind(value)


def _digits(value: int) -> str:
    """How many decimal digits ``value`` has, without converting it to text."""
    return f"about {int(abs(value).bit_length() * math.log10(2)) + 1}"


def _kind(value: Any) -> str:
    names = {bool: "a boolean", str: "a string", int: "an integer", float: "a number",
             list: "a list", dict: "a table"}  # fmt: skip
    return names.get(type(value), type(value).__name__)


def model_from_dict(data: Mapping[str, Any], path: Path | None = None) -> Model:
    """Validate a parsed model file (the TOML schema) into a :class:`Model`.

    Args:
        data: The parsed TOML document.
        path: The file it came from, for messages and relative URDF paths.

    Raises:
        ModelError: Anything missing, mistyped, unknown, non-finite or inconsistent.
    """
    r = _Reader(path)
    top = r.table(dict(data), "", _TOP_KEYS)
    if not top:
        raise r.fail("", "empty model file (needs name, convention and [[joint]] rows)")
    for required in ("name", "convention"):
        if required not in top:
            raise r.fail(required, "missing (required)")
    name = r.string(top["name"], "name")
    if not name.strip():
        raise r.fail("name", "must not be empty")
    convention = r.choice(top["convention"], "convention", _CONVENTIONS)
    unit = r.choice(top.get("angle_unit", "rad"), "angle_unit", _ANGLE_UNITS)
    to_rad = math.pi / 180.0 if unit == "deg" else 1.0

    raw_joints = top.get("joint")
    if raw_joints is None:
        raise r.fail("joint", "missing: the model needs at least one [[joint]]")
    if not isinstance(raw_joints, list):
        raise r.fail("joint", f"expected an array of tables [[joint]], got {_kind(raw_joints)}")
    if not raw_joints:
        raise r.fail("joint", "no joints: the model needs at least one [[joint]]")
    if len(raw_joints) > MAX_JOINTS:
        raise r.fail("joint", f"{len(raw_joints)} joints is more than the limit of {MAX_JOINTS}")

    def joint_value(value: float, field_: str, jtype: str) -> float:
        """A limit or pose value in radians / metres, within the physical bound."""
        if jtype == "prismatic":
            return r.bounded(value, field_, MAX_LENGTH_M, "m")
        return r.bounded(value, field_, MAX_JOINT_RAD, "rad")

    joints: list[Joint] = []
    seen: dict[str, int] = {}
    warnings: list[str] = []
    for i, raw in enumerate(raw_joints):
        where = f"joint[{i}]"
        row = r.table(raw, where, _JOINT_KEYS)
        for required in ("a", "alpha", "d"):
            if required not in row:
                raise r.fail(f"{where}.{required}", "missing (required)")
        jname = r.string(row.get("name", f"joint{i + 1}"), f"{where}.name")
        if jname in seen:
            raise r.fail(
                f"{where}.name",
                f"duplicate joint name {show_text(jname)} (also joint[{seen[jname]}])",
            )
        seen[jname] = i
        jtype = r.choice(row.get("type", "revolute"), f"{where}.type", _JOINT_TYPES)
        flip = row.get("flip", False)
        if not isinstance(flip, bool):
            raise r.fail(f"{where}.flip", f"expected true or false, got {_kind(flip)}")
        alpha = r.number(row["alpha"], f"{where}.alpha")
        theta = r.number(row.get("theta", 0.0), f"{where}.theta")
        limits = None
        if "limits" in row:
            lo, hi = r.numbers(row["limits"], f"{where}.limits", 2)
            if lo > hi:
                raise r.fail(f"{where}.limits", f"lower {lo} is greater than upper {hi}")
            scale = to_rad if jtype == "revolute" else 1.0
            limits = (
                joint_value(lo * scale, f"{where}.limits[0]", jtype),
                joint_value(hi * scale, f"{where}.limits[1]", jtype),
            )
        if unit == "rad":
            for label, value in (("alpha", alpha), ("theta", theta)):
                if abs(value) > 2 * math.pi + 1e-9:
                    warnings.append(
                        f"{where}.{label} = {value:g} is beyond ±2π: it looks like degrees "
                        'in a file with angle_unit = "rad"'
                    )
        joints.append(
            Joint(
                name=jname,
                type=jtype,  # type: ignore[arg-type]
                a=r.length(row["a"], f"{where}.a"),
                alpha=alpha * to_rad,
                d=r.length(row["d"], f"{where}.d"),
                theta=theta * to_rad,
                flip=flip,
                limits=limits,
            )
        )
    n = len(joints)

    def offset(value: Any, where: str) -> Offset:
        tbl = r.table(value, where, _OFFSET_KEYS)
        xyz = r.numbers(tbl.get("xyz", [0.0, 0.0, 0.0]), f"{where}.xyz", 3)
        for i, v in enumerate(xyz):
            r.bounded(v, f"{where}.xyz[{i}]", MAX_LENGTH_M, "m")
        rpy = r.numbers(tbl.get("rpy", [0.0, 0.0, 0.0]), f"{where}.rpy", 3)
        return Offset(xyz=(xyz[0], xyz[1], xyz[2]),
                      rpy=(rpy[0] * to_rad, rpy[1] * to_rad, rpy[2] * to_rad))  # fmt: skip

    base = offset(top["base"], "base") if "base" in top else Offset()
    tool = offset(top["tool"], "tool") if "tool" in top else Offset()

    poses: dict[str, tuple[float, ...]] = {}
    if "poses" in top:
        raw_poses = top["poses"]
        if not isinstance(raw_poses, dict):
            raise r.fail("poses", f"expected a table, got {_kind(raw_poses)}")
        for pname, values in raw_poses.items():
            nums = r.numbers(values, f"poses.{_key(pname)}", n)
            poses[pname] = tuple(
                joint_value(v * (to_rad if j.type == "revolute" else 1.0),
                            f"poses.{_key(pname)}[{k}]", j.type)
                for k, (v, j) in enumerate(zip(nums, joints, strict=True))
            )  # fmt: skip

    urdf = None
    if "urdf" in top:
        u = r.table(top["urdf"], "urdf", _URDF_KEYS)
        if "path" not in u:
            raise r.fail("urdf.path", "missing (required in [urdf])")
        upath = r.string(u["path"], "urdf.path")
        if not upath.strip() or upath.strip() == "example-robot-data:":
            raise r.fail(
                "urdf.path",
                f"{show_text(upath)} names no file: give the URDF's path (relative to this file) "
                "or example-robot-data:<subpath>",
            )
        raw_uj = u.get("joints")
        if not isinstance(raw_uj, list) or not all(isinstance(x, str) for x in raw_uj):
            raise r.fail("urdf.joints", "expected a list of URDF joint names in DH order")
        if len(raw_uj) != n:
            raise r.fail("urdf.joints", f"names {len(raw_uj)} URDF joints but the DH table has {n}")
        if len(set(raw_uj)) != len(raw_uj):
            raise r.fail("urdf.joints", "names a URDF joint twice")
        xacro = u.get("xacro", False)
        if not isinstance(xacro, bool):
            raise r.fail("urdf.xacro", f"expected true or false, got {_kind(xacro)}")
        xacro_args = _text_table(r, u.get("xacro_args", {}), "urdf.xacro_args", "a value")
        packages = _text_table(r, u.get("packages", {}), "urdf.packages", "a directory")
        for pname in packages:
            if not PACKAGE_NAME.fullmatch(pname):
                raise r.fail(
                    f"urdf.packages.{_key(pname)}",
                    "not a package name (letters, digits, '_', '.', '-')",
                )
        urdf = UrdfSpec(upath, tuple(raw_uj), xacro, xacro_args, packages)

    frames: dict[str, FrameSpec] = {
        "world": FrameSpec("world", "world"),
        "tcp": FrameSpec("tcp", "tcp"),
    }
    if "frames" in top:
        raw_frames = top["frames"]
        if not isinstance(raw_frames, dict):
            raise r.fail("frames", f"expected tables [frames.NAME], got {_kind(raw_frames)}")
        for fname, raw in raw_frames.items():
            where = f"frames.{_key(fname)}"
            tbl = r.table(raw, where, _FRAME_KEYS)
            if "dh" not in tbl:
                raise r.fail(f"{where}.dh", 'missing: the DH frame index 0…n, "tcp" or "world"')
            idx = tbl["dh"]
            if isinstance(idx, bool) or not (
                (isinstance(idx, int) and 0 <= idx <= n) or idx in ("tcp", "world")
            ):
                raise r.fail(f"{where}.dh", f'expected 0…{n}, "tcp" or "world", got {_value(idx)}')
            off = offset({k: tbl[k] for k in ("xyz", "rpy") if k in tbl}, where)
            twin = r.string(tbl["urdf"], f"{where}.urdf") if "urdf" in tbl else None
            source = r.string(tbl["source"], f"{where}.source") if "source" in tbl else ""
            if "source" in tbl and not source.strip():
                raise r.fail(f"{where}.source", "empty: say where the offset comes from")
            frames[fname] = FrameSpec(fname, idx, off, twin, source)

    check = CheckSpec()
    if "check" in top:
        c = r.table(top["check"], "check", _CHECK_KEYS)
        frame_from = r.string(c.get("from", "world"), "check.from")
        frame_to = r.string(c.get("to", "tcp"), "check.to")
        for side, frame_name in (("from", frame_from), ("to", frame_to)):
            if frame_name not in frames:
                raise r.fail(
                    f"check.{side}",
                    f"frame {show_text(frame_name)} is not defined; frames are: "
                    f"{', '.join(_key(f) for f in frames)}",
                )
        tols: dict[str, float] = {}
        for key, kind in _CHECK_LIMITS.items():
            if key in c:
                tols[key] = r.limit(c[key], f"check.{key}", kind)
        require: tuple[str, ...] = ()
        if "require" in c:
            raw_req = c["require"]
            if not isinstance(raw_req, list) or not all(isinstance(x, str) for x in raw_req):
                raise r.fail("check.require", 'expected a list such as ["table"]')
            try:
                require = parse_require(raw_req, "check.require")
            except ValueError as exc:
                raise r.fail("check.require", str(exc).split(": ", 1)[1]) from None
        jacobian = c.get("jacobian", False)
        if not isinstance(jacobian, bool):
            raise r.fail("check.jacobian", f"expected true or false, got {_value(jacobian)}")
        reference = r.string(
            c.get("jacobian_reference", "world-aligned"), "check.jacobian_reference"
        )
        if reference not in JACOBIAN_REFERENCES:
            raise r.fail(
                "check.jacobian_reference",
                f"unknown reference frame {show_text(reference)}; references are: "
                f"{', '.join(JACOBIAN_REFERENCES)}",
            )
        check = CheckSpec(
            frame_from,
            frame_to,
            require=require,
            jacobian=jacobian,
            jacobian_reference=reference,
            **tols,
        )

    lint_ignore: tuple[str, ...] = ()
    if "lint" in top:
        raw_ignore = r.table(top["lint"], "lint", _LINT_KEYS).get("ignore", [])
        if not isinstance(raw_ignore, list) or not all(isinstance(x, str) for x in raw_ignore):
            raise r.fail(
                "lint.ignore",
                f'expected a list of rule names such as ["limits"]; rules are: '
                f"{', '.join(LINT_RULES)}",
            )
        try:
            lint_ignore = parse_lint_rules(_key(x) for x in raw_ignore)
        except ValueError as exc:
            raise r.fail("lint.ignore", str(exc)) from None

    known = _known_differences(r, top.get("known_difference"))

    return Model(
        name=name,
        convention=convention,  # type: ignore[arg-type]
        joints=tuple(joints),
        description=r.string(top.get("description", ""), "description"),
        source=r.string(top.get("source", ""), "source"),
        base=base,
        tool=tool,
        poses=poses,
        urdf=urdf,
        frames=frames,
        check=check,
        angle_unit=unit,  # type: ignore[arg-type]
        path=path,
        warnings=tuple(warnings),
        lint_ignore=lint_ignore,
        known_differences=known,
    )


def _known_differences(r: _Reader, raw: Any) -> tuple[KnownDifference, ...]:
    """The ``[[known_difference]]`` entries, validated (see :class:`KnownDifference`)."""
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise r.fail(
            "known_difference",
            f"expected an array of tables [[known_difference]], got {_kind(raw)}",
        )
    allowed = ", ".join((*KNOWN_DIFFERENCE_BACKENDS, *(p + "…" for p in KNOWN_DIFFERENCE_PREFIXES)))
    entries: list[KnownDifference] = []
    listed: dict[str, int] = {}
    for i, item in enumerate(raw):
        where = f"known_difference[{i}]"
        tbl = r.table(item, where, _KNOWN_DIFFERENCE_KEYS)
        for required in ("backends", "finding"):
            if required not in tbl:
                raise r.fail(f"{where}.{required}", "missing (required)")
        names = tbl["backends"]
        if not isinstance(names, list) or not names or not all(isinstance(x, str) for x in names):
            raise r.fail(
                f"{where}.backends", f"expected a non-empty list of backend names: {allowed}"
            )
        for k, backend in enumerate(names):
            ok = backend in KNOWN_DIFFERENCE_BACKENDS or any(
                backend.startswith(p) and len(backend) > len(p) for p in KNOWN_DIFFERENCE_PREFIXES
            )
            if not ok:
                raise r.fail(
                    f"{where}.backends[{k}]",
                    f"{show_text(backend)} is not a backend whose evidence is independent of the "
                    f"table; known differences may name: {allowed}",
                )
            if backend in listed:
                raise r.fail(
                    f"{where}.backends[{k}]",
                    f"{show_text(backend)} is listed already, "
                    f"in known_difference[{listed[backend]}]",
                )
            listed[backend] = i
        finding = r.string(tbl["finding"], f"{where}.finding")
        if not finding.strip():
            raise r.fail(f"{where}.finding", "must not be empty: say what fkcheck diagnose names")
        bounds: dict[str, float] = {}
        for key, kind in _KNOWN_DIFFERENCE_LIMITS.items():
            if key not in tbl:
                raise r.fail(
                    f"{where}.{key}",
                    "missing (required: the largest error the recorded difference shows, "
                    "so that a larger one still fails)",
                )
            bounds[key] = r.limit(tbl[key], f"{where}.{key}", kind)
        entries.append(KnownDifference(tuple(names), finding, **bounds))
    return tuple(entries)
