"""A user's project: ``[tool.fkcheck]`` in the ``pyproject.toml`` that applies, and its models.

A repository that keeps its robots' tables sets its defaults once::

    [tool.fkcheck]
    models = ["robots/*.toml", "calib/arm.csv"]   # files, directories, globs
    samples = 2000
    require = ["table"]
    jacobian = true                               # also compare Jacobians

``fkcheck check`` / ``fkcheck lint`` without files, the pytest plugin and the
pre-commit hooks read it; a command-line flag always wins over it. The file
that applies is the nearest ``pyproject.toml`` at or above the working
directory, never above the repository's root (:func:`find_pyproject`), and
every output of ``fkcheck check`` names it. Paths and globs are relative to the
``pyproject.toml``'s directory, and must stay inside it (a glob never reaches
``..`` or an absolute path). The file is read like every input: a regular file
of at most 1 MiB of UTF-8, one clear line when it is wrong
(:class:`ProjectError`, exit 2).
"""

from __future__ import annotations

import os
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fkcheck.errors import FkcheckError
from fkcheck.io.files import InputFileError, read_text
from fkcheck.model.lint_rules import parse_lint_rules
from fkcheck.model.options import (
    BAG_KEYS,
    FLOAT_OPTIONS,
    PROJECT_KEYS,
    OptionLayer,
    OptionName,
    bag_problem,
    option_problem,
)
from fkcheck.model.read import is_model_file
from fkcheck.model.require import Kind, parse_require

__all__ = [
    "MODEL_SUFFIXES",
    "REPOSITORY_MARKERS",
    "ProjectConfig",
    "ProjectError",
    "expand_model_paths",
    "find_pyproject",
    "load_project",
    "read_project",
]

#: Suffixes of model files found in a directory or by a glob.
MODEL_SUFFIXES = (".toml", ".csv")
#: What marks a repository's root: no ``pyproject.toml`` above it applies.
REPOSITORY_MARKERS = (".git", ".hg")
#: How many model files one list may expand to (a glob over a huge tree stops here).
MAX_MODEL_FILES = 10_000

#: Every key, in the order messages list them: the project's own, then the options'.
_KEYS = ("models", "against", "lint_ignore", "ik_solvers", *PROJECT_KEYS.values(),
         *BAG_KEYS.values())  # fmt: skip
#: What a model file is, in messages.
_MODEL_FILES = "a .toml file with [[joint]] tables, or a DH .csv"


class ProjectError(FkcheckError):
    """A ``[tool.fkcheck]`` table that cannot be used.

    Attributes:
        path: The ``pyproject.toml``.
        field: The key, e.g. ``tool.fkcheck.samples``.
        problem: What is wrong.
    """

    def __init__(self, path: Path, field: str, problem: str) -> None:
        self.path = path
        self.field = field
        self.problem = problem
        super().__init__(f"{path}: {field}: {problem}" if field else f"{path}: {problem}")


@dataclass(frozen=True)
class ProjectConfig:
    """``[tool.fkcheck]`` of one ``pyproject.toml``; empty or ``None`` where it says nothing.

    Its check options are :attr:`options`: a key of :data:`~fkcheck.model.options.PROJECT_KEYS`
    (``samples``, ``seed``, ``timeout``, ``require``, ``jacobian``…) sets the
    :class:`~fkcheck.model.options.CheckOptions` attribute of that name, checked by
    the same rule as its flag.

    Attributes:
        path: The ``pyproject.toml`` it came from.
        models: Model files, directories or globs, relative to ``root``.
        against: Backends (as ``--against``). A ``module:function`` or ``cmd:PROGRAM``
            entry runs the project's own code, in a process of its own but as you.
        lint_ignore: Lint rules to ignore for every model.
        ik_solvers: IK solvers (as ``fkcheck ik --solver``) the pytest plugin checks
            against each model, one test each. A ``module:function`` entry runs the
            project's own code, in a process of its own but as you.
        options: The check options it sets, each named by its key and this file.
            ``jacobian_reference`` or ``tol_jacobian`` without ``jacobian`` sets
            ``jacobian`` too (they imply it, as ``--jacobian-reference`` and
            ``--tol-jacobian`` do).
        bag_joint_states: A ROS 2 bag's topic of ``sensor_msgs/msg/JointState``
            (``--against poses:BAG``; default ``/joint_states``), as ``--bag-joint-states``.
        bag_tf: A bag's topic of changing transforms (default ``/tf``), as ``--bag-tf``.
        bag_tf_static: A bag's topic of static transforms (default ``/tf_static``), as
            ``--bag-tf-static``.
        bag_stamp_tolerance: Seconds, 0 … 1: a bag's pose is paired with the joint
            state stamped at or before it at most this much earlier (default 0.001),
            as ``--bag-stamp-tolerance``.
    """

    path: Path
    models: tuple[str, ...] = ()
    against: tuple[str, ...] | None = None
    lint_ignore: tuple[str, ...] = ()
    ik_solvers: tuple[str, ...] = ()
    options: OptionLayer = field(default_factory=OptionLayer)
    bag_joint_states: str | None = None
    bag_tf: str | None = None
    bag_tf_static: str | None = None
    bag_stamp_tolerance: float | None = None

    def bag_settings(self) -> dict[str, Any]:
        """The bag settings it sets, by :class:`~fkcheck.backends.registry.BackendOptions` name."""
        given = {name: getattr(self, key) for name, key in BAG_KEYS.items()}
        return {name: value for name, value in given.items() if value is not None}

    @property
    def wants_jacobian(self) -> bool | None:
        """Whether Jacobians are compared: ``None`` leaves it to the model's ``[check]``."""
        wanted: bool | None = self.options.get("jacobian")
        return wanted

    @property
    def require(self) -> tuple[Kind, ...]:
        """Kinds of evidence that must be verified (on top of each model's ``[check]``)."""
        return tuple(self.options.get("require") or ())

    @property
    def root(self) -> Path:
        """The directory the paths are relative to (the ``pyproject.toml``'s)."""
        return self.path.parent

    def model_paths(self) -> list[Path]:
        """The model files ``models`` names, expanded (see :func:`expand_model_paths`)."""
        return expand_model_paths(self.models, self.root, where=(self.path, "tool.fkcheck.models"))


def find_pyproject(start: Path | None = None) -> Path | None:
    """The ``pyproject.toml`` that applies at ``start`` (default: the working directory).

    Found as pytest and ruff find theirs, but never above the repository: the
    nearest ``pyproject.toml`` at or above ``start``, looking no further than
    the first one (with or without ``[tool.fkcheck]``: then none applies) and
    no further than a directory holding one of :data:`REPOSITORY_MARKERS`
    (whose own ``pyproject.toml`` still counts). A ``pyproject.toml`` that is
    there but no regular file is found too: reading it says what it is.
    """
    here = (start or Path.cwd()).resolve()
    for directory in (here, *here.parents):
        candidate = directory / "pyproject.toml"
        if os.path.lexists(candidate):
            return candidate
        if any(os.path.lexists(directory / marker) for marker in REPOSITORY_MARKERS):
            return None
    return None


def _strings(path: Path, key: str, value: Any) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ProjectError(path, f"tool.fkcheck.{key}", "must be a string or a list of strings")
    return tuple(value)


def _option(path: Path, table: Mapping[str, Any], name: OptionName) -> Any:
    """Option ``name``'s value if the table sets it (checked by the one rule), else ``None``.

    The rule is :func:`fkcheck.model.options.option_problem`, as for flags and arguments.
    """
    key = PROJECT_KEYS[name]
    if key not in table:
        return None
    problem = option_problem(name, table[key])
    if problem is not None:
        raise ProjectError(path, f"tool.fkcheck.{key}", problem)
    value = table[key]
    return float(value) if name in FLOAT_OPTIONS else value  # timeout = 60


def read_project(path: Path, table: Mapping[str, Any]) -> ProjectConfig:
    """Validate a ``[tool.fkcheck]`` table read from ``path``.

    Raises:
        ProjectError: An unknown key or a value of the wrong kind.
    """
    unknown = sorted(set(table) - set(_KEYS))
    if unknown:
        raise ProjectError(
            path, f"tool.fkcheck.{unknown[0]}", f"unknown key; keys are: {', '.join(_KEYS)}"
        )
    try:
        lint_ignore = parse_lint_rules(_strings(path, "lint_ignore", table.get("lint_ignore", [])))
    except ValueError as exc:
        raise ProjectError(path, "tool.fkcheck.lint_ignore", str(exc)) from None
    return ProjectConfig(
        path=path,
        models=_strings(path, "models", table.get("models", [])),
        against=_strings(path, "against", table["against"]) if "against" in table else None,
        lint_ignore=lint_ignore,
        ik_solvers=_strings(path, "ik_solvers", table.get("ik_solvers", [])),
        options=_options(path, table),
        **_bag(path, table),
    )


def _bag(path: Path, table: Mapping[str, Any]) -> dict[str, Any]:
    """The bag settings the table sets, by key, each checked by its flag's rule."""
    out: dict[str, Any] = {}
    for name, key in BAG_KEYS.items():
        if key not in table:
            continue
        problem = bag_problem(name, table[key])
        if problem is not None:
            raise ProjectError(path, f"tool.fkcheck.{key}", problem)
        value = table[key]
        out[key] = float(value) if name == "bag_stamp_tolerance_s" else value
    return out


def _options(path: Path, table: Mapping[str, Any]) -> OptionLayer:
    """The check options the table sets, each checked and named by its key and ``path``."""
    values: dict[OptionName, Any] = {}
    for name in PROJECT_KEYS:
        value = _require(path, table) if name == "require" else _option(path, table, name)
        if value is not None and value != ():
            values[name] = value
    if "jacobian" not in values and ({"jacobian_reference", "tol_jacobian"} & set(values)):
        values["jacobian"] = True  # they imply it, as their flags do
    return OptionLayer(
        values, {name: f"[tool.fkcheck] {PROJECT_KEYS[name]} in {path}" for name in values}
    )


def _require(path: Path, table: Mapping[str, Any]) -> tuple[Kind, ...]:
    """``require``: a kind or a list of kinds (``table``, ``implementation``)."""
    try:
        return parse_require(_strings(path, "require", table.get("require", [])), "")
    except ValueError as exc:
        raise ProjectError(path, "tool.fkcheck.require", str(exc).lstrip(": ")) from None


def load_project(start: Path | None = None) -> ProjectConfig | None:
    """``[tool.fkcheck]`` of the nearest ``pyproject.toml``, or ``None`` when there is none.

    A ``pyproject.toml`` without a ``[tool.fkcheck]`` table gives ``None`` too.

    Raises:
        ProjectError: The file cannot be read, is not TOML, or the table is invalid.
    """
    path = find_pyproject(start)
    if path is None:
        return None
    try:
        data = tomllib.loads(read_text(path))
    except InputFileError as exc:
        raise ProjectError(path, "", exc.problem) from None
    except (tomllib.TOMLDecodeError, ValueError, RecursionError) as exc:
        raise ProjectError(path, "", f"not valid TOML: {exc}") from None
    tool = data.get("tool", {})
    table = tool.get("fkcheck") if isinstance(tool, dict) else None
    if table is None:
        return None
    if not isinstance(table, dict):
        raise ProjectError(path, "tool.fkcheck", "must be a table")
    return read_project(path, table)


def _inside(path: Path, root: Path) -> bool:
    try:
        path.resolve().relative_to(root.resolve())
    except ValueError:
        return False
    return True


def expand_model_paths(
    items: Iterable[str | Path],
    root: Path | None = None,
    *,
    where: tuple[Path, str] | None = None,
) -> list[Path]:
    """Model files from files, directories and globs, in order, each once.

    A directory gives its ``*.toml`` and ``*.csv`` files (not recursively),
    sorted, each read as a model (one that is not is bad input, named); a glob
    (``*``, ``?``, ``[``) its matching model files only, sorted
    (:func:`fkcheck.model.read.is_model_file`: ``[[joint]]`` tables or a DH
    CSV; ``pyproject.toml``, ``Cargo.toml`` or a poses CSV are passed over); a
    file is taken as it is (its reader checks it), and a path that exists is a
    file or directory, never a glob (``arm[2].toml``).
    With ``root`` (a project's directory), relative items are relative to it,
    and files, directories and globs must stay inside it (resolved: an absolute
    path, ``../`` or a link out of it is refused).

    Raises:
        FkcheckError: A glob or directory that names no model file; a file,
            directory or glob outside ``root``; or more than
            :data:`MAX_MODEL_FILES` files.
    """
    out: list[Path] = []
    seen: set[Path] = set()
    for raw in items:
        item = str(raw)
        path = Path(item) if root is None or Path(item).is_absolute() else root / item
        if any(c in item for c in "*?[") and not os.path.lexists(path):
            found = _glob_models(item, root, where)
        elif path.is_dir():
            found = _directory_models(item, path, root, where)
        elif root is not None and not _inside(path, root):  # absolute, ../, or a link out
            raise _paths_error(where, item, "a file outside the project")
        else:
            found = [path]
        for p in found:
            key = p.resolve()
            if key not in seen:
                seen.add(key)
                out.append(p)
        if len(out) > MAX_MODEL_FILES:
            raise _paths_error(where, str(found[0]), f"more than {MAX_MODEL_FILES} model files")
    return out


def _paths_error(where: tuple[Path, str] | None, item: str, problem: str) -> FkcheckError:
    """What is wrong with ``item``: a :class:`ProjectError` at ``where``, if given."""
    if where is not None:
        return ProjectError(where[0], where[1], f"{item!r}: {problem}")
    return FkcheckError(f"{item}: {problem}")


def _glob_models(item: str, root: Path | None, where: tuple[Path, str] | None) -> list[Path]:
    """The model files a glob matches (relative to ``root``, inside it), sorted; at least one."""
    if Path(item).is_absolute() or ".." in Path(item).parts:
        raise _paths_error(where, item, "a glob must be relative and stay inside the project")
    base = root if root is not None else Path.cwd()
    found = sorted(p for p in base.glob(item) if p.suffix.lower() in MODEL_SUFFIXES and p.is_file())
    if root is not None:
        found = [p for p in found if _inside(p, root)]
    found = [p for p in found if is_model_file(p)]
    if not found:
        raise _paths_error(where, item, f"matches no model file ({_MODEL_FILES})")
    return found


def _directory_models(
    item: str, path: Path, root: Path | None, where: tuple[Path, str] | None
) -> list[Path]:
    """A directory's ``.toml`` and ``.csv`` files (inside ``root``), sorted; at least one."""
    if root is not None and not _inside(path, root):
        raise _paths_error(where, item, "a directory outside the project")
    found = sorted(p for p in path.iterdir() if p.suffix.lower() in MODEL_SUFFIXES)
    found = [p for p in found if p.is_file()]
    if not found:
        raise _paths_error(where, item, "a directory with no .toml or .csv model file")
    return found
