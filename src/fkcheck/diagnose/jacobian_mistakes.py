"""The vocabulary of a Jacobian diagnosis: the convention mistakes, and what a diagnosis finds.

A :class:`JacobianMistake` is a convention mistake as a transformation of the
expected Jacobian; a :class:`JacobianDiagnosis` holds the explanations
:func:`fkcheck.diagnose.jacobian.diagnose_jacobian` found, and says them in words.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from fkcheck.core.jacobian import Reference, re_express
from fkcheck.core.typing import Float
from fkcheck.io.format import format_m, format_rad

__all__ = [
    "ANGULAR_FIRST",
    "MISTAKE_ORDER",
    "REFERENCE_NAMES",
    "ColumnError",
    "JacobianDiagnosis",
    "JacobianExplanation",
    "JacobianMistake",
    "JacobianResidual",
    "MistakeKind",
]

#: The kinds of convention mistake, in the order explanations of equal
#: complexity are ranked: a reference frame before a row order, before column
#: signs, order or a missing column, before a fitted point offset.
MistakeKind = Literal["reference", "blocks", "sign", "columns", "missing", "offset"]

#: The kinds in :data:`MistakeKind`'s order.
MISTAKE_ORDER: tuple[MistakeKind, ...] = get_args(MistakeKind)

#: Each reference frame in plain words, with its names in the two reference libraries.
REFERENCE_NAMES: dict[Reference, str] = {
    "world-aligned": (
        "world-aligned (the frame origin's velocity in world axes: Pinocchio "
        "LOCAL_WORLD_ALIGNED, Robotics Toolbox jacob0)"
    ),
    "local": "in the frame's own axes (local: Pinocchio LOCAL, Robotics Toolbox jacobe)",
    "world": (
        "the spatial twist at the world origin (world: Pinocchio WORLD; the reference "
        "point at the base, not at the frame)"
    ),
}

#: The rows of a Jacobian written angular first, in linear-first order (and back).
ANGULAR_FIRST = (3, 4, 5, 0, 1, 2)


@dataclass(frozen=True)
class JacobianResidual:
    """The largest entry-wise difference between two Jacobians.

    Attributes:
        linear: Largest over the linear rows (m/rad; m/m for a prismatic column).
        angular: Largest over the angular rows (rad/rad; rad/m for a prismatic column).
    """

    linear: float
    angular: float

    def within(self, tol_linear: float, tol_angular: float) -> bool:
        """Both within their tolerances (a non-finite difference never is)."""
        return bool(self.linear <= tol_linear and self.angular <= tol_angular)

    def text(self) -> str:
        """``linear 1.00e-03 m/rad, angular 2.00e-01 rad/rad``."""
        return f"linear {format_m(self.linear)}/rad, angular {format_rad(self.angular)}/rad"


@dataclass(frozen=True)
class ColumnError:
    """How far one joint's column is from the expected one.

    Attributes:
        joint: The joint's index, 0-based (the column).
        name: The joint's name.
        prismatic: Whether the joint is prismatic (the units are then per metre).
        linear: Largest difference in the linear rows.
        angular: Largest difference in the angular rows.
        agrees: Both within the tolerances.
    """

    joint: int
    name: str
    prismatic: bool
    linear: float
    angular: float
    agrees: bool

    def text(self) -> str:
        """``joint 3 (elbow): linear 1.00e-01 m/rad, angular 0.00e+00 rad/rad``."""
        per = "m" if self.prismatic else "rad"
        return (
            f"joint {self.joint + 1} ({self.name}): linear {format_m(self.linear)}/{per}, "
            f"angular {format_rad(self.angular)}/{per}"
        )


@dataclass(frozen=True)
class JacobianMistake:
    """A convention mistake, as the transformation it makes of the expected Jacobian.

    The transformations apply in this order: the point offset (in world-aligned
    axes), the reference frame, the columns, the row order.

    Attributes:
        reference: The reference frame the observed Jacobian is in (``None``: the
            expected one).
        angular_first: The angular rows come first.
        columns: Observed column ``j`` is expected column ``columns[j]`` times
            ``signs[j]``, or zero when ``columns[j]`` is ``None`` (``None``: the
            columns as expected).
        signs: ``±1`` per observed column (with ``columns``).
        point_offset_m: The linear part is that of the point ``r`` (m, in the
            target frame's axes) from the frame's origin (``None``: the origin).
    """

    reference: Reference | None = None
    angular_first: bool = False
    columns: tuple[int | None, ...] | None = None
    signs: tuple[int, ...] | None = None
    point_offset_m: tuple[float, float, float] | None = None

    @property
    def flipped(self) -> tuple[int, ...]:
        """Joints (0-based) whose own column has the opposite sign."""
        if self.columns is None or self.signs is None:
            return ()
        return tuple(
            j
            for j, (k, s) in enumerate(zip(self.columns, self.signs, strict=True))
            if k == j and s < 0
        )

    @property
    def missing(self) -> tuple[int, ...]:
        """Observed columns (0-based) left zero."""
        return (
            ()
            if self.columns is None
            else tuple(j for j, k in enumerate(self.columns) if k is None)
        )

    @property
    def moved(self) -> tuple[int, ...]:
        """Observed columns (0-based) that hold another joint's column."""
        if self.columns is None:
            return ()
        return tuple(j for j, k in enumerate(self.columns) if k is not None and k != j)

    @property
    def kinds(self) -> tuple[MistakeKind, ...]:
        """The mistakes it combines, in :data:`MISTAKE_ORDER`."""
        kinds: list[MistakeKind] = []
        if self.reference is not None:
            kinds.append("reference")
        if self.angular_first:
            kinds.append("blocks")
        if self.flipped:
            kinds.append("sign")
        if self.moved:
            kinds.append("columns")
        if self.missing:
            kinds.append("missing")
        if self.point_offset_m is not None:
            kinds.append("offset")
        return tuple(kinds)

    def apply(self, expected: Float, from_T_to: Float, reference: Reference) -> Float:
        """The expected Jacobian ``(N, 6, n)`` (in ``reference``) as this mistake makes it.

        Args:
            expected: The Jacobian without the mistake.
            from_T_to: The target frame's pose in the Jacobian's root, ``(N, 4, 4)``.
            reference: The reference frame ``expected`` is in.
        """
        jac = np.asarray(expected, dtype=float)
        if self.point_offset_m is not None:
            aligned = re_express(jac, from_T_to, reference, "world-aligned")
            lever = from_T_to[:, :3, :3] @ np.asarray(self.point_offset_m)  # (N, 3) world axes
            shift = np.cross(aligned[:, 3:], lever[:, :, None], axis=1)
            aligned = np.concatenate([aligned[:, :3] + shift, aligned[:, 3:]], axis=1)
            jac = re_express(aligned, from_T_to, "world-aligned", reference)
        if self.reference is not None:
            jac = re_express(jac, from_T_to, reference, self.reference)
        if self.columns is not None:
            signs = np.ones(len(self.columns)) if self.signs is None else np.asarray(self.signs)
            picked = [
                np.zeros_like(jac[:, :, 0]) if k is None else jac[:, :, k] * s
                for k, s in zip(self.columns, signs, strict=True)
            ]
            jac = np.stack(picked, axis=2)
        if self.angular_first:
            jac = jac[:, list(ANGULAR_FIRST)]
        return jac


@dataclass(frozen=True)
class JacobianExplanation:
    """One convention mistake that explains the disagreement.

    Attributes:
        mistake: The transformation.
        title: What it is, in plain words (one sentence).
        residual: What is left once the expected Jacobian is transformed this way.
        details: More evidence, one line each.
    """

    mistake: JacobianMistake
    title: str
    residual: JacobianResidual
    details: tuple[str, ...] = ()

    @property
    def kinds(self) -> tuple[MistakeKind, ...]:
        """The mistakes it combines."""
        return self.mistake.kinds


@dataclass(frozen=True)
class JacobianDiagnosis:
    """What the comparison of two Jacobians found.

    Attributes:
        reference: The reference frame the expected Jacobian is in.
        configurations: How many configurations were compared.
        before: The disagreement as given.
        tolerance: Linear tolerance (m/rad).
        angular_tolerance: Angular tolerance (rad/rad).
        columns: The error of each joint's column, as given.
        explanations: The mistakes that explain it, simplest first (empty when
            the Jacobians agree or nothing explains it).
        tried: The hypotheses tried, one line each.
    """

    reference: Reference
    configurations: int
    before: JacobianResidual
    tolerance: float
    angular_tolerance: float
    columns: tuple[ColumnError, ...]
    explanations: tuple[JacobianExplanation, ...]
    tried: tuple[str, ...]

    @property
    def agrees(self) -> bool:
        """The Jacobians agree as given: nothing to explain."""
        return self.before.within(self.tolerance, self.angular_tolerance)

    @property
    def explained(self) -> bool:
        """Some convention mistake explains the disagreement."""
        return bool(self.explanations)

    @property
    def best(self) -> JacobianExplanation | None:
        """The simplest explanation, if any."""
        return self.explanations[0] if self.explanations else None

    @property
    def first_disagreeing(self) -> ColumnError | None:
        """The first joint (from the base) whose column disagrees, if any."""
        return next((c for c in self.columns if not c.agrees), None)

    @property
    def headline(self) -> str:
        """One sentence: they agree, which convention explains it, or which column differs first."""
        if self.agrees:
            return f"the Jacobians agree ({self.before.text()})"
        if self.best is not None:
            return self.best.title
        first = self.first_disagreeing
        where = (
            f"; joint {first.joint + 1} ({first.name}) is the first column that disagrees"
            if first is not None
            else ""
        )
        return f"no convention explains it: the Jacobians differ by {self.before.text()}{where}"

    def text(self) -> str:
        """The headline, the other explanations, the columns and what was tried, one per line."""
        lines = [self.headline]
        for e in self.explanations[:1]:
            lines.extend(f"  {d}" for d in e.details)
        lines.extend(f"also explains it: {e.title}" for e in self.explanations[1:])
        lines.append(f"as given, over {self.configurations} configurations: {self.before.text()}")
        lines.extend(f"  {c.text()}" + ("" if c.agrees else "  DIFFERS") for c in self.columns)
        lines.append("tried: " + "; ".join(self.tried))
        return "\n".join(lines)
