"""Converting a DH table between the standard and the modified (Craig) convention, exactly.

Both conventions describe the same chain of elementary motions; only where the
``Tx(a)·Rx(α)`` part of each link is grouped differs. ``Tx`` and ``Rx`` commute
(both act along x), so regrouping is exact:

* standard → modified: ``B·Π Rz(θᵢ)Tz(dᵢ)·Tx(aᵢ)Rx(αᵢ)·T`` becomes modified rows
  ``(a_{i-1}, α_{i-1}, θᵢ, dᵢ)`` with ``a₀ = α₀ = 0``, and the last link's
  ``Tx(aₙ)Rx(αₙ)`` moves into the tool;
* modified → standard: the first row's ``Rx(α₀)Tx(a₀)`` moves into the base, row
  ``i`` takes the next row's ``a``, ``α``, and the last row gets ``aₙ = αₙ = 0``.

The intermediate DH frames differ between the conventions by exactly those
``Tx(a)Rx(α)`` factors; named frames (``[frames.NAME]``) are re-expressed on the
new frames so that every named frame, the TCP and the world stay where they
were — :func:`equivalence_error` measures that.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from fkcheck.core.dh import Convention
from fkcheck.core.geometry import invert, rot_x, translation
from fkcheck.core.typing import Float
from fkcheck.model.offsets import offset_from_matrix, snap
from fkcheck.model.types import FrameSpec, Joint, Model

__all__ = ["convert_model", "equivalence_error"]


def _tx_rx(a: float, alpha: float) -> Float:
    """``Tx(a)·Rx(α)`` (= ``Rx(α)·Tx(a)``)."""
    return translation(a, 0.0, 0.0) @ rot_x(alpha)


def _reframe(model: Model, factors: Sequence[Float]) -> dict[str, FrameSpec]:
    """Named frames re-expressed: a frame at DH index ``i`` gets ``factors[i] · offset``."""
    frames: dict[str, FrameSpec] = {}
    for name, spec in model.frames.items():
        if isinstance(spec.dh, int):
            offset = offset_from_matrix(factors[spec.dh] @ spec.offset.matrix)
            spec = replace(spec, offset=offset)
        frames[name] = spec
    return frames


def _to_modified(model: Model) -> Model:
    js = model.joints
    rows: list[Joint] = []
    for i, joint in enumerate(js):
        prev_a, prev_alpha = (0.0, 0.0) if i == 0 else (js[i - 1].a, js[i - 1].alpha)
        rows.append(replace(joint, a=prev_a, alpha=snap(prev_alpha, angle=True)))
    last = js[-1]
    tool = offset_from_matrix(_tx_rx(last.a, last.alpha) @ model.tool.matrix)
    # Standard frame i = modified frame i · Tx(a_i)Rx(α_i) for i = 1…n; frame 0 is shared.
    factors = [np.eye(4)] + [_tx_rx(j.a, j.alpha) for j in js]
    return replace(
        model, convention="modified", joints=tuple(rows), tool=tool, frames=_reframe(model, factors)
    )


def _to_standard(model: Model) -> Model:
    js = model.joints
    n = len(js)
    rows: list[Joint] = []
    for i, joint in enumerate(js):
        next_a, next_alpha = (js[i + 1].a, js[i + 1].alpha) if i + 1 < n else (0.0, 0.0)
        rows.append(replace(joint, a=next_a, alpha=snap(next_alpha, angle=True)))
    first = js[0]
    base = offset_from_matrix(model.base.matrix @ _tx_rx(first.a, first.alpha))
    # Modified frame j = standard frame j · (Tx(a'_j)Rx(α'_j))⁻¹ with a'_j, α'_j the
    # modified row j+1's values (0-based row j), for j = 0…n-1; frame n is shared.
    factors = [invert(_tx_rx(js[j].a, js[j].alpha)) for j in range(n)] + [np.eye(4)]
    return replace(
        model, convention="standard", joints=tuple(rows), base=base, frames=_reframe(model, factors)
    )


def convert_model(model: Model, to: Convention) -> Model:
    """The same robot as a DH table in convention ``to``.

    Args:
        model: The model.
        to: ``"standard"`` or ``"modified"``.

    Returns:
        A new model (the same one if it already uses ``to``) whose TCP, world and
        named frames are where the original's are for every configuration; base
        and tool absorb the regrouped first/last link factors.
    """
    if model.convention == to:
        return model
    converted = _to_modified(model) if to == "modified" else _to_standard(model)
    note = f"converted from {model.convention} DH by fkcheck convert"
    description = f"{model.description} ({note})" if model.description else note
    return replace(converted, description=description)


def equivalence_error(a: Model, b: Model, q: Float) -> tuple[float, float]:
    """Largest position (m) and rotation (rad) difference of every named frame of ``a``.

    Args:
        a: One model.
        b: Another model with the same joints and frame names (e.g. a conversion of ``a``).
        q: ``(N, n)`` configurations.

    Returns:
        ``(max position error, max rotation error)`` over all configurations and
        all of ``a``'s named frames (``world`` and ``tcp`` included).
    """
    from fkcheck.core.metrics import position_error_m, rotation_error_rad
    from fkcheck.model.frames import reference_poses

    names = list(a.frames)
    pa = reference_poses(a, q, names)
    pb = reference_poses(b, q, names)
    return float(position_error_m(pa, pb).max()), float(rotation_error_rad(pa, pb).max())
