"""The model's joints in a ROS 2 bag's joint states, matched by name.

Part of :mod:`fkcheck.backends.bag`: :class:`_Joints` finds each model joint in a
``sensor_msgs/msg/JointState``'s names (its own name or its URDF joint's) and
reads its value, refusing a message that names some of the model's joints but not
all, names one twice, or holds a value that is not a finite number within bounds.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from fkcheck.backends.bag_screen import MAX_JOINT_NAMES, _Bad
from fkcheck.core.typing import Float

__all__: list[str] = []


class _Joints:
    """The model's joints in a joint state's names: indices, cached per list of names."""

    def __init__(self, accepted: Sequence[Sequence[str]], bounds: Sequence[float]) -> None:
        self.accepted = [tuple(dict.fromkeys(names)) for names in accepted]
        self.bounds = np.asarray(bounds, dtype=np.float64)
        self.known = {n for names in self.accepted for n in names}
        self.ignored: set[str] = set()
        self._cache: dict[tuple[str, ...], list[int] | None] = {}

    def indices(self, names: tuple[str, ...]) -> list[int] | None:
        """Where each model joint is in ``names``; ``None`` when none of them is there.

        Raises:
            _Bad: Some of the model's joints are there and some are not, or
                one is named twice (by its own and its URDF name, say).
        """
        if names in self._cache:
            return self._cache[names]
        out = self._match(names)
        if len(self._cache) < 64:
            self._cache[names] = out
        return out

    def _match(self, names: tuple[str, ...]) -> list[int] | None:
        """:meth:`indices`, uncached; a match notes the names the model does not have."""
        if len(names) > MAX_JOINT_NAMES:
            raise _Bad(f"a joint state names {len(names):,} joints (at most {MAX_JOINT_NAMES:,})")
        where = {n: k for k, n in enumerate(names)}
        if len(where) != len(names):
            raise _Bad("a joint state names one joint twice")
        found = [[where[n] for n in options if n in where] for options in self.accepted]
        if not any(found):
            return None
        self._each_once(names, found)
        self.ignored.update(n for n in names if n not in self.known)
        return [f[0] for f in found]

    def _each_once(self, names: tuple[str, ...], found: list[list[int]]) -> None:
        """Refuse a match that lacks one of the model's joints or names one twice."""
        missing = [" or ".join(o) for o, f in zip(self.accepted, found, strict=True) if not f]
        if missing:
            raise _Bad(
                f"a joint state lacks the model's joint{'s' if len(missing) > 1 else ''} "
                f"{', '.join(missing)}; it names {', '.join(n[:60] for n in names[:20])}"
            )
        twice = [o for o, f in zip(self.accepted, found, strict=True) if len(f) > 1]
        if twice:
            raise _Bad(f"a joint state names joint {' and '.join(twice[0])} both")

    def values(self, msg: Any) -> Float | None:
        """The model's joint values in one joint state (``None``: it names none of them)."""
        names = tuple(str(n) for n in msg.name)
        at = self.indices(names)
        if at is None:
            return None
        position = np.asarray(msg.position, dtype=np.float64)
        if position.shape != (len(names),):
            raise _Bad(
                f"a joint state names {len(names)} joints but holds {position.size} positions"
            )
        q = position[at]
        bad = np.flatnonzero(~(np.abs(q) <= self.bounds))
        if bad.size:
            k = int(bad[0])
            raise _Bad(
                f"joint {self.accepted[k][0]} is {q[k]:g}, not a finite number within "
                f"±{self.bounds[k]:g}"
            )
        return q
