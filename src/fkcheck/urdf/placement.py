"""Where an undeclared URDF link sits on a model's DH chain: ``urdf:LINK``.

Part of :mod:`fkcheck.urdf.mapping`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

from fkcheck.errors import FkcheckError, FrameError
from fkcheck.io.format import format_deg, format_mm
from fkcheck.model.types import (
    URDF_FRAME_PREFIX,
    FrameSpec,
    Model,
)
from fkcheck.urdf.chain import MOVABLE, JointGeometry, UrdfKinematics
from fkcheck.urdf.chain_fit import DEFAULT_SAMPLES, LinkFit, _Fit, _Problem
from fkcheck.urdf.tree import listed

__all__ = [
    "link_frame",
    "with_link_frames",
]


def link_frame(model: Model, kin: UrdfKinematics, link: str, *, seed: int = 0) -> LinkFit:
    """Where an undeclared URDF link sits on the model's DH chain, by its ``[urdf]`` joints.

    The URDF receives each DH joint's value unchanged (as every URDF backend
    does). The link must stay at a constant offset from one DH frame ``0…n``
    over the samples, which the placement can only show when the whole chain
    moves as the table does: the placement is fitted from it.

    Raises:
        FrameError: ``link`` is not a link of the URDF (listing them).
        FkcheckError: The model has no ``[urdf]``, or the link cannot be placed,
            saying why: the table and the URDF disagree over the chain (no
            placement can be trusted; where the link hangs is named), or the link
            moves with a URDF joint the model does not map, or hangs below a
            joint fkcheck cannot follow.
    """
    where = f"{URDF_FRAME_PREFIX}{link}"
    if model.urdf is None:
        raise FkcheckError(f"{where}: model {model.name} has no [urdf]")
    if link not in kin.links:
        raise FrameError(link, f"URDF {kin.path.name}", kin.links)
    missing = [name for name in model.urdf.joints if name not in kin.joints]
    if missing:
        raise FkcheckError(
            f"{where}: model {model.name}'s [urdf] joints name {listed(missing)}, which "
            f"{kin.path.name} does not have"
        )
    hang = _hanging(kin, link, model.urdf.joints)
    if hang.unfollowed is not None:
        raise FkcheckError(
            f"{where}: URDF link {link!r} hangs below the {hang.unfollowed.type} joint "
            f"{hang.unfollowed.name!r}, which fkcheck cannot follow: it has no place on model "
            f"{model.name}'s DH chain"
        )
    problem = _Problem(model, kin, DEFAULT_SAMPLES, seed)
    signs = [1.0] * model.dof
    fit = problem.fit(model.urdf.joints, signs)
    if fit.score(problem.tol)[0] != 0:  # parallel turns, slides: polish it
        fit = min(fit, problem.fit(model.urdf.joints, signs, refine=True),
                  key=lambda f: f.score(problem.tol))  # fmt: skip
    rows = [problem.evaluate(fit, [link], k)[0] for k in range(model.dof + 1)]
    if fit.score(problem.tol)[0] != 0:
        raise FkcheckError(_untrusted(model, kin, link, fit, hang))
    for row in rows:
        if row.fits(*problem.tol):
            return row
    near = min(rows, key=lambda f: f.spread_m + f.spread_rad)
    moves = (
        f"moves with URDF joint {hang.unmapped!r}, which model {model.name}'s [urdf] joints do "
        "not map (its value is not the table's)"
        if hang.unmapped is not None
        else "does not move with any one DH frame"
    )
    raise FkcheckError(
        f"{where}: URDF link {link!r} {moves}: it is at no constant offset from any DH frame of "
        f"model {model.name} (nearest: DH frame {near.anchor}, moving by "
        f"{format_mm(near.spread_m)} / {format_deg(near.spread_rad)} over the samples), though "
        "the table and the URDF agree over the chain"
    )


@dataclass(frozen=True)
class _Hanging:
    """Where a URDF link hangs, by the URDF's tree alone.

    Attributes:
        anchor: The DH frame it moves with if the table agrees with the URDF: the
            DH joint of the last mapped joint above it (``0``: none, it is fixed
            to the chain's root side), or ``None`` when an unmapped joint moves it.
        joint: The last movable URDF joint above it, if any.
        unmapped: The first movable joint above it that ``[urdf] joints`` do not map.
        unfollowed: A joint above it that fkcheck cannot follow (floating, planar).
    """

    anchor: int | None
    joint: str | None = None
    unmapped: str | None = None
    unfollowed: JointGeometry | None = None


def _hanging(kin: UrdfKinematics, link: str, mapped: Sequence[str]) -> _Hanging:
    """Which joints move ``link``, read off the URDF's tree."""
    path = [] if link == kin.root else kin.chain(kin.root, link)
    for joint in path:
        if joint.type != "fixed" and joint.type not in MOVABLE:
            return _Hanging(None, unfollowed=joint)
    movable = [j.name for j in path if j.type != "fixed"]
    unmapped = next((name for name in movable if name not in mapped), None)
    if not movable:
        return _Hanging(0)
    if unmapped is not None:
        return _Hanging(None, movable[-1], unmapped)
    return _Hanging(list(mapped).index(movable[-1]) + 1, movable[-1])


def _untrusted(model: Model, kin: UrdfKinematics, link: str, fit: _Fit, hang: _Hanging) -> str:
    """The refusal when the chain itself does not move as the table does."""
    tip = kin.joints[fit.joints[-1]].child
    if hang.anchor == 0:
        place = f"URDF link {link!r} is fixed to the chain's root side (DH frame 0's side)"
    elif hang.anchor is not None:
        place = (
            f"URDF link {link!r} moves with URDF joint {hang.joint!r} (DH joint {hang.anchor}: "
            f"it belongs on DH frame {hang.anchor})"
        )
    else:
        place = (
            f"URDF link {link!r} moves with URDF joint {hang.unmapped!r}, which the model's "
            "[urdf] joints do not map"
        )
    known = [
        k
        for k in model.known_differences
        if k.reads == "urdf" or any(b.endswith("-urdf") for b in k.backends)
    ]
    recorded = (
        f" (the model file records a difference with its URDF: {known[0].finding})" if known else ""
    )
    return (
        f"{URDF_FRAME_PREFIX}{link}: {place}, but no placement of it on model {model.name}'s DH "
        f"frames can be trusted: the table and the URDF disagree over the chain — its last DH "
        f"frame strays up to {format_mm(fit.dev_m)} / {format_deg(fit.dev_rad)} from URDF link "
        f"{tip!r} over the samples{recorded}, and the placement is fitted from that chain. "
        f"Find the disagreement first (fkcheck check / fkcheck diagnose on the model's own "
        f'frames), or declare [frames.NAME] with dh, its offset and urdf = "{link}" to compare '
        "it anyway"
    )


def with_link_frames(
    model: Model, kin: UrdfKinematics, names: Sequence[str]
) -> tuple[Model, dict[str, LinkFit]]:
    """The model with a frame ``urdf:LINK`` added for each undeclared link ``names`` ask for.

    A name that is not ``urdf:LINK``, or whose link a declared frame already
    maps, is left to :func:`fkcheck.model.resolve_frame`.

    Returns:
        ``(model, placed)``: the model (the same object when nothing was added)
        and each added frame's placement, by frame name.
    """
    placed: dict[str, LinkFit] = {}
    for name in names:
        if not name.startswith(URDF_FRAME_PREFIX) or name in placed:
            continue
        link = name[len(URDF_FRAME_PREFIX) :]
        if any(spec.urdf == link for spec in model.frames.values()):
            continue
        placed[name] = link_frame(model, kin, link)
    if not placed:
        return model, placed
    frames = dict(model.frames)
    for name, fit in placed.items():
        frames[name] = FrameSpec(name, fit.anchor, fit.offset, fit.link)
    return replace(model, frames=frames), placed
