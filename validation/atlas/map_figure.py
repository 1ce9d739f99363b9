"""The atlas's error maps as pictures, drawn one after another on one figure.

A map (``MapFigure.draw``) is a model's tip error at equal load over its map axis (``AtlasModel.map_axes[0]``)
and the load, the worst over its other shape inputs (``regions.grid``; grey: beyond the atlas), on a log
colour scale from 0.01 to 100 % of L, with the 0.5/1/3/5 % region boundaries as labelled contours and
each seed claim's ranges on these axes as dashed green lines.

``MapFigure`` draws every map of a page on the same figure, cleared between maps: the figure's Agg
renderer keeps what it measured (text extents, parsed math text such as the log axis's 10^k labels),
which a new figure would measure again.  The figure has no layout engine; ``place`` sets the map's and
its colour bar's rectangles from one measurement of what lies outside each (tick labels, axis labels,
title), with the constrained layout's rules: a pad of ``PAD`` inches at the figure's edges, a colour bar
``BAR_ASPECT`` times as long as it is wide, the height of the map, a ``BAR_GAP`` share of the map's width
to its right (or more, where the map's tick labels reach out further).  The measurement is taken again
when the new rectangles change an axis's ticks (a locator spaces its ticks by the axis's length).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from validation.atlas.claims import Claim
from validation.atlas.expected import REGION_LEVELS
from validation.atlas.minor_ticks import mark_minor_ticks
from validation.atlas.models import MODELS
from validation.atlas.regions import grid

SIZE = (6.4, 4.4)  # inches
DPI = 110  # of the figure and of its PNG
PAD = 3 / 72  # inches between what is drawn and the figure's edge (the constrained layout's)
BAR_ASPECT = 20.0  # the colour bar's length over its width (matplotlib's colour bar)
BAR_GAP = 0.05  # between the map and its colour bar, as a share of the map's width (matplotlib's)
# where the map and its colour bar are first measured (left, bottom, width, height; figure fractions):
# where most maps end up
MAP_AT = (0.103, 0.107, 0.728, 0.804)
BAR_AT = (0.867, 0.107, 0.028, 0.804)
PLACINGS = 3  # measurements at most: the ticks settle after the first move, seldom the second


def _reach(ax: Axes, renderer: RendererAgg) -> np.ndarray:
    """How far (inches) the axes' decorations reach beyond its box: left, bottom, right, top (>= 0)."""
    box = ax.get_window_extent(renderer)
    drawn = ax.get_tightbbox(renderer, for_layout_only=True)
    if drawn is None:
        return np.zeros(4)
    reach = [box.x0 - drawn.x0, box.y0 - drawn.y0, drawn.x1 - box.x1, drawn.y1 - box.y1]
    return np.maximum(reach, 0.0) / renderer.dpi


def rectangles(
    size: tuple[float, float], reach_map: np.ndarray, reach_bar: np.ndarray
) -> tuple[tuple[float, float, float, float], tuple[float, float, float, float]]:
    """The map's and its colour bar's rectangles (left, bottom, width, height; figure fractions) in a
    figure of ``size`` inches whose decorations reach ``reach_map`` and ``reach_bar`` (``_reach``) beyond
    them: everything ``PAD`` inside the figure, the bar beside the map (module docstring)."""
    width, height = size
    left = PAD + reach_map[0]
    bottom = PAD + max(reach_map[1], reach_bar[1])
    top = height - PAD - max(reach_map[3], reach_bar[3])
    bar_right = width - PAD - reach_bar[2]
    bar_left = bar_right - (top - bottom) / BAR_ASPECT
    right = min((bar_left + BAR_GAP * left) / (1.0 + BAR_GAP), bar_left - reach_bar[0] - PAD - reach_map[2])
    tall = (top - bottom) / height
    return (
        (left / width, bottom / height, (right - left) / width, tall),
        (bar_left / width, bottom / height, (bar_right - bar_left) / width, tall),
    )


def _ticks(axes: Sequence[Axes]) -> list[np.ndarray]:
    return [a.get_majorticklocs() for ax in axes for a in (ax.xaxis, ax.yaxis)]


def place(canvas: FigureCanvasAgg, ax: Axes, bar: Axes) -> None:
    """Set the rectangles of ``ax`` and of its colour bar's axes ``bar`` on ``canvas``'s figure
    (``rectangles``) from what lies outside them as they stand, measured again while the move changes
    their ticks."""
    renderer = canvas.get_renderer()
    width, height = canvas.figure.get_size_inches()
    for _ in range(PLACINGS):
        before = _ticks((ax, bar))
        at_map, at_bar = rectangles((width, height), _reach(ax, renderer), _reach(bar, renderer))
        ax.set_position(at_map)
        bar.set_position(at_bar)
        if all(np.array_equal(a, b) for a, b in zip(before, _ticks((ax, bar)))):
            return


class MapFigure:
    """One figure on which the maps are drawn one after another (module docstring)."""

    def __init__(self) -> None:
        self.figure = Figure(figsize=SIZE, dpi=DPI)
        self.canvas = FigureCanvasAgg(self.figure)

    def draw(self, frame: pd.DataFrame, model: str, path: Path, claims: Sequence[Claim] = ()) -> Path:
        """The map of ``model`` from the atlas ``frame`` with the ``claims``' ranges, written to ``path``
        (a PNG, ``DPI`` dots an inch, zlib level 1; written beside it and moved there)."""
        fig = self.figure
        fig.clear()
        ax, bar_ax = fig.add_axes(MAP_AT), fig.add_axes(BAR_AT)
        _draw(fig, ax, bar_ax, frame, model, claims)
        mark_minor_ticks(fig)
        place(self.canvas, ax, bar_ax)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.stem + ".tmp.png")
        fig.savefig(tmp, dpi=DPI, pil_kwargs={"compress_level": 1})
        tmp.replace(path)
        return path


def _draw(fig: Figure, ax: Axes, bar_ax: Axes, frame: pd.DataFrame, model: str, claims: Sequence[Claim]) -> None:
    """The map of ``model`` on ``ax``, its colour bar on ``bar_ax`` (module docstring)."""
    m = MODELS[model]
    x, loads, error = grid(frame, model, "tip_error")
    ax.set_facecolor("0.85")
    shown = np.clip(error, 1e-3, 100.0)
    mesh = ax.pcolormesh(x, loads, shown, shading="nearest", cmap="viridis", norm=LogNorm(vmin=0.01, vmax=100.0))
    bar = fig.colorbar(mesh, cax=bar_ax)
    bar.set_label("tip error at equal load (% of L)")
    if x.size > 1:
        lines = ax.contour(
            x,
            loads,
            np.nan_to_num(error, nan=1e3),
            levels=list(REGION_LEVELS),
            colors=["white", "#ffd166", "#ef476f", "black"],
            linewidths=1.2,
        )
        ax.clabel(lines, fmt=lambda v: f"{v:g} %", fontsize=8)
    for claim in claims:
        if model not in claim.models:
            continue
        for column, lo, hi in claim.range:
            if column == m.map_axes[0]:
                for v in (lo, hi):
                    if x.min() < v < x.max():
                        ax.axvline(v, color="#06d6a0", ls="--", lw=1.0)
            elif column in frame and column not in ("in_fit_range",) and x.size > 1:
                _, _, g = grid(frame, model, column)
                g = np.abs(g)
                for v in (lo, hi):
                    if np.nanmin(g) < v < np.nanmax(g):
                        ax.contour(x, loads, g, levels=[v], colors="#06d6a0", linestyles="--", linewidths=1.0)
    ax.set_yscale("log")
    ax.set_xlabel(
        next((a.label for a in m.shape_axes if a.name == m.map_axes[0]), "") if m.map_axes[0] != "load" else ""
    )
    ax.set_ylabel(m.load.label)
    ax.set_title(f"{m.title}\n(worst over the other inputs; dashed green: the seeds' claimed ranges)", fontsize=9)
