"""When the table agrees: the numbers agreement says nothing about, and what would settle them.

A diagnosis with nothing to explain is not a proof of every number: an offset
of a compared frame may carry what a number produces (``d1`` and a base frame
fitted around it), the configurations may not tell a number from others, or its
effect may be too faint for the tolerance (:mod:`fkcheck.model.coverage` decides
which). :func:`unsettled_numbers` names those numbers of a table-independent
comparison, each with why and with what would settle it.
"""

from __future__ import annotations

from dataclasses import dataclass

from fkcheck.core.typing import Float
from fkcheck.model.coverage import NumberEvidence, Reason, coverage
from fkcheck.model.types import Model

__all__ = ["Unsettled", "unsettled_numbers"]


@dataclass(frozen=True)
class Unsettled:
    """A table number an agreeing comparison does not identify.

    Attributes:
        name: ``d1``, ``θ6``, ``[base] z``.
        group: ``joint 1 (shoulder_pan)``, ``[base]``.
        why: Why agreement says nothing about it (``[frames.base]: translation
            along z of DH frame 0``).
        settle: What would settle it, one sentence.
    """

    name: str
    group: str
    why: str
    settle: str


def _settle(reason: Reason, by: tuple[str, ...]) -> str:
    """What would settle a number not identifiable for ``reason``."""
    frames = " and ".join(by) or "the compared frames"
    if reason in ("offset", "taken"):
        return (
            "compare frames that sit exactly on DH frames (--from/--to: no offset there to "
            f"carry a number), or take {frames} from the vendor's drawing and say so with "
            'source = "…" (what it carries is then vouched for, not verified)'
        )
    if reason == "direction":
        return "configurations that turn this joint and the ones after it (more --samples)"
    if reason == "configurations":
        return "more configurations that move the joints apart (--samples, or more measured poses)"
    return "a tighter tolerance (--tol-pos/--tol-rot), or configurations where it shows more"


def _entry(n: NumberEvidence) -> Unsettled:
    why = n.absorbed_by or {
        "direction": "the configurations cannot tell which way the joint turns",
        "configurations": "the configurations cannot tell it from other numbers",
        "faint": "its effect is too faint for the tolerance",
    }.get(n.reason, "not identifiable")
    return Unsettled(n.name, n.group, why, _settle(n.reason, n.by))


def unsettled_numbers(
    model: Model, pair: tuple[str, str], tol: tuple[float, float], q: Float
) -> tuple[Unsettled, ...]:
    """The table numbers a comparison of ``pair`` on ``q`` cannot identify, in table order.

    Args:
        model: The model.
        pair: ``(from, to)`` frames compared.
        tol: ``(m, rad)`` tolerances, as the comparison's.
        q: The configurations compared, ``(N, n)``.

    Raises:
        FrameError: An unknown frame.
    """
    numbers = coverage(model, pair[0], pair[1], tol[0], tol[1], q=q)
    return tuple(_entry(n) for n in numbers.by_status("not-identifiable"))
