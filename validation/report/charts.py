"""A case page's charts, drawn by the reader's browser with plotly.js from the numbers embedded in the page.

Drawing a case's charts with matplotlib in the report (tick and text layout, the PNG encoder) would
be most of the report's time; here the report only writes each chart's numbers (7 significant
digits) as a plotly.js figure (``data`` traces, ``layout``) and the browser draws it. The plotting library
is plotly.js, the bundle the ``plotly`` pip package ships (``plotly/package_data/plotly.min.js``),
copied once into the report's ``js/`` folder (``install_plotly``); the Python side of ``plotly`` is not
imported.

Three charts, each as wide as the page (never wider: the page does not scroll sideways), its legend
beside or above the plot area (never on it), every axis a quantity in words with its unit
(``axis_title``: 'x displacement at P [in]', 'input angle θ2 [deg]', 'joint torque T_j [lbf·in]'):

- ``outputs_chart``: a panel per output (quantity at a point), its value (in the case's unit) against
  the case's driving load (in its unit, else the load level index); a line per method (a colour and a
  dash each) and hollow markers per printed column of the source, named by what was printed and where
  ('printed: ANSYS [bapat2015 Table 9.4]'; another method's value compared with is no printed column);
  one legend, an entry per method and per printed column, a click on an entry hiding that method in
  every panel. An output that is one number of the whole case (``Quantity.per_level`` False: a
  mechanism's degrees of freedom, a limit load) gets no panel: a point on the load axis would place it
  at a load it does not belong to (the page's tables give it);
- ``shapes_chart``: the deformed shapes, one load level at a time on a slider (a last step draws them
  all, the earlier lighter), a line per method, measured points as markers at their level, x and y in
  the case's length unit on equal scales;
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
from validation.report.summary import METHOD_NAMES

PLOTLY_JS = "js/plotly.min.js"  # under the report folder
METHOD_STYLE = {
    "fem": ("#1f77b4", "solid"),
    "prbm": ("#ff7f0e", "dash"),
    "elastica": ("#2ca02c", "dot"),
    "bcm": ("#9467bd", "dashdot"),
}
REF_MARKER = {
    "PRBM": "square-open",
    "ANSYS": "triangle-up-open",
    "elliptic": "diamond-open",
    "measured": "circle-open",
    "exact": "star-open",
    "BCM": "triangle-down-open",
    "chain": "cross-open",
    "published": "x-open",
}
PANEL_WIDTH, PANEL_HEIGHT = 420, 300  # pixels of one output's panel (its width: at most, the page decides)
SHAPES_WIDTH = 760  # pixels, at most, of the deformed-shapes chart
FONT = {"size": 11}
# what an axis says of each quantity (``QUANTITIES``' names are the case files' words, not a reader's)
AXIS_NAMES = {
    "x": "x position",
    "y": "y position",
    "dx": "x displacement",
    "dy": "y displacement",
    "rotation": "rotation θ",
    "force_x": "force Fx",
    "force_y": "force Fy",
    "moment": "moment M",
    "reaction_x": "reaction Rx",
    "reaction_y": "reaction Ry",
    "reaction_moment": "reaction moment",
    "input_angle": "input angle θ2",
    "input_torque": "input torque T",
    "strain_energy": "strain energy U",
    "mechanical_advantage": "mechanical advantage",
    "dof": "degrees of freedom",
    "prb_angle": "PRB angle Θ",
    "limit_load": "limit load",
    "max_stress": "largest bending stress σ",
    "inflection_points": "inflection points",
}
# printed rows that are another method's value (an agreement between methods, the FEM against the exact
# elastica): no number of the source, so no 'printed' marker
METHOD_CHECKS = ("agreement", "fem-elastica")
TITLE_CHARACTERS = 58  # an axis title longer than this wraps at a space (a panel is about 400 pixels wide)
UNIT_TEXT = str.maketrans({"*": "·"})
POWERS = {"^2": "²", "^3": "³", "^4": "⁴", "^-1": "⁻¹"}


# '<', '>', '&' (and the two line separators JavaScript once read as line ends) as JSON escapes: a string of
# the case file can then neither close the <script> element ('</script>'), open a comment ('<!--') nor
# be read as markup, whatever it holds; the browser's JSON reading gives the same string back
SCRIPT_SAFE = str.maketrans({"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028", "\u2029": "\\u2029"})


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
    """One chart of a page: its element id, plotly.js ``data`` and ``layout``, its height and the widest it
    is drawn (pixels; None: the page's width). Its width is the page's (``autosize``), never more: a chart
    never makes the page scroll sideways."""

    id: str
    data: list[dict]
    layout: dict
    height: int
    max_width: int | None = None

    def html(self) -> str:
        """The chart's element and the script that draws it (plotly.js loaded by the page)."""
        spec = script_json({"data": self.data, "layout": self.layout})  # the id is the report's own word
        width = f"max-width:{self.max_width}px;" if self.max_width else ""
        return (
            f"<div id='{self.id}' class='chart' style='{width}height:{self.height}px'></div><script>"
            f"(function(){{const f={spec};Plotly.newPlot('{self.id}',f.data,f.layout,"
            "{responsive:true,displaylogo:false});})();</script>"
        )


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


def unit_text(unit: str) -> str:
    """A unit as a reader writes it: 'lbf*in' as 'lbf·in', 'EI/L^2' as 'EI/L²'; no unit (a ratio) as '-'."""
    text = str(unit or "").translate(UNIT_TEXT)
    for power, superscript in POWERS.items():
        text = text.replace(power, superscript)
    return text if text not in ("", "1") else "-"


def axis_title(name: str, unit: str) -> str:
    """``name [unit]`` (``unit_text``), wrapped at a space (``<br>``) when longer than ``TITLE_CHARACTERS``;
    escaped for plotly.js (``plotly_text``) line by line."""
    for power, superscript in POWERS.items():
        name = name.replace(power, superscript)
    words, lines = f"{name} [{unit_text(unit)}]".split(" "), [""]
    for word in words:
        if lines[-1] and len(lines[-1]) + 1 + len(word) > TITLE_CHARACTERS:
            lines.append(word)
        else:
            lines[-1] = f"{lines[-1]} {word}" if lines[-1] else word
    return "<br>".join(plotly_text(line) for line in lines)


def quantity_name(quantity: str, point: str = "") -> str:
    """An output in words: 'x displacement at P', 'input angle θ2' (``AXIS_NAMES``)."""
    name = AXIS_NAMES.get(quantity, quantity.replace("_", " "))
    return f"{name} at {point}" if point else name


def _axis(title: str, **extra) -> dict:
    """An axis titled ``title`` (already escaped and wrapped: `axis_title`); its margin grows to hold the
    title and the tick labels (``automargin``)."""
    return {
        "title": {"text": title, "font": FONT, "standoff": 6},
        "tickfont": {"size": 10},
        "zeroline": False,
        "showline": True,
        "linecolor": "#444",
        "mirror": True,
        "gridcolor": "#e4e4e4",
        "automargin": True,
        **extra,
    }


def _layout(height: int, **extra) -> dict:
    """A figure as wide as its element (``autosize``), its legend outside the plot area: on the right of
    it (``x`` past 1), where the figure's margin grows to hold it."""
    return {
        "height": height,
        "autosize": True,
        "margin": {"l": 70, "r": 20, "t": 30, "b": 55},
        "font": FONT,
        "plot_bgcolor": "white",
        "legend": {
            "font": {"size": 11},
            "x": 1.02,
            "xanchor": "left",
            "y": 1,
            "yanchor": "top",
            "bgcolor": "rgba(0,0,0,0)",
        },
        **extra,
    }


def _grid_layout(titles: list[tuple[str, str]], ncols: int, height: int) -> dict:
    """Independent axes for ``len(titles)`` panels in rows of ``ncols``, each with its (x, y) titles; the
    legend in one row above the panels (clear of the first row's frame: the figure's top margin grows to
    hold it)."""
    nrows = -(-len(titles) // ncols)
    layout = _layout(
        height,
        grid={
            "rows": nrows,
            "columns": ncols,
            "pattern": "independent",
            "xgap": 0.25,
            "ygap": 0.3 if nrows > 1 else 0.2,
        },
        legend={
            "orientation": "h",
            "y": 1 + 12 / (PANEL_HEIGHT * nrows),
            "yanchor": "bottom",
            "x": 0,
            "xanchor": "left",
            "font": {"size": 11},
            "bgcolor": "rgba(0,0,0,0)",
        },
    )
    for k, (xtitle, ytitle) in enumerate(titles):
        suffix = "" if k == 0 else str(k + 1)
        layout[f"xaxis{suffix}"] = _axis(xtitle)
        layout[f"yaxis{suffix}"] = _axis(ytitle)
    return layout


def _trace(x, y, name: str, panel: int, shown: set[str], **style) -> dict:
    """A trace in panel ``panel`` (0-based), in the legend group ``name`` (listed once)."""
    suffix = "" if panel == 0 else str(panel + 1)
    trace = {
        "type": "scatter",
        "x": numbers(x),
        "y": numbers(y),
        "name": plotly_text(name),
        "legendgroup": name,
        "showlegend": name not in shown,
        "xaxis": f"x{suffix}",
        "yaxis": f"y{suffix}",
        **style,
    }
    shown.add(name)
    return trace


OUTPUT_COLUMNS = [
    "quantity",
    "point",
    "method",
    "level",
    "value",
    "reference_label",
    "reference_value",
    "unit",
    "check",
]


@dataclass
class Panel:
    """One output's numbers: each method's (level, value) and each printed column's (level, value), in
    the table's order, first of each level; its unit."""

    unit: str
    methods: dict[str, dict[int, float]]
    printed: dict[str, list[tuple[int, float]]]


def _panels(table: pd.DataFrame) -> dict[tuple[str, str], Panel]:
    """The table's outputs (quantity, point) that follow the load levels (``Quantity.per_level``), in order
    of first appearance, each as a ``Panel``; a printed column is a number of the source (a row compared
    with another method, ``METHOD_CHECKS``, is none)."""
    panels: dict[tuple[str, str], Panel] = {}
    seen: set[tuple] = set()
    for quantity, point, method, level, value, label, printed, unit, check in table.reindex(columns=OUTPUT_COLUMNS)[
        OUTPUT_COLUMNS
    ].itertuples(index=False, name=None):
        if pd.isna(quantity) or not QUANTITIES[quantity].per_level:
            continue
        panel = panels.setdefault((quantity, point), Panel(unit, {}, {}))
        panel.methods.setdefault(method, {}).setdefault(int(level), value)
        if pd.isna(printed) or pd.isna(label) or check in METHOD_CHECKS:
            continue
        if (quantity, point, label, level, printed) not in seen:
            seen.add((quantity, point, label, level, printed))
            panel.printed.setdefault(label, []).append((int(level), printed))
    return panels


def printed_name(label: str, sources: dict[str, str]) -> str:
    """A printed column's legend entry: what was printed and by whom, 'printed: ANSYS [bapat2015 Table 9.3]'
    (``sources``: each label's source, where known)."""
    return f"printed: {label}" + (f" [{sources[label]}]" if sources.get(label) else "")


def outputs_chart(
    chart_id: str, axis: np.ndarray, axis_label: str, table: pd.DataFrame, sources: dict[str, str] | None = None
) -> Chart | None:
    """A panel per output, every method as a line (its colour and dash) and every printed column as
    markers named by `printed_name` (module docstring); ``axis`` is the x value of each level and
    ``axis_label`` its title (`axis_title`). None when the table has no output."""
    panels = _panels(table)
    if not panels:
        return None
    ncols = min(3, len(panels))
    nrows = -(-len(panels) // ncols)
    data: list[dict] = []
    titles: list[tuple[str, str]] = []
    shown: set[str] = set()
    for index, ((quantity, point), panel) in enumerate(panels.items()):
        for method in sorted(panel.methods):
            levels = sorted(panel.methods[method])
            color, dash = METHOD_STYLE.get(method, ("#000000", "solid"))
            data.append(
                _trace(
                    axis[levels],
                    [panel.methods[method][k] for k in levels],
                    method_name(method),
                    index,
                    shown,
                    mode="lines+markers",
                    line={"color": color, "dash": dash, "width": 2},
                    marker={"size": 4},
                )
            )
        for label in sorted(panel.printed):
            printed_levels, values = zip(*panel.printed[label])
            data.append(
                _trace(
                    axis[list(printed_levels)],
                    values,
                    printed_name(label, sources or {}),
                    index,
                    shown,
                    mode="markers",
                    marker={"symbol": REF_MARKER.get(label, "x-open"), "size": 8, "color": "black"},
                )
            )
        titles.append((axis_label, axis_title(quantity_name(quantity, point), panel.unit)))
    height = PANEL_HEIGHT * nrows + 90
    return Chart(chart_id, data, _grid_layout(titles, ncols, height), height, max_width=PANEL_WIDTH * ncols + 90)


def method_name(method: str) -> str:
    """A method as the page names it (``METHOD_NAMES``: 'FEM', 'exact elastica')."""
    return METHOD_NAMES.get(method, method)


@dataclass(frozen=True)
class ShapeLine:
    """One method's deformed shape at one step of the chart's slider (a load level, or a frame of a
    continuation): its polylines joined with gaps, as x and y arrays."""

    method: str
    step: int
    x: np.ndarray
    y: np.ndarray


def _padded(values: list[np.ndarray]) -> list[float | None]:
    """The range of ``values`` (NaN skipped) widened by 5 % each side (a point range by 1)."""
    finite = np.concatenate([v[np.isfinite(v)] for v in values] + [np.zeros(0)])
    if not len(finite):
        return [-1.0, 1.0]
    low, high = float(finite.min()), float(finite.max())
    pad = 0.05 * (high - low) or 0.05 * max(abs(low), 1.0)
    return numbers([low - pad, high + pad])


def _slider(steps: list[str], visible: list[list[bool]], opacity: list[list[float]], active: int, prefix: str) -> dict:
    """A plotly.js slider over ``steps``: each step shows its traces (``visible``, ``opacity``: one list a
    step, an entry a trace); the step labels hidden where there are too many to read (the current one is
    said above the slider)."""
    crowded = len(steps) > 12
    return {
        "active": active,
        "currentvalue": {"prefix": plotly_text(prefix), "font": {"size": 12}},
        "pad": {"t": 45, "b": 10},
        "len": 1.0,
        "x": 0,
        "y": 0,
        "yanchor": "top",
        "font": {"size": 10, "color": "rgba(0,0,0,0)" if crowded else "#444"},
        "steps": [
            {"label": plotly_text(label), "method": "restyle", "args": [{"visible": shown, "opacity": alpha}]}
            for label, shown, alpha in zip(steps, visible, opacity)
        ],
    }


def shapes_chart(
    chart_id: str,
    lines: list[ShapeLine],
    measured: list[tuple[int, float, float]],
    length_unit: str,
    steps: list[str],
    prefix: str = "load level: ",
    first: int = -1,
) -> Chart | None:
    """Deformed shapes on equal x and y scales, one step of a slider at a time (``steps``: each step's
    label; ``first``: the step first shown, else the last; a last step 'all' draws every step, lighter the
    earlier):
    each method in its colour and dash (a legend entry each), the measured points (``measured``: step,
    x, y) as markers. The axes' ranges hold every step, so the slider never rescales them."""
    if not lines:
        return None
    methods = list(dict.fromkeys(line.method for line in lines))
    legend = [
        {
            "type": "scatter",
            "x": [None],
            "y": [None],
            "mode": "lines",
            "name": plotly_text(method_name(m)),
            "legendgroup": m,
            "line": {
                "color": METHOD_STYLE.get(m, ("#000000",))[0],
                "dash": METHOD_STYLE.get(m, ("", "solid"))[1],
                "width": 2,
            },
        }
        for m in methods
    ]
    if measured:
        legend.append(
            {
                "type": "scatter",
                "x": [None],
                "y": [None],
                "mode": "markers",
                "name": "measured",
                "legendgroup": "measured",
                "marker": {"symbol": "circle-open", "size": 8, "color": "black"},
            }
        )
    drawn = [
        (
            line.step,
            {
                "type": "scatter",
                "x": numbers(line.x),
                "y": numbers(line.y),
                "mode": "lines",
                "legendgroup": line.method,
                "showlegend": False,
                "hoverinfo": "skip",
                "line": {
                    "color": METHOD_STYLE.get(line.method, ("#000000",))[0],
                    "dash": METHOD_STYLE.get(line.method, ("", "solid"))[1],
                    "width": 1.8,
                },
            },
        )
        for line in lines
    ]
    drawn += [
        (
            step,
            {
                "type": "scatter",
                "x": numbers([x]),
                "y": numbers([y]),
                "mode": "markers",
                "showlegend": False,
                "legendgroup": "measured",
                "marker": {"symbol": "circle-open", "size": 8, "color": "black"},
            },
        )
        for step, x, y in measured
    ]
    used = sorted({step for step, _ in drawn})
    labels = [steps[k] for k in used] + ["all"]
    fixed = [True] * len(legend)
    visible = [fixed + [step == k for step, _ in drawn] for k in used] + [fixed + [True] * len(drawn)]
    fade = [0.25 + 0.75 * used.index(step) / max(len(used) - 1, 1) for step, _ in drawn]
    opacity = [[1.0] * (len(legend) + len(drawn))] * len(used) + [[1.0] * len(legend) + fade]
    active = used.index(first) if first in used else len(used) - 1
    data = legend + [dict(trace, visible=visible[active][len(legend) + i]) for i, (_, trace) in enumerate(drawn)]
    height = 520
    layout = _layout(
        height,
        margin={"l": 70, "r": 20, "t": 30, "b": 40},
        xaxis=_axis(axis_title("x", length_unit), range=_padded([line.x for line in lines])),
        yaxis=_axis(
            axis_title("y", length_unit), range=_padded([line.y for line in lines]), scaleanchor="x", scaleratio=1
        ),
        sliders=[_slider(labels, visible, opacity, active, prefix)],
    )
    return Chart(chart_id, data, layout, height, max_width=SHAPES_WIDTH)


def path_chart(chart_id: str, path: dict) -> Chart:
    """A FEM continuation's equilibrium path (load against its control displacement), limit points marked."""
    shown: set[str] = set()
    data = [
        _trace(
            path["displacement"],
            path["load"],
            "FEM path",
            0,
            shown,
            mode="lines",
            line={"color": METHOD_STYLE["fem"][0], "width": 2},
        )
    ]
    limits = list(path.get("limit_points", []))
    if limits:
        d, p = zip(*limits)
        data.append(
            _trace(
                d,
                p,
                "limit point",
                0,
                shown,
                mode="markers",
                marker={"symbol": "triangle-down", "size": 10, "color": "red"},
            )
        )
    height = 380
    layout = _layout(
        height,
        xaxis=_axis(_titled(path.get("displacement_label", "control displacement"))),
        yaxis=_axis(_titled(path.get("load_label", "load"))),
    )
    return Chart(chart_id, data, layout, height, max_width=SHAPES_WIDTH)


def _titled(label: str) -> str:
    """A label of the form 'name [unit]' as an axis title (`axis_title`); without a unit, as it is."""
    name, bracket, unit = label.rpartition(" [")
    if bracket and unit.endswith("]"):
        return axis_title(name, unit[:-1])
    return plotly_text(label)
