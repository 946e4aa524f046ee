"""How joints and DH parameters are called in text: ``α4 (wrist_1)``, ``joint[3].alpha (wrist_1)``.

One rule, so that no count can be misread: a joint is always shown with its
name. Beside the name, a number keeps the notation of where it comes from —
prose and DH symbols count from 1, as published tables do (``joint 4``, ``α4``,
``row 4``); a model-file field path counts from 0, as the file's ``[[joint]]``
list, TOML and every :class:`~fkcheck.errors.ModelError` path do
(``joint[3].alpha``). ``joint 4 (wrist_1)`` and ``joint[3].alpha (wrist_1)``
name the same joint, and say so.

In a standard table, row *i* (1-based) holds ``aᵢ``, ``αᵢ``, ``dᵢ``, ``θᵢ``; in a
modified (Craig) table it holds ``a_{i-1}``, ``α_{i-1}``, ``dᵢ``, ``θᵢ``. Messages
name parameters the way the published table does, plus the model's joint name.
"""

from __future__ import annotations

import re
from typing import Literal

from fkcheck.model.types import Model

__all__ = ["PARAMS", "Param", "field_text", "param_field", "param_symbol"]

_JOINT_FIELD = re.compile(r"joint\[(\d+)\]")

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


def field_text(model: Model, field: str) -> str:
    """``"joint[3].alpha (wrist_1)"``: a file field, with its joint's name when it is a joint's.

    A joint with the reader's default name (``joint1`` for ``joint[0]``) is
    said in prose, ``joint[0].alpha (joint 1)``: the count every other message
    uses, with a space, so that it cannot read as a name. Other fields
    (``base.xyz``, ``frames.tool0.rpy``) come back unchanged.
    """
    found = _JOINT_FIELD.match(field)
    if found is None or int(found.group(1)) >= model.dof:
        return field
    i = int(found.group(1))
    name = model.joints[i].name
    return f"{field} (joint {i + 1})" if name == f"joint{i + 1}" else f"{field} ({name})"
