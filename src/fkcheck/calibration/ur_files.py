"""A Universal Robots arm's factory calibration, read from the three files it comes in.

Every UR arm leaves the factory with its own kinematics: the nominal DH table of
its type plus per-robot corrections. They reach a user in three forms:

* **``calibration.conf``** (the controller's file, section ``[mounting]``):
  ``delta_theta``, ``delta_a``, ``delta_d``, ``delta_alpha`` — six values each,
  *added* to the nominal standard-DH table (radians, metres) — with
  ``joint_checksum`` and ``calibration_status`` (0 not initialised, 1 not
  linearised, 2 linearised);
* **KinematicsInfo** (the primary interface's message, as UR's drivers and
  ``ur_calibration`` log it): the full table ``dh_theta``, ``dh_a``, ``dh_d``,
  ``dh_alpha`` (nominal + delta) with ``checksum`` and ``calibration_status``;
* **``ur_calibration``'s YAML** (``kinematics: {shoulder: {x, y, z, roll,
  pitch, yaw}, upper_arm: …, wrist_3: …}`` and ``hash: calib_…``): the joint
  origins UR's ROS description (``kinematics_params``) reads, not a DH table.

A *linearised* table (status 2) is normal: the nearly parallel shoulder, elbow
and wrist axes put d2/d3 hundreds of metres away, with θ2/θ3 compensating (up
to several radians). Such numbers are read as they are.

Each file is read as every input is: a regular file of bounded size, UTF-8;
numbers must be finite plain decimals; anything missing, repeated or of the
wrong count is one line naming the file and the field.
"""

from __future__ import annotations

import configparser
import hashlib
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from fkcheck.errors import FkcheckError
from fkcheck.io.files import InputFileError, read_bytes
from fkcheck.io.numbers import NumberError, parse_number, show_text

__all__ = [
    "DH_FIELDS",
    "LINK_FIELDS",
    "MAX_CALIBRATION_BYTES",
    "UR_LINKS",
    "CalibrationError",
    "CalibrationForm",
    "DhValues",
    "LinkOrigin",
    "UrCalibration",
    "read_ur_calibration",
]

#: A calibration file is a few kilobytes; a megabyte is far beyond any real one.
MAX_CALIBRATION_BYTES = 1 << 20
#: The links of ``ur_calibration``'s YAML, base to tip (one per joint).
UR_LINKS = ("shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3")
#: The six numbers of one link of the YAML: metres, then radians (URDF ``rpy``).
LINK_FIELDS = ("x", "y", "z", "roll", "pitch", "yaw")
#: The four rows of a DH table, in the order UR writes them.
DH_FIELDS = ("theta", "a", "d", "alpha")
#: The largest number a calibration may hold (m or rad): the model files' bound.
_BOUND = 1e3
#: How many joints a UR arm has.
_JOINTS = 6

CalibrationForm = Literal["calibration.conf", "KinematicsInfo", "ur_calibration YAML"]


class CalibrationError(FkcheckError):
    """A calibration file that cannot be read, or does not fit the nominal model."""

    def __init__(self, path: Path | str, problem: str) -> None:
        self.path = Path(path)
        self.problem = problem
        super().__init__(f"{path}: {problem}")


@dataclass(frozen=True)
class DhValues:
    """Six joints' standard-DH numbers (θ and α in radians, a and d in metres)."""

    theta: tuple[float, ...]
    a: tuple[float, ...]
    d: tuple[float, ...]
    alpha: tuple[float, ...]

    def row(self, field: str) -> tuple[float, ...]:
        """One of :data:`DH_FIELDS`."""
        values: tuple[float, ...] = getattr(self, field)
        return values


@dataclass(frozen=True)
class LinkOrigin:
    """One joint's origin in ``ur_calibration``'s YAML: ``xyz`` (m) and URDF ``rpy`` (rad)."""

    link: str
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]


@dataclass(frozen=True)
class UrCalibration:
    """One calibration file, as read.

    Attributes:
        form: Which of the three files it is.
        path: The file.
        sha256: The SHA-256 of its bytes (hex), for provenance.
        delta: ``calibration.conf``'s deltas (added to the nominal table).
        table: KinematicsInfo's full table (nominal + delta).
        links: The YAML's joint origins, base to tip.
        status: ``calibration_status`` (0, 1, 2) where the file gives it.
        checksums: The joints' checksums as the file writes them.
        hash: The YAML's ``hash`` (``calib_…``), ``""`` elsewhere.
    """

    form: CalibrationForm
    path: Path
    sha256: str
    delta: DhValues | None = None
    table: DhValues | None = None
    links: tuple[LinkOrigin, ...] | None = None
    status: int | None = None
    checksums: tuple[str, ...] = ()
    hash: str = ""

    @property
    def linearised(self) -> bool:
        """The controller says the table is linearised (status 2)."""
        return self.status == 2

    @property
    def identity(self) -> str:
        """What names this calibration in provenance: the hash, checksums or file digest."""
        if self.hash:
            return self.hash
        if self.checksums:
            return "joint checksums " + " ".join(self.checksums)
        return f"sha256:{self.sha256}"


def _number(path: Path, field: str, text: str) -> float:
    try:
        value = parse_number(text)
    except NumberError as exc:
        raise CalibrationError(path, f"{field}: {exc}") from None
    if abs(value) > _BOUND:
        raise CalibrationError(path, f"{field}: {value:g} is beyond ±{_BOUND:g}")
    return value


def _six(path: Path, field: str, text: str) -> tuple[float, ...]:
    """Six numbers written ``[ v, v, … ]`` or ``[v v …]`` (commas or spaces)."""
    body = text.strip()
    if not (body.startswith("[") and body.endswith("]")):
        raise CalibrationError(path, f"{field}: expected six numbers in [ ], got {show_text(body)}")
    tokens = [t for t in re.split(r"[\s,]+", body[1:-1]) if t]
    if len(tokens) != _JOINTS:
        raise CalibrationError(path, f"{field}: expected {_JOINTS} numbers, got {len(tokens)}")
    return tuple(_number(path, f"{field}[{i}]", t) for i, t in enumerate(tokens))


def _checksums(path: Path, field: str, text: str) -> tuple[str, ...]:
    body = text.strip()
    if body.startswith("[") and body.endswith("]"):
        body = body[1:-1]
    tokens = tuple(t for t in re.split(r"[\s,]+", body) if t)
    if len(tokens) != _JOINTS or not all(
        re.fullmatch(r"(0x)?[0-9A-Fa-f]{1,16}", t) for t in tokens
    ):
        raise CalibrationError(path, f"{field}: expected {_JOINTS} integers (decimal or 0x…)")
    return tokens


def _status(path: Path, field: str, text: str) -> int:
    token = text.strip()
    if token not in {"0", "1", "2"}:
        raise CalibrationError(
            path,
            f"{field}: expected 0 (not initialised), 1 (not linearised) or 2 (linearised), "
            f"got {show_text(token)}",
        )
    return int(token)


def _read_conf(path: Path, text: str, digest: str) -> UrCalibration:
    parser = configparser.ConfigParser(
        inline_comment_prefixes=("#",), comment_prefixes=("#", ";"), interpolation=None
    )
    try:
        parser.read_string(text, source=str(path))
    except configparser.Error as exc:
        first = str(exc).splitlines()[0]
        raise CalibrationError(path, f"not a calibration.conf: {_cut(first)}") from None
    if not parser.has_section("mounting"):
        raise CalibrationError(path, "no [mounting] section: this is not a UR calibration.conf")
    mounting = parser["mounting"]
    rows = {}
    for field in DH_FIELDS:
        key = f"delta_{field}"
        if key not in mounting:
            raise CalibrationError(path, f"[mounting] has no {key}")
        rows[field] = _six(path, key, mounting[key])
    status = None
    if "calibration_status" in mounting:
        status = _status(path, "calibration_status", mounting["calibration_status"])
    checksums: tuple[str, ...] = ()
    if "joint_checksum" in mounting:
        checksums = _checksums(path, "joint_checksum", mounting["joint_checksum"])
    return UrCalibration(
        "calibration.conf", path, digest, delta=DhValues(**rows), status=status, checksums=checksums
    )


#: One ``key: value`` line of a KinematicsInfo dump (a log prefix before it is allowed).
_INFO_LINE = re.compile(
    r"(?:^|[\s\]:])(checksum|dh_theta|dh_a|dh_d|dh_alpha|calibration_status):\s*(.*)$"
)


def _read_info(path: Path, text: str, digest: str) -> UrCalibration:
    found: dict[str, str] = {}
    for line in text.splitlines():
        match = _INFO_LINE.search(line)
        if match is None:
            continue
        key, value = match.group(1), match.group(2)
        if key in found:
            raise CalibrationError(path, f"{key} is given twice")
        found[key] = value
    missing = [f"dh_{f}" for f in DH_FIELDS if f"dh_{f}" not in found]
    if missing:
        raise CalibrationError(path, f"KinematicsInfo without {', '.join(missing)}")
    rows = {f: _six(path, f"dh_{f}", found[f"dh_{f}"]) for f in DH_FIELDS}
    status = (
        _status(path, "calibration_status", found["calibration_status"])
        if "calibration_status" in found
        else None
    )
    checksums = _checksums(path, "checksum", found["checksum"]) if "checksum" in found else ()
    return UrCalibration(
        "KinematicsInfo", path, digest, table=DhValues(**rows), status=status, checksums=checksums
    )


def _shown_value(value: object) -> str:
    """A YAML value as a message names it, bounded whatever its size: never a whole ``repr``."""
    if isinstance(value, str):
        return show_text(value)
    if isinstance(value, bool | int | float) or value is None:
        return show_text(str(value))  # (an int's digits are bounded by the loader)
    if isinstance(value, Mapping):
        return f"a mapping of {len(value)} keys"
    if isinstance(value, list):
        return f"a list of {len(value)} items"
    return f"a {type(value).__name__}"


def _yaml_number(path: Path, field: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise CalibrationError(path, f"{field}: expected a number, got {_shown_value(value)}")
    try:
        number = float(value)
    except OverflowError:  # (the loader bounds an integer's digits; kept for any other int)
        raise CalibrationError(
            path, f"{field}: {_shown_value(value)} is beyond ±{_BOUND:g}"
        ) from None
    if not math.isfinite(number):
        raise CalibrationError(path, f"{field}: must be finite, got {number}")
    if abs(number) > _BOUND:
        raise CalibrationError(path, f"{field}: {number:g} is beyond ±{_BOUND:g}")
    return number


#: How deep a ur_calibration YAML may nest: ``kinematics`` → link → number is three.
MAX_YAML_DEPTH = 8
#: How many values (keys, numbers, mappings) it may hold: ``ur_calibration`` writes 89.
#: PyYAML's pure-Python reader takes ~60 µs a value: 300,000 of them (a list in 1 MiB) took 19 s.
MAX_YAML_NODES = 1000
#: How long a message quotes a line of the YAML parser's own (its tags, keys…).
_SHOWN_PROBLEM = 160


def _cut(text: str) -> str:
    """A message of a library's, on one line and at most :data:`_SHOWN_PROBLEM` characters."""
    flat = " ".join(text.split())
    return flat if len(flat) <= _SHOWN_PROBLEM else flat[:_SHOWN_PROBLEM] + "…"


def _calibration_yaml_loader() -> type[Any]:
    """PyYAML's safe loader, cut down to what ``ur_calibration`` writes.

    Plain data only, and bounded work whatever the text: no anchors or aliases
    (an alias bomb of 600 bytes expands to billions of values), at most
    :data:`MAX_YAML_DEPTH` levels of nesting (the composer recurses per level),
    numbers of at most :data:`~fkcheck.io.numbers.MAX_NUMBER_CHARS` characters
    (a 4000-digit integer is no length in metres), at most :data:`MAX_YAML_NODES`
    values (PyYAML is pure Python here), each key once per mapping
    and no merge keys (``<<``): ``ur_calibration`` writes none of them. A
    refusal is PyYAML's own error, with the line it is on.
    """
    import yaml
    from yaml.composer import ComposerError
    from yaml.constructor import ConstructorError

    from fkcheck.io.numbers import MAX_NUMBER_CHARS

    class Loader(yaml.SafeLoader):  # type: ignore[misc]  # (no stubs)
        """yaml's safe loader without aliases, deep nesting, long numbers or repeated keys."""

        _depth = 0
        _nodes = 0

        def compose_node(self, parent: Any, index: Any) -> Any:
            event = self.peek_event()
            if isinstance(event, yaml.AliasEvent) or event.anchor is not None:
                raise ComposerError(
                    None, None,
                    "an anchor or alias (&name, *name): a ur_calibration YAML has none; "
                    "write each value out",
                    event.start_mark,
                )  # fmt: skip
            if self._depth >= MAX_YAML_DEPTH:
                raise ComposerError(
                    None, None,
                    f"nested more than {MAX_YAML_DEPTH} levels deep (a ur_calibration YAML "
                    "has three: kinematics, link, number)",
                    event.start_mark,
                )  # fmt: skip
            self._nodes += 1
            if self._nodes > MAX_YAML_NODES:
                raise ComposerError(
                    None, None,
                    f"more than {MAX_YAML_NODES} values (a ur_calibration YAML has 89)",
                    event.start_mark,
                )  # fmt: skip
            self._depth += 1
            try:
                return super().compose_node(parent, index)
            finally:
                self._depth -= 1

        def construct_mapping(self, node: Any, deep: bool = False) -> Any:
            seen: dict[Any, int] = {}
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    raise ConstructorError(
                        None, None, "a merge key (<<): write each value out", key_node.start_mark
                    )
                key = self.construct_object(key_node, deep=True)
                try:
                    first = seen.setdefault(key, key_node.start_mark.line + 1)
                except TypeError:
                    raise ConstructorError(
                        None, None, "a key that is not a name or a number", key_node.start_mark
                    ) from None
                if first != key_node.start_mark.line + 1:
                    raise ConstructorError(
                        None, None,
                        f"key {_shown_value(key)} given twice (first on line {first}): "
                        "which one is the robot's?",
                        key_node.start_mark,
                    )  # fmt: skip
            return super().construct_mapping(node, deep)

        def _bounded(self, node: Any) -> None:
            if len(node.value) > MAX_NUMBER_CHARS:
                raise ConstructorError(
                    None, None,
                    f"number too long: {len(node.value)} characters (at most {MAX_NUMBER_CHARS})",
                    node.start_mark,
                )  # fmt: skip

        def construct_yaml_int(self, node: Any) -> Any:
            self._bounded(node)
            return super().construct_yaml_int(node)

        def construct_yaml_float(self, node: Any) -> Any:
            self._bounded(node)
            return super().construct_yaml_float(node)

    Loader.add_constructor("tag:yaml.org,2002:int", Loader.construct_yaml_int)
    Loader.add_constructor("tag:yaml.org,2002:float", Loader.construct_yaml_float)
    return Loader


def _load_yaml(path: Path, text: str) -> Any:
    """The YAML's data, by :func:`_calibration_yaml_loader`; any refusal is one line."""
    import yaml

    try:
        return yaml.load(text, Loader=_calibration_yaml_loader())
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}: " if mark is not None else ""
        problem = getattr(exc, "problem", None) or "not YAML"
        raise CalibrationError(path, f"{where}{_cut(problem)}") from None
    except RecursionError:  # (the depth limit comes first; kept as xacro's load_yaml keeps it)
        raise CalibrationError(path, "nested too deeply") from None


def _read_yaml(path: Path, text: str, digest: str) -> UrCalibration:
    data = _load_yaml(path, text)
    if not isinstance(data, Mapping) or not isinstance(data.get("kinematics"), Mapping):
        raise CalibrationError(path, "no 'kinematics' mapping: this is not a ur_calibration YAML")
    kin = data["kinematics"]
    links = []
    for link in UR_LINKS:
        entry = kin.get(link)
        if not isinstance(entry, Mapping):
            raise CalibrationError(
                path, f"kinematics.{link}: missing (the links are {', '.join(UR_LINKS)})"
            )
        values = []
        for key in LINK_FIELDS:
            if key not in entry:
                raise CalibrationError(path, f"kinematics.{link}.{key}: missing")
            values.append(_yaml_number(path, f"kinematics.{link}.{key}", entry[key]))
        links.append(
            LinkOrigin(link, (values[0], values[1], values[2]), (values[3], values[4], values[5]))
        )
    unknown = [k for k in kin if k not in UR_LINKS and k != "hash"]
    if unknown:
        raise CalibrationError(
            path,
            f"kinematics: unknown link {_shown_value(unknown[0])} (the links are "
            f"{', '.join(UR_LINKS)})",
        )
    raw_hash = kin.get("hash", "")
    if not isinstance(raw_hash, str) or not re.fullmatch(r"(calib_[0-9]{1,24})?", raw_hash):
        raise CalibrationError(path, "kinematics.hash: expected calib_ and digits")
    return UrCalibration("ur_calibration YAML", path, digest, links=tuple(links), hash=raw_hash)


def _form(text: str) -> CalibrationForm | None:
    """Which form a text is, by what only that form holds."""
    if re.search(r"^\s*\[mounting\]", text, re.MULTILINE):
        return "calibration.conf"
    if re.search(r"dh_theta:", text):
        return "KinematicsInfo"
    if re.search(r"^kinematics:", text, re.MULTILINE):
        return "ur_calibration YAML"
    return None


def read_ur_calibration(path: Path | str) -> UrCalibration:
    """Read a UR calibration in any of its three forms (told apart by content).

    Raises:
        CalibrationError: Not one of the three forms, or a field missing,
            repeated, of the wrong count, not a finite number, or beyond ±1000.
        InputFileError: Missing, not a regular file, too large, not UTF-8.
    """
    path = Path(path)
    data = read_bytes(path, MAX_CALIBRATION_BYTES)
    digest = hashlib.sha256(data).hexdigest()
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise InputFileError(path, f"line {line}: not UTF-8 text") from None
    form = _form(text)
    if form == "calibration.conf":
        return _read_conf(path, text, digest)
    if form == "KinematicsInfo":
        return _read_info(path, text, digest)
    if form == "ur_calibration YAML":
        return _read_yaml(path, text, digest)
    raise CalibrationError(
        path,
        "not a UR calibration: expected the controller's calibration.conf ([mounting] "
        "delta_theta …), a KinematicsInfo dump (dh_theta: […] …) or ur_calibration's YAML "
        "(kinematics: shoulder: …)",
    )
