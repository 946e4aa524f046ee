"""The TOML block ``fkcheck map`` proposes, with its evidence in comments.

Part of :mod:`fkcheck.urdf.mapping`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from fkcheck.io.format import format_deg, format_mm
from fkcheck.model.types import (
    FrameSpec,
    Model,
    UrdfSpec,
)
from fkcheck.model.write import frame_toml, toml_comment, toml_string, xacro_toml
from fkcheck.urdf.chain_fit import Anchor
from fkcheck.urdf.map_result import MapResult, ProposedFrame

__all__ = [
    "proposal_toml",
]


def proposal_toml(
    result: MapResult,
    section: str = "urdf",
    twin: Callable[[FrameSpec], FrameSpec] | None = None,
) -> str:
    """The ``[urdf]`` (or ``section``) and ``[frames.*]`` block, with the evidence in comments.

    ``twin`` maps a proposed frame (whose ``urdf`` names its link) onto the
    description's format (:meth:`fkcheck.description.types.DescriptionFormat.with_frame`);
    default: as it is, ``urdf = "LINK"``.

    Every comment goes through :func:`~fkcheck.model.write.toml_comment`: names
    from the URDF or the model (which may hold newlines) can never start a line
    of TOML of their own.
    """
    model = result.model
    tol_m, tol_rad = result.tolerances
    out = toml_comment(
        [
            f"fkcheck map: model {model.name} onto {result.urdf_path}",
            f"{result.configurations} configurations (seed {result.seed}); a link is at a "
            "constant offset when it stays within",
            f"the model's check tolerances ({tol_m:g} m, {tol_rad:g} rad); numbers within 1e-9 "
            "of 0, a multiple of 90° or a whole µm are snapped to it.",
        ]
    )
    out += ["", f"[{section}]", f"path = {toml_string(result.urdf_path)}"]
    out += toml_comment(_joint_notes(result))
    out.append(f"joints = [{', '.join(toml_string(j.urdf) for j in result.joints)}]")
    if result.xacro_args is not None:
        out += toml_comment(
            "A xacro file: fkcheck expands it only with this opt-in (it runs the file's Python)."
        )
        urdf = UrdfSpec(result.urdf_path, (), True, dict(result.xacro_args), dict(result.packages))
        out += xacro_toml(urdf)
    out += _frame_groups(result, twin)
    for near in result.nearest:
        where = "DH frame 0" if near.anchor == 0 else f"DH frame {near.anchor}"
        out += [
            "",
            *toml_comment(
                f"NO URDF link sits at a constant offset from {where}: the nearest, "
                f"{near.link}, moves by {format_mm(near.spread_m)} / {format_deg(near.spread_rad)} "
                "over the samples."
            ),
        ]
    out += _check_block(result)
    return "\n".join(out) + "\n"


def _joint_notes(result: MapResult) -> list[str]:
    """The comment over ``joints``: how well they fit, each one's direction, the rows changed."""
    model = result.model
    notes: list[str] = []
    if result.joints_fit:
        notes.append(
            f"The joints, found by how they move (last DH frame vs URDF link: "
            f"{result.fit_m:.2g} m, {result.fit_rad:.2g} rad):"
        )
    else:
        notes.append(
            f"NO chain of the URDF moves like this table: the nearest leaves the last DH frame "
            f"{format_mm(result.fit_m)} / {format_deg(result.fit_rad)} off its link:"
        )
    for j in result.joints:
        if j.flipped:
            notes.append(
                f"  {j.dh} = {j.urdf}: turns the OTHER way; the URDF gets q unchanged, so set "
                f"flip = {'false' if _flip_of(model, j.dh) else 'true'} on [[joint]] {j.dh}"
            )
        else:
            notes.append(f"  {j.dh} = {j.urdf}: same direction")
    moved = [line for line in result.edits.lines(model) if not line.endswith(("= true", "= false"))]
    if moved:
        notes.append(
            "The chain moves like the table only with these rows changed (a vendor's zeros "
            "a quarter turn apart, or a number typed otherwise: one of the two is wrong):"
        )
        notes += [f"  {line}" for line in moved]
        notes.append("The frames below are those of the table so changed: change it, then paste.")
    notes += [f"Another chain moves the same way: {', '.join(other)}" for other in result.also_fit]
    return notes


def _frame_groups(result: MapResult, twin: Callable[[FrameSpec], FrameSpec] | None) -> list[str]:
    """The proposed ``[frames.*]`` tables, grouped by end, each with its evidence."""
    n = result.model.dof
    ends: tuple[Anchor, ...] = (0, "world", n, "tcp")
    groups: tuple[tuple[str, tuple[Anchor, ...] | None], ...] = (
        ("DH frame 0", (0, "world")),
        ("the middle DH frames", None),
        (f"the last DH frame ({n}) and the TCP", (n, "tcp")),
    )
    out: list[str] = []
    for title, members in groups:
        chosen = [
            p
            for p in result.frames
            if (p.spec.dh in members if members is not None else p.spec.dh not in ends)
        ]
        if not chosen:
            continue
        out += [
            "",
            *toml_comment(
                f"--- Links at a constant offset from {title}, most common name first ---"
            ),
        ]
        out += [_frame_lines(result, p, twin) for p in chosen]
    return out


def _frame_lines(
    result: MapResult, p: ProposedFrame, twin: Callable[[FrameSpec], FrameSpec] | None
) -> str:
    """One proposed frame's table, its evidence, note and warning in comments over it."""
    comment = []
    if p.fit is not None:
        new = "" if p.declared else " (not declared in the model)"
        comment.append(f"{p.fit.link}: {p.fit.evidence()}{new}")
    if p.note:
        comment.append(p.note)
    comment += _absorb_warning(p, result.absorbs.get(p.spec.name, ()))
    spec = p.spec if twin is None else twin(p.spec)
    return frame_toml(spec, result.model.angle_unit, comment).rstrip("\n")


def _absorb_warning(p: ProposedFrame, hidden: Sequence[str]) -> list[str]:
    """The comment over a frame whose offset could be hiding table numbers."""
    if not hidden or p.spec.source:
        return []
    anchor = (
        "the world"
        if p.spec.dh == "world"
        else "the TCP"
        if p.spec.dh == "tcp"
        else (f"DH frame {p.spec.dh}")
    )
    chosen = [h for h in hidden if _CHOSEN in h]
    carried = [h for h in hidden if _CHOSEN not in h]
    out = []
    if carried:
        names = ", ".join(h.split(":", 1)[0] for h in carried)
        out += [
            f"NOT IDENTIFIABLE: this offset from {anchor} carries what {names} of the table "
            f"{'produces' if len(carried) == 1 else 'produce'}:",
            *(f"  {h}" for h in carried),
        ]
    if chosen:
        names = ", ".join(h.split(":", 1)[0] for h in chosen)
        out += [
            f"NOT IDENTIFIABLE: another link fixed beside this one could be {anchor} instead, "
            f"with {names} of the table changed:",
            *(f"  {h}" for h in chosen),
        ]
    return [
        *out,
        "either the URDF defines the link so, or the table is off by it: fkcheck cannot tell "
        "(a check through this frame does not verify those numbers). If the vendor defines "
        'the link so, vouch for it: source = "<where the vendor says so>".',
    ]


#: What a number a choice among links could hide says (:func:`fkcheck.model.coverage`).
_CHOSEN = "of the description would be"


def _check_block(result: MapResult) -> list[str]:
    """The proposed ``[check]`` pair, live when the model declares no check of its own."""
    if result.pair is None or result.numbers is None:
        return []
    frm, to = result.pair
    lines = [
        "",
        *toml_comment(
            [
                "--- The check: at each end the outermost link whose offset hides the fewest "
                "table numbers ---",
                f"It can verify {result.numbers.scope()}.",
            ]
        ),
    ]
    body = ["[check]", f"from = {toml_string(frm)}", f"to = {toml_string(to)}"]
    if not result.check_declared:
        return lines + body
    own = result.model.check
    for twin in result.twins:  # the model's own check then compares these links
        lines.append(
            frame_toml(
                twin,
                result.model.angle_unit,
                f"The model's own [check] compares {own.frame_from} → {own.frame_to}: "
                f"{twin.urdf} sits exactly on {twin.name}.",
            ).rstrip("\n")
        )
    # a second [check] would not parse
    lines += toml_comment(["The model declares its own [check]: to check this pair, set there:"])
    lines += toml_comment(body)
    return lines


def _flip_of(model: Model, joint: str) -> bool:
    return next(j.flip for j in model.joints if j.name == joint)
