"""Property-based fuzzing of the calibration readers (issue 31): calibration.conf,
KinematicsInfo and ur_calibration's YAML.

Each reader gets random bytes and structured mutations of a valid file (those of
:mod:`tests.hostile.test_property_inputs`, and YAML's own hostile tokens: anchors and
aliases, merge keys, tags, deep nesting, long numbers, expressions). Whatever it gets it
either reads the file — every number then finite and within ±1000, six of each, and
(YAML) every key of every mapping once — or refuses it with one FkcheckError line. Each
example runs under a time bound and an address-space cap (:func:`tests.helpers.address_space_cap`):
an alias bomb that expands, or a message that reprs a whole value, fails the test with
MemoryError instead of taking the machine's memory. `nox -s fuzz` runs these with 10x
the examples; `nox -s bounded` runs them under its own 2 GiB limit too.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from fkcheck.calibration.ur_files import UrCalibration, read_ur_calibration
from fkcheck.model.read import load_model
from tests.calibration.ur_test_data import composed, write_conf, write_kinematics_info, write_yaml
from tests.helpers import address_space_cap, deadline
from tests.hostile.test_property_inputs import HOSTILE_TOKENS, _read_or_refuse, mutated

#: What one read may add to the address space: the readers need a few MB; the alias
#: bomb of issue 31 needed 1.4 GB resident.
EXTRA_BYTES = 256 << 20
#: What one read may take: refusals take milliseconds, the largest valid file ~0.1 s.
TIME_BOUND_S = 10.0
#: The readers' bound on every number, metres or radians.
BOUND = 1e3

#: Issue 31's alias bomb, in one flow value: 9⁹ ones, a repr of 1.26 billion characters.
ALIAS_BOMB = (
    "[&a0 [1, 1, 1, 1, 1, 1, 1, 1, 1], "
    + ", ".join(f"&a{i} [{', '.join([f'*a{i - 1}'] * 9)}]" for i in range(1, 9))
    + "]"
)
YAML_TOKENS = (
    ALIAS_BOMB, "[" * 60_000 + "]" * 60_000, "{a: " * 30_000 + "1" + "}" * 30_000, "9" * 4000,
    "&a", "*a", "&a [1, 2]", "*b", "<<: *a", "<<: {x: 1}", "!!python/object:os.system 1",
    "!!binary aGk=", "!!set {a}", "!!timestamp 2001-12-14", "[" * 50 + "]" * 50,
    "{a: " * 50 + "1" + "}" * 50, "9" * 5000, "0." + "1" * 200, ".nan", "-.inf", "0x1F",
    "0o17", "0b101", "1_000", "190:20:30", "~", "null", "yes", "'${0.5}'", '"$(eval 1)"',
    "'1'", "1e400", "-0", "? [a, b]\n  : 1", "--- \n...", "%YAML 1.1",
)  # fmt: skip


@pytest.fixture(scope="module")
def seeds(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """A valid file of each form, as UR's writers write it."""
    where = tmp_path_factory.mktemp("seeds")
    table = composed(load_model("ur10e").joints, "ur10e-test-b")
    files = {
        "conf": write_conf(where / "calibration.conf", "ur10e-test-b"),
        "info": write_kinematics_info(where / "info.log", table, 2),
        "yaml": write_yaml(where / "robot_calibration.yaml", table),
    }
    return {form: path.read_text(encoding="utf-8") for form, path in files.items()}


@pytest.fixture(scope="module")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("fuzz-calibration")


@st.composite
def yaml_mutated(draw: st.DrawFn, text: str) -> bytes:
    """``text`` with a YAML token put in place of a value, or after a key, then mutated."""
    lines = text.split("\n")
    k = draw(st.integers(0, len(lines) - 1))
    key, colon, _ = lines[k].partition(":")
    token = draw(st.sampled_from(YAML_TOKENS))
    lines[k] = f"{key}: {token}" if colon else f"{lines[k]} {token}"
    text = "\n".join(lines)
    if draw(st.booleans()):
        return draw(mutated(text))
    return text.encode("utf-8")


def _assert_read_is_bounded(cal: UrCalibration) -> None:
    rows: list[tuple[float, ...]] = []
    for values in (cal.delta, cal.table):
        if values is not None:
            rows += [values.row(f) for f in ("theta", "a", "d", "alpha")]
    if cal.links is not None:
        assert len(cal.links) == 6
        rows += [link.xyz + link.rpy for link in cal.links]
    assert rows
    for row in rows:
        assert all(math.isfinite(v) and abs(v) <= BOUND for v in row), row
    assert len(cal.sha256) == 64


def _keys_once(text: str) -> bool:
    """Every mapping of the YAML has each key once (PyYAML's composer, no values built)."""
    import yaml

    def walk(node: yaml.Node, seen: set[int]) -> bool:
        if id(node) in seen:
            return True
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            keys = [(k.tag, k.value) for k, _ in node.value if isinstance(k, yaml.ScalarNode)]
            if len(keys) != len(set(keys)):
                return False
            return all(walk(k, seen) and walk(v, seen) for k, v in node.value)
        if isinstance(node, yaml.SequenceNode):
            return all(walk(item, seen) for item in node.value)
        return True

    return walk(yaml.compose(text, Loader=yaml.SafeLoader), set())


def _fuzz(workdir: Path, name: str, content: bytes) -> UrCalibration | None:
    path = workdir / name
    path.write_bytes(content)
    with deadline(TIME_BOUND_S), address_space_cap(EXTRA_BYTES):
        cal = _read_or_refuse(read_ur_calibration, path)
    if cal is not None:
        _assert_read_is_bounded(cal)
    return cal


def _contents(text: str) -> st.SearchStrategy[bytes]:
    return st.one_of(st.binary(max_size=600), mutated(text))


@given(data=st.data())
def test_property_calibration_conf_reader_reads_or_refuses(workdir, seeds, data):
    cal = _fuzz(workdir, "calibration.conf", data.draw(_contents(seeds["conf"])))
    if cal is not None and cal.form == "calibration.conf":
        assert cal.delta is not None


@given(data=st.data())
def test_property_kinematics_info_reader_reads_or_refuses(workdir, seeds, data):
    cal = _fuzz(workdir, "info.log", data.draw(_contents(seeds["info"])))
    if cal is not None and cal.form == "KinematicsInfo":
        assert cal.table is not None


@given(data=st.data())
def test_property_ur_calibration_yaml_reader_reads_or_refuses(workdir, seeds, data):
    content = data.draw(st.one_of(_contents(seeds["yaml"]), yaml_mutated(seeds["yaml"])))
    cal = _fuzz(workdir, "robot_calibration.yaml", content)
    if cal is not None and cal.form == "ur_calibration YAML":
        assert _keys_once(content.decode("utf-8-sig"))


@given(token=st.one_of(st.sampled_from(YAML_TOKENS + HOSTILE_TOKENS), st.text(max_size=40)))
def test_property_any_yaml_value_is_a_number_or_one_line(workdir, seeds, token):
    text = seeds["yaml"].replace("    z: 0.18053981171425867\n", f"    z: {token}\n", 1)
    cal = _fuzz(workdir, "value.yaml", text.encode("utf-8", "surrogatepass"))
    if cal is not None and cal.links is not None:
        assert isinstance(cal.links[0].xyz[2], float)


def test_the_cap_turns_a_blow_up_into_a_memory_error():
    """The cap holds: a 1 GiB allocation inside it fails, and the limit is put back."""
    import resource

    before = resource.getrlimit(resource.RLIMIT_AS)
    with pytest.raises(MemoryError), address_space_cap(EXTRA_BYTES):
        bytearray(1 << 30)
    assert resource.getrlimit(resource.RLIMIT_AS) == before
