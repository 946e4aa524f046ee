"""``fkcheck check``: compare the in-house core with reference backends.

``fkcheck check MODEL`` checks one model and writes whichever of ``--json``,
``--junit``, ``--html`` and ``--summary`` it is given. ``fkcheck check A B DIR``
checks several (bundled names, ``.toml``/``.csv`` files, directories of them;
globs are the shell's business) and ``fkcheck check --all`` every bundled model:
one terminal table with a row per model, one exit code, and with ``--out-dir``
each model's ``<stem>.json``, ``<stem>.html`` and ``<stem>.junit.xml`` plus
``index.html``, the dashboard linking them (``--all`` writes into ``reports/``
unless ``--out-dir`` says otherwise). File names come from each model file's
stem; two models with one stem are refused (exit 2) rather than one
overwriting the other. With no MODEL and no ``--all``, the models listed in
``[tool.fkcheck] models`` of the nearest ``pyproject.toml`` are checked; that
table also gives defaults for ``--samples``, ``--seed``, ``--sampler``,
``--timeout``, ``--against``, ``--require``, ``--tol-pos``, ``--tol-rot`` and a
ROS 2 bag's ``--bag-*`` settings (a flag on the command line wins; ``--isolated``
ignores the table). Every
model is read, and its URDF screened, before any check runs: bad input in any
of them is one line and exit 2.

Either way, when the environment variable ``GITHUB_STEP_SUMMARY`` names a file (as on
GitHub Actions), the Markdown summary is appended to it — if it is a regular
file, or a new one in an existing directory, and neither an input nor an output
of the run; otherwise a warning says why and the check goes on with its own
exit code (the CI page's file is not the check's business). Every output path
is checked before the check runs (:mod:`fkcheck.io.output_paths`): a path
that is an input, shared by two outputs, not a regular file, or in a directory
that cannot take it is bad input (exit 2). The HTML report of a
failing check has a Diagnosis section (``fkcheck diagnose`` run against the
disagreeing backends) unless ``--no-diagnose`` is given; the JSON is the same
with or without it. The diagnosis runs for every failing check (one model or
many) unless ``--no-diagnose`` is given: its one line is printed under the
results (``diagnosis (pinocchio-urdf): one number differs: a2 (J2)``, per
model in a run over many), and ``--html``, ``--junit``, ``--summary``,
``$GITHUB_STEP_SUMMARY`` and the annotations show it — with
``GITHUB_ACTIONS=true`` each failure is also printed as an ``::error`` line at
the model file (:mod:`fkcheck.report.annotations`). On a terminal the
header prints before the backends run; their progress goes to stderr
(:mod:`fkcheck.cli.progress`; ``--quiet`` turns it off).
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fkcheck.cli.progress import PLAIN_INTERVAL_S
from fkcheck.core.tolerances import MAX_TOL_JACOBIAN, MAX_TOL_POS_M, MAX_TOL_ROT_RAD
from fkcheck.core.typing import JACOBIAN_REFERENCES
from fkcheck.errors import FkcheckError
from fkcheck.model.options import (
    DEFAULT_SAMPLER,
    DEFAULT_SAMPLES,
    DEFAULT_SEED,
    DEFAULT_TIMEOUT_S,
    MAX_SAMPLES,
    MAX_TIMEOUT_S,
    SAMPLERS,
)

if TYPE_CHECKING:
    from fkcheck.cli._targets import Target
    from fkcheck.description.types import Description
    from fkcheck.model.project import ProjectConfig

from fkcheck.cli._arguments import add_bag_arguments, apply_bag_settings
from fkcheck.cli._targets import ONLY_MODELS_HELP
from fkcheck.cli.check_run import require_from_args, run_many, run_one

__all__ = ["DEFAULT_OUT_DIR", "add_parser", "run"]

#: Where ``--all`` writes its reports unless ``--out-dir`` says otherwise.
DEFAULT_OUT_DIR = Path("reports")


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    from fkcheck.backends.registry import against_help
    from fkcheck.cli.expand import add_allow_xacro

    p = sub.add_parser(
        "check",
        help="cross-check the in-house DH core against reference libraries",
        description="Compare from_T_to, pose by pose, between the in-house DH core and each "
        "reference backend, for one model or many (one table, one exit code). "
        "[tool.fkcheck] in the nearest pyproject.toml gives the models when none is named, "
        "and defaults for the options; a flag given here wins. Exit 0: every backend that "
        "ran agrees for every model; 1: a backend disagrees or errors, none ran, or "
        "required evidence is missing; 2: bad input (in any model: nothing runs).",
    )
    p.add_argument(
        "models",
        metavar="MODEL",
        nargs="*",
        help="bundled model names (ur5), .toml/.csv files or directories of them; none: "
        "[tool.fkcheck] models of the nearest pyproject.toml, or --all",
    )
    p.add_argument(
        "--all",
        action="store_true",
        help="check every bundled model; write <model>.json/.html/.junit.xml and index.html "
        f"into --out-dir (default {DEFAULT_OUT_DIR}/)",
    )
    p.add_argument(
        "--out-dir",
        type=Path,
        metavar="DIR",
        help="write each model's <stem>.json/.html/.junit.xml and index.html here "
        f"(--all: default {DEFAULT_OUT_DIR}/)",
    )
    p.add_argument(
        "--against",
        action="append",
        metavar="LIST",
        help=against_help(),
    )
    p.add_argument(
        "--require",
        action="append",
        metavar="KIND",
        help="evidence that must be verified, else the verdict is 'unverified' (exit 1): "
        "'table' (checked against something independent of the table: a URDF, measured "
        "poses, a published table) or 'implementation'; comma-separated or repeated; adds "
        "to the model's [check] require",
    )
    p.add_argument(
        "--samples",
        type=int,
        help=f"random samples (default {DEFAULT_SAMPLES}, at most {MAX_SAMPLES:_})",
    )
    p.add_argument(
        "--seed",
        type=int,
        help=f"seed of the random samples (default {DEFAULT_SEED}, 0 … 2**64 - 1)",
    )
    p.add_argument("--sampler", choices=SAMPLERS, help=f"(default {DEFAULT_SAMPLER})")
    p.add_argument("--from", dest="frame_from", metavar="FRAME", help="frame the pose is in")
    p.add_argument("--to", dest="frame_to", metavar="FRAME", help="frame whose pose is compared")
    p.add_argument("--tol-pos", type=float, metavar="M",
                   help=f"position tolerance, metres (at most {MAX_TOL_POS_M:g})")  # fmt: skip
    p.add_argument("--tol-rot", type=float, metavar="RAD",
                   help=f"rotation tolerance, radians (at most {MAX_TOL_ROT_RAD:g})")  # fmt: skip
    p.add_argument(
        "--jacobian",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="also compare each backend's Jacobian of the --to frame with the core's (its "
        "library's own, or central differences of its poses); a disagreement fails the check "
        "(default: the model's [check] jacobian)",
    )
    p.add_argument(
        "--jacobian-reference",
        choices=JACOBIAN_REFERENCES,
        help="the Jacobian's reference frame: world-aligned (the --to origin's velocity in "
        "--from axes; Pinocchio LOCAL_WORLD_ALIGNED, RTB jacob0), local (--to axes; LOCAL, "
        "jacobe), world (the twist at the --from origin; WORLD); implies --jacobian",
    )
    p.add_argument(
        "--tol-jacobian",
        type=float,
        metavar="TOL",
        help="Jacobian tolerance, m/rad (linear rows) and rad/rad (angular rows); default "
        f"1e-6, at most {MAX_TOL_JACOBIAN:g}; implies --jacobian",
    )
    add_allow_xacro(p)
    _add_pair_arguments(p)
    add_bag_arguments(p)
    p.add_argument("--only-models", action="store_true", help=ONLY_MODELS_HELP)
    p.add_argument(
        "--isolated",
        action="store_true",
        help="ignore [tool.fkcheck] of pyproject.toml: the flags and the defaults only (as "
        "plain fkcheck, the main job, runs)",
    )
    p.add_argument("--timeout", type=float, metavar="S",
                   help=f"time limit per backend, seconds (default {DEFAULT_TIMEOUT_S:g}, at "
                   f"most {MAX_TIMEOUT_S:g})")  # fmt: skip
    p.add_argument(
        "--full",
        action="store_true",
        default=None,
        help="every backend compares every configuration, however long it takes (the "
        "--timeout still applies); by default a backend whose declared cost does not fit "
        "half its time limit compares a stated subset: all structured configurations and "
        "the first of the random samples",
    )
    p.add_argument(
        "--processes",
        type=int,
        metavar="N",
        help="at most N processes for each isolated backend (default: one per usable core); "
        "1 on a CI runner shared with other jobs. It changes the time a check takes, never "
        "its result",
    )
    p.add_argument("--json", type=Path, metavar="PATH", help="write the JSON result here")
    p.add_argument("--junit", type=Path, metavar="PATH", help="write JUnit XML here")
    p.add_argument("--html", type=Path, metavar="PATH", help="write the HTML report here")
    p.add_argument(
        "--summary",
        type=Path,
        metavar="PATH",
        help="write a Markdown summary here (also appended to $GITHUB_STEP_SUMMARY when set)",
    )
    p.add_argument(
        "--no-diagnose",
        dest="diagnose",
        action="store_false",
        help="a failing check: leave out its diagnosis (the one line printed, the reports' "
        "Diagnosis section; it runs fkcheck diagnose against each distinct disagreeing "
        "backend, about a second each)",
    )
    p.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        help="no progress on stderr (the result table and verdict still print)",
    )
    p.add_argument(
        "--progress-interval",
        type=float,
        default=PLAIN_INTERVAL_S,
        metavar="S",
        help="when stderr is not a terminal (a CI log): seconds between the plain progress "
        f"lines of each running backend (default {PLAIN_INTERVAL_S:g})",
    )
    p.set_defaults(run=run)


def _add_pair_arguments(p: argparse.ArgumentParser) -> None:
    """Two descriptions and no table (:mod:`fkcheck.description.derived`)."""
    pair = p.add_argument_group(
        "two descriptions, no table (--source A --against-description B)",
        "derive the DH table from A alone (as table-from does) and check B against it with "
        "B's own readers (MuJoCo and Pinocchio for an MJCF, the URDF parsers for a URDF); "
        "joints are matched by name. It shows whether A and B agree, not whether either "
        "holds the vendor's numbers. Each chain runs from the link its first moving joint "
        "hangs from to the link its last one moves, unless given",
    )
    pair.add_argument("--source", metavar="DESCRIPTION",
                      help="the URDF or MJCF the table is derived from")  # fmt: skip
    pair.add_argument("--against-description", metavar="DESCRIPTION",
                      help="the URDF or MJCF checked against it")  # fmt: skip
    pair.add_argument("--base", metavar="LINK", help="the source chain's base link or body")
    pair.add_argument("--tip", metavar="LINK", help="the source chain's tip link, body or site")
    pair.add_argument("--checked-base", metavar="LINK",
                      help="the checked chain's base (default: --base, else chosen)")  # fmt: skip
    pair.add_argument("--checked-tip", metavar="LINK",
                      help="the checked chain's tip (default: --tip, else chosen)")  # fmt: skip


def _pair_target(args: argparse.Namespace) -> Target:
    """``--source A --against-description B``: the model of the table derived from ``A``.

    Raises:
        FkcheckError: One of the two missing, or given with what does not go with it.
    """
    from fkcheck.cli._targets import Target
    from fkcheck.description.derived import ChainEnds, derived_model
    from fkcheck.io.text import terminal_text

    if args.source is None or args.against_description is None:
        given, missing = ("--source", "--against-description")[:: 1 if args.source else -1]
        raise FkcheckError(f"{given} needs {missing} (the two descriptions to compare)")
    ends, expand = (
        " (the chain's ends: --base, --tip)",
        " (expand the xacro file first: fkcheck expand)",
    )
    clashes = [("MODEL", bool(args.models), ""), ("--all", args.all, ""),
               ("--out-dir", args.out_dir is not None, ""),
               ("--from", args.frame_from is not None, ends),
               ("--to", args.frame_to is not None, ends),
               ("--allow-xacro", args.allow_xacro, expand)]  # fmt: skip
    for flag, given, hint in clashes:
        if given:
            raise FkcheckError(f"{flag} does not go with --source{hint}")
    source, checked = (_pair_file(args.source), _pair_file(args.against_description))
    if source.path.resolve() == checked.path.resolve():
        raise FkcheckError(
            f"--source and --against-description both name {source.path}: a description "
            "agrees with itself; give the other one"
        )
    model = derived_model(
        source, checked, ChainEnds(args.base, args.tip),
        ChainEnds(args.checked_base, args.checked_tip),
        names=(args.source, args.against_description),
    )  # fmt: skip
    print(f"fkcheck: {terminal_text(model.source)}")
    return Target(args.against_description, checked.path.stem, model)


def _pair_file(spec: str) -> Description:
    """One of ``--source``/``--against-description``, read; a xacro file is refused with its fix.

    Raises:
        UrdfError: Missing, unsafe, not valid; xacro (expanded first by ``fkcheck expand``,
            which takes its arguments and packages).
    """
    from fkcheck.description.registry import read_description_file
    from fkcheck.errors import XacroRefused

    try:
        return read_description_file(spec)
    except XacroRefused as refused:
        raise XacroRefused(
            refused.path,
            "is xacro: expand it first (fkcheck expand FILE.xacro --arg NAME=VALUE "
            "--package NAME=DIR -o robot.urdf) and give the URDF",
        ) from None


def _apply_project(args: argparse.Namespace, project: ProjectConfig | None) -> None:
    """Resolve the check's options, flag > ``[tool.fkcheck]`` > default, into ``args.options``.

    :func:`fkcheck.model.options.resolve_options` decides and checks them (a bad
    value is exit 2, named by its flag); the flags' attributes are set to the
    values decided, for the header and the reproducing command lines.
    """
    from fkcheck.cli.check_run import jacobian_from_args
    from fkcheck.model.options import FLAGS, OPTIONS, resolve_options

    # A flag whose dest is its option's name needs no line here.
    given: dict[str, Any] = {name: getattr(args, name, None) for name in OPTIONS}
    given |= {
        "timeout_s": args.timeout, "tol_pos_m": args.tol_pos, "tol_rot_rad": args.tol_rot,
        "require": require_from_args(args), "jacobian": jacobian_from_args(args),
    }  # fmt: skip
    layer = project.options if project is not None else None
    options = resolve_options(given, labels=FLAGS, project=layer)
    args.options = options
    args.samples, args.seed, args.sampler = options.samples, options.seed, options.sampler
    args.timeout = options.timeout_s
    args.tol_pos, args.tol_rot = options.tol_pos_m, options.tol_rot_rad
    args.jacobian, args.jacobian_reference = options.jacobian, options.jacobian_reference
    args.tol_jacobian = options.tol_jacobian
    args.require = list(options.require) or None
    if args.against is None and project is not None and project.against is not None:
        args.against = list(project.against)
    apply_bag_settings(args, project)
    args.lint_ignore = project.lint_ignore if project is not None else ()


def _validate(args: argparse.Namespace) -> None:
    if args.all and args.models:
        raise FkcheckError(
            f"--all checks every bundled model: drop MODEL ({' '.join(args.models)!r})"
        )
    if args.all or args.out_dir is not None:
        per_model = "--all" if args.all else "--out-dir"
        for flag, value in (("--json", args.json), ("--junit", args.junit),
                            ("--html", args.html)):  # fmt: skip
            if value is not None:
                raise FkcheckError(
                    f"{flag} does not go with {per_model} (each model's files go to --out-dir)"
                )
    if args.all:
        for flag, value in (("--from", args.frame_from), ("--to", args.frame_to)):
            if value is not None:
                raise FkcheckError(f"{flag} does not go with --all (frames are per model)")


def _validate_many(args: argparse.Namespace) -> None:
    """Options that name one model's files do not go with several models."""
    for flag, value in (("--json", args.json), ("--junit", args.junit), ("--html", args.html)):
        if value is not None:
            raise FkcheckError(
                f"{flag} writes one model's file: with several models use --out-dir DIR "
                "(each model's .json/.html/.junit.xml and index.html)"
            )


def _targets(args: argparse.Namespace, project: ProjectConfig | None) -> list[Target]:
    """The models to check: ``--all``'s bundled ones, the arguments, or the project's."""
    from fkcheck.cli._targets import Target, load_targets
    from fkcheck.model.read import bundled_model_paths, load_model

    if args.all:
        bundled = bundled_model_paths().items()
        return [Target(stem, stem, load_model(path)) for stem, path in bundled]
    if not args.models and (project is None or not project.models):
        where = f" (none in {project.path})" if project is not None else ""
        raise FkcheckError(
            "give a MODEL (e.g. ur5) or --all, or list models in [tool.fkcheck] models = "
            f"[...] of pyproject.toml{where}"
        )
    return load_targets(args.models, project)


def run(args: argparse.Namespace) -> int:
    """Run the check, print, write the requested files."""
    from fkcheck.cli._targets import named_model_files, project_config

    if args.only_models:
        models = named_model_files(args.models, "check")
        if models is None:  # files were named, none a model: nothing to check
            return 0
        args.models = models
    project = None if args.isolated else project_config()
    # Named by every output (header, JSON, HTML), as the working directory sees it.
    args.config = None if project is None else os.path.relpath(project.path)
    _apply_project(args, project)
    _validate(args)
    require_from_args(args)  # bad --require is exit 2 before anything runs
    pair = (args.source, args.against_description, args.base, args.tip, args.checked_base,
            args.checked_tip)  # fmt: skip
    if any(given is not None for given in pair):
        if args.source is None and args.against_description is None:
            raise FkcheckError("--base, --tip, --checked-base and --checked-tip go with --source")
        return run_one(args, _pair_target(args))
    targets = _targets(args, project)
    if args.allow_xacro:
        from dataclasses import replace

        from fkcheck.urdf.source import allow_xacro

        targets = [replace(t, model=allow_xacro(t.model)) for t in targets]
    one_file = len(args.models) == 1 and not Path(args.models[0]).is_dir()
    if args.all or args.out_dir is not None or not one_file:
        _validate_many(args)
        out_dir = args.out_dir or (DEFAULT_OUT_DIR if args.all else None)
        return run_many(args, targets, out_dir)
    return run_one(args, targets[0])
