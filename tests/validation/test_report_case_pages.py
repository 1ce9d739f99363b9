"""A case page that fits the window and says what it draws: every axis a quantity in words with its
unit, legends beside the data (never on it), load levels one at a time on a slider, markers only for
numbers a source printed (naming the source), the picture's colour bar over the field's real range,
and, in a real browser at 1366 x 900, no sideways scrolling, no legend on a plot, no 'NaN' shown."""

import re
from pathlib import Path

import numpy as np
import pytest

from tests.validation.test_report import window
from validation.case.loader import case_by_id, load_case
from validation.report import paraview
from validation.report.build import _output_chart, _path_chart, _shape_chart, build_report
from validation.report.charts import axis_title, unit_text
from validation.run.case_run import run_case
from validation.run.outcome import tabulate
from validation.sweep.plot import _at_value

pytestmark = pytest.mark.xdist_group("report")

# a user's own case: a segment and a force, no printed value (an agreement between two methods only)
USER_CASE = """
[case]
id = "user_beam"
title = "A user's cantilever"
group = "user"
units = "SI"
description = "A segment and a force; nothing printed."

[segment]
boundary = "fixed-free"
length = 0.1
E = 2.0e9
section = { kind = "rectangle", width = 0.01, thickness = 0.001 }

[[loads]]
kind = "force"
point = "tip"
direction = [0.0, 1.0]
ramp = { start = 0.1, stop = 1.0, count = 4 }

[[outputs]]
quantity = "y"
[[outputs]]
quantity = "rotation"

[methods.fem]
[methods.prbm]

[[agreements]]
method = "prbm"
against = "fem"
quantities = ["y"]
tolerance = { rel = 0.05 }
basis = "the user's own limit"
"""
SNAKE = re.compile(r"\b[a-z]+_[a-z_]+\b")  # a case file's name for a quantity ('input_angle'), not words


@pytest.fixture(scope="module")
def user_case(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("user") / "user_beam.toml"
    path.write_text(USER_CASE)
    return path


def _charts(loaded):
    result = run_case(loaded, use_cache=True)
    table = tabulate(result)
    return [c for c in (_path_chart(result), _shape_chart(result), _output_chart(result, table)) if c]


def _titles(chart) -> list[str]:
    return [axis["title"]["text"] for key, axis in chart.layout.items() if key.startswith(("xaxis", "yaxis"))]


def test_every_axis_says_its_quantity_in_words_with_its_unit():
    """Test 2 [bapat2015, Table 9.4]: the coupler point's displacements and the input angle against the
    design torque, in words with units; no case-file name (input_angle), no unit written twice."""
    charts = {c.id: c for c in _charts(case_by_id("bapat2015_test2"))}
    titles = _titles(charts["outputs"]) + _titles(charts["shapes"])
    assert titles and all(re.search(r"\[[^\]]+\]$", t) for t in titles), titles
    assert not [t for t in titles if SNAKE.search(t)], titles
    assert {"x displacement at P [in]", "input angle θ2 [deg]", "design input torque T_j [lbf·in]"} <= set(titles)
    names = [t["name"] for chart in charts.values() for t in chart.data if t.get("name")]
    assert not [n for n in names if SNAKE.search(n)], names


def test_units_and_long_titles_read_as_written_by_hand():
    assert unit_text("lbf*in") == "lbf·in" and unit_text("EI/L^2") == "EI/L²" and unit_text("1") == "-"
    long = axis_title("M_j at the beam end (printed M at Q 27.844, 58.678 cw, moved to E by eq. 173)", "lbf*in")
    assert long.count("<br>") == 1 and all(len(line) <= 60 for line in long.split("<br>"))
    assert axis_title("</script> & x", "N") == "&lt;/script&gt; &amp; x [N]"  # escaped for plotly.js


def test_legends_stand_beside_the_data():
    """Each chart's legend is outside its plot area: on the right (x past 1) or above it (y past 1,
    anchored at its bottom); a transparent box, so it covers no frame line."""
    for cid in ("cantilever_tip_load", "bapat2015_test2", "seed004_parallel_guided"):
        for chart in _charts(case_by_id(cid)):
            legend = chart.layout["legend"]
            beside = legend.get("x", 1.02) > 1 and legend.get("xanchor", "left") == "left"
            above = legend.get("y", 1) > 1 and legend.get("yanchor") == "bottom"
            assert beside or above, (cid, chart.id, legend)
            assert "width" not in chart.layout and chart.layout["autosize"], (cid, chart.id)  # as wide as the page


def test_load_levels_are_steps_of_a_slider_not_a_tangle():
    """Test 2's shapes: a step per load level (P0..P3) and one of them all; each step shows one level's
    shapes of every method, the last level first; every method a colour and a dash of its own."""
    case = case_by_id("bapat2015_test2")
    shapes = next(c for c in _charts(case) if c.id == "shapes")
    slider = shapes.layout["sliders"][0]
    steps = slider["steps"]
    assert [s["label"] for s in steps] == case.case.level_labels + ["all"]
    n = len(shapes.data)
    for step in steps:
        assert len(step["args"][0]["visible"]) == n and len(step["args"][0]["opacity"]) == n
    first = steps[slider["active"]]["args"][0]["visible"]
    assert slider["active"] == len(case.case.level_labels) - 1
    assert [t.get("visible", True) for t in shapes.data] == first
    levels_shown = [sum(step["args"][0]["visible"]) for step in steps[:-1]]
    assert max(levels_shown) < sum(steps[-1]["args"][0]["visible"])  # one level at a time, 'all' shows all
    styles = {t["name"]: (t["line"]["color"], t["line"]["dash"]) for t in shapes.data if t.get("name")}
    assert len(set(styles.values())) == len(styles) >= 3, styles


def test_markers_say_what_was_printed_and_by_whom(user_case):
    """A printed column names its source; another method's value (an agreement, the FEM against the
    exact elastica) is no printed marker; a user's case that prints nothing has none."""
    names = {t["name"] for c in _charts(case_by_id("bapat2015_test2")) for t in c.data if t.get("name")}
    printed = {n for n in names if n.startswith("printed")}
    assert {"printed: PRBM [bapat2015 Table 9.4]", "printed: measured [bapat2015 Table 9.4]"} <= printed
    assert not [n for n in printed if "elastica" in n or "fem" in n.lower()], printed
    names = {t.get("name") for c in _charts(load_case(user_case)) for t in c.data}
    assert not [n for n in names if n and "printed" in n], names


def test_the_colour_bar_spans_the_real_range():
    """Rounding noise at the unloaded end of a moment field (-1.12e-8 beside 22.9) is zero on the bar;
    a real negative moment is kept; a constant field still has a range."""
    assert paraview.colour_range([-1.12e-8, 3.0, 22.9]) == (0.0, 22.9)
    assert paraview.colour_range([-4.0, 0.5, 4.25]) == (-4.0, 4.25)
    low, high = paraview.colour_range([2.0, 2.0])
    assert low < 2.0 < high


def test_the_picture_fits_the_mechanism_in_its_free_part():
    """The camera puts what is drawn inside ``DRAWN`` (clear of the title, legend and colour bar)."""

    class Camera:
        pass

    camera, bounds = Camera(), (-1.0, 13.0, -2.0, 8.0)
    paraview.fit_camera(camera, bounds)
    width, height = paraview.CANVAS
    half_h = camera.parallel_scale
    half_w = half_h * width / height
    cx, cy, _ = camera.focal_point
    (x0, x1), (y0, y1) = paraview.DRAWN
    to_x = lambda x: (x - (cx - half_w)) / (2 * half_w)  # noqa: E731 - world x as a fraction of the width
    to_y = lambda y: (y - (cy - half_h)) / (2 * half_h)  # noqa: E731
    assert x0 <= to_x(bounds[0]) < to_x(bounds[1]) <= x1
    assert y0 <= to_y(bounds[2]) < to_y(bounds[3]) <= y1


def test_a_sweep_level_without_spread_is_drawn_at_its_value():
    """Level 0 of a Monte Carlo sweep (unloaded: every sample at 0 give or take 1e-16) gets an axis
    around 0 at the study's scale, not one 1e-16 wide; a real spread keeps its own limits."""
    limits = []
    _at_value(lambda lo, hi: limits.append((lo, hi)), np.array([1e-16, -2e-16, 0.0]), scale=0.8)
    assert limits == [(pytest.approx(-0.04), pytest.approx(0.04))]
    _at_value(lambda lo, hi: limits.append((lo, hi)), np.array([0.1, 0.2]), scale=0.8)
    assert len(limits) == 1


PAGE_CHECKS = """
const out = {width: document.documentElement.scrollWidth, window: window.innerWidth, overlaps: [],
             nan: /\\bnan\\b/i.test(document.body.innerText)};
document.querySelectorAll('div.chart').forEach(chart => {
  const plots = [...chart.querySelectorAll('.nsewdrag')].map(r => r.getBoundingClientRect());
  chart.querySelectorAll('.legend').forEach(l => { const a = l.getBoundingClientRect();
    plots.forEach(p => { if (Math.min(a.right, p.right) - Math.max(a.left, p.left) > 0.5 &&
                             Math.min(a.bottom, p.bottom) - Math.max(a.top, p.top) > 0.5) out.overlaps.push(chart.id); });
  });
});
return out;"""


def test_case_pages_fit_a_1366_pixel_window(tmp_path, user_case, chromium):
    """At 1366 x 900: no case page scrolls sideways (with every fold open), no legend lies on a plot
    area, and no 'NaN' is shown."""
    build_report(tmp_path, use_cache=True, jobs=1, cases=["cantilever_tip_load", "bapat2015_test2", str(user_case)])
    with window(chromium, 1366, 900) as browser:
        for cid in ("cantilever_tip_load", "bapat2015_test2", "user_beam"):
            browser.get((tmp_path / "cases" / f"{cid}.html").as_uri())
            browser.execute_script("document.querySelectorAll('details').forEach(d => d.open = true)")
            page = browser.execute_script(PAGE_CHECKS)
            assert page["width"] <= page["window"], (cid, page)
            assert page["overlaps"] == [] and not page["nan"], (cid, page)
