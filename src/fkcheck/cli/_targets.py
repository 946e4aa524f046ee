"""Which models a command runs on: its arguments, or ``[tool.fkcheck] models``.

``fkcheck check`` and ``fkcheck lint`` take any number of bundled model names,
model files and directories (globs are the shell's business); with none, the
models listed in the nearest ``pyproject.toml``'s ``[tool.fkcheck]``
(:mod:`fkcheck.model.project`). Every model is read before any is used, so bad
input in any file is one line and exit 2 before anything runs.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from fkcheck.errors import FkcheckError

if TYPE_CHECKING:
    from fkcheck.model.project import ProjectConfig
    from fkcheck.model.types import Model

__all__ = [
    "ONLY_MODELS_HELP",
    "Target",
    "load_targets",
    "model_files_only",
    "named_model_files",
    "project_config",
    "unique_stems",
]

#: ``--only-models``'s help, the same for ``check`` and ``lint``.
ONLY_MODELS_HELP = (
    "pass over each named .toml/.csv file that is not a robot model file (a .toml without "
    "[[joint]] tables, a .csv that is not a DH table: pyproject.toml, Cargo.toml, a poses "
    "CSV), saying so on stderr; for the pre-commit hooks, which name every changed "
    ".toml/.csv file"
)


@dataclass(frozen=True)
class Target:
    """One model to run on.

    Attributes:
        arg: How the command line (or the project) named it: ``ur5`` or a path.
        stem: The name its output files take (the file's stem, or the bundled name).
        model: The model, read and validated.
    """

    arg: str
    stem: str
    model: Model


def project_config() -> ProjectConfig | None:
    """``[tool.fkcheck]`` of the nearest ``pyproject.toml``, or ``None``.

    Raises:
        ProjectError: The table is there but invalid (exit 2).
    """
    from fkcheck.model.project import load_project

    return load_project()


def load_targets(items: Sequence[str], project: ProjectConfig | None) -> list[Target]:
    """The models ``items`` name (directories expanded), else the project's, all read.

    Raises:
        FkcheckError: No model given and no ``[tool.fkcheck] models`` to fall back on,
            a directory without model files.
        ModelError: A model file that cannot be read (the first one, by name).
    """
    from fkcheck.backends.registry import check_known_differences
    from fkcheck.model.project import expand_model_paths
    from fkcheck.model.read import load_model

    if items:
        paths: list[Path] = expand_model_paths(items)
    elif project is not None and project.models:
        paths = project.model_paths()
    else:
        where = f" in {project.path}" if project is not None else ""
        raise FkcheckError(
            "give a MODEL (a bundled name such as ur5, a .toml/.csv file or a directory), "
            f"or list them in [tool.fkcheck] models = [...] of pyproject.toml{where}"
        )
    targets = []
    for path in paths:
        model = load_model(path)
        check_known_differences(model)  # the names are the registry's
        stem = model.path.stem if model.path is not None else str(path)
        targets.append(Target(_shown(path), stem, model))
    return targets


def _shown(path: Path) -> str:
    """``path`` as a message names it: relative to the working directory when inside it."""
    if path.is_absolute():
        try:
            return str(path.relative_to(Path.cwd()))
        except ValueError:
            return str(path)
    return str(path)


def model_files_only(items: Sequence[str]) -> tuple[list[str], list[str]]:
    """``(kept, passed over)``: the named files that are robot model files, and the others.

    A name that is no regular file (a bundled name, a directory, a path that is
    not there) is kept: its reader says what it is. The rule is
    :func:`fkcheck.model.read.is_model_file`, as for globs and directories.
    """
    from fkcheck.model.read import is_model_file

    kept: list[str] = []
    passed: list[str] = []
    for item in items:
        path = Path(item)
        (kept if not path.is_file() or is_model_file(path) else passed).append(item)
    return kept, passed


def named_model_files(items: Sequence[str], command: str) -> list[str] | None:
    """``--only-models``: the named model files; ``None`` when files were named but none is one.

    Each file passed over is named in one line on stderr (as the terminal shows text).
    """
    from fkcheck.io.text import terminal_text

    kept, passed = model_files_only(items)
    if passed:
        print(
            f"fkcheck {command}: not robot model files, passed over: "
            f"{terminal_text(', '.join(passed))}",
            file=sys.stderr,
        )
    if items and not kept:
        print(f"fkcheck {command}: no robot model file among the files named", file=sys.stderr)
        return None
    return kept


def unique_stems(targets: Sequence[Target]) -> None:
    """Refuse two models whose output files would share a name.

    Raises:
        FkcheckError: Two models with one file stem (``a/arm.toml``, ``b/arm.csv``).
    """
    seen: dict[str, Target] = {}
    for target in targets:
        other = seen.setdefault(target.stem.casefold(), target)
        if other is not target:
            raise FkcheckError(
                f"{target.arg} and {other.arg} would both write {target.stem}.json/.html/"
                ".junit.xml: rename one, or check them in two runs"
            )
