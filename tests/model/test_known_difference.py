"""``[[known_difference]]``: the schema, strictly validated (one clear line, exit 2)."""

from __future__ import annotations

import pytest

from fkcheck import ModelError, load_model
from fkcheck.backends import registry
from fkcheck.cli.main import main
from fkcheck.model.types import KnownDifference

TOP = 'name = "m"\nconvention = "standard"\n'
JOINT = "[[joint]]\na = 0.1\nalpha = 0.0\nd = 0.2\n"
HEAD = TOP + JOINT
RECORD = '[[known_difference]]\nbackends = ["pinocchio-urdf"]\nfinding = "d1 0.3 mm"\n'
BOUNDS = "max_position_m = 0.001\nmax_angle_rad = 2e-5\n"
GOOD = RECORD + BOUNDS


def test_a_known_difference_is_read_with_its_bounds(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(
        HEAD + GOOD + '[[known_difference]]\nbackends = ["rtb-urdf", "rtb-model:UR5"]\n'
        'finding = "x"\nmax_position_m = 0.1\nmax_angle_rad = 0.1\n'  # the bounds: allowed
    )
    model = load_model(path)
    assert model.known_differences == (
        KnownDifference(("pinocchio-urdf",), "d1 0.3 mm", 0.001, 2e-5),
        KnownDifference(("rtb-urdf", "rtb-model:UR5"), "x", 0.1, 0.1),
    )


def test_every_urdf_reader_is_selected_by_what_it_reads(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(HEAD + GOOD.replace('backends = ["pinocchio-urdf"]', 'reads = "urdf"'))
    (known,) = load_model(path).known_differences
    assert (known.backends, known.reads) == ((), "urdf")
    for name in registry.names(reads="urdf"):
        assert known.applies_to(name, "urdf")
    assert not known.applies_to("rtb-dh", "dh")
    assert not known.applies_to("poses:x.csv", "poses")


def test_the_names_it_accepts_are_the_registrys_table_evidence():
    names = registry.known_difference_names()
    assert set(registry.names(reads="urdf")) <= set(names)
    assert {"rtb-model:", "poses:"} <= set(names)
    for name in names:
        declared = next(r for r in registry.registrations() if r.name == name)
        assert declared.declared("evidence") == "table"
    assert not {"rtb-dh", "pinocchio-dh", "cmd:"} & set(names)


BAD = {
    "not_an_array": ('known_difference = "x"\n', r"known_difference: expected an array of tables"),
    "unknown_key": (GOOD + "why = 1\n", r"known_difference\[0\]\.why: unknown key; allowed"),
    "missing_finding": (
        '[[known_difference]]\nbackends = ["rtb-urdf"]\n',
        r"known_difference\[0\]\.finding: missing",
    ),
    "missing_backends": (
        '[[known_difference]]\nfinding = "x"\n',
        r"known_difference\[0\]\.backends: missing \(required: the backends by name, or "
        r'reads = "urdf" for every URDF reader\)',
    ),
    "reads_the_table": (
        '[[known_difference]]\nreads = "dh"\nfinding = "x"\n',
        r"known_difference\[0\]\.reads: 'dh' is not one of: urdf, mjcf$",
    ),
    "reads_not_text": (
        '[[known_difference]]\nreads = ["urdf"]\nfinding = "x"\n',
        r"known_difference\[0\]\.reads: expected a string",
    ),
    "reads_twice": (
        GOOD.replace('backends = ["pinocchio-urdf"]', 'reads = "urdf"')
        + '[[known_difference]]\nreads = "urdf"\nfinding = "y"\n',
        r"known_difference\[1\]\.reads: selected already, in known_difference\[0\]",
    ),
    "backends_not_a_list": (
        '[[known_difference]]\nbackends = "rtb-urdf"\nfinding = "x"\n',
        r"backends: expected a non-empty list of backend names$",
    ),
    "backends_empty": (
        '[[known_difference]]\nbackends = []\nfinding = "x"\n',
        r"backends: expected a non-empty list",
    ),
    "listed_twice": (
        GOOD + '[[known_difference]]\nbackends = ["pinocchio-urdf"]\nfinding = "y"\n',
        r"known_difference\[1\]\.backends\[0\]: 'pinocchio-urdf' is listed already",
    ),
    "finding_not_text": (
        '[[known_difference]]\nbackends = ["rtb-urdf"]\nfinding = 3\n',
        r"finding: expected a string, got an integer",
    ),
    "finding_blank": (
        '[[known_difference]]\nbackends = ["rtb-urdf"]\nfinding = "  "\n',
        r"finding: must not be empty",
    ),
    "bound_missing": (
        RECORD + "max_angle_rad = 1\n",
        r"known_difference\[0\]\.max_position_m: missing \(required: the largest error",
    ),
    "angle_bound_missing": (RECORD + "max_position_m = 0.01\n", r"max_angle_rad: missing"),
    "bound_not_a_number": (
        RECORD + 'max_position_m = "1mm"\nmax_angle_rad = 1\n',
        r"max_position_m: expected a number",
    ),
    "bound_zero": (
        RECORD + "max_position_m = 0.01\nmax_angle_rad = 0\n",
        r"max_angle_rad: must be > 0 and at most 0\.1 rad .*, got 0$",
    ),
    "bound_bool": (
        RECORD + "max_position_m = 0.01\nmax_angle_rad = true\n",
        r"max_angle_rad: expected a number",
    ),
    "bound_nan": (
        RECORD + "max_position_m = nan\nmax_angle_rad = 1\n",
        r"max_position_m: must be a finite number",
    ),
    # Bounds beyond any finding would excuse a wrong model (a 500 mm error as "expected").
    "position_bound_huge": (
        RECORD + "max_position_m = 1e300\nmax_angle_rad = 1e-3\n",
        r"known_difference\[0\]\.max_position_m: must be > 0 and at most 0\.1 m \(a larger "
        r"difference is a wrong model, not a known difference\), got 1e\+300$",
    ),
    "position_bound_arm_sized": (
        RECORD + "max_position_m = 0.5\nmax_angle_rad = 1e-3\n",
        r"max_position_m: must be > 0 and at most 0\.1 m .*, got 0\.5$",
    ),
    "angle_bound_huge": (
        RECORD + "max_position_m = 1e-3\nmax_angle_rad = 10\n",
        r"known_difference\[0\]\.max_angle_rad: must be > 0 and at most 0\.1 rad \(5\.7°: a "
        r"larger one, such as a missing 90° θ offset, is a wrong model.*\), got 10$",
    ),
    "angle_bound_quarter_turn": (
        RECORD + "max_position_m = 1e-3\nmax_angle_rad = 1.5707963\n",
        r"max_angle_rad: must be > 0 and at most 0\.1 rad .*, got 1\.5708$",
    ),
    "position_bound_negative": (
        RECORD + "max_position_m = -1e-3\nmax_angle_rad = 1e-3\n",
        r"max_position_m: must be > 0 and at most 0\.1 m .*, got -0\.001$",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_known_difference_is_one_clear_error(tmp_path, case):
    text, match = BAD[case]
    path = tmp_path / f"{case}.toml"
    path.write_text(TOP + text + JOINT)  # top-level keys first, then the table
    with pytest.raises(ModelError, match=match) as info:
        load_model(path)
    assert str(info.value).startswith(str(path))
    assert "\n" not in str(info.value)


#: Names the registry refuses: read as TOML, refused when the model is used.
BAD_NAMES = {
    "unknown_backend": (
        '[[known_difference]]\nbackends = ["pinocchio-urdff"]\nfinding = "x"\n',
        r"backends\[0\]: 'pinocchio-urdff' is not a backend .*may name: pinocchio-urdf, "
        r"yourdfpy-urdf, rtb-urdf, .*rtb-model:…, .*poses:…",
    ),
    "implementation_backend": (
        '[[known_difference]]\nbackends = ["rtb-dh"]\nfinding = "x"\n',
        r"'rtb-dh' is not a backend whose evidence is independent of the table",
    ),
    "bare_prefix": (
        '[[known_difference]]\nbackends = ["rtb-model:"]\nfinding = "x"\n',
        r"'rtb-model:' is not a backend",
    ),
    "second_entry": (
        GOOD
        + '[[known_difference]]\nbackends = ["rtb-urdf", "cmd:./fk"]\nfinding = "y"\n'
        + BOUNDS,
        r"known_difference\[1\]\.backends\[1\]: 'cmd:\./fk' is not a backend",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD_NAMES))
def test_a_name_the_registry_refuses_is_one_clear_error(tmp_path, case):
    text, match = BAD_NAMES[case]
    path = tmp_path / f"{case}.toml"
    path.write_text(TOP + text + (BOUNDS if case != "second_entry" else "") + JOINT)
    model = load_model(path)  # the reader checks the form; the names are the registry's
    with pytest.raises(ModelError, match=match) as info:
        registry.check_known_differences(model)
    assert str(info.value).startswith(str(path))
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    "case",
    ["unknown_key", "unknown_backend", "bound_zero", "position_bound_huge", "angle_bound_huge"],
)
@pytest.mark.parametrize("command", ["lint", "check", "diagnose"])
def test_bad_known_difference_exits_2_with_one_line(tmp_path, capsys, case, command):
    path = tmp_path / f"{case}.toml"
    text = BAD[case][0] if case in BAD else BAD_NAMES[case][0] + BOUNDS
    path.write_text(TOP + text + JOINT)
    assert main([command, str(path), "--samples", "2"][: 2 if command == "lint" else 4]) == 2
    _out, err = capsys.readouterr()
    assert "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert str(path) in err


@pytest.mark.parametrize(
    ("position", "angle", "match"),
    [
        (0.2, 1e-3, r"KnownDifference\.max_position_m: must be > 0 and at most 0\.1 m"),
        (1e-3, 3.2, r"KnownDifference\.max_angle_rad: must be > 0 and at most 0\.1 rad"),
        (1e-3, float("nan"), r"KnownDifference\.max_angle_rad: .*, got nan$"),
    ],
)
def test_a_known_difference_built_in_memory_is_bounded_too(position, angle, match):
    with pytest.raises(ValueError, match=match):  # a ToleranceError: also an FkcheckError
        KnownDifference(("pinocchio-urdf",), "x", position, angle)
