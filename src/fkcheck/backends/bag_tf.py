"""The tf tree of a ROS 2 bag: transforms by frame id, and the pose between two frames.

Part of :mod:`fkcheck.backends.bag`: :class:`_Tree` holds each child frame's parent
and transform (``/tf_static``'s valid at all times, ``/tf``'s with their stamp) and
gives the transform between the check's two frames; :func:`_matrix` reads a
``geometry_msgs/msg/Transform`` within the limits of :mod:`.bag_screen`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from fkcheck.backends.bag_screen import (
    MAX_DEPTH,
    MAX_FRAME_ID_CHARS,
    MAX_FRAMES,
    QUATERNION_NORM_TOL,
    _Bad,
)
from fkcheck.core.typing import Float
from fkcheck.model.types import MAX_LENGTH_M

__all__: list[str] = []

_NS = 1_000_000_000


def _stamp_ns(header: Any) -> int:
    stamp = header.stamp
    sec, nanosec = int(stamp.sec), int(stamp.nanosec)
    if not 0 <= nanosec < _NS:
        raise _Bad(f"a stamp's nanosec is {nanosec} (0 … 999999999)")
    return sec * _NS + nanosec


def _frame_id(name: str) -> str:
    """A frame id as tf2 compares it: without a leading ``/``."""
    if len(name) > MAX_FRAME_ID_CHARS:
        raise _Bad(f"a frame id of {len(name)} characters (at most {MAX_FRAME_ID_CHARS})")
    return name[1:] if name.startswith("/") else name


def _matrix(transform: Any) -> Float:
    """``parent_T_child`` of a ``geometry_msgs/msg/Transform``, its quaternion normalised."""
    t, r = transform.translation, transform.rotation
    x, y, z, w = float(r.x), float(r.y), float(r.z), float(r.w)
    p = (float(t.x), float(t.y), float(t.z))
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if not (math.isfinite(norm) and all(math.isfinite(v) for v in p)):
        raise _Bad("a transform with a non-finite number")
    if abs(norm - 1.0) > QUATERNION_NORM_TOL:
        raise _Bad(f"a rotation quaternion of norm {norm:.6g} (tf2 needs unit length)")
    if max(abs(v) for v in p) > MAX_LENGTH_M:
        raise _Bad(f"a translation beyond ±{MAX_LENGTH_M:g} m")
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), p[0]],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), p[1]],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), p[2]],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


class _Tree:
    """The tf tree: each child frame's parent and transform; changing ones with their stamp."""

    def __init__(self, base: str, tip: str) -> None:
        self.base, self.tip = base, tip
        self.static: dict[str, tuple[str, Any]] = {}  # child: (parent, Transform message)
        self.moving: dict[str, tuple[str, Any, int]] = {}  # child: (parent, Transform, stamp)
        # The child frames from base and from tip up to their common ancestor, once
        # connected; recomputed only after a frame's parent changed.
        self.path: tuple[tuple[str, ...], tuple[str, ...]] | None = None
        self._changed = True
        self._on: frozenset[str] = frozenset()

    def _set_parent(self, child: str, old: str | None, parent: str) -> None:
        if old is None and len(self.static) + len(self.moving) >= MAX_FRAMES:
            raise _Bad(f"more than {MAX_FRAMES:,} frames in the tf tree")
        if old != parent:
            self._changed = True

    def set_static(self, parent: str, child: str, transform: Any) -> None:
        """Store one static transform."""
        old = self.static.get(child)
        self._set_parent(child, old[0] if old else None, parent)
        self.static[child] = (parent, transform)

    def set_moving(self, parent: str, child: str, transform: Any, stamp: int) -> bool:
        """Store one changing transform; whether it is on the compared path."""
        old = self.moving.get(child)
        self._set_parent(child, old[0] if old else self._parent(child), parent)
        self.moving[child] = (parent, transform, stamp)
        return child in self._on_path()

    def _parent(self, child: str) -> str | None:
        if child in self.moving:
            return self.moving[child][0]
        if child in self.static:
            return self.static[child][0]
        return None

    def _up(self, frame: str) -> tuple[str, ...]:
        """``frame`` and its ancestors, to the root."""
        chain = [frame]
        seen = {frame}
        parent = self._parent(frame)
        while parent is not None:
            if parent in seen:
                raise _Bad(f"the tf tree has a loop through frame {parent[:80]!r}")
            if len(chain) > MAX_DEPTH:
                raise _Bad(f"a tf tree deeper than {MAX_DEPTH} frames")
            chain.append(parent)
            seen.add(parent)
            parent = self._parent(parent)
        return tuple(chain)

    def _on_path(self) -> frozenset[str]:
        """The child frames whose transforms make up the compared path (empty: none yet)."""
        if self._changed:
            self._changed = False
            up_base, up_tip = self._up(self.base), self._up(self.tip)
            common = next((f for f in up_tip if f in set(up_base)), None)
            if common is None:
                self.path, self._on = None, frozenset()
            else:
                self.path = (up_base[: up_base.index(common)], up_tip[: up_tip.index(common)])
                self._on = frozenset((*self.path[0], *self.path[1]))
        return self._on

    def pose(self) -> tuple[Float, int | None] | None:
        """``base_T_tip`` and the stamp of its changing transforms (``None``: none changes).

        ``None`` when the frames are not connected, or the changing transforms on the
        path carry different stamps.
        """
        self._on_path()
        if self.path is None:
            return None
        up_base, up_tip = self.path
        stamps: set[int] = set()

        def to_common(chain: tuple[str, ...]) -> Float | None:
            out = None  # None: the identity (base is the common frame, as for UR's driver)
            for child in chain:  # child, its parent, …: common_T_frame = … · parent_T_child
                if child in self.moving:
                    _, transform, stamp = self.moving[child]
                    stamps.add(stamp)
                else:
                    transform = self.static[child][1]
                out = _matrix(transform) if out is None else _matrix(transform) @ out
            return out

        common_T_base, common_T_tip = to_common(up_base), to_common(up_tip)
        if len(stamps) > 1:
            return None
        stamp = stamps.pop() if stamps else None
        if common_T_tip is None:
            common_T_tip = np.eye(4)
        if common_T_base is None:
            return common_T_tip, stamp
        base_T_common = np.eye(4)  # the rigid inverse: rotation transposed
        base_T_common[:3, :3] = common_T_base[:3, :3].T
        base_T_common[:3, 3] = -common_T_base[:3, :3].T @ common_T_base[:3, 3]
        return base_T_common @ common_T_tip, stamp

    def needles(self) -> tuple[bytes, ...] | None:
        """The path's child frame ids as bytes, once the path is known (else ``None``).

        A tf message whose serialised bytes hold none of them cannot change the path
        (only a new parent of a frame on it could), so it need not be deserialised.
        """
        self._on_path()
        return None if self.path is None else tuple(f.encode() for f in self._on)
