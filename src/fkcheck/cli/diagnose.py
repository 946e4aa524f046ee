"""``fkcheck diagnose``: explain a disagreement between the table and a reference."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fkcheck.errors import FkcheckError, Skip, failure_text

if TYPE_CHECKING:
    from fkcheck.backends.base import Backend
    from fkcheck.core.typing import Float
    from fkcheck.model.types import Model

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    from fkcheck.cli._arguments import add_bag_arguments
    from fkcheck.cli.expand import add_allow_xacro
    from fkcheck.core.tolerances import MAX_TOL_POS_M, MAX_TOL_ROT_RAD
    from fkcheck.engine.stream import READ_MIN_S
    from fkcheck.model.options import DEFAULT_TIMEOUT_S, MAX_TIMEOUT_S

    p = sub.add_parser(
        "diagnose",
        help="explain why a table disagrees with a reference (frames, parameters, mistakes)",
        description="Explain a disagreement, most likely explanation first, each with the "
        "residual before and after: constant frame offsets (base_link vs base, flange vs "
        "tool0, with the model-file text that fixes them), joint axes compared as lines, "
        "typical mistakes tested as hypotheses (degrees, convention, a sign, a θ offset, a "
        "reversed joint, one parameter) and a fit of every parameter. Exit 0: the table "
        "agrees or the disagreement is explained; 1: not explained; 2: bad input.",
    )
    p.add_argument("model", metavar="MODEL", help="bundled model name (ur5) or a .toml/.csv file")
    p.add_argument(
        "--against",
        metavar="BACKEND",
        help="the reference (default: pinocchio-urdf when the model has a [urdf]); e.g. "
        "rtb-model:UR5, poses:measured.csv",
    )
    p.add_argument("--from", dest="frame_from", metavar="FRAME", help="frame the pose is in")
    p.add_argument("--to", dest="frame_to", metavar="FRAME", help="frame whose pose is compared")
    p.add_argument("--samples", type=int, default=200, help="random samples (default 200)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random samples (default 0)")
    p.add_argument("--tol-pos", type=float, metavar="M",
                   help=f"position tolerance, metres (at most {MAX_TOL_POS_M:g})")  # fmt: skip
    p.add_argument("--tol-rot", type=float, metavar="RAD",
                   help=f"rotation tolerance, radians (at most {MAX_TOL_ROT_RAD:g})")  # fmt: skip
    p.add_argument("--timeout", type=float, metavar="S",
                   help="time limit of reading a recording (--against poses:FILE), seconds, as "
                   f"fkcheck check's (default {DEFAULT_TIMEOUT_S:g}, at least "
                   f"{READ_MIN_S:g} for the read, at most {MAX_TIMEOUT_S:g})")  # fmt: skip
    p.add_argument("--json", type=Path, metavar="PATH", help="write the diagnosis as JSON here")
    add_allow_xacro(p)
    add_bag_arguments(p)  # fkcheck check's, and its [tool.fkcheck] keys
    p.add_argument(
        "--isolated",
        action="store_true",
        help="ignore [tool.fkcheck] of pyproject.toml (its bag_* keys): the flags and the "
        "defaults only, as fkcheck check --isolated",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Diagnose, print, write JSON."""
    from fkcheck.backends import registry
    from fkcheck.backends.registry import (
        BackendOptions,
        check_known_differences,
        make_backend,
    )
    from fkcheck.cli._arguments import apply_bag_settings, bag_options
    from fkcheck.cli._outputs import backend_inputs, model_inputs, plan, writes
    from fkcheck.cli._targets import project_config
    from fkcheck.diagnose import diagnose, format_text, to_dict
    from fkcheck.io.atomic import write_text_atomic
    from fkcheck.io.strict_json import strict_json
    from fkcheck.io.text import terminal_lines, terminal_text
    from fkcheck.model.options import DEFAULT_TIMEOUT_S, check_option
    from fkcheck.model.read import load_model

    check_option("samples", args.samples, "--samples", lowest=1)
    check_option("seed", args.seed, "--seed")
    if args.tol_pos is not None:
        check_option("tol_pos_m", args.tol_pos, "--tol-pos")
    if args.tol_rot is not None:
        check_option("tol_rot_rad", args.tol_rot, "--tol-rot")
    timeout_s = DEFAULT_TIMEOUT_S if args.timeout is None else args.timeout
    check_option("timeout_s", timeout_s, "--timeout")
    # A ROS 2 bag's settings: a --bag-* flag, else its [tool.fkcheck] key (as for check)
    project = None if args.isolated else project_config()
    apply_bag_settings(args, project)
    model = load_model(args.model)
    check_known_differences(model)  # the names are the registry's, as for check and lint
    if args.allow_xacro:
        from fkcheck.urdf.source import allow_xacro

        model = allow_xacro(model)
    for warning in model.warnings:
        print(f"fkcheck: warning: {terminal_text(warning)}", file=sys.stderr)
    name = args.against
    if name is None:
        from fkcheck.description.registry import LANGUAGES, model_format

        fmt = model_format(model)
        if fmt is None:
            readers = {n for language in LANGUAGES for n in registry.names(reads=language)}
            others = [n for n in registry.known_difference_names() if n not in readers]
            independent = ", ".join(n + "…" if n.endswith(":") else n for n in others)
            raise FkcheckError(
                f"model {model.name} has no [urdf] to diagnose against: give --against "
                f"a backend independent of its table ({independent})"
            )
        name = registry.names(format=fmt.name, default=True)[0]  # pinocchio-urdf for a URDF
    # the frames too: a ROS 2 bag (poses:BAG) composes its transform for them
    # and reads its topics with the settings given
    options = BackendOptions(
        frame_from=args.frame_from, frame_to=args.frame_to, **bag_options(args)
    )
    backend = make_backend(name, options)
    outputs = [("--json", args.json)]
    inputs = [*model_inputs(model, expand=writes(outputs)), *backend_inputs([backend], model)]
    if project is not None:  # read, so no output replaces it (as for check)
        inputs.append(("the configuration file", project.path))
    plan(args, outputs, inputs)
    reference = _Reference(backend)
    reason = reference.unavailable_reason(model)
    if reason is not None:
        raise FkcheckError(f"cannot diagnose against {backend.name}: it cannot run here: {reason}")
    result = diagnose(
        model,
        reference,
        frame_from=args.frame_from,
        frame_to=args.frame_to,
        samples=args.samples,
        seed=args.seed,
        tol_pos_m=args.tol_pos,
        tol_rot_rad=args.tol_rot,
        timeout_s=timeout_s,
    )
    sys.stdout.write(terminal_lines(format_text(result)))
    if not result.agrees:  # another reader of the same file may show it is this one's
        finding = _reader_finding(model, backend, args)
        if finding:
            print(
                f"note: {terminal_text(finding)}; the explanations above fit the table to "
                f"{terminal_text(backend.name)}'s reading, they do not say the table is wrong"
            )
    if args.json is not None:
        write_text_atomic(args.json, strict_json(to_dict(result), indent=2) + "\n")
    return 0 if result.agrees or result.explained else 1


class _Reference:
    """The reference as ``diagnose`` uses it: its failure is one line and exit 2.

    A check reports a backend that cannot run or fails as that backend's result
    (``skipped``, ``error``) and goes on with the others; a diagnosis has only
    this one, so the same words (:func:`~fkcheck.errors.failure_text`) end the
    command as bad input: a missing library, a frame the URDF does not map, a
    plugin that does not import.
    """

    def __init__(self, backend: Backend) -> None:
        self._backend = backend

    def __getattr__(self, member: str) -> Any:
        return getattr(self._backend, member)

    def unavailable_reason(self, model: Model) -> str | None:
        """Why the backend cannot run on ``model``, or one line when asking it failed.

        Raises:
            FkcheckError: Bad input, or asking it failed.
        """
        reason: str | None = self._answer(self._backend.unavailable_reason, model)
        return reason

    def frame_poses(self, model: Model, q: Float, frames: Sequence[str]) -> Float:
        """The backend's poses, or one line naming it and what went wrong.

        Raises:
            FkcheckError: Bad input, or the backend cannot run or failed.
        """
        poses: Float = self._answer(self._backend.frame_poses, model, q, frames)
        return poses

    def _answer(self, call: Callable[..., Any], *args: Any) -> Any:
        name = self._backend.name
        try:
            return call(*args)
        except FkcheckError:
            raise
        except Skip as exc:
            raise FkcheckError(
                f"cannot diagnose against {name}: it cannot run here: {exc}"
            ) from None
        except Exception as exc:  # the check reports it as the backend's error
            raise FkcheckError(
                f"cannot diagnose against {name}: it failed: {failure_text(exc)}"
            ) from None


#: Configurations of the check that looks for a reader finding: enough to see a reader
#: metres off (pinocchio#2782 is off at every configuration), and about a second.
_READER_SAMPLES = 20


def _reader_finding(model: Model, backend: Backend, args: argparse.Namespace) -> str:
    """When another reader of the same description agrees with the table: the finding.

    A short check of ``backend`` with the other readers of its format
    (:mod:`fkcheck.engine.readers`), on the diagnosis's frames and tolerances;
    ``""`` for a backend that reads no description, or when no other reader agrees.
    """
    from fkcheck.api import check
    from fkcheck.backends import registry

    if not getattr(backend, "formats", ()):
        return ""
    others = [n for n in registry.names(reads=backend.reads) if n != backend.name]
    if not others:
        return ""
    given = {
        "frame_from": args.frame_from,
        "frame_to": args.frame_to,
        "tol_pos_m": args.tol_pos,
        "tol_rot_rad": args.tol_rot,
    }
    try:
        outcome = check(
            model,
            [backend.name, *others],
            diagnose=False,
            samples=_READER_SAMPLES,
            seed=args.seed,
            **{k: v for k, v in given.items() if v is not None},
        )
    except FkcheckError:  # the others cannot be asked here: nothing to say of them
        return ""
    row = next(r for r in outcome.check.backends if r.name == backend.name)
    return row.reader_finding
