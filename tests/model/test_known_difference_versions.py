"""``[[known_difference]] versions = …``: a reader's own difference, for its library's versions."""

from __future__ import annotations

import math

import pytest

from fkcheck import ModelError, load_model
from fkcheck.core.tolerances import MAX_READER_POSITION_M
from fkcheck.model.types import KnownDifference
from fkcheck.model.version_spec import parse_versions, release, release_text, versions_match

TOP = 'name = "m"\nconvention = "standard"\n[[joint]]\na = 0.1\nalpha = 0.0\nd = 0.2\n'
READER = (
    '[[known_difference]]\nbackends = ["pinocchio-mjcf"]\nversions = "{versions}"\n'
    'finding = "pinocchio#2782"\nmax_position_m = {pos}\nmax_angle_rad = {rot}\n'
)


def model_with(tmp_path, versions="<=4.1.0", pos="1.95", rot="3.141592653589793", extra=""):
    path = tmp_path / "m.toml"
    path.write_text(TOP + READER.format(versions=versions, pos=pos, rot=rot) + extra)
    return load_model(path)


def test_a_readers_difference_is_read_with_its_versions_and_large_bounds(tmp_path):
    (known,) = model_with(tmp_path).known_differences
    assert known == KnownDifference(
        ("pinocchio-mjcf",), "pinocchio#2782", 1.95, math.pi, versions="<=4.1.0"
    )
    assert known.applies_to_version("4.1.0")
    assert known.applies_to_version("4.0.2")
    assert not known.applies_to_version("4.1.1")
    assert not known.applies_to_version(None)  # an unknown version matches none


def test_without_versions_the_bounds_stay_at_a_tenth(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(TOP + READER.replace('versions = "{versions}"\n', "").format(pos=1.7, rot=0.1))
    with pytest.raises(ModelError, match=r"max_position_m: .*0\.1 m.* wrong model"):
        load_model(path)


BAD = {
    "operator": ("~=4.1", "", r"versions: '~=4\.1' is not an operator and a release"),
    "words": ("latest", "", r"versions: 'latest' is not an operator"),
    "empty": ("", "", r"versions: '' is not an operator"),
    "beyond 10 m": ("<=4.1.0", "", r"max_position_m: .*10 m"),
    "with reads": (
        "<=4.1.0",
        'reads = "mjcf"\n',
        r"versions: records one reader's library versions: name that one backend alone",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_versions_record_is_one_clear_line(tmp_path, case):
    versions, extra, match = BAD[case]
    pos = "11.0" if case == "beyond 10 m" else "1.0"
    text = TOP + READER.format(versions=versions, pos=pos, rot=1.0)
    if extra:
        text = text.replace('finding = "', extra + 'finding = "')
    path = tmp_path / "m.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match=match):
        load_model(path)


def test_two_backends_with_versions_are_refused(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(
        TOP
        + READER.format(versions="<=4.1.0", pos=1, rot=1).replace(
            '["pinocchio-mjcf"]', '["pinocchio-mjcf", "mujoco-mjcf"]'
        )
    )
    with pytest.raises(ModelError, match=r"name that one backend alone"):
        load_model(path)


def test_the_type_refuses_what_the_file_refuses():
    with pytest.raises(ValueError, match="name it alone"):
        KnownDifference(("a", "b"), "x", 1.0, 1.0, versions="<=1")
    with pytest.raises(ValueError, match="is not an operator"):
        KnownDifference(("a",), "x", 1.0, 1.0, versions="4")
    KnownDifference(("a",), "x", MAX_READER_POSITION_M, math.pi, versions="<=1")


@pytest.mark.parametrize(
    ("spec", "version", "expected"),
    [
        ("<=4.1.0", "4.1.0", True),
        ("<=4.1.0", "4.1", True),  # padded with zeros
        ("<4.1.1", "4.1.1rc1", False),  # the release part only
        ("<=4.1.0", "4.1.0.post2", True),
        (">=3, <4", "3.9.9", True),
        (">=3, <4", "4.0.0", False),
        ("==4.1.0", "4.1.0", True),
        ("!=4.1.0", "4.1.0", False),
        (">4", "10.0", True),  # numbers, not text: 10 > 4
        ("<=4.1.0", "not installed", False),
    ],
)
def test_versions_compare_release_numbers(spec, version, expected):
    assert versions_match(spec, version) is expected


def test_a_spec_is_parsed_into_clauses():
    assert parse_versions(">=4.0, <=4.1.0") == ((">=", (4, 0, 0, 0, 0)), ("<=", (4, 1, 0, 0, 0)))
    assert release("v2.3") == (2, 3, 0, 0, 0)
    with pytest.raises(ValueError, match="longer than 200"):
        parse_versions("<1," * 100)


@pytest.mark.parametrize(
    ("installed", "written"),
    [("4.1.0", "4.1.0"), ("4.1.1rc1", "4.1.1"), ("3.3.7.post2", "3.3.7"), ("v2.3", "2.3"),
     ("1.2.3.4.5.6", "1.2.3.4.5"), ("unknown", None)],
)  # fmt: skip
def test_the_release_written_in_a_clause_matches_the_installed_version(installed, written):
    # What the reader-finding hint prints after "<=": a record of it must match.
    assert release_text(installed) == written
    if written is not None:
        assert versions_match(f"<={written}", installed)
        assert versions_match(f"=={written}", installed)


def _versions_for(tmp_path, backend: str):
    """A model recording ``versions = "<=1.0"`` for ``backend``."""
    path = tmp_path / "m.toml"
    path.write_text(
        TOP + READER.format(versions="<=1.0", pos=1, rot=1).replace("pinocchio-mjcf", backend)
    )
    return load_model(path)


@pytest.mark.parametrize("backend", ["pinocchio-mjcf", "mujoco-urdf", "rtb-model:UR5"])
def test_versions_for_a_backend_with_a_library_are_taken(tmp_path, backend):
    from fkcheck.backends import registry

    registry.check_known_differences(_versions_for(tmp_path, backend))  # no error


def test_versions_for_a_backend_without_a_library_are_refused_at_load(tmp_path):
    """Measured poses have no library version: a ``versions`` record of them never applies."""
    from fkcheck.backends import registry

    model = _versions_for(tmp_path, "poses:rec.csv")
    with pytest.raises(ModelError) as info:
        registry.check_known_differences(model)
    said = str(info.value)
    assert said.startswith(f"{model.path}: known_difference[0].versions: 'poses:rec.csv' ")
    assert "names no distributions" in said
    assert "never apply" in said
    assert "record them for: pinocchio-urdf, yourdfpy-urdf, rtb-urdf, mujoco-urdf," in said
    assert "mujoco-mjcf, pinocchio-mjcf, rtb-model:…, or a third-party backend" in said
    assert "poses:" not in said.split("record them for:")[1]
    assert "\n" not in said


@pytest.mark.parametrize(("distributions", "refused"), [((), True), (("acme-fk",), False)])
def test_a_used_backend_says_whether_it_has_a_library(tmp_path, distributions, refused):
    """A third-party backend a check uses is held to its own ``distributions``."""
    from types import SimpleNamespace

    from fkcheck.backends import registry

    model = _versions_for(tmp_path, "acme-reader")
    used = SimpleNamespace(name="acme-reader", evidence="table", distributions=distributions)
    if refused:
        with pytest.raises(ModelError, match=r"'acme-reader' computes with no library"):
            registry.check_known_differences(model, [used])
    else:
        registry.check_known_differences(model, [used])
