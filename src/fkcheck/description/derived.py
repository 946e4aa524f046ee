"""A description checked against another: the table derived from one, the other read as it is.

A user who converts a URDF into an MJCF (or back) has two descriptions and no
table. :func:`derived_model` derives the DH table from the *source*
description alone (:func:`fkcheck.urdf.to_dh.dh_from_urdf`, as ``fkcheck
table-from`` does) and declares the *checked* description in the model's
section of its format, so that a check reads it with that format's own readers
(MuJoCo and Pinocchio for an MJCF, the URDF parsers for a URDF): nothing of
the checked file reaches the table. Joints are matched by name; each
description's chain runs from its base to its tip, given or chosen by
:func:`default_ends`. The model records both files (:class:`~fkcheck.model.types.DerivedTable`),
so every output says which was the source and that the table was derived.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from itertools import pairwise
from pathlib import Path

from fkcheck.description.registry import format_named
from fkcheck.description.types import Description
from fkcheck.errors import FkcheckError
from fkcheck.model.types import DerivedTable, FrameSpec, Model, default_frames
from fkcheck.urdf.chain import JointGeometry, KinematicTree

__all__ = ["ChainEnds", "default_ends", "derived_model"]


@dataclass(frozen=True)
class ChainEnds:
    """A chain's base and tip links (bodies, sites); ``None``: chosen by :func:`default_ends`."""

    base: str | None = None
    tip: str | None = None


def default_ends(tree: KinematicTree, given: ChainEnds) -> tuple[str, str]:
    """``(base, tip)`` of ``tree``'s arm: ``given``'s, else the ends of its moving joints.

    The base is the link the first moving joint hangs from, the tip the link the
    last one moves: what a conversion must keep, whatever tool frames or sites
    either file adds.

    Raises:
        FkcheckError: The moving joints are not one chain (a gripper's fingers, two
            arms), so there is no single end to choose: give it.
    """
    if given.base is not None and given.tip is not None:
        return given.base, given.tip
    moving = [j for j in tree.joints.values() if j.type != "fixed"]
    if not moving:
        raise FkcheckError(f"{tree.kind} {tree.path.name}: it has no moving joint")
    ordered = _one_chain(tree, moving)
    if ordered is None:
        which = "--base and --tip" if given.base is None and given.tip is None else "both ends"
        raise FkcheckError(
            f"{tree.kind} {tree.path.name}: its moving joints "
            f"({', '.join(j.name for j in moving)}) are not one chain; give {which}"
        )
    return given.base or ordered[0].parent, given.tip or ordered[-1].child


def _one_chain(tree: KinematicTree, moving: list[JointGeometry]) -> list[JointGeometry] | None:
    """``moving`` in order from the root, when each lies below the one before; else ``None``."""
    below_root = {j.name: len(_ancestry(tree, j)) for j in moving}
    ordered = sorted(moving, key=lambda j: below_root[j.name])
    for upper, lower in pairwise(ordered):
        if upper.name not in {j.name for j in _ancestry(tree, lower)}:
            return None
    return ordered


def _ancestry(tree: KinematicTree, joint: JointGeometry) -> list[JointGeometry]:
    """The joints above ``joint``, up to the root."""
    by_child = {j.child: j for j in tree.joints.values()}
    out: list[JointGeometry] = []
    link = joint.parent
    while link in by_child and len(out) <= len(by_child):
        out.append(by_child[link])
        link = by_child[link].parent
    return out


def derived_model(
    source: Description,
    checked: Description,
    source_ends: ChainEnds,
    checked_ends: ChainEnds,
    *,
    names: tuple[str, str],
) -> Model:
    """The table derived from ``source`` alone, with ``checked`` declared to be read by its readers.

    Args:
        source: The description the table is derived from.
        checked: The description checked against it (only its joint names and
            frame names are asked here; its geometry is its readers' business).
        source_ends: The source chain's base and tip (``None``: :func:`default_ends`).
        checked_ends: The checked chain's; an end not given is the source's end
            given, else :func:`default_ends`'s.
        names: ``(source, checked)`` as the command line named them.

    Returns:
        A model whose table and frames come from ``source``, whose check runs
        from the source's base to its tip, mapped onto the checked chain's, and
        whose :attr:`~fkcheck.model.types.Model.derived` names both files.

    Raises:
        FkcheckError: No single chain to choose, or the two chains' moving joints
            differ by name or order (both lists in the message).
        FrameError: A base or tip that is not a link of its description.
        UrdfError: The source's chain cannot be a DH table (:func:`dh_from_urdf`).
    """
    from fkcheck.urdf.to_dh import dh_from_urdf

    base, tip = default_ends(source.tree, source_ends)
    chosen = ChainEnds(checked_ends.base or source_ends.base, checked_ends.tip or source_ends.tip)
    checked_base, checked_tip = default_ends(checked.tree, chosen)
    table = dh_from_urdf(source.tree, base, tip).model
    theirs = tuple(
        j.name for j in checked.tree.movable(checked.tree.chain(checked_base, checked_tip))
    )
    if theirs != table.joint_names:
        missing = [n for n in table.joint_names if n not in theirs]
        raise FkcheckError(
            f"joints are matched by name, and they differ: {names[0]} ({base} → {tip}) has "
            f"{', '.join(table.joint_names)}; {names[1]} ({checked_base} → {checked_tip}) has "
            f"{', '.join(theirs) or '(none)'}"
            + (f" (not there: {', '.join(missing)})" if missing else " (another order)")
        )
    fmt = format_named(checked.format)
    frames = default_frames()
    for name, dh, twin in ((base, "world", checked_base), (tip, "tcp", checked_tip)):
        frames[name] = fmt.with_frame(FrameSpec(name, dh), twin)  # type: ignore[arg-type]
    model = replace(
        table,
        name=source.tree.name or Path(names[0]).stem,
        description=f"{source.tree.name}: {base} → {tip}, derived by fkcheck from {names[0]}",
        source=f"derived by fkcheck from {names[0]} (the source, {base} → {tip}), checked "
        f"against {names[1]} ({checked_base} → {checked_tip})",
        urdf=None,
        frames=frames,
        derived=DerivedTable(names[0], names[1], checked_base, checked_tip),
    )
    return fmt.declared(model, str(checked.path.resolve()), theirs)
