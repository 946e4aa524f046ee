"""A read recording's rows as a table: configurations looked up, duplicates refused.

Part of :mod:`fkcheck.backends.measured`: :class:`_Table` finds the row of each
configuration (a hash lookup, a k-d tree for ones within :data:`MATCH_TOL` that are
not bit for bit a row); :func:`_check_duplicates` refuses two rows with one
configuration and different poses.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.backends.poses_columns import PosesFileError
from fkcheck.backends.recording import Recording, RowKeeper
from fkcheck.core.typing import Float

__all__ = ["MATCH_TOL"]

#: Joint values within this of a file row (radians / metres) are that row; two rows
#: this close must have poses this close (metres and radians).
MATCH_TOL = 1e-9


def _check_duplicates(q: Float, poses: Float, linenos: NDArray[np.int64], path: Path) -> None:
    """Refuse two rows with the same configuration (within MATCH_TOL) but different poses."""
    from scipy.spatial import cKDTree

    from fkcheck.core.metrics import position_error_m, rotation_error_rad

    def refuse_if_different(a: NDArray[np.intp], b: NDArray[np.intp], same: str) -> None:
        pos = position_error_m(poses[a], poses[b])
        rot = rotation_error_rad(poses[a], poses[b])
        bad = np.flatnonzero((pos > MATCH_TOL) | (rot > MATCH_TOL))
        if bad.size:
            k = int(bad[0])
            first, second = sorted((linenos[int(a[k])], linenos[int(b[k])]))
            raise PosesFileError(
                path,
                f"lines {first} and {second} have the same configuration{same} but poses "
                f"differing by {pos[k]:.3g} m and {rot[k]:.3g} rad; keep one of them",
            )

    # Identical configurations: each row against the first row like it.
    _, first, inverse = np.unique(_key_values(q), axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    rows = np.flatnonzero(first[inverse] != np.arange(q.shape[0]))
    refuse_if_different(rows, first[inverse[rows]], "")
    # Configurations within MATCH_TOL but not identical: each against its nearest other.
    unique = np.sort(first)
    if unique.size > 1:
        dist, near = cKDTree(q[unique]).query(
            q[unique], k=2, p=np.inf, distance_upper_bound=MATCH_TOL
        )
        close = np.flatnonzero(np.isfinite(dist[:, 1]))
        refuse_if_different(unique[close], unique[near[close, 1]], f" (within {MATCH_TOL:g})")


def _key_values(q: Float) -> Float:
    """``q`` as a C-contiguous copy with -0.0 made 0.0: equal rows have equal bytes."""
    return np.ascontiguousarray(q, dtype=np.float64) + 0.0


class _Table:
    """A read poses file (the rows kept of it), with a lookup from configurations to its rows."""

    def __init__(self, q: Float, poses: Float, recording: Recording, kept: RowKeeper) -> None:
        self.q = q
        self.poses = poses
        self.pair = recording.pair
        self.method = recording.method
        self.recording = recording
        self.keeper = kept
        keys = _key_values(q)
        self._index = {keys[k].tobytes(): k for k in range(keys.shape[0] - 1, -1, -1)}
        self._tree: Any = None

    def rows_of(self, q: Float) -> NDArray[np.intp]:
        """The file row of each configuration (within MATCH_TOL), ``-1`` where none is."""
        q = _key_values(q)
        rows = np.array([self._index.get(row.tobytes(), -1) for row in q], dtype=np.intp)
        inexact = np.flatnonzero(rows < 0)
        if inexact.size:
            from scipy.spatial import cKDTree

            if self._tree is None:
                self._tree = cKDTree(self.q)
            dist, near = self._tree.query(q[inexact], p=np.inf, distance_upper_bound=MATCH_TOL)
            found = np.isfinite(dist)
            rows[inexact[found]] = near[found]
        return rows
