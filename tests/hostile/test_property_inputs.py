"""Property-based fuzzing of the text readers (issue 15): model TOML, DH CSV, --q-file,
measured poses CSV, UR RTDE recordings, and the number parser under them.

Each reader gets random bytes and structured mutations of a valid file (a number
replaced by a hostile token, a slice deleted, text inserted, a line repeated or moved,
a byte-order mark, a separator doubled). Whatever it gets, it either reads the file —
and then every number it returns is finite and within the documented bounds — or raises
a FkcheckError subclass whose message is one line. Never another exception.
The poses readers run under a memory cap (:data:`POSES_MEMORY_CAP`, an address-space
limit over what the process already holds), and their mutations include a line
repeated thousands of times: a blow-up fails the test instead of the machine (issue
31: 10 million short rows took 7.7 GB). `nox -s fuzz` runs these with 10x the examples.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import resource
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from hypothesis import event, given
from hypothesis import strategies as st

from fkcheck import load_model
from fkcheck.backends.measured import MeasuredPoses, read_poses_file
from fkcheck.errors import FkcheckError
from fkcheck.io.numbers import MAX_NUMBER_CHARS, NumberError, parse_number, parse_numbers
from fkcheck.model.joint_input import read_q_file
from fkcheck.model.read import bundled_model_paths
from fkcheck.model.types import MAX_JOINT_RAD, MAX_LENGTH_M, Model
from tests.paths import DATA_DIR

DATA = DATA_DIR
UR5 = load_model("ur5")

HOSTILE_TOKENS = (
    "", " ", "1_0", "٣", "٠٫٥", "０.５", "0x1p-3", "nan", "-inf", "Infinity", "1e400",
    "-1e308", "1e308", "9" * 400, "9" * 5000, "1e", ".", "+-1", "1..2", "-0", "\ufeff",
    "\x00", "\u2028", "\x1b[2J", "[[[", "{", '"', "'''", "1,2", ";", "#", "\r", "\n",
)  # fmt: skip
_NUMBER = re.compile(r"[-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?")


@pytest.fixture(scope="module")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@st.composite
def mutated(draw: st.DrawFn, text: str) -> bytes:
    """``text`` with one to four structured mutations, as bytes (maybe not UTF-8)."""
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(
            st.sampled_from(
                ("number", "delete", "insert", "repeat", "flood", "move", "bom", "separator")
            )
        )
        lines = text.split("\n")
        if kind == "number":
            spans = [m.span() for m in _NUMBER.finditer(text)]
            if spans:
                start, stop = draw(st.sampled_from(spans))
                token = draw(st.one_of(st.sampled_from(HOSTILE_TOKENS), st.text(max_size=12)))
                text = text[:start] + token + text[stop:]
        elif kind == "delete" and text:
            start = draw(st.integers(0, len(text) - 1))
            text = text[:start] + text[start + draw(st.integers(1, 40)) :]
        elif kind == "insert":
            at = draw(st.integers(0, len(text)))
            text = text[:at] + draw(st.text(max_size=30)) + text[at:]
        elif kind == "repeat":
            k = draw(st.integers(0, len(lines) - 1))
            lines.insert(k, lines[k])
            text = "\n".join(lines)
        elif kind == "flood":  # one line many times: rows, not bytes, grow
            k = draw(st.integers(0, len(lines) - 1))
            lines[k:k] = [lines[k]] * draw(st.integers(100, 5000))
            text = "\n".join(lines)
        elif kind == "move":
            line = lines.pop(draw(st.integers(0, len(lines) - 1)))
            lines.insert(draw(st.integers(0, len(lines))), line)
            text = "\n".join(lines)
        elif kind == "bom":
            text = "\ufeff" + text
        elif kind == "separator":
            text = text.replace(",", draw(st.sampled_from((",,", ";", ", ", "\t"))), 1)
    raw = text.encode("utf-8", "surrogatepass")
    if draw(st.booleans()) and raw:  # sometimes a byte that breaks UTF-8
        at = draw(st.integers(0, len(raw) - 1))
        raw = raw[:at] + draw(st.sampled_from((b"\xff", b"\xc3", b"\x80"))) + raw[at:]
    return raw


def _contents(valid: str) -> st.SearchStrategy[bytes]:
    return st.one_of(st.binary(max_size=600), mutated(valid))


def _read_or_refuse(read, path: Path):
    """``read(path)``, or ``None`` when it refuses with one FkcheckError line."""
    try:
        result = read(path)
    except FkcheckError as exc:
        refused = exc
    else:
        event("read")
        return result
    message = str(refused)
    assert message, type(refused)
    assert "\n" not in message, message
    assert "\r" not in message, message
    event(f"refused: {type(refused).__name__}")
    return None


def _assert_model_bounded(model: Model) -> None:
    for joint in model.joints:
        assert abs(joint.a) <= MAX_LENGTH_M
        assert abs(joint.d) <= MAX_LENGTH_M
        assert math.isfinite(joint.alpha)
        assert math.isfinite(joint.theta)
        if joint.limits is not None:
            bound = MAX_LENGTH_M if joint.type == "prismatic" else MAX_JOINT_RAD
            assert all(abs(v) <= bound for v in joint.limits)
    assert np.isfinite(model.fk(np.zeros(model.dof))).all()


BUNDLED_TOML = [bundled_model_paths()[m].read_text(encoding="utf-8") for m in ("ur5", "panda")]
SEED_CSV = (DATA / "ur5_seed001.csv").read_text(encoding="utf-8")
Q_FILE = "# logged joint states\n0.1,-0.5,1.0,-1.2,-1.5,0.7\n0,0,0,0,0,0\n-3e-1;2.5e0;.1;0.;-0;1\n"
PENDANT = (DATA / "ur5_pendant.csv").read_text(encoding="utf-8")
RTDE = (DATA / "ur5_rtde_recording.csv").read_text(encoding="utf-8")
STANFORD = load_model("stanford")
#: A Stanford arm's poses with each joint in its own unit (q3 prismatic, in mm).
STANFORD_POSES = (
    "q1_deg,q2_deg,q3_mm,q4_deg,q5_deg,q6,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg\n"
    "0,0,500,0,0,0,0,0,1000,0,0,0\n10,-20,700,30,40,0.5,100,-200,900,10,20,30\n"
)
#: Address space a poses reader may take over what the process holds, bytes: a
#: valid file of these sizes needs a few MB; a reader that holds far more than it
#: must hits this instead of the machine's memory.
POSES_MEMORY_CAP = 512 << 20


def _vm_bytes() -> int:
    """The process's address space now (``/proc/self/statm``'s first field)."""
    with open("/proc/self/statm", encoding="ascii") as f:
        return int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")


@contextlib.contextmanager
def _memory_cap(extra: int = POSES_MEMORY_CAP) -> Iterator[None]:
    """An address-space limit of what the process holds plus ``extra``, while inside."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    cap = _vm_bytes() + extra
    if hard != resource.RLIM_INFINITY:
        cap = min(cap, hard)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


@given(data=st.data(), which=st.sampled_from([0, 1]))
def test_property_toml_model_reader_loads_or_refuses(workdir, data, which):
    path = workdir / "model.toml"
    path.write_bytes(data.draw(_contents(BUNDLED_TOML[which])))
    model = _read_or_refuse(load_model, path)
    if model is not None:
        _assert_model_bounded(model)


@given(content=_contents(SEED_CSV))
def test_property_dh_csv_reader_loads_or_refuses(workdir, content):
    path = workdir / "table.csv"
    path.write_bytes(content)
    model = _read_or_refuse(load_model, path)
    if model is not None:
        _assert_model_bounded(model)
        assert model.convention == "standard"


@given(content=_contents(Q_FILE))
def test_property_q_file_reader_loads_or_refuses(workdir, content):
    path = workdir / "q.csv"
    path.write_bytes(content)
    q = _read_or_refuse(lambda p: read_q_file(p, UR5), path)
    if q is not None:
        assert q.shape == (q.shape[0], 6)
        assert q.shape[0] >= 1
        assert np.isfinite(q).all()


@given(content=_contents(PENDANT))
def test_property_poses_csv_reader_loads_or_refuses(workdir, content):
    path = workdir / "poses.csv"
    path.write_bytes(content)
    with _memory_cap():
        table = _read_or_refuse(lambda p: read_poses_file(p, UR5), path)
    if table is not None:
        q, poses, _ = table
        assert q.shape == (poses.shape[0], 6)
        assert np.isfinite(q).all()
        assert np.isfinite(poses).all()
        assert (np.abs(q) <= MAX_JOINT_RAD).all()
        # Every row's own configuration finds a pose: the one of that row, or of an
        # identical configuration, which then has the same pose (else it was refused).
        backend = MeasuredPoses(str(path))
        pair = table[2] or (UR5.check.frame_from, UR5.check.frame_to)
        found = _read_or_refuse(lambda _: backend.frame_poses(UR5, q, pair), path)
        assert found is not None
        np.testing.assert_allclose(found[1], poses, atol=1e-9)


@given(text=st.one_of(st.text(max_size=30), st.sampled_from(HOSTILE_TOKENS)))
def test_property_number_parser_is_strict_and_agrees_with_float(text):
    try:
        value = parse_number(text)
    except NumberError as exc:
        problem = exc.problem
    else:
        token = text.strip(" \t")
        assert token.isascii()
        assert "_" not in token
        assert len(token) <= MAX_NUMBER_CHARS
        assert math.isfinite(value)
        assert value == float(token)
        return
    assert "\n" not in problem


@given(
    fields=st.lists(
        st.one_of(
            st.floats(allow_nan=False, allow_infinity=False).map(repr),
            st.sampled_from(HOSTILE_TOKENS),
            st.text(alphabet="0123456789+-.eE _\t", max_size=8),
        ),
        min_size=1,
        max_size=8,
    ),
    separator=st.sampled_from((",", ";")),
)
def test_property_line_parser_fast_path_agrees_with_field_by_field(fields, separator):
    line = separator.join(fields)
    try:
        expected = [parse_number(f) for f in re.split("[,;]", line)]
    except NumberError:
        with pytest.raises(NumberError) as info:
            parse_numbers(line, ",;")
        assert info.value.index is not None
        assert info.value.column is not None
        return
    assert parse_numbers(line, ",;") == expected


@given(value=st.floats(allow_nan=False, allow_infinity=False))
def test_property_every_float_reads_back_exactly(value):
    assert parse_number(repr(value)) == value
    assert parse_numbers(f" {value!r} ,{value!r}") == [value, value]


@given(content=_contents(RTDE))
def test_property_rtde_recording_reader_loads_or_refuses(workdir, content):
    path = workdir / "rtde.csv"
    path.write_bytes(content)
    with _memory_cap():
        table = _read_or_refuse(lambda p: read_poses_file(p, UR5), path)
    if table is not None:
        q, poses, _ = table
        assert q.shape == (poses.shape[0], 6)
        assert np.isfinite(q).all()
        assert np.isfinite(poses).all()
        assert (np.abs(q) <= MAX_JOINT_RAD).all()
        assert (poses[:, 3] == [0.0, 0.0, 0.0, 1.0]).all()  # rigid transforms' last row


@given(content=_contents(STANFORD_POSES))
def test_property_poses_units_per_joint_type_load_or_refuse(workdir, content):
    # Mutated headers give suffixes of other quantities (q3_deg, x_deg): refused in one
    # line; what is read is within the bounds of each joint's own unit.
    path = workdir / "stanford.csv"
    path.write_bytes(content)
    with _memory_cap():
        table = _read_or_refuse(lambda p: read_poses_file(p, STANFORD), path)
    if table is not None:
        q, poses, _ = table
        assert q.shape == (poses.shape[0], 6)
        assert (np.abs(q[:, 2]) <= MAX_LENGTH_M).all()
        assert np.isfinite(poses).all()


def test_the_memory_cap_fails_a_blow_up_instead_of_the_machine():
    with _memory_cap(), pytest.raises(MemoryError):
        np.ones(POSES_MEMORY_CAP // 8 * 2)  # twice the cap
    assert np.ones(POSES_MEMORY_CAP // 8 * 2).size  # and it is lifted after
