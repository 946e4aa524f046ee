"""How DH parameters are called in text: ``d1``, ``α4``, ``a2`` — the textbook names.

In a standard table, row *i* (1-based) holds ``aᵢ``, ``αᵢ``, ``dᵢ``, ``θᵢ``; in a
modified (Craig) table it holds ``a_{i-1}``, ``α_{i-1}``, ``dᵢ``, ``θᵢ``. Messages
name parameters the way the published table does, plus the model's joint name.
"""

from __future__ import annotations

from typing import Literal

from fkcheck.model.types import Model

__all__ = ["PARAMS", "Param", "param_field", "param_symbol"]

Param = Literal["a", "alpha", "d", "theta"]
PARAMS: tuple[Param, ...] = ("a", "alpha", "d", "theta")
_GREEK = {"a": "a", "alpha": "α", "d": "d", "theta": "θ"}


def param_symbol(model: Model, joint: int, param: str) -> str:
    """``"d1"``, ``"α0"`` (modified row 1), … for 0-based row ``joint``."""
    index = joint + 1
    if model.convention == "modified" and param in ("a", "alpha"):
        index = joint
    return f"{_GREEK[param]}{index}"


def param_field(model: Model, joint: int, param: str) -> str:
    """``"d1 (joint[0].d, shoulder_pan)"``: the symbol, the file field and the joint name."""
    return (
        f"{param_symbol(model, joint, param)} (joint[{joint}].{param}, {model.joints[joint].name})"
    )
