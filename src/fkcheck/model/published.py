"""Published DH tables fkcheck knows, and values that are known variants of them.

The bundled models are the manufacturers' (or the literature's) published
tables. Some widely copied tables differ from them in a single value — a
rounded number, an older datasheet, a typo that spread. Knowing them lets
``lint`` and ``diagnose`` say *where a number comes from*, not only that it is off.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from fkcheck.model.names import Param
from fkcheck.model.read import bundled_model_paths, load_model
from fkcheck.model.types import Model

__all__ = ["KNOWN_VARIANTS", "KnownVariant", "published_tables", "variant_note"]


@dataclass(frozen=True)
class KnownVariant:
    """A value seen in circulation that differs from a published table.

    Attributes:
        model: The bundled (published) table it is a variant of.
        joint: Joint row, 0-based.
        param: ``a``, ``alpha``, ``d`` or ``theta``.
        value: The variant value (m or rad).
        source: Where it is found.
    """

    model: str
    joint: int
    param: Param
    value: float
    source: str


#: Values a test compares with the libraries that ship them.
KNOWN_VARIANTS: tuple[KnownVariant, ...] = (
    KnownVariant(
        "ur5",
        0,
        "d",
        0.089459,
        "Robotics Toolbox for Python's packaged UR5 (roboticstoolbox.models.DH.UR5)",
    ),
)


@lru_cache(maxsize=1)
def published_tables() -> tuple[Model, ...]:
    """The bundled models, read once."""
    return tuple(load_model(path) for path in bundled_model_paths().values())


def variant_note(model: str, joint: int, param: str, value: float, tol: float = 1e-12) -> str:
    """Where ``value`` is known from, if it is a known variant of ``model``'s row; else ``""``."""
    for v in KNOWN_VARIANTS:
        if (v.model, v.joint, v.param) == (model, joint, param) and abs(v.value - value) <= tol:
            return v.source
    return ""
