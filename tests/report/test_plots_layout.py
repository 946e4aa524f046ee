"""The report's pictures lay themselves out: nothing drawn is cut off at the figure's edge.

The pictures place their axes from the measured sizes of their tick labels, axis
labels, titles and legends (:func:`fkcheck.report.plots._place`), not with a layout
engine. These tests draw each picture and ask Matplotlib where what it drew ended
up: inside the figure, and no axis's ticks and labels, title or legend over another panel.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from fkcheck.report import plots
from tests.report_cases import golden_check

#: How far (inches) text may reach past the figure's edge: a rounding of a pixel.
EDGE_IN = 1.0 / plots.DPI


def _narrow():
    """Every backend's errors within one decade: the log axes label minor ticks (10 pt)."""
    check = golden_check()
    rng = np.random.default_rng(1)
    n = check.q.shape[0]
    backends = [
        b
        if b.position_error_m is None
        else dataclasses.replace(
            b,
            position_error_m=rng.uniform(2e-6, 3e-6, n),
            rotation_error_rad=rng.uniform(1.1e-6, 1.4e-6, n),
        )
        for b in check.backends
    ]
    return dataclasses.replace(check, backends=tuple(backends))


def _many_counts():
    """A histogram whose counts run into six digits (its y labels are widest)."""
    check = golden_check()
    n = 250_000
    rng = np.random.default_rng(2)
    q = rng.uniform(-1.0, 1.0, size=(n, check.q.shape[1]))
    backends = [
        b
        if b.position_error_m is None
        else dataclasses.replace(
            b,
            position_error_m=np.full(n, 3e-4),
            rotation_error_rad=np.full(n, 2e-9),
            worst_index=0,
        )
        for b in check.backends
    ]
    return dataclasses.replace(check, q=q, backends=tuple(backends))


CHECKS = {"golden": golden_check, "narrow": _narrow, "many": _many_counts}


def _drawn(monkeypatch, picture, check):
    """The figure ``picture`` drew for ``check`` (drawn once more, to be measured)."""
    figures = []
    real = plots.png_data_uri

    def keep(fig):
        figures.append(fig)
        return real(fig)

    monkeypatch.setattr(plots, "png_data_uri", keep)
    if picture is plots.arm_drawing:
        failing = next(r for r in check.backends if r.status == "fail")
        assert picture(check, failing, failing.detail) is not None
    else:
        assert picture(check) is not None
    (fig,) = figures
    fig.canvas.draw()
    return fig


@pytest.mark.parametrize("name", CHECKS)
@pytest.mark.parametrize(
    "picture",
    [plots.error_distribution, plots.error_against_joints, plots.arm_drawing],
    ids=["distribution", "joints", "arm"],
)
def test_nothing_drawn_runs_past_the_figures_edge(monkeypatch, picture, name):
    fig = _drawn(monkeypatch, picture, CHECKS[name]())
    drawn = fig.get_tightbbox(fig.canvas.get_renderer())  # inches: every artist drawn
    width, height = fig.get_size_inches()
    assert drawn.x0 >= -EDGE_IN
    assert drawn.y0 >= -EDGE_IN
    assert drawn.x1 <= width + EDGE_IN
    assert drawn.y1 <= height + EDGE_IN


@pytest.mark.parametrize("name", CHECKS)
@pytest.mark.parametrize(
    "picture",
    [plots.error_distribution, plots.error_against_joints],
    ids=["distribution", "joints"],
)
def test_labels_and_legends_stay_clear_of_the_other_panels(monkeypatch, picture, name):
    """An axis's ticks, tick labels and label, a title, a legend: never over another panel."""
    fig = _drawn(monkeypatch, picture, CHECKS[name]())
    renderer = fig.canvas.get_renderer()
    frames = [ax.get_window_extent(renderer) for ax in fig.axes]
    overlaps = []
    for k, ax in enumerate(fig.axes):
        pieces = {
            "x axis": ax.xaxis.get_tightbbox(renderer),
            "y axis": ax.yaxis.get_tightbbox(renderer),
            "title": ax.title.get_window_extent(renderer) if ax.get_title() else None,
        }
        for what, box in pieces.items():
            for j, frame in enumerate(frames):
                if box is not None and j != k and box.overlaps(frame):
                    overlaps.append((k, what, j))
    for legend in [*fig.legends, *(ax.get_legend() for ax in fig.axes)]:
        if legend is not None:
            box = legend.get_window_extent(renderer)
            overlaps += [("legend", j) for j, frame in enumerate(frames) if box.overlaps(frame)]
    assert overlaps == []
