r"""Command-line values that become text in what fkcheck writes: UTF-8, or refused in one line.

Python decodes the command line with surrogate escapes: a byte that is not
UTF-8 (``k=1.0\xff``) arrives as a lone surrogate (``\udcff``). A file name may
hold one (the file is found by its bytes), but a value written into a URDF, a
model file or a report — a xacro argument, a package directory ``$(find …)``
puts into the URDF, a model or robot name — cannot: :func:`utf8_text`, an
argparse ``type``, refuses it (``fkcheck …: error: argument --arg: …``, exit 2).

A ROS 2 bag's settings (``--bag-*``, ``--against poses:BAG``) are defined here
once for ``fkcheck check`` and ``fkcheck diagnose``: :func:`add_bag_arguments`
(each value by the rule of its ``[tool.fkcheck]`` key), :func:`apply_bag_settings`
(the keys under the flags) and :func:`bag_options` (what the backend receives).
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from fkcheck.model.project import ProjectConfig

__all__ = ["add_bag_arguments", "apply_bag_settings", "bag_options", "utf8_text"]


def utf8_text(value: str) -> str:
    """``value`` if it is UTF-8 text; else :class:`argparse.ArgumentTypeError` naming the byte."""
    for char in value:
        if "\udc80" <= char <= "\udcff":
            byte = ord(char) - 0xDC00
            raise argparse.ArgumentTypeError(
                f"{value!r} is not UTF-8 text (byte 0x{byte:02x}): it cannot be written into a "
                "URDF, model or report"
            )
    return value


def _stamp_tolerance(value: str) -> float:
    """``--bag-stamp-tolerance``: seconds, by the rule of its ``[tool.fkcheck]`` key."""
    from fkcheck.model.options import bag_problem

    try:
        seconds = float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{value!r} is not a number of seconds") from None
    problem = bag_problem("bag_stamp_tolerance_s", seconds)
    if problem is not None:
        raise argparse.ArgumentTypeError(problem)
    return seconds


def _topic(value: str) -> str:
    """``--bag-joint-states`` and the other topics: by the rule of their ``[tool.fkcheck]`` keys."""
    from fkcheck.model.options import bag_problem

    problem = bag_problem("bag_tf", utf8_text(value))
    if problem is not None:
        raise argparse.ArgumentTypeError(problem)
    return value


def add_bag_arguments(p: argparse.ArgumentParser) -> None:
    """The settings of a ROS 2 bag given as ``--against poses:BAG`` (fkcheck.backends.bag).

    Each may be set in ``[tool.fkcheck]`` too (:data:`fkcheck.model.options.BAG_KEYS`);
    a flag wins (:func:`apply_bag_settings`).
    """
    bag = p.add_argument_group(
        "ROS 2 bags (--against poses:BAG)",
        "each may also be set in [tool.fkcheck] of pyproject.toml (bag_joint_states, bag_tf, "
        "bag_tf_static, bag_stamp_tolerance); a flag wins",
    )
    bag.add_argument("--bag-joint-states", type=_topic,
                     metavar="TOPIC", help="topic of sensor_msgs/msg/JointState (default "
                     "/joint_states)")  # fmt: skip
    bag.add_argument("--bag-tf", type=_topic, metavar="TOPIC",
                     help="topic of the changing transforms (default /tf)")  # fmt: skip
    bag.add_argument("--bag-tf-static", type=_topic, metavar="TOPIC",
                     help="topic of the static transforms (default /tf_static)")  # fmt: skip
    bag.add_argument(
        "--bag-stamp-tolerance",
        dest="bag_stamp_tolerance_s",
        type=_stamp_tolerance,
        metavar="S",
        help="pair each pose with the joint state stamped at or before it, at most this many "
        "seconds earlier (default 0.001: half a cycle at 500 Hz; at most 1)",
    )


def apply_bag_settings(args: argparse.Namespace, project: ProjectConfig | None) -> None:
    """Fill each ``--bag-*`` flag not given from ``project``'s key (a flag wins over the key)."""
    for name, value in (project.bag_settings() if project is not None else {}).items():
        if getattr(args, name, None) is None:
            setattr(args, name, value)


def bag_options(args: argparse.Namespace) -> dict[str, Any]:
    """The bag settings given (flag or key), by ``BackendOptions`` attribute.

    The ones not given are left out: :class:`~fkcheck.backends.registry.BackendOptions`'
    defaults apply.
    """
    from fkcheck.model.options import BAG_FLAGS

    return {name: value for name in BAG_FLAGS if (value := getattr(args, name, None)) is not None}
