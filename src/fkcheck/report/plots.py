"""The report's pictures, drawn with Matplotlib's Agg renderer into inline PNG data URIs.

Figures are built with :class:`matplotlib.figure.Figure` directly (no pyplot,
no global backend switch) and embedded as ``data:image/png;base64`` so the page
needs no file next to it and no network. Matplotlib is imported inside the
functions: importing :mod:`fkcheck.report` stays light.

Errors are drawn on log scales; an error of exactly zero (two implementations
agreeing to the last bit) cannot sit on a log axis and is drawn at
:data:`LOG_FLOOR`, which the captions say.
"""

from __future__ import annotations

import base64
import io
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from fkcheck.core.typing import Float
from fkcheck.engine.evidence import FailureDetail
from fkcheck.engine.results import REFERENCE_NAME, BackendResult, CheckResult
from fkcheck.io.text import terminal_text
from fkcheck.report.views import Image

if TYPE_CHECKING:
    from matplotlib.figure import Figure


__all__ = [
    "LOG_FLOOR",
    "arm_drawing",
    "backend_colors",
    "error_against_joints",
    "error_distribution",
    "png_data_uri",
]


#: Errors at or below this are drawn at this value on log axes (exact agreement is 0).
LOG_FLOOR = 1e-18
#: Pixels per inch of the embedded PNGs.
DPI = 96
#: At most this many points per backend and panel (a seeded subset beyond); keeps
#: the page small and the drawing fast for large runs. The worst point is always kept.
MAX_POINTS = 20_000

_PALETTE = (
    "#d62728",
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
    "#7f7f7f",
)


def _text(value: str) -> str:
    """Text from a model or a backend name, shown literally.

    One line, control characters as visible escapes
    (:func:`fkcheck.io.text.terminal_text`), ``$`` escaped (it would start mathtext).
    """
    return terminal_text(value).replace("$", r"\$")


def png_data_uri(fig: Figure) -> str:
    """Render a figure to a ``data:image/png;base64,…`` URI."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI, metadata={"Software": None})
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def backend_colors(check: CheckResult) -> dict[str, str]:
    """A fixed colour per backend, in result order (the same in every picture)."""
    return {r.name: _PALETTE[k % len(_PALETTE)] for k, r in enumerate(check.backends)}


def _new_figure(width_in: float, height_in: float) -> Figure:
    """A figure drawn by Agg at :data:`DPI`, without a layout engine (see :func:`_place`)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=DPI)
    FigureCanvasAgg(fig)
    return fig


#: Points per inch (Matplotlib's font sizes, paddings and tick lengths are in points).
_PT = 72.0
#: Blank room at a figure's edges and between a label and what it labels, points.
_PAD_PT = 4.0


def _text_size(fig: Figure, text: str, size: float | str) -> tuple[float, float]:
    """Width and height (inches) of one line of text at a font size, as Agg draws it."""
    from matplotlib import cbook
    from matplotlib.font_manager import FontProperties

    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    math = cbook.is_math_text(text)
    width, height, _ = renderer.get_text_width_height_descent(
        text, FontProperties(size=size), ismath=math
    )
    # A line is at least as tall as "lp" (what Matplotlib's text layout reserves).
    _, line, _ = renderer.get_text_width_height_descent("lp", FontProperties(size=size), False)
    return width / fig.dpi, max(height, line) / fig.dpi


def _tick_labels(axis: Any, which: str) -> list[str]:
    """The labels of an axis's ``major`` or ``minor`` ticks at its current limits.

    Asked of its locator and formatter as the axis asks them when it draws,
    without building the ticks (what made a layout engine slow).
    """
    locator = getattr(axis, f"get_{which}_locator")()
    formatter = getattr(axis, f"get_{which}_formatter")()
    scale = axis.get_transform()  # ticks are kept or dropped on the drawn (e.g. log) scale
    low, high = sorted(scale.transform(np.asarray(axis.get_view_interval(), dtype=float)))
    close = 1e-10 * (high - low)  # a tick a round-off beyond the limits is drawn
    locs = np.asarray(locator(), dtype=float)
    drawn = scale.transform(locs) if locs.size else locs
    texts = formatter.format_ticks(locs)
    return [t for x, t in zip(drawn, texts, strict=True) if t and low - close <= x <= high + close]


def _tick_room(fig: Figure, axis: Any, *, across: bool, size: float | None = None) -> float:
    """Room (inches) an axis's ticks and their labels take beside the axes.

    Args:
        fig: The figure.
        axis: Its x or y axis.
        across: The labels' width (a y axis: labels beside it); else their height.
        size: The major tick labels' font size, points, when set (``tick_params``,
            which sets the major ticks' only); else Matplotlib's default.
    """
    import matplotlib as mpl

    rc = mpl.rcParams
    if across:
        default, tick = rc["ytick.labelsize"], rc["ytick.major.size"] + rc["ytick.major.pad"]
    else:
        default, tick = rc["xtick.labelsize"], rc["xtick.major.size"] + rc["xtick.major.pad"]
    labels = [(t, default if size is None else size) for t in _tick_labels(axis, "major")]
    labels += [(t, default) for t in _tick_labels(axis, "minor")]
    sizes = [_text_size(fig, text, at) for text, at in labels]
    label = max((w if across else h for w, h in sizes), default=0.0)
    return label + float(tick) / _PT


def _place(
    fig: Figure,
    grid: tuple[int, int],
    *,
    left: float,
    right: float,
    top: float,
    bottom: float,
    wspace: float = 0.0,
    hspace: float = 0.0,
) -> None:
    """Place a grid of ``(rows, columns)`` subplots with margins and gaps given in inches.

    The pictures lay themselves out: each measures what lies outside its axes
    (tick labels, axis labels, titles, legends) and leaves that much room.
    Matplotlib's ``constrained`` layout did the same by building and measuring
    every tick of every panel twice per drawing: about half of a picture's time.
    """
    width, height = fig.get_size_inches()
    rows, cols = grid
    panel_w = (width - left - right - wspace * (cols - 1)) / cols
    panel_h = (height - top - bottom - hspace * (rows - 1)) / rows
    fig.subplots_adjust(
        left=left / width,
        right=1.0 - right / width,
        top=1.0 - top / height,
        bottom=bottom / height,
        wspace=wspace / panel_w,
        hspace=hspace / panel_h,
    )


def _layered(k: int, count: int, thinnest: float, thickest: float) -> float:
    """Line width or marker size for the k-th of ``count`` series, earlier ones wider.

    Identical results (three URDF backends agreeing) then stay visible one behind another.
    """
    if count <= 1:
        return thinnest
    return thickest - (thickest - thinnest) * k / (count - 1)


def _floor(values: Float) -> Float:
    floored: Float = np.maximum(values, LOG_FLOOR)
    return floored


def _subset(n: int, keep: int | None) -> NDArray[np.intp]:
    """Indices of at most MAX_POINTS configurations (seeded), always including ``keep``."""
    if n <= MAX_POINTS:
        return np.arange(n)
    picked = np.random.default_rng(0).choice(n, MAX_POINTS, replace=False)
    if keep is not None:
        picked = np.append(picked, keep)
    indices: NDArray[np.intp] = np.sort(picked)
    return indices


def _ran(check: CheckResult) -> list[BackendResult]:
    return [r for r in check.backends if r.position_error_m is not None and r.position_error_m.size]


def error_distribution(check: CheckResult) -> Image | None:
    """Histograms of each backend's position and rotation error on log axes.

    Returns:
        The picture, or ``None`` when no backend ran.
    """
    ran = _ran(check)
    if not ran:
        return None
    colors = backend_colors(check)
    fig = _new_figure(11.0, 3.4)
    axes = fig.subplots(1, 2)
    panels = (
        ("position error [m]", check.tol_pos_m, [r.position_error_m for r in ran]),
        ("rotation error [rad]", check.tol_rot_rad, [r.rotation_error_rad for r in ran]),
    )
    for ax, (label, tol, series) in zip(axes, panels, strict=True):
        values = [_floor(np.asarray(v)) for v in series]
        low = min(float(v.min()) for v in values)
        high = max(float(v.max()) for v in [*values, np.array([tol])])
        edges = np.logspace(math.log10(low) - 0.5, math.log10(high) + 0.5, 61)
        for k, (result, v) in enumerate(zip(ran, values, strict=True)):
            ax.hist(
                v,
                bins=edges,
                histtype="step",
                linewidth=_layered(k, len(ran), 1.4, 4.0),
                color=colors[result.name],
                label=_text(result.name),
            )
        ax.axvline(tol, color="black", linestyle="--", linewidth=1.0, label="tolerance")
        ax.set_xscale("log")
        ax.set_xlabel(label)
        ax.set_ylabel("configurations")
        ax.grid(True, which="major", alpha=0.3)
    legend = axes[1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    for _ in range(2):  # the second time measures the ticks of the panels' final size
        _place_side_by_side(fig, axes, legend.get_window_extent().width / fig.dpi)
    n = check.q.shape[0]
    return Image(
        src=png_data_uri(fig),
        alt="Histograms of position and rotation error per backend, log scale",
        caption=(
            f"Error distribution over the {n} configurations, per backend, against "
            f"{REFERENCE_NAME} (log scale; dashed: tolerance). Errors of exactly 0 are drawn "
            f"at {LOG_FLOOR:g}. A backend to the right of the dashed line disagrees. Backends "
            "listed first are drawn wider, so identical distributions show one behind another."
        ),
    )


def _place_side_by_side(fig: Figure, axes: Any, legend_in: float) -> None:
    """Lay out :func:`error_distribution`'s two panels, its legend (this wide) at the right."""
    import matplotlib as mpl

    pad = _PAD_PT / _PT
    size = mpl.rcParams["axes.labelsize"]
    label = _text_size(fig, "configurations", size)[1] + float(mpl.rcParams["axes.labelpad"]) / _PT
    beside = [label + _tick_room(fig, ax.yaxis, across=True) for ax in axes]
    below = max(_tick_room(fig, ax.xaxis, across=False) for ax in axes)
    # The top y tick label stands half above the axes; a count's offset (×1e6) above it.
    above = _text_size(fig, "0", mpl.rcParams["ytick.labelsize"])[1]
    if any(ax.yaxis.get_major_formatter().get_offset() for ax in axes):
        above *= 2
    width = fig.get_size_inches()[0]
    _place(
        fig,
        (1, len(axes)),
        left=pad + beside[0],
        right=pad + legend_in + 0.01 * width / 2,  # the legend starts at 1.01 of the axes
        top=pad + above,
        bottom=pad + label + below,
        wspace=2 * pad + beside[1],
    )


def error_against_joints(check: CheckResult) -> Image | None:
    """Small multiples: error against each joint's value, one column per joint.

    Top row position error, bottom row rotation error, log scale. A constant
    error (a wrong constant in the table) draws a flat band in every panel; an
    error one joint drives shows structure in that joint's panel. Each failing
    backend's worst configuration is ringed.

    Returns:
        The picture, or ``None`` when no backend ran.
    """
    ran = _ran(check)
    if not ran:
        return None
    model = check.model
    n = model.dof
    colors = backend_colors(check)
    cols = n
    fig = _new_figure(max(6.0, 1.75 * cols + 1.6), 4.6)
    axes = np.asarray(fig.subplots(2, cols, sharey="row", squeeze=False))
    q = check.q
    for j, joint in enumerate(model.joints):
        prismatic = joint.type == "prismatic"
        x_all = q[:, j] if prismatic else np.degrees(q[:, j])
        for row, (attr, tol) in enumerate(
            (("position_error_m", check.tol_pos_m), ("rotation_error_rad", check.tol_rot_rad))
        ):
            ax = axes[row, j]
            for k, result in enumerate(ran):
                values = np.asarray(getattr(result, attr))
                keep = _subset(values.size, result.worst_index)
                ax.plot(
                    x_all[keep],
                    _floor(values[keep]),
                    ".",
                    markersize=_layered(k, len(ran), 2.0, 5.0),
                    alpha=0.5,
                    color=colors[result.name],
                    label=_text(result.name),
                    rasterized=True,
                )
                if result.status == "fail" and result.worst_index is not None:
                    k = result.worst_index
                    ax.plot(
                        [x_all[k]],
                        [max(float(values[k]), LOG_FLOOR)],
                        "o",
                        markersize=9,
                        markerfacecolor="none",
                        markeredgecolor="black",
                        markeredgewidth=1.2,
                    )
            ax.axhline(tol, color="black", linestyle="--", linewidth=0.8)
            ax.set_yscale("log")
            ax.grid(True, which="major", alpha=0.3)
            ax.tick_params(labelsize=7)
            if row == 0:
                ax.set_title(f"J{j + 1} {_text(joint.name)}", fontsize=8)
            else:
                ax.set_xlabel(f"q{j + 1} [{'m' if prismatic else '°'}]", fontsize=8)
        axes[0, 0].set_ylabel("position error [m]", fontsize=8)
        axes[1, 0].set_ylabel("rotation error [rad]", fontsize=8)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    legend = fig.legend(
        handles,
        labels,
        loc="lower center",
        bbox_to_anchor=(0.5, 0.0),
        borderaxespad=_PAD_PT / 8,  # in font sizes: _PAD_PT above the figure's bottom edge
        ncols=min(len(labels), 6),
        fontsize=8,
        markerscale=4,
        frameon=False,
    )
    for _ in range(2):  # the second time measures the ticks of the panels' final size
        _place_panels(fig, axes, legend.get_window_extent().y1 / fig.dpi)
    return Image(
        src=png_data_uri(fig),
        alt="Position and rotation error against each joint's value, one panel per joint",
        caption=(
            "Error against each joint's value (top: position, bottom: rotation; log scale; "
            "dashed: tolerance; ringed: each failing backend's worst configuration). A flat "
            "band across every panel is a constant error that no joint drives (a wrong "
            "constant, offset or mapping); structure in one joint's panel points at that joint."
        ),
    )


def _place_panels(fig: Figure, axes: Any, legend_top_in: float) -> None:
    """Lay out :func:`error_against_joints`'s panels above its legend (whose top is given).

    Fonts as that function sets them: 7 pt major ticks, 8 pt titles and axis labels;
    the panels of a row share their y axis, so only the first column has y tick labels.
    """
    import matplotlib as mpl

    pad = _PAD_PT / _PT
    label = _text_size(fig, "q1 [°]", 8)[1] + float(mpl.rcParams["axes.labelpad"]) / _PT
    title = _text_size(fig, "J1", 8)[1] + float(mpl.rcParams["axes.titlepad"]) / _PT
    beside = max(_tick_room(fig, ax.yaxis, across=True, size=7) for ax in axes[:, 0])
    below = [max(_tick_room(fig, ax.xaxis, across=False, size=7) for ax in row) for row in axes]
    tick = float(mpl.rcParams["ytick.major.size"]) / _PT
    _place(
        fig,
        axes.shape,
        left=pad + label + beside,
        right=pad,
        top=pad + title,
        bottom=legend_top_in + pad + label + below[1],
        wspace=2 * pad + tick,
        hspace=below[0] + pad,  # the second row has no titles
    )


def _triad(ax: Any, T: Float, length: float, style: str, width: float, alpha: float) -> None:
    origin = T[:3, 3]
    for axis, color in zip(range(3), ("#d62728", "#2ca02c", "#1f77b4"), strict=True):
        tip = origin + length * T[:3, axis]
        ax.plot(
            *zip(origin, tip, strict=True),
            linestyle=style,
            color=color,
            linewidth=width,
            alpha=alpha,
        )


def arm_drawing(check: CheckResult, result: BackendResult, detail: FailureDetail) -> Image | None:
    """A 3D stick drawing of the arm at a backend's worst configuration.

    Drawn from what the engine kept (``detail``): the in-house chain through its
    DH frame origins (black, joints as dots) with each joint axis (grey, the DH z
    axis the joint turns about), the in-house ``from`` and ``to`` frames as solid
    triads (x red, y green, z blue), and the backend's ``to`` frame as a dashed
    triad placed at the in-house ``from`` frame times the backend's
    ``from_T_to`` (every backend has its own root, so ``from`` is where the two
    are made to coincide). For a backend built from the DH table, its whole
    chain is overlaid too (dashed, in its colour). When the table's joint axes
    disagree with the URDF's at this configuration, the URDF's axes are
    overlaid (dotted, in the backend's colour) so a flipped or shifted axis shows.

    Returns:
        The picture, or ``None`` when there is no worst configuration.
    """
    if result.worst_index is None:
        return None
    model = check.model
    k = result.worst_index
    frames, tcp = detail.arm.world_T_dh, detail.arm.world_T_tcp
    world_T_from, world_T_to = detail.arm.world_T_from, detail.arm.world_T_to
    points = np.vstack(
        [frames[:, :3, 3], tcp[None, :3, 3], world_T_to[None, :3, 3], world_T_from[None, :3, 3]]
    )
    extent = float(np.ptp(points, axis=0).max()) or 1.0
    axis_len = 0.12 * extent
    triad_len = 0.18 * extent
    color = backend_colors(check)[result.name]

    fig = _new_figure(7.6, 6.6)
    pad = _PAD_PT / _PT
    _place(
        fig, (1, 1), left=pad, right=pad, top=pad, bottom=pad
    )  # a 3D axes draws its labels inside
    ax = fig.add_subplot(projection="3d")
    chain = np.vstack([frames[:, :3, 3], tcp[None, :3, 3]])
    ax.plot(*chain.T, "-", color="black", linewidth=2.5, label=f"{REFERENCE_NAME} chain")
    ax.plot(*frames[:, :3, 3].T, "o", color="black", markersize=4)
    joint_frames = frames[:-1] if model.convention == "standard" else frames[1:]
    for j, (T, joint) in enumerate(zip(joint_frames, model.joints, strict=True)):
        origin, z = T[:3, 3], T[:3, 2] * (-1.0 if joint.flip else 1.0)
        ends = np.vstack([origin, origin + axis_len * z])
        ax.plot(*ends.T, "-", color="#666666", linewidth=2.0)
        ax.text(*(origin + axis_len * z), f"J{j + 1}", fontsize=7, color="#444444")
    _triad(ax, world_T_from, triad_len, "-", 2.0, 0.9)
    _triad(ax, world_T_to, triad_len, "-", 2.0, 0.9)
    ax.text(*world_T_from[:3, 3], f" {_text(check.frame_from)}", fontsize=8)
    ax.text(*world_T_to[:3, 3], f" {_text(check.frame_to)}", fontsize=8)
    drawn = "in-house chain and frames"
    if detail.dh_parting is not None:
        theirs = detail.dh_parting.theirs
        ax.plot(
            *theirs[:, :3, 3].T,
            "--",
            color=color,
            linewidth=2.0,
            label=f"{_text(result.name)} DH chain",
        )
        drawn += f"; {result.name}'s DH chain (dashed)"
    axes = detail.urdf_axes
    if axes is not None and axes.first is not None:
        urdf_lines = zip(axes.lines.urdf_points, axes.lines.urdf_directions, strict=True)
        for j, (point, direction) in enumerate(urdf_lines):
            start = (world_T_from @ np.append(point, 1.0))[:3]
            end = start + axis_len * (world_T_from[:3, :3] @ direction)
            ax.plot(
                *np.vstack([start, end]).T,
                ":",
                color=color,
                linewidth=2.4,
                label="URDF joint axes" if j == 0 else None,
            )
        drawn += "; the URDF's joint axes (dotted), which the table's do not all match"
    if np.isfinite(detail.worst.theirs[0]).all():  # indices[0] is the worst configuration
        their_to = world_T_from @ detail.worst.theirs[0]
        _triad(ax, their_to, triad_len, "--", 2.0, 1.0)
        ax.plot(
            *their_to[:3, 3],
            "s",
            color=color,
            markersize=6,
            label=f"{_text(result.name)}: {_text(check.frame_to)}",
        )
        drawn += f"; {result.name}'s {check.frame_to} frame (dashed triad, square)"
    center = points.mean(axis=0)
    half = 0.55 * extent
    ax.set_xlim(center[0] - half, center[0] + half)
    ax.set_ylim(center[1] - half, center[1] + half)
    ax.set_zlim(center[2] - half, center[2] + half)
    ax.set_box_aspect((1.0, 1.0, 1.0))
    ax.set_xlabel("x [m]", fontsize=8)
    ax.set_ylabel("y [m]", fontsize=8)
    ax.set_zlabel("z [m]", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.view_init(elev=22, azim=-60)
    ax.legend(fontsize=7, loc="upper left")
    pos = result.position_error_m
    rot = result.rotation_error_rad
    size = ""
    if pos is not None and rot is not None:
        size = (
            f" Here they differ by {pos[k] * 1e3:.3g} mm and {math.degrees(rot[k]):.3g}°; "
            f"differences under about {extent * 10:.0f} mm "
            "or a degree are too small to see at this scale (the tables below give them)."
        )
    return Image(
        src=png_data_uri(fig),
        alt=f"3D stick drawing of {model.name} at {result.name}'s worst configuration",
        caption=(
            f"The arm at {result.name}'s worst configuration (#{k}), in the world frame: "
            f"{drawn}. Black: DH frame origins joined base to TCP; grey: joint axes J1…J"
            f"{model.dof}; triads: x red, y green, z blue; solid = {REFERENCE_NAME}, dashed = "
            f"{result.name}, placed so that both {check.frame_from} frames coincide.{size}"
        ),
    )
