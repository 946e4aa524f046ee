"""Robot models: the TOML schema (and the plain DH CSV), validated into frozen dataclasses.

A model file holds a DH table and, optionally, base/tool transforms, named
poses, the reference URDF with its joint order, named frames that tie DH frames
to URDF frames, and the default check. Everything is validated on load; a bad
file raises :class:`~fkcheck.errors.ModelError` naming the file, the field and
the problem. Angles are stored in radians whatever the file's ``angle_unit``.

Files are read by :mod:`fkcheck.input_files` (a regular file of at most 1 MiB,
UTF-8, a leading byte-order mark skipped), the CSV's numbers by
:func:`fkcheck.numbers.parse_number` (plain ASCII decimals only). Numbers are
bounded by what an arm can be, so that the forward kinematics of a valid model
never overflows: every length (``a``, ``d``, ``xyz``, prismatic limits and pose
values) is within ±:data:`MAX_LENGTH_M` (1 km), every revolute limit and pose
value within ±:data:`MAX_JOINT_RAD` (1000 rad, 159 turns). Fixed angles
(``alpha``, ``theta``, ``rpy``) only enter sines and cosines (and ``θ + q``, with
``q`` bounded), so they need to be finite only.
"""

from __future__ import annotations

import math
import sys
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from fkcheck import dh
from fkcheck._typing import Float
from fkcheck.errors import FrameError, ModelError
from fkcheck.input_files import MAX_MODEL_FILE_BYTES, InputFileError, read_text
from fkcheck.numbers import NumberError, parse_number, show_text, split_fields
from fkcheck.tolerances import DEFAULT_TOL_POS_M, DEFAULT_TOL_ROT_RAD
from fkcheck.transforms import matrix_from_xyz_rpy
from fkcheck.verdict import parse_require

__all__ = [
    "MAX_JOINTS",
    "MAX_JOINT_RAD",
    "MAX_LENGTH_M",
    "URDF_FRAME_PREFIX",
    "CheckSpec",
    "FrameSpec",
    "Joint",
    "Model",
    "Offset",
    "UrdfSpec",
    "bundled_model_paths",
    "load_model",
    "model_from_dict",
    "resolve_frame",
]

JointType = Literal["revolute", "prismatic"]
DhIndex = int | Literal["world", "tcp"]

#: Larger tables are refused: no real arm has them, and a typo-generated file
#: with 10 000 rows should fail fast rather than build a huge chain.
MAX_JOINTS = 256
#: Largest length a model may hold, metres (``a``, ``d``, ``xyz``, prismatic limits
#: and pose values). No arm is a kilometre long; 256 joints this long still keep
#: every pose far from float overflow (``a = 1e308`` made the reference NaN).
MAX_LENGTH_M = 1e3
#: Largest revolute limit or pose value, radians (159 turns). Limits make the
#: sampling box, whose width must stay finite.
MAX_JOINT_RAD = 1e3

_TOP_KEYS = {
    "name", "description", "source", "convention", "angle_unit",
    "joint", "base", "tool", "poses", "urdf", "frames", "check",
}  # fmt: skip
_JOINT_KEYS = {"name", "type", "a", "alpha", "d", "theta", "flip", "limits"}
_OFFSET_KEYS = {"xyz", "rpy"}
_URDF_KEYS = {"path", "joints"}
_FRAME_KEYS = {"dh", "xyz", "rpy", "urdf"}
_CHECK_KEYS = {"from", "to", "tol_pos_m", "tol_rot_rad", "require"}
_CONVENTIONS = ("standard", "modified")
_JOINT_TYPES = ("revolute", "prismatic")
_ANGLE_UNITS = ("rad", "deg")
_INT_DIGITS = sys.get_int_max_str_digits()
_CSV_COLUMNS = ("a", "alpha", "d", "theta_offset")


@dataclass(frozen=True)
class Offset:
    """A fixed transform given as URDF-style ``xyz`` (m) and fixed-axis ``rpy`` (rad)."""

    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def matrix(self) -> Float:
        """The 4×4 homogeneous transform."""
        return matrix_from_xyz_rpy(self.xyz, self.rpy)

    @property
    def is_identity(self) -> bool:
        """Whether both translation and rotation are exactly zero."""
        return not any(self.xyz) and not any(self.rpy)


@dataclass(frozen=True)
class Joint:
    """One row of the DH table, in metres and radians.

    Attributes:
        name: Joint name, unique in the model.
        type: ``"revolute"`` or ``"prismatic"``.
        a: Link length (m); in a modified table, ``a_{i-1}``.
        alpha: Link twist (rad); in a modified table, ``α_{i-1}``.
        d: Link offset (m); for a prismatic joint, added to q.
        theta: Angle offset (rad) added to q; for a prismatic joint, the fixed angle.
        flip: The joint moves the other way (q enters with a minus sign).
        limits: ``(lower, upper)`` in rad (revolute) or m (prismatic), or ``None``.
    """

    name: str
    a: float
    alpha: float
    d: float
    theta: float = 0.0
    type: JointType = "revolute"
    flip: bool = False
    limits: tuple[float, float] | None = None


@dataclass(frozen=True)
class UrdfSpec:
    """Where the model's reference URDF is, and which URDF joint is which DH joint.

    Attributes:
        path: As written: a path (relative to the model file) or
            ``example-robot-data:<subpath>``.
        joints: URDF joint names in DH order, one per DH joint.
    """

    path: str
    joints: tuple[str, ...]


@dataclass(frozen=True)
class FrameSpec:
    """A named frame: where it sits on the DH chain and its URDF twin.

    Attributes:
        name: The frame's name.
        dh: DH frame index ``0…n``, ``"tcp"`` (after the tool) or ``"world"``.
        offset: Fixed transform from that DH frame to this frame.
        urdf: Name of the same frame in the URDF, or ``None``.
    """

    name: str
    dh: DhIndex
    offset: Offset = field(default_factory=Offset)
    urdf: str | None = None


@dataclass(frozen=True)
class CheckSpec:
    """The default check: which frame pair, and the tolerances.

    Attributes:
        frame_from: Name of the frame the pose is expressed in.
        frame_to: Name of the frame whose pose is compared.
        tol_pos_m: Position tolerance, metres.
        tol_rot_rad: Rotation tolerance, radians.
        require: Kinds of evidence a check must verify (``"table"``,
            ``"implementation"``; see :mod:`fkcheck.verdict`).
    """

    frame_from: str = "world"
    frame_to: str = "tcp"
    tol_pos_m: float = DEFAULT_TOL_POS_M
    tol_rot_rad: float = DEFAULT_TOL_ROT_RAD
    require: tuple[str, ...] = ()


@dataclass(frozen=True)
class Model:
    """A validated robot model. Lengths in metres, angles in radians.

    Attributes:
        name: Model name.
        convention: ``"standard"`` or ``"modified"`` DH.
        joints: The DH table, base to tip.
        description: Free text.
        source: Where the numbers come from.
        base: Fixed transform world → DH frame 0.
        tool: Fixed transform last DH frame → TCP.
        poses: Named configurations (radians / metres).
        urdf: The reference URDF, if any.
        frames: Named frames (always includes ``world`` and ``tcp``).
        check: The default check.
        angle_unit: The unit the file was written in (for display and export).
        path: The file it was read from, if any.
        warnings: Things that look wrong but are not errors (e.g. degrees in a radian file).
    """

    name: str
    convention: dh.Convention
    joints: tuple[Joint, ...]
    description: str = ""
    source: str = ""
    base: Offset = field(default_factory=Offset)
    tool: Offset = field(default_factory=Offset)
    poses: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    urdf: UrdfSpec | None = None
    frames: Mapping[str, FrameSpec] = field(default_factory=dict)
    check: CheckSpec = field(default_factory=CheckSpec)
    angle_unit: Literal["rad", "deg"] = "rad"
    path: Path | None = None
    warnings: tuple[str, ...] = ()

    @property
    def dof(self) -> int:
        """Number of joints."""
        return len(self.joints)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Joint names, base to tip."""
        return tuple(j.name for j in self.joints)

    @cached_property
    def chain(self) -> dh.DHChain:
        """The table as arrays for the FK core."""
        js = self.joints
        return dh.DHChain(
            convention=self.convention,
            a=np.array([j.a for j in js], dtype=np.float64),
            alpha=np.array([j.alpha for j in js], dtype=np.float64),
            d=np.array([j.d for j in js], dtype=np.float64),
            theta=np.array([j.theta for j in js], dtype=np.float64),
            prismatic=np.array([j.type == "prismatic" for j in js], dtype=bool),
            sign=np.array([-1.0 if j.flip else 1.0 for j in js]),
            world_T_base=self.base.matrix,
            flange_T_tool=self.tool.matrix,
        )

    @cached_property
    def limits(self) -> Float:
        """Joint limits as ``(n, 2)``; ``±inf`` where a joint has none."""
        return np.array(
            [j.limits if j.limits is not None else (-math.inf, math.inf) for j in self.joints],
            dtype=np.float64,
        ).reshape(self.dof, 2)

    def fk(self, q: ArrayLike, all_frames: bool = False) -> Float:
        """Forward kinematics with the in-house core.

        Args:
            q: Joint values, shape ``(n,)`` or ``(N, n)``, radians / metres.
            all_frames: Return DH frames ``0…n`` (base included, tool not).

        Returns:
            ``world_T_tcp`` as ``(4, 4)`` or ``(N, 4, 4)``; with ``all_frames``,
            ``(n+1, 4, 4)`` or ``(N, n+1, 4, 4)``.

        Raises:
            JointInputError: Wrong shape or non-finite values.
        """
        return dh.fk(self.chain, q, all_frames=all_frames)


#: Prefix that names a frame by its URDF link: ``urdf:tool0``.
URDF_FRAME_PREFIX = "urdf:"


def resolve_frame(model: Model, name: str) -> FrameSpec:
    """The named frame, or :class:`~fkcheck.errors.FrameError` listing the model's frames.

    ``urdf:LINK`` names the declared frame whose URDF twin is ``LINK``.
    """
    if name.startswith(URDF_FRAME_PREFIX):
        link = name[len(URDF_FRAME_PREFIX) :]
        twins = [spec for spec in model.frames.values() if spec.urdf == link]
        if twins:
            return twins[0]
        mapped = [f"urdf:{s.urdf} (= {s.name})" for s in model.frames.values() if s.urdf]
        raise FrameError(
            name,
            f"model {model.name}: no declared frame has URDF twin {link!r}; to compare a "
            f'link, declare [frames.NAME] with dh, its offset and urdf = "{link}"',
            mapped,
        )
    try:
        return model.frames[name]
    except KeyError:
        raise FrameError(name, f"model {model.name}", model.frames) from None


# --------------------------------------------------------------------------- loading


def bundled_models_dir() -> Path:
    """The directory holding the bundled model files."""
    here = Path(__file__).resolve().parent
    for candidate in (here / "_bundled_models", here.parents[1] / "models"):
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


def _model_from_csv(content: str, path: Path) -> Model:
    """Read the seed's plain DH CSV: ``name,a,alpha,d,theta_offset``, standard DH, radians."""
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
        raw_uj = u.get("joints")
        if not isinstance(raw_uj, list) or not all(isinstance(x, str) for x in raw_uj):
            raise r.fail("urdf.joints", "expected a list of URDF joint names in DH order")
        if len(raw_uj) != n:
            raise r.fail("urdf.joints", f"names {len(raw_uj)} URDF joints but the DH table has {n}")
        if len(set(raw_uj)) != len(raw_uj):
            raise r.fail("urdf.joints", "names a URDF joint twice")
        urdf = UrdfSpec(path=upath, joints=tuple(raw_uj))

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
            frames[fname] = FrameSpec(fname, idx, off, twin)

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
        for key in ("tol_pos_m", "tol_rot_rad"):
            if key in c:
                tols[key] = r.number(c[key], f"check.{key}")
                if tols[key] <= 0:
                    raise r.fail(f"check.{key}", "must be positive")
        require: tuple[str, ...] = ()
        if "require" in c:
            raw_req = c["require"]
            if not isinstance(raw_req, list) or not all(isinstance(x, str) for x in raw_req):
                raise r.fail("check.require", 'expected a list such as ["table"]')
            try:
                require = parse_require(raw_req, "check.require")
            except ValueError as exc:
                raise r.fail("check.require", str(exc).split(": ", 1)[1]) from None
        check = CheckSpec(frame_from, frame_to, require=require, **tols)

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
    )
