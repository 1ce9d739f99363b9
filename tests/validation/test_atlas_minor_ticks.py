"""Minor ticks drawn as one line of tick marks (validation/atlas/minor_ticks.py) give the picture matplotlib
gives, pixel for pixel: a log-log plot with a log colour bar under the constrained layout (the atlas's maps
and scatter), a linear axis with minor ticks, an axis turned around; an axis whose minor ticks carry labels
(a log axis over less than a decade) keeps matplotlib's own ticks."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.ticker import AutoMinorLocator, NullLocator  # noqa: E402
from PIL import Image  # noqa: E402

from validation.atlas.minor_ticks import MinorTickMarks, mark_minor_ticks  # noqa: E402


def _map(fig, ax) -> None:
    """A small error map as ``map_figure.MapFigure`` draws one: log load axis, log colour bar, contours."""
    x, y = np.linspace(5.0, 175.0, 9), np.geomspace(0.04, 70.0, 25)
    z = np.outer(y, 1.0 + x / 50.0) / 3.0
    mesh = ax.pcolormesh(x, y, z, shading="nearest", norm=LogNorm(vmin=0.01, vmax=100.0))
    fig.colorbar(mesh, ax=ax).set_label("tip error (% of L)")
    ax.contour(x, y, z, levels=[0.5, 1.0, 3.0, 5.0])
    ax.set_yscale("log")
    ax.set(xlabel="load angle (deg)", ylabel="force", title="a map\nsecond line")


def _scatter(fig, ax) -> None:
    grid = np.geomspace(1e-3, 100.0, 50)
    ax.fill_between(grid, grid / 2, grid * 2, color="0.9")
    ax.scatter([0.01, 0.3, 4.0, 20.0], [0.02, 0.2, 5.0, 9.0], s=18)
    ax.set(xscale="log", yscale="log", xlim=(1e-3, 100.0), ylim=(1e-3, 100.0))


def _linear(fig, ax) -> None:
    ax.plot([0.0, 3.0, 1.0], [2.0, -1.0, 4.0])
    ax.xaxis.set_minor_locator(AutoMinorLocator())
    ax.yaxis.set_minor_locator(AutoMinorLocator())
    ax.invert_yaxis()


def _png(draw, marked: bool) -> np.ndarray:
    fig, ax = plt.subplots(figsize=(5.0, 3.6), layout="constrained")
    draw(fig, ax)
    if marked:
        mark_minor_ticks(fig)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    return np.asarray(Image.open(buffer))


@pytest.mark.parametrize("draw", [_map, _scatter, _linear])
def test_the_marks_are_matplotlib_s_minor_ticks_pixel_for_pixel(draw):
    plain, marked = _png(draw, marked=False), _png(draw, marked=True)
    assert plain.shape == marked.shape
    assert (plain == marked).all()


def test_the_marks_replace_the_unlabelled_minor_ticks_only():
    fig, ax = plt.subplots(layout="constrained")
    _map(fig, ax)
    labelled = fig.add_axes((0.1, 0.1, 0.2, 0.2))
    labelled.set(yscale="log", ylim=(2.0, 8.0))  # less than a decade: its minor ticks carry labels
    mark_minor_ticks(fig)
    bar = fig.axes[1]
    marks = [a for a in ax.get_children() + bar.get_children() if isinstance(a, MinorTickMarks)]
    marks = [m for m in marks if m.axis is ax.yaxis or m.axis is bar.yaxis]
    assert len(marks) == 2  # the map's load axis and its colour bar, one side each
    assert isinstance(ax.yaxis.get_minor_locator(), NullLocator)
    assert not isinstance(labelled.yaxis.get_minor_locator(), NullLocator)
    assert not any(isinstance(a, MinorTickMarks) for a in labelled.get_children())
    fig.canvas.draw()
    assert all(len(m.get_ydata()) > 10 for m in marks)  # placed when drawn, inside the view
    plt.close(fig)
