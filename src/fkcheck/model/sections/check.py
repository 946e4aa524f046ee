"""``[check]``: the model's default check — frame pair, tolerances, requirements, Jacobian."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from fkcheck.core.tolerances import LimitKind
from fkcheck.core.typing import JACOBIAN_REFERENCES, JacobianReference
from fkcheck.io.numbers import show_text
from fkcheck.model.require import parse_require
from fkcheck.model.sections.reader import Reader, is_text_list, shown_key, shown_value
from fkcheck.model.types import CheckSpec, FrameSpec

__all__ = ["CHECK_KEYS", "read_check"]

CHECK_KEYS = {
    "from", "to", "tol_pos_m", "tol_rot_rad", "require",
    "jacobian", "jacobian_reference", "tol_jacobian",
}  # fmt: skip
#: The tolerance keys and the range each must be within (:mod:`fkcheck.core.tolerances`).
CHECK_LIMITS: dict[str, LimitKind] = {
    "tol_pos_m": "tol_pos", "tol_rot_rad": "tol_rot", "tol_jacobian": "tol_jacobian",
}  # fmt: skip


def read_check(r: Reader, raw: Any, frames: Mapping[str, FrameSpec]) -> CheckSpec:
    """The ``[check]`` table; ``from`` and ``to`` name frames of ``frames``."""
    c = r.table(raw, "check", CHECK_KEYS)
    frame_from = r.string(c.get("from", "world"), "check.from")
    frame_to = r.string(c.get("to", "tcp"), "check.to")
    for side, frame_name in (("from", frame_from), ("to", frame_to)):
        if frame_name not in frames:
            raise r.fail(
                f"check.{side}",
                f"frame {show_text(frame_name)} is not defined; frames are: "
                f"{', '.join(shown_key(f) for f in frames)}",
            )
    tols = {
        key: r.limit(c[key], f"check.{key}", limit_kind)
        for key, limit_kind in CHECK_LIMITS.items()
        if key in c
    }
    require = _require(r, c["require"]) if "require" in c else ()
    jacobian = c.get("jacobian", False)
    if not isinstance(jacobian, bool):
        raise r.fail("check.jacobian", f"expected true or false, got {shown_value(jacobian)}")
    return CheckSpec(
        frame_from,
        frame_to,
        require=require,
        jacobian=jacobian,
        jacobian_reference=_jacobian_reference(r, c.get("jacobian_reference", "world-aligned")),
        **tols,
    )


def _require(r: Reader, raw: Any) -> tuple[str, ...]:
    """``require``: the kinds of evidence the check must verify (:mod:`fkcheck.model.require`)."""
    if not is_text_list(raw):
        raise r.fail("check.require", 'expected a list such as ["table"]')
    try:
        return parse_require(raw, "check.require")
    except ValueError as exc:
        raise r.fail("check.require", str(exc).split(": ", 1)[1]) from None


def _jacobian_reference(r: Reader, raw: Any) -> JacobianReference:
    """``jacobian_reference``: one of :data:`~fkcheck.core.typing.JACOBIAN_REFERENCES`."""
    reference = r.string(raw, "check.jacobian_reference")
    if reference not in JACOBIAN_REFERENCES:
        raise r.fail(
            "check.jacobian_reference",
            f"unknown reference frame {show_text(reference)}; references are: "
            f"{', '.join(JACOBIAN_REFERENCES)}",
        )
    return reference
