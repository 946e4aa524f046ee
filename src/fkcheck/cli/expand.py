"""``fkcheck expand``: a xacro description expanded to a plain URDF file.

Also the xacro options other commands share (:func:`add_xacro_options`,
:func:`xacro_inputs`): ``--allow-xacro``, ``--arg NAME=VALUE`` and
``--package NAME=DIR``.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from fkcheck.cli._arguments import utf8_text
from fkcheck.errors import FkcheckError

__all__ = ["add_allow_xacro", "add_parser", "add_xacro_options", "run", "xacro_inputs"]


def add_allow_xacro(p: argparse.ArgumentParser) -> None:
    """Add ``--allow-xacro``: the one opt-in to expanding a xacro URDF, same words everywhere."""
    p.add_argument(
        "--allow-xacro",
        action="store_true",
        help="expand a xacro URDF, as xacro = true in the model's [urdf] does (in a limited "
        "child process; ${…} is Python that runs with your rights: only for files you trust)",
    )


def add_xacro_options(p: argparse.ArgumentParser, *, allow: bool = True) -> None:
    """Add ``--arg`` and ``--package`` (and, with ``allow``, ``--allow-xacro``) to ``p``."""
    if allow:
        add_allow_xacro(p)
    p.add_argument(
        "--arg",
        dest="xacro_args",
        action="append",
        default=[],
        type=utf8_text,
        metavar="NAME=VALUE",
        help="a xacro argument, as NAME:=VALUE on xacro's command line (repeatable)",
    )
    p.add_argument(
        "--package",
        dest="xacro_packages",
        action="append",
        default=[],
        type=utf8_text,
        metavar="NAME=DIR",
        help="a package $(find NAME) resolves to DIR, or to fkcheck:<subpath> bundled with "
        "fkcheck (repeatable); no other package is found",
    )


def _pair(text: str, flag: str, what: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise FkcheckError(f"{flag} {text!r}: expected NAME={what}")
    return name, value


def xacro_inputs(args: argparse.Namespace) -> tuple[dict[str, str], dict[str, Path]]:
    """The ``--arg`` and ``--package`` values: arguments by name, package directories by name.

    Raises:
        FkcheckError: A value is not ``NAME=VALUE``, a package name is not one,
            a name is given twice, or (on a command with ``--allow-xacro``) they
            are given without it.
    """
    from fkcheck.urdf.locate import locate
    from fkcheck.urdf.xacro import check_package_name

    if not getattr(args, "allow_xacro", True) and (args.xacro_args or args.xacro_packages):
        flag = "--arg" if args.xacro_args else "--package"
        raise FkcheckError(f"{flag} goes with --allow-xacro (it is for a xacro file)")
    values: dict[str, str] = {}
    for text in args.xacro_args:
        name, value = _pair(text, "--arg", "VALUE")
        if name in values:
            raise FkcheckError(f"--arg {name} is given twice")
        values[name] = value
    packages: dict[str, Path] = {}
    for text in args.xacro_packages:
        name, where = _pair(text, "--package", "DIR")
        try:
            check_package_name(name)
        except ValueError as exc:
            raise FkcheckError(f"--package: {exc}") from None
        if name in packages:
            raise FkcheckError(f"--package {name} is given twice")
        packages[name] = locate(where)  # a directory, or fkcheck:<subpath> (bundled)
    return values, packages


def add_parser(sub: Any) -> None:
    """Register the subcommand."""
    p = sub.add_parser(
        "expand",
        help="expand a xacro description to a plain URDF",
        description="Expand a xacro file to a plain URDF (with xacrodoc, no ROS needed), the "
        "file fkcheck and every URDF parser read. ${…} and $(eval …) are evaluated by "
        "fkcheck's own evaluator, never as Python (arithmetic, properties, arguments, math, "
        "lists and mappings; attribute access, lambdas, comprehensions and format strings are "
        "refused). The expansion runs in a child process with no environment and a time and "
        "memory limit; $(find NAME) resolves only to the packages given with --package (never "
        "ROS_PACKAGE_PATH), $(env …) is refused, includes and load_yaml read only from the "
        "file's directory and those packages, and the result must pass the screen every URDF "
        "passes (no DTD or entity, no xacro left, a valid tree). -o may not name the xacro "
        "file or any file it includes. Exit 2 with one line on any problem; nothing is "
        "written then.",
    )
    p.add_argument(
        "xacro",
        type=str,
        metavar="FILE.xacro",
        help="the xacro file, or fkcheck:<subpath> for one bundled with fkcheck "
        "(fkcheck:ur_description/urdf/ur.urdf.xacro)",
    )
    add_xacro_options(p, allow=False)
    p.add_argument(
        "--arg-file",
        dest="xacro_files",
        action="append",
        default=[],
        metavar="NAME=FILE",
        help="a xacro argument naming a file (kinematics_params=calibration.yaml): passed as its "
        "absolute path, and that file alone becomes readable by the expansion (repeatable)",
    )
    p.add_argument(
        "-o", "--output", type=Path, required=True, metavar="ROBOT.urdf", help="the URDF to write"
    )
    p.add_argument(
        "--timeout",
        type=float,
        metavar="S",
        help="time limit of the expansion, seconds (default 60, at most 86400)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Expand, screen, write atomically."""
    from fkcheck.cli._outputs import plan
    from fkcheck.io.atomic import write_text_atomic
    from fkcheck.io.text import terminal_text
    from fkcheck.model.options import check_option
    from fkcheck.urdf.locate import locate
    from fkcheck.urdf.xacro import XACRO_TIMEOUT_S, expand_xacro, screen_expansion

    xacro = locate(args.xacro)
    timeout = XACRO_TIMEOUT_S if args.timeout is None else args.timeout
    check_option("timeout_s", timeout, "--timeout")  # the one rule of every time limit
    values, packages = xacro_inputs(args)
    files: dict[str, Path] = {}
    for text in args.xacro_files:
        name, where = _pair(text, "--arg-file", "FILE")
        if name in files or name in values:
            raise FkcheckError(f"--arg-file {name}: {name} is given twice (--arg or --arg-file)")
        files[name] = Path(where)
    expansion = expand_xacro(xacro, values, packages, timeout, files)
    text = expansion.text
    info = screen_expansion(xacro, text)
    sources = [("the xacro file", xacro)]
    sources += [("a file the xacro file includes", f) for f in expansion.files[1:]]
    plan(args, [("-o", args.output)], sources)
    write_text_atomic(args.output, text if text.endswith("\n") else text + "\n")
    movable = sum(1 for joint in info.joints.values() if joint.type != "fixed")
    print(
        f"wrote {terminal_text(args.output)}: {len(info.links)} links, {len(info.joints)} "
        f"joints ({movable} moving), root {terminal_text(info.root)}"
    )
    return 0
