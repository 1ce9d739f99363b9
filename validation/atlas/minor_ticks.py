"""Minor ticks drawn as one line of tick marks: the same pixels as matplotlib's, at a fraction of the cost.

Matplotlib keeps a ``Tick`` (two tick lines, two labels and a grid line) for every minor tick and moves
and relabels all of them each time the axis is measured, which the constrained layout does tens of times
a figure; a log axis has some forty minor ticks, and on the atlas's maps and scatter they are about a
third of the drawing time.  Where an axis's minor ticks have no labels and no grid lines (a log axis over
more than a decade), ``mark_minor_ticks`` draws them instead as one ``MinorTickMarks`` line per side: the
tick marker of the axis's own minor tick at every location its minor locator gives, less those on a major
tick and those outside the view, worked out when the figure is drawn (after the layout, as matplotlib
does: a log locator's ticks depend on the axis's length).  Tick marks take no part in the layout, so the
axes land where they did and the picture is the same, pixel for pixel (for raster output; an SVG would
group its elements differently).
"""

from __future__ import annotations

import numpy as np
from matplotlib.axis import XAxis, YAxis
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import Locator, NullLocator

OVERLAP = 1e-5  # a minor tick this close to a major one (share of the view, scaled) is dropped: as matplotlib
INSIDE = 1e-10  # a tick this far outside the view (share of it, transformed) is still drawn: as matplotlib


class MinorTickMarks(Line2D):
    """The minor tick marks of one side of an axis (``side``: its minor tick's tick line), placed at draw
    time from the axis's minor ``locator``."""

    def __init__(self, axis: XAxis | YAxis, locator: Locator, side: Line2D) -> None:
        super().__init__([], [])
        self.update_from(side)
        self.set_transform(side.get_transform())
        self.set_in_layout(False)
        self._axis, self._locator = axis, locator
        self._across = float(np.asarray(side.get_xdata() if axis.axis_name == "y" else side.get_ydata(), float)[0])

    @property
    def axis(self) -> XAxis | YAxis:
        return self._axis

    def locations(self) -> np.ndarray:
        """The minor ticks matplotlib would draw: the locator's, less those on a major tick
        (``Axis.get_minorticklocs``) and those outside the view (``Axis._update_ticks``)."""
        axis = self._axis
        minor = np.asarray(self._locator(), float)
        if minor.size == 0:
            return minor
        scale = axis.get_transform()  # the scale's (``Axis.get_minorticklocs``)
        if axis.remove_overlapping_locs:
            major = scale.transform(np.asarray(axis.get_major_locator()(), float))
            lo, hi = sorted(scale.transform(axis.get_view_interval()))
            near = np.isclose(scale.transform(minor)[:, None], major[None, :], atol=(hi - lo) * OVERLAP, rtol=0)
            minor = minor[~near.any(axis=1)]
        transform = axis.get_transform()
        lo, hi = sorted(transform.transform(sorted(axis.get_view_interval())))
        slack = (hi - lo) * INSIDE
        at = transform.transform(minor)
        return minor[(lo - slack <= at) & (at <= hi + slack)]

    def draw(self, renderer) -> None:
        locations = self.locations()
        across = np.full(locations.size, self._across)
        self.set_data(*((across, locations) if self._axis.axis_name == "y" else (locations, across)))
        super().draw(renderer)


def _unlabelled(axis: XAxis | YAxis) -> bool:
    """Whether the axis's minor ticks show nothing but their marks (no label, no grid line). A log axis's
    formatter labels its minor ticks only when the view spans less than about a decade: a choice made
    from the view, which the layout does not change."""
    if isinstance(axis.get_minor_locator(), NullLocator):
        return False
    tick = axis.get_minor_ticks(1)[0]
    if tick.gridline.get_visible():
        return False
    return not any(axis.get_minor_formatter().format_ticks(list(axis.get_minorticklocs())))


def mark_minor_ticks(fig: Figure) -> None:
    """Draw the unlabelled minor ticks of every 2-D axis of ``fig`` as ``MinorTickMarks`` (module
    docstring); call it once everything is plotted, before saving."""
    for ax in fig.axes:
        if ax.name != "rectilinear":
            continue
        for axis in (ax.xaxis, ax.yaxis):
            if not _unlabelled(axis):
                continue
            locator = axis.get_minor_locator()
            tick = axis.get_minor_ticks(1)[0]
            for side in (tick.tick1line, tick.tick2line):
                if side.get_visible():
                    ax.add_artist(MinorTickMarks(axis, locator, side)).set_clip_on(False)
            axis.set_minor_locator(NullLocator())
