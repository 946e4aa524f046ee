"""What a subcommand reads and writes, handed to the output-path policy before it runs.

:func:`plan` checks a command's outputs against its inputs
(:func:`fkcheck.io.output_paths.plan_outputs`) and stores the plan on
``args.output_plan``, where :func:`fkcheck.cli.main.main` finds it to say which
files an interrupted run wrote. :func:`model_inputs` and
:func:`backend_inputs` name the files a model and its backends read.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from fkcheck.io.output_paths import (
    OutputPlan,
    append_step_summary,
    plan_outputs,
    step_summary_problem,
)
from fkcheck.io.text import terminal_text

if TYPE_CHECKING:
    from fkcheck.backends.base import Backend
    from fkcheck.description.types import Description
    from fkcheck.model.types import Model

__all__ = [
    "STEP_SUMMARY",
    "Input",
    "append_to_step_summary",
    "backend_inputs",
    "description_inputs",
    "model_inputs",
    "plan",
    "step_summary_target",
    "writes",
]

#: ``(what it is, path)``: a file the run reads.
Input = tuple[str, Path | str | None]

#: The environment variable naming GitHub's job-summary file.
STEP_SUMMARY = "GITHUB_STEP_SUMMARY"


def writes(outputs: Iterable[tuple[str, Path | str | None]]) -> bool:
    """Whether a run with these outputs writes a file: one is given, or ``$GITHUB_STEP_SUMMARY``."""
    return any(path is not None for _, path in outputs) or bool(os.environ.get(STEP_SUMMARY))


def description_inputs(described: Description, what: str) -> list[Input]:
    """Every file a description was made of: the file (``what``), then each file it read."""
    how = "xacro include or load_yaml" if described.format == "xacro" else "include"
    found: list[Input] = [(what, described.path)]
    found += [(f"a file {what} reads ({how})", f) for f in described.files[1:]]
    return found


def model_inputs(model: Model, *, expand: bool = True) -> list[Input]:
    """The model file and, when it has one that exists, every file its URDF is made of.

    A plain URDF is screened here (:func:`fkcheck.description.registry.load_description`),
    before any output path is planned: input is refused before anything, even a
    probe of an output directory, touches the disk. A xacro file the model opts
    in to (``xacro = true``) is expanded here too when ``expand`` (a run that
    writes a file: :func:`writes`), so that its includes and ``load_yaml`` files
    are inputs no output replaces; the check reuses that expansion
    (:func:`fkcheck.urdf.xacro.read_xacro` keeps it). A run that writes
    nothing only locates it: expanding is left to the backends that read it.

    Raises:
        UrdfError: The URDF is missing, not a regular file, unsafe or broken, or
            its xacro expansion failed.
    """
    from fkcheck.description.registry import load_description, model_format
    from fkcheck.errors import BackendUnavailable

    found: list[Input] = [(f"the model file of {model.name}", model.path)]
    fmt = model_format(model)
    if fmt is None:
        return found
    what = f"the {fmt.language.upper()} of {model.name}"
    try:
        if fmt.executes and not expand:
            return [*found, (what, fmt.locate(model))]
        return [*found, *description_inputs(load_description(model, mapping=False), what)]
    except BackendUnavailable:  # example-robot-data is not installed: no file here
        return found


def backend_inputs(backends: Iterable[Backend], model: Model) -> list[Input]:
    """Files the backends read for ``model`` beyond the model's own (:meth:`Backend.inputs`).

    A measured-poses CSV, a ``cmd:`` program and the files on its command line,
    a plugin's module (found without importing it).
    """
    return [
        (f"a file of backend {backend.name}", path)
        for backend in backends
        for path in backend.inputs(model)
    ]


def plan(
    args: argparse.Namespace,
    outputs: Sequence[tuple[str, Path | str | None]],
    inputs: Iterable[Input],
) -> OutputPlan:
    """Check the outputs (exit 2 on a bad one) and keep the plan on ``args.output_plan``.

    Raises:
        OutputPathError: See :func:`fkcheck.io.output_paths.plan_outputs`.
    """
    result = plan_outputs(outputs, inputs)
    args.output_plan = result
    return result


def _warn(path: str, problem: str) -> None:
    print(
        f"fkcheck: warning: ${STEP_SUMMARY} {terminal_text(path)}: {terminal_text(problem)}; "
        "the summary is not appended there",
        file=sys.stderr,
    )


def step_summary_target(inputs: Iterable[Input], output_plan: OutputPlan) -> str | None:
    """``$GITHUB_STEP_SUMMARY`` when it can take the summary; else warn (once) and ``None``.

    A problem with the CI page's file is a warning, not a failed check: the
    check's verdict and exit code stay what they are.
    """
    path = os.environ.get(STEP_SUMMARY)
    if not path:
        return None
    problem = step_summary_problem(path, inputs, output_plan)
    if problem is not None:
        _warn(path, problem)
        return None
    return path


def append_to_step_summary(path: str | None, text: str) -> None:
    """Append to the step summary chosen by :func:`step_summary_target`; warn if that fails."""
    if path is None:
        return
    problem = append_step_summary(path, text + "\n")
    if problem is not None:
        _warn(path, problem)
