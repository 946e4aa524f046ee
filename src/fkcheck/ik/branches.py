"""Which branch of a 6R arm a configuration is on: shoulder, elbow, wrist.

An analytic 6R solver returns up to eight configurations for a pose, one per
branch; a missed solution is named by its branch. The branches are read from
the geometry of the configuration's DH frames (world coordinates from the
in-house FK), so the same words fit a UR and a spherical-wrist (OPW) arm:

* **shoulder right / left** — the wrist point ``p5`` (origin of DH frame 5, on
  joint 6's axis: the wrist centre of a spherical wrist, the point a UR's IK
  finds θ1 from) is ahead of the base axis along ``x1``, DH frame 1's x axis
  (the direction the shoulder faces), or behind it: right when
  ``(p5 − o0)·x1 > 0``. The two θ1 solutions of a pose have it on both sides;
* **elbow up / down** — the elbow (origin of DH frame 2, on joint 3's axis) is
  on the ``+z0`` (upward, in the base's axes) side of the line from the
  shoulder (origin of DH frame 1) to the wrist ``w`` (origin of DH frame 4: the
  wrist centre of a spherical wrist; on a UR, wrist 1's axis shifted along it,
  so in the arm's plane where wrist 1 is) in the arm's plane, or below it;
* **wrist no-flip / flip** — the sign of ``sin θ5``, joint 5's DH angle
  (offset and direction included): the two wrist solutions have ``θ5`` and
  ``−θ5``; flip when it is negative.

A quantity within :data:`DEGENERATE` of zero (the shoulder's wrist point on the
base axis, the elbow straight, ``θ5 = 0``) is on neither side: that part of the
branch is ``"singular"``.
"""

from __future__ import annotations

import numpy as np

from fkcheck.core.typing import Float
from fkcheck.model.types import Model

__all__ = ["DEGENERATE", "branch_names", "branch_values", "classifiable"]

#: Below this (metres² for the elbow's cross product, metres for the shoulder's
#: reach, a pure number for sin θ5) a branch quantity counts as zero: 1e-9, a
#: nanometre at an arm's scale, far above float round-off (1e-15 m) and far below
#: any configuration a solver is asked to tell apart from its twin.
DEGENERATE = 1e-9


def classifiable(model: Model) -> bool:
    """Whether branches are named for ``model``: six revolute joints."""
    return model.dof == 6 and all(j.type == "revolute" for j in model.joints)


def branch_values(model: Model, q: Float, *, raw: bool = False) -> Float:
    """The signed shoulder, elbow and wrist quantities of configurations ``(N, 6)``: ``(N, 3)``.

    With ``raw``, the elbow's is ``z1 · ((o2 − o1) × (w − o1))``, before it is turned
    to the base's +z side: a sinusoid of each joint's value
    (:mod:`fkcheck.ik.poses` finds its zeros from three values).
    """
    q = np.asarray(q, dtype=np.float64).reshape(-1, model.dof)
    frames = model.fk(q, all_frames=True)  # (N, 7, 4, 4), in the world
    o0, o1, o2, w, p5 = (frames[:, i, :3, 3] for i in (0, 1, 2, 4, 5))
    z0 = frames[:, 0, :3, 2]
    x1 = frames[:, 1, :3, 0]
    z1 = frames[:, 1, :3, 2]
    shoulder = np.einsum("ij,ij->i", p5 - o0, x1)
    # The in-plane normal to shoulder → wrist, turned to the base's +z side.
    normal = np.cross(z1, w - o1)
    if not raw:
        up = np.einsum("ij,ij->i", normal, z0)
        normal *= np.where(up < 0.0, -1.0, 1.0)[:, None]
    elbow = np.einsum("ij,ij->i", o2 - o1, normal)
    joint5 = model.joints[4]
    theta5 = joint5.theta + (-1.0 if joint5.flip else 1.0) * q[:, 4]
    wrist = np.sin(theta5)
    return np.stack([shoulder, elbow, wrist], axis=1)


def branch_names(values: Float) -> list[str]:
    """Each row of :func:`branch_values` in words: ``"shoulder right, elbow up, wrist flip"``."""
    words = (("right", "left"), ("up", "down"), ("no-flip", "flip"))
    parts = ("shoulder", "elbow", "wrist")
    names = []
    for row in np.atleast_2d(values):
        said = []
        for part, (plus, minus), value in zip(parts, words, row, strict=True):
            side = "singular" if abs(value) <= DEGENERATE else (plus if value > 0 else minus)
            said.append(f"{part} {side}")
        names.append(", ".join(said))
    return names
