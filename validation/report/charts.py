"""A case page's charts, drawn by the reader's browser with plotly.js from the numbers embedded in the page.

Drawing a case's charts with matplotlib in the report (tick and text layout, the PNG encoder) would
be most of the report's time; here the report only writes each chart's numbers (7 significant
digits) as a plotly.js figure (``data`` traces, ``layout``) and the browser draws it. The plotting library
is plotly.js, the bundle the ``plotly`` pip package ships (``plotly/package_data/plotly.min.js``),
copied once into the report's ``js/`` folder (``install_plotly``); the Python side of ``plotly`` is not
imported.

Three charts:

- ``outputs_chart``: a panel per output (quantity at a point), its value (in the case's unit) against
  the case's first load (in its unit, else the load level index); a line per method and hollow
  markers per printed column of the source; one legend, an entry per method and per printed column,
  a click on an entry hiding that method in every panel. An output that is one number of the whole
  case (``Quantity.per_level`` False: a mechanism's degrees of freedom, a limit load) gets no panel: a
  point on the load axis would place it at a load it does not belong to (the page's tables give it);
- ``shapes_chart``: the deformed shapes of every level, a line per method (levels separated by gaps),
  measured tip points as markers, x and y in the case's length unit on equal scales;
- ``path_chart``: a FEM continuation's equilibrium path with its limit points.
"""
from __future__ import annotations

import html
import importlib.util
import json
import math
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from validation.case.capabilities import QUANTITIES

PLOTLY_JS = "js/plotly.min.js"   # under the report folder
METHOD_STYLE = {"fem": ("#1f77b4", "solid"), "prbm": ("#ff7f0e", "dash"), "elastica": ("#2ca02c", "dot"),
                "bcm": ("#9467bd", "dashdot")}
REF_MARKER = {"PRBM": "square-open", "ANSYS": "triangle-up-open", "elliptic": "diamond-open",
              "measured": "circle-open", "exact": "star-open", "BCM": "triangle-down-open",
              "chain": "cross-open", "published": "x-open"}
PANEL_WIDTH, PANEL_HEIGHT = 420, 300   # pixels of one output's panel
FONT = {"size": 11}


# '<', '>', '&' (and the two line separators JavaScript once read as line ends) as JSON escapes: a string of
# the case file can then neither close the <script> element ('</script>'), open a comment ('<!--') nor
# be read as markup, whatever it holds; the browser's JSON reading gives the same string back
SCRIPT_SAFE = str.maketrans({"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028",
                             "\u2029": "\\u2029"})


def plotly_text(text: str) -> str:
    """A label for plotly.js, which reads a few HTML tags in its text (<b>, <a href>, <br>): escaped, so
    that it shows a case file's string as written and never as markup."""
    return html.escape(text, quote=False)


def script_json(value) -> str:
    """``value`` as JSON that is safe inside an HTML <script> element (``SCRIPT_SAFE``)."""
    return json.dumps(value, separators=(",", ":"), allow_nan=False).translate(SCRIPT_SAFE)


class PlotlyMissing(RuntimeError):
    """The ``plotly`` package (whose plotly.js bundle draws the charts) is not installed."""


@dataclass(frozen=True)
class Chart:
    """One chart of a page: its element id, plotly.js ``data`` and ``layout``, and its height."""

    id: str
    data: list[dict]
    layout: dict
    height: int

    def html(self) -> str:
        """The chart's element and the script that draws it (plotly.js loaded by the page)."""
        spec = script_json({"data": self.data, "layout": self.layout})   # the id is the report's own word
        return (f"<div id='{self.id}' class='chart' style='height:{self.height}px'></div><script>"
                f"(function(){{const f={spec};Plotly.newPlot('{self.id}',f.data,f.layout,"
                "{responsive:true,displaylogo:false});})();</script>")


def plotly_bundle() -> Path:
    """The plotly.js bundle of the installed ``plotly`` package (the package is not imported)."""
    spec = importlib.util.find_spec("plotly")
    if spec is None or not spec.submodule_search_locations:
        raise PlotlyMissing("the report's charts need the 'plotly' package (pip install plotly)")
    bundle = Path(list(spec.submodule_search_locations)[0]) / "package_data" / "plotly.min.js"
    if not bundle.is_file():
        raise PlotlyMissing(f"the 'plotly' package has no plotly.js bundle at {bundle.name}")
    return bundle


def install_plotly(out: Path) -> Path:
    """Copy the plotly.js bundle to ``out/js/`` unless the same file is there; returns its path."""
    bundle, target = plotly_bundle(), out / PLOTLY_JS
    if not target.is_file() or target.stat().st_size != bundle.stat().st_size:
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(bundle, target)
    return target


def numbers(values) -> list[float | None]:
    """Values as JSON numbers of 7 significant digits; NaN and infinity as null (a gap in a line)."""
    return [float(f"{v:.7g}") if math.isfinite(v) else None for v in np.asarray(values, float).ravel()]


def _axis(title: str, **extra) -> dict:
    return {"title": {"text": plotly_text(title), "font": FONT}, "tickfont": {"size": 10}, "zeroline": False,
            "showline": True, "linecolor": "#444", "mirror": True, "gridcolor": "#e4e4e4", **extra}


def _layout(height: int, **extra) -> dict:
    return {"height": height, "margin": {"l": 70, "r": 20, "t": 30, "b": 55}, "font": FONT,
            "plot_bgcolor": "white", "legend": {"font": {"size": 11}}, **extra}


def _grid_layout(titles: list[tuple[str, str]], ncols: int, height: int) -> dict:
    """Independent axes for ``len(titles)`` panels in rows of ``ncols``, each with its (x, y) titles."""
    nrows = -(-len(titles) // ncols)
    layout = _layout(height, grid={"rows": nrows, "columns": ncols, "pattern": "independent",
                                   "xgap": 0.22, "ygap": 0.38 if nrows > 1 else 0.2},
                     legend={"orientation": "h", "y": 1.0, "yanchor": "bottom", "x": 0, "font": {"size": 11}})
    for k, (xtitle, ytitle) in enumerate(titles):
        suffix = "" if k == 0 else str(k + 1)
        layout[f"xaxis{suffix}"] = _axis(xtitle)
        layout[f"yaxis{suffix}"] = _axis(ytitle)
    return layout


def _trace(x, y, name: str, panel: int, shown: set[str], **style) -> dict:
    """A trace in panel ``panel`` (0-based), in the legend group ``name`` (listed once)."""
    suffix = "" if panel == 0 else str(panel + 1)
    trace = {"type": "scatter", "x": numbers(x), "y": numbers(y), "name": plotly_text(name), "legendgroup": name,
             "showlegend": name not in shown, "xaxis": f"x{suffix}", "yaxis": f"y{suffix}", **style}
    shown.add(name)
    return trace


OUTPUT_COLUMNS = ["quantity", "point", "method", "level", "value", "reference_label", "reference_value", "unit"]


@dataclass
class Panel:
    """One output's numbers: each method's (level, value) and each printed column's (level, value), in
    the table's order, first of each level; its unit."""

    unit: str
    methods: dict[str, dict[int, float]]
    printed: dict[str, list[tuple[int, float]]]


def _panels(table: pd.DataFrame) -> dict[tuple[str, str], Panel]:
    """The table's outputs (quantity, point) that follow the load levels (``Quantity.per_level``), in order
    of first appearance, each as a ``Panel``."""
    panels: dict[tuple[str, str], Panel] = {}
    seen: set[tuple] = set()
    for quantity, point, method, level, value, label, printed, unit in \
            table[OUTPUT_COLUMNS].itertuples(index=False, name=None):
        if pd.isna(quantity) or not QUANTITIES[quantity].per_level:
            continue
        panel = panels.setdefault((quantity, point), Panel(unit, {}, {}))
        panel.methods.setdefault(method, {}).setdefault(int(level), value)
        if not pd.isna(printed) and not pd.isna(label) and (quantity, point, label, level, printed) not in seen:
            seen.add((quantity, point, label, level, printed))
            panel.printed.setdefault(label, []).append((int(level), printed))
    return panels


def outputs_chart(chart_id: str, axis: np.ndarray, axis_label: str, table: pd.DataFrame) -> Chart | None:
    """A panel per output, every method as a line and every printed column as markers (module docstring);
    ``axis`` is the x value of each level. None when the table has no output."""
    panels = _panels(table)
    if not panels:
        return None
    ncols = min(3, len(panels))
    nrows = -(-len(panels) // ncols)
    data, titles, shown = [], [], set()
    for index, ((quantity, point), panel) in enumerate(panels.items()):
        for method in sorted(panel.methods):
            levels = sorted(panel.methods[method])
            color, dash = METHOD_STYLE.get(method, ("#000000", "solid"))
            data.append(_trace(axis[levels], [panel.methods[method][k] for k in levels], method, index, shown,
                               mode="lines+markers", line={"color": color, "dash": dash, "width": 2},
                               marker={"size": 4}))
        for label in sorted(panel.printed):
            levels, values = zip(*panel.printed[label])
            data.append(_trace(axis[list(levels)], values, f"printed {label}", index, shown, mode="markers",
                               marker={"symbol": REF_MARKER.get(label, "x-open"), "size": 8, "color": "black"}))
        titles.append((axis_label, f"{quantity}{'@' + point if point else ''} [{panel.unit}]"))
    height = PANEL_HEIGHT * nrows + 60
    layout = _grid_layout(titles, ncols, height)
    layout["width"] = PANEL_WIDTH * ncols + 90
    return Chart(chart_id, data, layout, height)


@dataclass(frozen=True)
class ShapeLine:
    """One method's deformed shapes: every level's polylines joined with gaps, as x and y arrays."""

    method: str
    x: np.ndarray
    y: np.ndarray


def shapes_chart(chart_id: str, lines: list[ShapeLine], measured: list[tuple[float, float]],
                 length_unit: str) -> Chart | None:
    """Deformed shapes, a line per method and the measured points, on equal x and y scales."""
    if not lines:
        return None
    shown: set[str] = set()
    data = []
    for line in lines:
        color, dash = METHOD_STYLE.get(line.method, ("#000000", "solid"))
        data.append(_trace(line.x, line.y, line.method, 0, shown, mode="lines",
                           line={"color": color, "dash": dash, "width": 1.5}))
    if measured:
        xs, ys = zip(*measured)
        data.append(_trace(xs, ys, "measured", 0, shown, mode="markers",
                           marker={"symbol": "circle-open", "size": 8, "color": "black"}))
    height = 460
    layout = _layout(height, width=620, xaxis=_axis(f"x [{length_unit}]"),
                     yaxis=_axis(f"y [{length_unit}]", scaleanchor="x", scaleratio=1))
    return Chart(chart_id, data, layout, height)


def path_chart(chart_id: str, path: dict) -> Chart:
    """A FEM continuation's equilibrium path (load against its control displacement), limit points marked."""
    shown: set[str] = set()
    data = [_trace(path["displacement"], path["load"], "FEM path", 0, shown, mode="lines",
                   line={"color": METHOD_STYLE["fem"][0], "width": 2})]
    limits = list(path.get("limit_points", []))
    if limits:
        d, p = zip(*limits)
        data.append(_trace(d, p, "limit point", 0, shown, mode="markers",
                           marker={"symbol": "triangle-down", "size": 10, "color": "red"}))
    height = 380
    layout = _layout(height, width=620, xaxis=_axis(path.get("displacement_label", "control displacement")),
                     yaxis=_axis(path.get("load_label", "load")))
    return Chart(chart_id, data, layout, height)
