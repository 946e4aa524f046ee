"""Which joints a frame pair spans: the joints whose motion changes the compared pose.

Joint *i* (1-based) moves DH frames *i*…*n* and the TCP; ``world`` and DH frame
0 never move. A named frame moves with its anchor (``FrameSpec.dh``), so the pose
of one frame in another changes with joint *i* exactly when one anchor is
moved by it and the other is not: the joints between the two anchors. A pair
that spans no joint (``tcp`` → ``tcp``, ``world`` → a frame on DH frame 0) is
constant over every configuration, so comparing it verifies none of the table.
"""

from __future__ import annotations

from fkcheck.model.types import DhIndex, Model, resolve_frame

__all__ = ["anchor_level", "joints_spanned"]


def anchor_level(model: Model, anchor: DhIndex) -> int:
    """The number of joints that move an anchor: ``world`` 0, DH frame *k* *k*, ``tcp`` *n*."""
    if anchor == "world":
        return 0
    if anchor == "tcp":
        return model.dof
    return anchor


def joints_spanned(model: Model, frame_from: str, frame_to: str) -> tuple[int, ...]:
    """The joints (1-based, in order) whose motion changes ``from_T_to``.

    Args:
        model: The model.
        frame_from: A frame name of the model (``urdf:LINK`` names a declared twin).
        frame_to: Another (or the same) frame name.

    Returns:
        The joints between the two frames' anchors; ``()`` when the pair is
        constant over every configuration.

    Raises:
        FrameError: A name is not a frame of the model.
    """
    levels = sorted(
        anchor_level(model, resolve_frame(model, name).dh) for name in (frame_from, frame_to)
    )
    return tuple(range(levels[0] + 1, levels[1] + 1))
