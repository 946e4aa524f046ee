"""[tool.fkcheck] in a user's pyproject.toml, and the model files it names."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from fkcheck.errors import FkcheckError
from fkcheck.model.project import (
    ProjectError,
    expand_model_paths,
    find_pyproject,
    load_project,
)

#: The least a model file holds: its reader checks the rest.
MODEL_TOML = 'name = "arm"\nconvention = "standard"\n\n[[joint]]\na = 0.1\nalpha = 0\nd = 0\n'
MODEL_CSV = "# name,a,alpha,d,theta_offset\nj1,0.1,0,0,0\n"


def _project(tmp_path: Path, table: str) -> Path:
    (tmp_path / "pyproject.toml").write_text(f"[project]\nname = 'x'\n\n[tool.fkcheck]\n{table}\n")
    robots = tmp_path / "robots"
    robots.mkdir()
    for name in ("b.toml", "a.toml"):
        (robots / name).write_text(MODEL_TOML)
    (robots / "c.csv").write_text(MODEL_CSV)
    (robots / "notes.txt").write_text("")
    return tmp_path


def test_nearest_pyproject_is_found_from_a_subdirectory(tmp_path):
    root = _project(tmp_path, 'models = ["robots/*.toml"]\nsamples = 200\nrequire = ["table"]')
    deep = root / "robots" / "sub"
    deep.mkdir()
    assert find_pyproject(deep) == (root / "pyproject.toml").resolve()
    config = load_project(deep)
    assert config is not None
    assert config.options.get("samples") == 200
    assert config.require == ("table",)
    assert [p.name for p in config.model_paths()] == ["a.toml", "b.toml"]


def test_directories_give_their_model_files_sorted_and_each_once(tmp_path):
    root = _project(tmp_path, 'models = ["robots", "robots/a.toml"]')
    config = load_project(root)
    assert config is not None
    assert [p.name for p in config.model_paths()] == ["a.toml", "b.toml", "c.csv"]


@pytest.mark.parametrize(
    ("table", "wanted"),
    [
        ("", None),  # the model's [check] jacobian decides
        ("jacobian = true", True),
        ("jacobian = false", False),
        ('jacobian_reference = "local"', True),  # implies it, as --jacobian-reference does
        ("tol_jacobian = 1e-5", True),
        ("jacobian = false\ntol_jacobian = 1e-5", False),
    ],
)
def test_jacobian_keys_read_as_the_flags(tmp_path, table, wanted):
    config = load_project(_project(tmp_path, table))
    assert config is not None
    assert config.wants_jacobian is wanted


def test_the_bag_keys_read_as_their_flags(tmp_path):
    table = (
        'bag_joint_states = "/arm/joint_states"\nbag_tf = "/arm/tf"\n'
        'bag_tf_static = "/arm/tf_static"\nbag_stamp_tolerance = 0  # an int: seconds\n'
    )
    config = load_project(_project(tmp_path, table))
    assert config is not None
    settings = config.bag_settings()
    assert settings == {
        "bag_joint_states": "/arm/joint_states",
        "bag_tf": "/arm/tf",
        "bag_tf_static": "/arm/tf_static",
        "bag_stamp_tolerance_s": 0.0,
    }
    assert isinstance(settings["bag_stamp_tolerance_s"], float)
    other = tmp_path / "other"
    other.mkdir()
    assert load_project(_project(other, "samples = 3")).bag_settings() == {}


def test_no_table_means_no_project(tmp_path):
    (tmp_path / "pyproject.toml").write_text("[project]\nname = 'x'\n")
    assert load_project(tmp_path) is None


@pytest.mark.parametrize(
    ("table", "match"),
    [
        ("sample = 3", r"tool\.fkcheck\.sample: unknown key; keys are: models, against"),
        (
            "samples = -1",
            r"tool\.fkcheck\.samples: must be an integer from 0 to 10_000_000 \(.*\), got -1$",
        ),
        ("seed = -1", r"tool\.fkcheck\.seed: must be an integer from 0 to 2\*\*64 - 1 .*got -1$"),
        ("samples = true", r"tool\.fkcheck\.samples: must be an integer"),
        ('require = ["tabel"]', r"tool\.fkcheck\.require: 'tabel' is not a kind of evidence"),
        ("models = [1]", r"tool\.fkcheck\.models: must be a string or a list of strings"),
        ('sampler = "grid"', r"tool\.fkcheck\.sampler: 'grid' unknown; samplers are"),
        (
            "tol_pos_m = nan",
            r"tool\.fkcheck\.tol_pos_m: must be > 0 and at most 0\.01 m .*, got nan$",
        ),
        # Limits without limits: 1000 m or 10 rad accept any table, π or more any rotation.
        (
            "tol_pos_m = 1000",
            r"tool\.fkcheck\.tol_pos_m: must be > 0 and at most 0\.01 m \(1 cm: a looser check "
            r"cannot tell a wrong link length from a right one\), got 1000$",
        ),
        (
            "tol_rot_rad = 10",
            r"tool\.fkcheck\.tol_rot_rad: must be > 0 and at most 0\.1 rad \(5\.7°: .*at π accepts "
            r"every rotation\), got 10$",
        ),
        ("tol_rot_rad = 3.15", r"tool\.fkcheck\.tol_rot_rad: must be > 0 .*, got 3\.15$"),
        ('tol_pos_m = "1mm"', r"tool\.fkcheck\.tol_pos_m: must be > 0 .*, got '1mm'$"),
        ("tol_pos_m = true", r"tool\.fkcheck\.tol_pos_m: must be > 0 .*, got True$"),
        ("timeout = 0", r"tool\.fkcheck\.timeout: must be > 0 and at most 86400 s .*, got 0$"),
        ("jacobian = 1", r"tool\.fkcheck\.jacobian: must be true or false"),
        (
            'jacobian_reference = "base"',
            r"tool\.fkcheck\.jacobian_reference: 'base' unknown; references are: world, local, "
            "world-aligned",
        ),
        ("tol_jacobian = -1e-6", r"tool\.fkcheck\.tol_jacobian: must be > 0 .*, got -1e-06$"),
        (
            "tol_jacobian = 1e300",
            r"tool\.fkcheck\.tol_jacobian: must be > 0 and at most 0\.01 m/rad and rad/rad .*, "
            r"got 1e\+300$",
        ),
        # A ROS 2 bag's settings, by the rule of their --bag-* flags.
        (
            "bag_stamp_tolerance = 2",
            r"tool\.fkcheck\.bag_stamp_tolerance: must be seconds from 0 to 1 \(a larger lag "
            r"pairs poses with other cycles' readings\), got 2$",
        ),
        ("bag_stamp_tolerance = -0.001", r"bag_stamp_tolerance: must be seconds .*, got -0\.001$"),
        ("bag_stamp_tolerance = nan", r"bag_stamp_tolerance: must be seconds .*, got nan$"),
        ('bag_stamp_tolerance = "1ms"', r"bag_stamp_tolerance: must be seconds .*, got '1ms'$"),
        ("bag_stamp_tolerance = true", r"bag_stamp_tolerance: must be seconds .*, got True$"),
        (
            "bag_tf = 1",
            r"tool\.fkcheck\.bag_tf: must be a topic name \(at most 256 characters of text, no "
            r"spaces\), got 1$",
        ),
        ('bag_joint_states = ""', r"tool\.fkcheck\.bag_joint_states: must be a topic name"),
        ('bag_tf_static = "/tf static"', r"tool\.fkcheck\.bag_tf_static: must be a topic name"),
        ('bag_tf = "/tf\\u0007"', r"tool\.fkcheck\.bag_tf: must be a topic name"),
        ("bag_tf = ['/tf']", r"tool\.fkcheck\.bag_tf: must be a topic name .*, got \['/tf'\]$"),
        ("bag_topic = '/tf'", r"tool\.fkcheck\.bag_topic: unknown key; keys are: .*bag_tf, "),
    ],
)
def test_a_bad_table_is_one_line_naming_the_key(tmp_path, table, match):
    _project(tmp_path, table)
    with pytest.raises(ProjectError, match=match) as info:
        load_project(tmp_path)
    assert "\n" not in str(info.value)
    assert str(info.value).startswith(str(tmp_path / "pyproject.toml"))


def test_a_tolerance_beyond_its_bound_in_a_parent_directory_names_that_file(tmp_path):
    # The nearest pyproject.toml may sit far above: the error says which one it is.
    root = _project(tmp_path, "tol_pos_m = 1000\ntol_rot_rad = 1e-3")
    deep = root / "robots" / "sub"
    deep.mkdir()
    with pytest.raises(
        ProjectError,
        match=r"^"
        + re.escape(str((root / "pyproject.toml").resolve()))
        + r": tool\.fkcheck\.tol_pos_m: must be > 0 and at most 0\.01 m .*, got 1000$",
    ):
        load_project(deep)


def test_tolerances_within_their_bounds_are_read(tmp_path):
    _project(tmp_path, "tol_pos_m = 0.01\ntol_rot_rad = 0.1\ntol_jacobian = 1e-2")
    config = load_project(tmp_path)
    assert config is not None
    got = [config.options.get(n) for n in ("tol_pos_m", "tol_rot_rad", "tol_jacobian")]
    assert got == [0.01, 0.1, 0.01]


def test_not_toml_is_one_line(tmp_path):
    (tmp_path / "pyproject.toml").write_text("[tool.fkcheck\n")
    with pytest.raises(ProjectError, match=r"pyproject\.toml: not valid TOML"):
        load_project(tmp_path)


@pytest.mark.parametrize("models", ['["../*.toml"]', '["/etc/*.toml"]', '["robots/*.yaml"]'])
def test_globs_stay_inside_the_project_and_must_match(tmp_path, models):
    project = tmp_path / "p"
    project.mkdir()
    root = _project(project, f"models = {models}")
    (tmp_path / "outside.toml").write_text("")
    config = load_project(root)
    assert config is not None
    with pytest.raises(ProjectError, match=r"tool\.fkcheck\.models: '.*': "):
        config.model_paths()


@pytest.mark.parametrize(
    "entry", ["../outside.toml", "{outside}", "link.toml", "a/../../outside.toml"]
)
def test_files_stay_inside_the_project_as_directories_and_globs_do(tmp_path, entry):
    # Absolute and ../ file entries were read, against the documentation (issue 31).
    project = tmp_path / "p"
    (project / "a").mkdir(parents=True)
    outside = tmp_path / "outside.toml"
    outside.write_text(MODEL_TOML)
    (project / "link.toml").symlink_to(outside)
    shown = entry.format(outside=outside)
    root = _project(project, f"models = [{json.dumps(shown)}]")
    config = load_project(root)
    assert config is not None
    with pytest.raises(ProjectError, match=rf"tool\.fkcheck\.models: '{re.escape(shown)}': a file "
                       "outside the project$"):  # fmt: skip
        config.model_paths()


def test_a_file_inside_the_project_through_dot_dot_is_taken(tmp_path):
    project = tmp_path / "p"
    (project / "a").mkdir(parents=True)
    (project / "arm.toml").write_text(MODEL_TOML)
    root = _project(project, 'models = ["a/../arm.toml"]')
    config = load_project(root)
    assert config is not None
    assert [p.resolve() for p in config.model_paths()] == [(project / "arm.toml").resolve()]


def test_a_directory_without_models_is_refused_on_the_command_line(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(
        FkcheckError, match=r"empty: a directory with no \.toml or \.csv model file"
    ):
        expand_model_paths([tmp_path / "empty"])


# --- which pyproject.toml applies: the nearest, never above the repository ----------------------

HOSTILE_TABLE = '[tool.fkcheck]\nagainst = ["cmd:./x.sh"]\ntol_pos_m = 0.01\n'


@pytest.mark.parametrize("marker", [".git", ".hg", ".git-file"])
def test_a_pyproject_above_the_repository_never_applies(tmp_path, marker):
    (tmp_path / "pyproject.toml").write_text(HOSTILE_TABLE)
    repo = tmp_path / "checkout"
    deep = repo / "robots" / "sub"
    deep.mkdir(parents=True)
    if marker == ".git-file":  # a worktree or submodule: .git is a file
        (repo / ".git").write_text("gitdir: /elsewhere\n")
    else:
        (repo / marker).mkdir()
    assert find_pyproject(deep) is None
    assert load_project(deep) is None
    assert load_project(repo) is None


def test_the_repositorys_own_pyproject_applies_from_any_subdirectory(tmp_path):
    (tmp_path / "pyproject.toml").write_text(HOSTILE_TABLE)
    repo = tmp_path / "checkout"
    (repo / ".git").mkdir(parents=True)
    deep = repo / "robots" / "sub"
    deep.mkdir(parents=True)
    (repo / "pyproject.toml").write_text("[tool.fkcheck]\nsamples = 7\n")
    config = load_project(deep)
    assert config is not None
    assert config.path == (repo / "pyproject.toml").resolve()
    assert (config.options.get("samples"), config.against) == (7, None)


def test_the_first_pyproject_ends_the_search_even_without_a_table(tmp_path):
    (tmp_path / "pyproject.toml").write_text(HOSTILE_TABLE)
    inner = tmp_path / "inner"
    deep = inner / "sub"
    deep.mkdir(parents=True)
    (inner / "pyproject.toml").write_text("[project]\nname = 'inner'\n")
    assert find_pyproject(deep) == (inner / "pyproject.toml").resolve()
    assert load_project(deep) is None


def test_a_pyproject_that_is_no_regular_file_is_found_and_refused(tmp_path):
    (tmp_path / "pyproject.toml").write_text(HOSTILE_TABLE)
    inner = tmp_path / "inner"
    (inner / "pyproject.toml").mkdir(parents=True)  # it does not send the search further up
    with pytest.raises(ProjectError, match=r"inner/pyproject\.toml: is a directory"):
        load_project(inner)


# --- globs and directories pick model files only; a path that exists is never a glob -------------


def test_a_glob_over_every_toml_picks_the_model_files_only(tmp_path):
    root = _project(tmp_path, 'models = ["**/*.toml", "**/*.csv"]')
    (root / "Cargo.toml").write_text('[package]\nname = "x"\n')
    (root / "robots" / "settings.toml").write_text("[joint_limits]\nmax = 3\n")
    (root / "robots" / "poses.csv").write_text("q1,q2,x,y,z,qx,qy,qz,qw\n0,0,1,0,0,0,0,0,1\n")
    (root / "robots" / "broken.toml").write_text("[[joint]]\na = \n")  # a model, if a broken one
    config = load_project(root)
    assert config is not None
    found = [p.relative_to(root).as_posix() for p in config.model_paths()]
    assert found == ["robots/a.toml", "robots/b.toml", "robots/broken.toml", "robots/c.csv"]


def test_a_directory_named_gives_every_toml_and_csv_file_in_it(tmp_path):
    """Named, a directory is a directory of models: a file in it that is none is not hidden."""
    root = _project(tmp_path, 'models = ["robots"]')
    (root / "robots" / "Cargo.toml").write_text('[package]\nname = "x"\n')
    config = load_project(root)
    assert config is not None
    assert [p.name for p in config.model_paths()] == ["Cargo.toml", "a.toml", "b.toml", "c.csv"]


def test_a_glob_with_no_model_file_says_what_a_model_file_is(tmp_path):
    root = _project(tmp_path, 'models = ["*.toml"]')
    config = load_project(root)
    assert config is not None
    with pytest.raises(
        ProjectError,
        match=r"tool\.fkcheck\.models: '\*\.toml': matches no model file \(a \.toml file with "
        r"\[\[joint\]\] tables, or a DH \.csv\)$",
    ):
        config.model_paths()


@pytest.mark.parametrize("name", ["arm[2].toml", "arm*.toml", "arm?.csv"])
def test_a_path_that_exists_is_never_a_glob(tmp_path, monkeypatch, name):
    root = _project(tmp_path, f"models = [{name!r}]")
    (root / name).write_text(MODEL_CSV if name.endswith(".csv") else MODEL_TOML)
    (root / "arm2.toml").write_text(MODEL_TOML)  # what arm[2].toml matches as a glob
    (root / "arm1.csv").write_text(MODEL_CSV)
    config = load_project(root)
    assert config is not None
    assert config.model_paths() == [root / name]
    monkeypatch.chdir(root)
    assert expand_model_paths([name]) == [Path(name)]
