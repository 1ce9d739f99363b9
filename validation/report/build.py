"""Build the report an engineer reads: a summary page, a page per case, findings, reproducibility.

``prbm-validate report`` runs (or reuses the cached results of) every case and writes, under the
output folder: ``index.html`` and ``index.md`` (a headline, the picture of the whole validation from
``report_overview``, the per-chapter summary and the findings with their evidence from
``report_summary``, machine and versions), ``cases/<id>.html`` and ``.md`` (the one-sentence result,
charts drawn by the browser from the page's numbers (``charts``: plotly.js under ``js/``), findings, then
every output at every level for every method beside the printed values, folded),
``results.csv`` (and ``results.parquet``), ``summary.csv``, and the ParaView series of every method
under ``vtu/<id>/`` (``paraview``), rendered off-screen for the case page; ``timing.csv`` and
``timing.txt``: where the run's time went (``validation.run.timeline``), the CSV also ordering the next
report's cases longest first.

Those files are one output set (``validation.run.output_set``): the report is built beside the folder,
starting from the previous report's pages (a page whose case and code are unchanged is kept, not drawn
again), and put in place whole; the other commands' folders inside it (``latest/``, ``bench/``,
``stress/``, ``sweeps/<id>/``, ...) are carried over as they are. A report of which no case could run
writes nothing. The previous pages come in as hard links (copying and then deleting a report's
thousands of files costs seconds of disk time): a page drawn again first removes its files
(``_clear_page``) and the domain study its folder, so that nothing is written through a link into the
previous report.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import html
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import time
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass, field, replace
from functools import lru_cache
from importlib import metadata
from operator import itemgetter
from pathlib import Path
from typing import Callable, Sequence

import numpy as np
import pandas as pd

from validation.report import atlas_page, paraview
from validation.report.page import CSS, SORT_JS, _fmt, _html_table, _image, _link, _md_table, _page  # noqa: F401
from validation.sweep import domain_study
from validation.run import cache
from validation.run.exit_status import ExitStatus, print_error
from validation.run.output_set import OutputSet, is_leftover
from validation.report.paraview import normalise_shapes  # noqa: F401  (also used by tests)
from references import key_of_seed_file
from validation.case.loader import find_case_files
from validation.case.loads import driving_load, load_name, load_unit
from validation.case.readings import readings_groups
from validation.run.readings_rank import Status as RankStatus, rank_readings
from validation.report.charts import (
    PLOTLY_JS,
    Chart,
    PlotlyMissing,
    ShapeLine,
    axis_title,
    install_plotly,
    method_name,
    outputs_chart,
    path_chart,
    plotly_bundle,
    shapes_chart,
    unit_text,
)
from validation.report.format import by_case, rows_of, sig, verdict_html
from validation.report.overview import CLAIMS, OverviewPoint, case_points, overview_points, plot_overview
from validation.report.summary import (
    METHOD_NAMES,
    CaseSummary,
    Finding,
    case_sentence,
    findings,
    findings_html,
    group_order,
    key_terms,
    summarise,
    summary_markdown,
    summary_tables_html,
    verdict_counts_line,
)
from validation.run.compare import verdict_by_method
from validation.run.verdict import MethodVerdict, Verdict, counts_sentence, method_verdicts, vocabulary_lines
from validation.run.runner import CaseResult
from validation.run.outcome import (
    CASE_STRINGS,
    PrbmFemNumbers,
    reliable_estimates,
    run_cases,
    sorted_rows,
    summary,
    summary_row,
    tabulate,
)
from validation.run.timeline import Timed, breakdown, command_age, csv_text, timed

TIMING_CSV = "timing.csv"
DOMAINS = "sweeps/chapter4_domains"  # the chapter-4 domain study the whole report runs (``DomainStudy``)
# what the report writes in its folder (everything else there is another command's, carried over), and
# what it reuses of the previous report: the case pages (redrawn only when their digest changes), the
# ParaView series they link to, the plotly.js bundle, the domain study, the atlas page's pictures (``atlas_page``:
# redrawn only when the atlas changes; the atlas datasets under ``atlas/`` are ``prbm-validate atlas``'s, carried)
OWNED = (
    "index.html",
    "index.md",
    "overview.png",
    "overview.svg",
    "results.csv",
    "results.parquet",
    "summary.csv",
    TIMING_CSV,
    "timing.txt",
    "cases",
    "vtu",
    "js",
    DOMAINS,
    "atlas.html",
    "atlas_figures",
)
REUSED = ("cases", "vtu", "js", DOMAINS, "atlas_figures")
LINKED = ("cases", "vtu", DOMAINS, "atlas_figures")  # reused as hard links: removed, never written through
DEPENDENCIES = [
    "numpy",
    "scipy",
    "scikit-fem",
    "meshio",
    "pyvista",
    "pandas",
    "matplotlib",
    "plotly",
    "pydantic",
    "tqdm",
    "openseespy",
    "pyarrow",
]


def reproducibility() -> dict[str, str]:
    info = {
        "date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "python": sys.version.split()[0],
        "platform": platform.platform(),
    }
    cpu = platform.processor()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    info["processor"] = cpu or "unknown"
    try:
        info["git commit"] = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
            cwd=Path(__file__).parent,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        info["git commit"] = "unknown"
    for name in DEPENDENCIES:
        try:
            info[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            info[name] = "not installed"
    info["command"] = "prbm-validate report"
    return info


UNIT_IN_NAME = re.compile(r"\s*\((?:in-lb|lb-in|lbf?|in|deg|rad|N|mm|m|N\*?mm|N\*?m)\)\s*$")


def _level_axis(result: CaseResult) -> tuple[np.ndarray, str]:
    """The x value of each level, the driving load's (`driving_load`: the first that changes), and its axis
    title (`axis_title`: its name with a unit written in it, '(in-lb)', given once as the unit)."""
    case = result.loaded.case
    index = driving_load(case)
    if index is None:
        return np.arange(case.n_levels(), dtype=float), axis_title("load level", "-")
    load = case.loads[index]
    name = UNIT_IN_NAME.sub("", load_name(load, index, case)) or load.kind
    return np.asarray(load.levels(), float), axis_title(name, load_unit(load, case))


def _output_chart(result: CaseResult, table: pd.DataFrame) -> Chart | None:
    """A panel per output (value against the driving load), every method a line, printed columns as
    markers saying what was printed and where (`_cited`)."""
    axis, label = _level_axis(result)
    sources: dict[str, list[str]] = {}
    for ref in result.loaded.case.references:
        where = _cited(ref.source)
        if where not in sources.setdefault(ref.label, []):
            sources[ref.label].append(where)
    cited = {label: "; ".join(places[:2]) + ("; ..." if len(places) > 2 else "") for label, places in sources.items()}
    return outputs_chart("outputs", axis, label, table, cited)


def _cited(source) -> str:
    """Where a printed number is, short: the document's key ('bapat2015', else the file) and its table
    ('Table 9.4'), else its section ('§2.1')."""
    try:
        document = key_of_seed_file(source.file)
    except ValueError:
        document = source.file
    if source.table and source.table[0].isdigit():
        return f"{document} Table {source.table}"
    if source.section or source.table:
        return f"{document} §{source.section}" if source.section else f"{document} {source.table}"
    return document


def _joined(polylines: list[np.ndarray]) -> np.ndarray:
    """Polylines as one (n, 2) array with a NaN row between them: one line to draw instead of many."""
    parts = [np.vstack([line[:, :2], [[np.nan, np.nan]]]) for line in polylines if line.size]
    return np.concatenate(parts) if parts else np.zeros((0, 2))


def _shape_chart(result: CaseResult) -> Chart | None:
    """Deformed shapes, a load level at a time on a slider: each method's shape at each level (a
    continuation's steps thinned as its ParaView series, each a step of its own), measured points as
    markers at their level."""
    shapes = {m: normalise_shapes(r.extras["shapes"]) for m, r in result.runs.items() if r.extras.get("shapes")}
    if not shapes:
        return None
    case = result.loaded.case
    axis, title = _level_axis(result)
    steps = case.level_labels or [sig(v, 4) for v in axis]
    prefix = "load level: " if case.level_labels else title.replace("<br>", " ") + " = "
    lines = []
    for method, per_level in shapes.items():
        fields = result.runs[method].extras.get("fields")
        own = len(per_level) != case.n_levels()  # a continuation: its own steps, by load factor
        load = (
            fields.load_factor
            if fields is not None and len(fields.load_factor) == len(per_level)
            else np.arange(len(per_level), dtype=float)
        )
        for k in paraview.frames_shown(load):
            if own:
                steps.append(f"{method_name(method)} path, load factor {sig(load[k], 3)}")
            points = _joined([np.asarray(line) for line in per_level[k]])
            if len(points):
                lines.append(ShapeLine(method, len(steps) - 1 if own else k, points[:, 0], points[:, 1]))
    measured: dict[tuple[str, int], dict[str, float]] = {}
    for ref in case.references:
        if ref.label == "measured" and ref.quantity in ("x", "y"):
            measured.setdefault((ref.point, ref.level), {})[ref.quantity] = ref.value
    measured_points = [(level, v["x"], v["y"]) for (_, level), v in measured.items() if "x" in v and "y" in v]
    return shapes_chart("shapes", lines, measured_points, case.unit("length"), steps, prefix, first=case.n_levels() - 1)


def _path_chart(result: CaseResult) -> Chart | None:
    """Equilibrium path of a continuation run, limit points marked."""
    run = result.runs.get("fem")
    path = run.extras.get("path") if run else None
    return path_chart("path", path) if path else None


def _first_by(rows: list[tuple], key, column: int, value: int) -> dict[tuple, dict[str, float]]:
    """The first ``value`` of each (key, ``column``) pair of ``rows`` (``column`` not NA), by key."""
    out: dict[tuple, dict[str, float]] = {}
    for row in rows:
        label = row[column]
        if not pd.isna(label):
            out.setdefault(key(row), {}).setdefault(label, row[value])
    return out


def _labels(by_key: dict[tuple, dict[str, float]]) -> list[str]:
    """The labels (sorted) with at least one number over the keys (``pivot_table``'s columns)."""
    return sorted(
        {
            label
            for part in by_key.values()
            for label in part
            if not all(pd.isna(p.get(label, np.nan)) for p in by_key.values())
        }
    )


def _spread(
    by_key: dict[tuple, dict[str, float]], keys: list[tuple], labels: list[str], prefix: str = ""
) -> dict[str, np.ndarray]:
    """A column per label (``prefix`` before each name), each over ``keys`` (NaN where a key has no value
    under the label): ``pivot_table``'s columns, left-joined on ``keys``."""
    return {prefix + c: np.array([by_key.get(k, {}).get(c, np.nan) for k in keys], float) for c in labels}


GLANCE_KEY = ["quantity", "point", "level"]
GLANCE_COLUMNS = GLANCE_KEY + [
    "method",
    "value",
    "reference_label",
    "reference_value",
    "error_estimate",
    "level_label",
    "unit",
]


UNRELIABLE = "unreliable"


def unreliable_estimates(table: pd.DataFrame) -> list[bool]:
    """Per row, whether its error estimate is marked unreliable (not ``outcome.reliable_estimates``)."""
    return [not reliable for reliable in reliable_estimates(table)]


def marked_estimates(table: pd.DataFrame) -> pd.DataFrame:
    """The table with each error estimate marked unreliable (``unreliable_estimates``) shown as the word
    ``UNRELIABLE`` instead of its number."""
    marked = unreliable_estimates(table)
    if not any(marked):
        return table
    out = table.copy()
    out["error_estimate"] = out["error_estimate"].astype(object).mask(np.array(marked), UNRELIABLE)
    return out


def glance(table: pd.DataFrame) -> pd.DataFrame:
    """Every output at every level in one row: each method's value, each printed column, and the
    differences an engineer asks about first (PRBM - FEM, each model - measured, FEM - exact)."""
    if table.empty or table["quantity"].isna().all():
        return pd.DataFrame()
    columns = [table[c].tolist() for c in GLANCE_COLUMNS]
    estimate = GLANCE_COLUMNS.index("error_estimate")
    columns[estimate] = [UNRELIABLE if bad else e for e, bad in zip(columns[estimate], unreliable_estimates(table))]
    rows = [row for row in zip(*columns) if not pd.isna(row[0])]
    key = itemgetter(0, 1, 2)
    values, printed = _first_by(rows, key, 3, 4), _first_by(rows, key, 5, 6)
    # a row per output with a method's value (sorted), one frame built at once (no index to join on)
    shown = _labels(values)
    keys = sorted(k for k, part in values.items() if any(not pd.isna(part.get(c, np.nan)) for c in shown))
    key_columns = {
        name: [k[i] for k in keys] if keys else pd.Series([], dtype=object)  # as an empty index
        for i, name in enumerate(GLANCE_KEY)
    }
    numbers = _spread(values, keys, shown) | _spread(printed, keys, _labels(printed), "printed ")
    fem_est: dict[tuple, object] = {}  # a float, or UNRELIABLE
    for row in rows:
        if row[3] == "fem":
            fem_est.setdefault(key(row), row[7])
    estimates = {"fem ± (estimate)": [fem_est.get(k, np.nan) for k in keys]} if fem_est else {}  # or UNRELIABLE
    out = pd.DataFrame(key_columns | numbers | estimates | _differences(numbers))
    labels: dict[tuple, str] = {}
    units: dict[str, str] = {}
    for row in rows:
        labels.setdefault(key(row), row[8])
        units.setdefault(row[0], row[9])
    out.insert(3, "load", [labels.get(k, k[2]) for k in zip(out["quantity"], out["point"], out["level"])])
    out.insert(1, "unit", out["quantity"].map(units))
    return out.drop(columns=["level"])


def _differences(numbers: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The differences an engineer asks about first, where both sides are columns of ``numbers`` (each
    method's values, and each printed column as 'printed <label>'): PRBM - FEM, each model - measured,
    FEM - exact."""
    pairs = [
        ("PRBM - FEM", "prbm", "fem"),
        ("PRBM - measured", "prbm", "printed measured"),
        ("FEM - measured", "fem", "printed measured"),
        ("FEM - exact", "fem", "elastica"),
    ]
    return {name: numbers[left] - numbers[right] for name, left, right in pairs if {left, right} <= numbers.keys()}


def _case_files(result: CaseResult, out: Path) -> tuple[list[str], str | None]:
    """The ParaView series of the case under ``vtu/<id>/`` and their off-screen rendering (or None)."""
    cid = result.loaded.id
    series = paraview.case_series(result.loaded.case, result.runs)
    pvds = paraview.write_case_series(result.loaded.case, result.runs, out / "vtu" / cid, series)
    labels = result.loaded.case.level_labels
    title = f"{cid}: last load level" + (f" ({labels[-1]})" if labels else "")
    render = (
        paraview.render_series(
            series, out / "cases" / f"{cid}_render.png", title, unit_text(result.loaded.case.unit("moment"))
        )
        if series
        else None
    )
    return [str(p.relative_to(out)) for p in pvds], render.name if render else None


def _prb_model(result: CaseResult) -> tuple[pd.DataFrame | None, str | None]:
    """The PRBM adapter's record of the model it built for each beam (mechanisms without hand-given
    links): beam, model, how its ends are held, pivots, springs, gamma, K_Theta and why."""
    run = result.runs.get("prbm")
    if run is None or not run.extras.get("prb_model"):
        return None, None
    rows = [
        {
            "beam": b["beam"],
            "model": b["model"],
            "ends": "-".join(b["ends"]),
            "pivots": "; ".join(f"({x:.4g}, {y:.4g})" for x, y in b["pivots"]),
            "springs": "; ".join(f"{k:.4g}" for k in b["springs"]),
            "gamma": b["gamma"],
            "K_theta": b["K_theta"],
            "why": b["reason"],
        }
        for b in run.extras["prb_model"]
    ]
    return pd.DataFrame(rows), run.extras.get("lock")


def _with_model_range(cols: dict[str, str], table: pd.DataFrame) -> dict[str, str]:
    """The shown columns with, where any row has one, the flag of a value whose model was not made for its
    load (outside the fits' range or the atlas's validity, an inflection the model cannot take), and the
    PRBM error atlas's expected tip error after the unit (the PRBM's rows; NaN for the other methods)."""
    if "applicability" in table and table["applicability"].fillna("").ne("").any():
        cols = {**cols, "applicability": "outside the model's range"}
    if "expected_error" not in table or not pd.to_numeric(table["expected_error"], errors="coerce").notna().any():
        return cols
    items = list(cols.items())
    at = list(cols).index("unit") + 1
    return dict(items[:at] + [("expected_error", "atlas expected error (% of L)")] + items[at:])


# a case page fits the window's width: a chart is as wide as the page (at most its own width), a wide table
# scrolls inside its fold, a picture shrinks to the page
CASE_CSS = "div.chart{width:100%}details{max-width:100%;overflow-x:auto}img{max-width:100%;height:auto}"


@dataclass(frozen=True)
class DrawnPage:
    """What drawing a case page worked out that the index uses too: its one-sentence result
    (`case_sentence`), its link, its methods' verdicts (`method_verdicts`) and its findings (`findings`)."""

    sentence: str
    link: str
    verdicts: dict[str, MethodVerdict]
    findings: tuple[Finding, ...]


def _case_page(result: CaseResult, table: pd.DataFrame, out: Path) -> DrawnPage:
    """Write the case's page (html and md); returns what the index takes from it (``DrawnPage``) rather
    than working it out again."""
    case = result.loaded.case
    cid = case.case.id
    folder = out / "cases"
    charts = [c for c in (_path_chart(result), _shape_chart(result), _output_chart(result, table)) if c]
    pvds, render = _case_files(result, out)
    images = [render] if render else []
    cols = {
        "method": "method",
        "quantity": "quantity",
        "point": "point",
        "level_label": "load level",
        "value": "value",
        "unit": "unit",
        "verdict": "verdict",
        "error_estimate": "FEM error estimate",
        "reference_label": "printed column",
        "reference_value": "printed value",
        "abs_error": "absolute error",
        "rel_error": "relative error",
        "norm_error": "error / characteristic length",
        "within_tolerance": "within stated tolerance",
        "converged": "converged",
    }
    cols = _with_model_range(cols, table)
    listed = table["quantity"].notna()  # a method asked for no output has one row, without a quantity
    shown = marked_estimates(table if listed.all() else table[listed])[list(cols)].rename(columns=cols)
    verdicts = method_verdicts(
        case, result.runs, table, verdict_by_method(case, result.runs, table) if len(table) else {}
    )
    badges = [(m, verdicts[m].verdict, verdicts[m].reason, r) for m, r in result.runs.items()]
    runs = pd.DataFrame(
        [
            {
                "method": METHOD_NAMES.get(m, m),
                "verdict": v.value,
                "why": w[:300],
                "status": r.status.value if r.status else "",
                "time [s]": r.wall_time,
                "message": r.message[:300],
            }
            for m, v, w, r in badges
        ]
    )
    source = case.case.source.label() if case.case.source else ""
    items = findings([result], table)
    sentence = case_sentence(result, table)
    status = " ".join(f"{html.escape(METHOD_NAMES.get(m, m))} {verdict_html(v, w)}" for m, v, w, _ in badges)
    body = (
        f"<p><a href='../index.html'>all cases</a></p><h1>{html.escape(case.case.title)}</h1>"
        f"<p class='lead'><b>{html.escape(sentence)}</b></p><p>{status}</p>"
        f"<p><b>id</b> <code>{html.escape(cid)}</code> &middot; <b>group</b> {html.escape(case.case.group)} "
        f"&middot; <b>units</b> {html.escape(case.case.units)} &middot; <b>source</b> {html.escape(source)}</p>"
    )
    body += "".join(chart.html() for chart in charts[:2])
    if items:
        body += "<h2>Findings</h2>" + findings_html(items, {cid: f"{cid}.html"}, shown=6)
    body += "".join(chart.html() for chart in charts[2:])
    body += "".join(_image(name, name) for name in images)
    details = f"<p>{html.escape(case.case.description)}</p>"
    if case.case.assumptions:
        details += (
            "<h3>Assumptions</h3><ul>" + "".join(f"<li>{html.escape(a)}</li>" for a in case.case.assumptions) + "</ul>"
        )
    body += f"<details><summary>Description and assumptions</summary>{details}</details>"
    body += f"<details><summary>Methods: verdict, status, time, message</summary>{_html_table(runs)}</details>"
    at_a_glance = glance(table)
    prb_model, prb_lock = _prb_model(result)
    if prb_model is not None:
        body += (
            "<h2>PRB model built from the geometry</h2>"
            + (f"<p><b>Lock:</b> {html.escape(prb_lock)}</p>" if prb_lock else "")
            + f"<details><summary>Each beam's model, pivots and springs</summary>{_html_table(prb_model)}"
            "</details>"
        )
    if len(at_a_glance):
        body += (
            "<details><summary>At a glance: every method beside the printed columns</summary><p>Differences "
            "are in the output's unit (FEM - exact uses the exact elastica where the case runs it; "
            "'fem ± (estimate)' is the FEM's own Richardson error estimate, or 'unreliable': no bound).</p>"
            + _html_table(at_a_glance)
            + "</details>"
        )
    body += (
        "<details><summary>Every output (full precision)</summary><p>The relative error is relative to "
        "the printed value; error / characteristic length is the absolute error over the segment length "
        "or the mechanism's extent (useful where a value is near zero).</p>"
    )
    body += (
        _html_table(
            shown,
            lambda r: (
                "" if pd.isna(r["within stated tolerance"]) else ("good" if r["within stated tolerance"] else "bad")
            ),
            digits=6,
        )
        + "</details>"
    )
    if pvds:
        body += (
            "<details><summary>ParaView files</summary><p>One <code>.pvd</code> series per method, "
            "time = the case's first load; open it in ParaView and colour by the point data.</p><ul>"
            + "".join(f"<li>{_link(f'../{v}', v)}</li>" for v in pvds)
            + "</ul></details>"
        )
    install_plotly(out)
    (folder / f"{cid}.html").write_text(
        _page(case.case.title, body, f"<style>{CASE_CSS}</style><script src='../{PLOTLY_JS}'></script>")
    )
    md = [
        f"# {case.case.title}\n",
        f"**{sentence}**\n",
        f"`{cid}` · {case.case.group} · units {case.case.units} · {source}\n",
        case.case.description + "\n",
    ]
    md += [f"- {a}" for a in case.case.assumptions]
    md += ["\n## Methods\n", _md_table(runs)]
    if prb_model is not None:
        md += (
            ["\n## PRB model built from the geometry\n"]
            + ([f"Lock: {prb_lock}\n"] if prb_lock else [])
            + [_md_table(prb_model)]
        )
    if len(at_a_glance):
        md += ["\n## At a glance\n", _md_table(at_a_glance)]
    md += ["\n## Every output\n", _md_table(shown)]
    if charts:
        md += [f"\nCharts ({', '.join(chart.id for chart in charts)}): drawn in [the HTML page]({cid}.html)."]
    md += [f"\n![{name}]({name})" for name in images]
    (folder / f"{cid}.md").write_text("\n".join(md) + "\n")
    return DrawnPage(sentence, f"cases/{cid}.html", verdicts, tuple(items))


@lru_cache(maxsize=1)
def _code_digest() -> str:
    """The source of the modules that draw a case page: a page is rewritten when they change (read once
    a process)."""
    here = Path(__file__).parent
    names = ["build.py", "charts.py", "format.py", "summary.py", "paraview.py", "page.py"]
    sources = [here / n for n in names] + [here.parent / "run" / n for n in ("verdict.py", "compare.py", "outcome.py")]
    return hashlib.sha256(b"".join(p.read_bytes() for p in sources)).hexdigest()


@dataclass(frozen=True)
class PageLink:
    """Where a case's page is, why it could not be drawn (None: it was) and the case's row of the index
    (``summarise``), worked out in the worker that drew the page (None: the index works it out)."""

    case: str
    link: str
    error: str | None = None
    summary: CaseSummary | None = None
    measured: atlas_page.CaseMeasured | None = None
    findings: tuple[Finding, ...] | None = None  # the case's `findings`, in the index's order
    summary_row: dict | None = None  # the case's row of ``summary.csv`` (``outcome.summary_row``)
    overview: tuple[OverviewPoint, ...] | None = None  # the case's points of the overview (``case_points``)


# A page's tables hold their text in the storage the case's rows come in from ``outcome.Tabulate``
# (Python strings rather than pandas 3's pyarrow-backed default: a page filters, sorts and takes rows of
# small tables hundreds of times, where pyarrow's per-call conversions are a large part of the table
# work); what a page shows is the same (the results files written by the main process keep the default).
PAGE_STRINGS = CASE_STRINGS


def _page_job(args) -> PageLink:
    """Write one case page unless its digest (case text and results) is unchanged since last time.
    A page that cannot be drawn becomes a page saying why, so one case never costs the others'."""
    result, part, out = args
    cid = result.loaded.id
    digest = hashlib.sha256((result.loaded.text + _rows_text(part) + _code_digest()).encode()).hexdigest()
    stamp = out / "cases" / f"{cid}.digest"
    if stamp.exists() and stamp.read_text() == digest and (out / "cases" / f"{cid}.html").exists():
        return _drawn_link(result, part, f"cases/{cid}.html")
    _clear_page(out, cid)
    try:
        drawn = _case_page(result, part, out)
    except Exception as exc:  # noqa: BLE001 - any drawing error is reported, the other pages go on
        error = f"{cid}: its page could not be drawn: {type(exc).__name__}: {exc}"
        link = f"cases/{cid}.html"
        (out / link).write_text(_page(cid, f"<h1>{html.escape(cid)}</h1><p class='bad'>{html.escape(error)}</p>"))
        stamp.unlink(missing_ok=True)
        return PageLink(cid, link, error)
    stamp.write_text(digest)
    return _drawn_link(result, part, drawn.link, drawn)


def _rows_text(part: pd.DataFrame) -> str:
    """What a page shows of a case's rows, less the timings (``wall_time``, ``cached``), as text for its
    digest: each column's name and the text of its values, in order (the same whatever the table's storage
    of strings)."""
    return repr([(c, [str(v) for v in part[c].tolist()]) for c in part.columns if c not in ("wall_time", "cached")])


def _drawn_link(result: CaseResult, part: pd.DataFrame, link: str, drawn: DrawnPage | None = None) -> PageLink:
    """The link of a case's page with what the report's main process takes from the case: its row of the
    index (``summarise``) and of ``summary.csv`` (``summary_row``), both from the same numbers
    (``PrbmFemNumbers``), and its findings. The sentence, verdicts and findings of the page just ``drawn``
    are taken as they are; for a page kept from the last report (``drawn`` None) they are worked out."""
    numbers = PrbmFemNumbers.of(part)
    if drawn is None:
        summary, items = summarise(result, part, numbers=numbers), tuple(findings([result], part))
    else:
        summary, items = summarise(result, part, drawn.sentence, drawn.verdicts, numbers), drawn.findings
    row = summary_row(result.loaded.case.case.group, result.loaded.id, part, result, numbers) if len(part) else None
    return PageLink(result.loaded.id, link, summary=summary, findings=items, summary_row=row)


def _clear_page(out: Path, cid: str) -> None:
    """Remove the files of a case's page before it is drawn again: they may be hard links to the previous
    report's (module docstring), which a write would change."""
    for name in (f"{cid}.html", f"{cid}.md", f"{cid}.digest", f"{cid}_render.png"):
        (out / "cases" / name).unlink(missing_ok=True)
    shutil.rmtree(out / "vtu" / cid, ignore_errors=True)


@dataclass(frozen=True)
class PageWriter:
    """``run_cases``' ``after``: a case's page drawn in the worker that ran the case, right after it
    (so pages are drawn while other cases still run), from its ``rows``: ``tabulate`` of the case in the
    order of the whole table (``outcome.sorted_rows``; tabulated here when not given), with what the
    report's main process takes from the case (its rows of the index and of ``summary.csv``, its points
    of the overview: ``PageLink``). With ``measured`` (the previous report's ``measured.json``, whose
    entries are reused where their key holds) the case's measured levels for the atlas page
    (``atlas_page.case_measured``) are worked out here too, beside the other cases rather than on the
    report's serial path."""

    out: Path
    measured: Path | None = None

    def __call__(self, result: CaseResult, rows: pd.DataFrame | None = None) -> PageLink:
        with pd.option_context("mode.string_storage", PAGE_STRINGS):
            part = sorted_rows(tabulate(result)) if rows is None else rows
            link = replace(_page_job((result, part, self.out)), overview=tuple(case_points(result, part)))
        if self.measured is None:
            return link
        return replace(link, measured=_case_measured(result, part, self.measured))


def _case_measured(result: CaseResult, part: pd.DataFrame, previous: Path) -> atlas_page.CaseMeasured | None:
    """``atlas_page.case_measured`` of a case, None where it fails: the atlas page works it out again
    and reports why it could not."""
    try:
        return atlas_page.case_measured(result, part, _previous_measured(previous))
    except Exception:  # noqa: BLE001 - the atlas page is optional; it says what went wrong
        return None


def _previous_measured(path: Path) -> dict:
    """The previous report's measured levels (``measured.json``; empty where there is none), read once
    per process and file version."""
    try:
        return _read_measured(str(path), path.stat().st_mtime_ns)
    except OSError:
        return {}


@lru_cache(maxsize=2)
def _read_measured(path: str, version: int) -> dict:
    """``atlas_page.read_measured`` once per file version (``version``: its modification time)."""
    return atlas_page.read_measured(Path(path))


def _build_pages(
    results: list[CaseResult], table: pd.DataFrame, out: Path, jobs: int, done: dict | None = None
) -> list[PageLink]:
    """The page of every case; the pages not in ``done`` (already drawn) are drawn here."""
    done = done or {}
    todo = [r for r in results if r.loaded.id not in done]
    parts = by_case(table) if todo else {}  # the whole report's pages are drawn in the pool's workers
    tasks = [(r, rows_of(parts, table, r.loaded.id), out) for r in todo]
    if jobs > 1 and len(tasks) > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            drawn = list(pool.map(_page_job, tasks, chunksize=4))
    else:
        drawn = [_page_job(t) for t in tasks]
    return list(done.values()) + drawn


def _readings_section(results, table: pd.DataFrame, links: dict) -> tuple[list[str], list[str]]:
    """Readings of one experiment side by side against the measured points (`readings`); on the index,
    each experiment one line: the readings ranked by the FEM's rms distance, nearest first, and whether
    the ranking its base case records holds (`readings_rank`); its table behind a click."""
    groups = readings_groups(results, table)
    if not groups:
        return [], []
    ranked = {r.experiment: r for r in rank_readings(results, table)}
    body = ["<h2>Load readings against the measurements</h2>"]
    md = ["\n## Load readings against the measurements\n"]
    for group in groups:
        best = group.table.groupby("method", sort=False).head(1)  # sorted by rms: each method's closest
        note = "closest: " + "; ".join(
            f"{r['method']}: {r['case']}, rms {r['rms']:.4g}, largest {r['max']:.4g} over {r['levels']} levels"
            for _, r in best.iterrows()
        )
        ranking = ranked.get(group.experiment)
        if ranking is not None:
            flag = " class='bad'" if ranking.status is RankStatus.DIFFERS else ""
            body.append(f"<p{flag}>{html.escape(ranking.line())}</p>")
            md.append(f"\n{ranking.line()}\n")
        body += [
            f"<details class='fold'><summary><b>{html.escape(group.experiment)}</b>: {html.escape(note)}</summary>",
            _html_table(group.table, lambda r: "good" if r["closest"] else ""),
            "</details>",
        ]
        md += [f"\n### {group.experiment}\n", note + "\n", _md_table(group.table)]
    return body, md


OVERVIEW_CAPTION = (
    "Each dot: one load level of one case that compares a PRBM position with the FEM's (the headline's "
    "cases; the title names any it cannot place). x: the largest FEM displacement over the characteristic "
    "length L; y: the largest PRBM-to-FEM position difference in % of L, at equal load; colour and marker: "
    "the PRBM model. Lines: the accuracy claims printed in the sources, each labelled with what it claims; "
    "[ananthasuresh_l18] prints no numeric accuracy, only that its n-fits work 'comfortably and quite "
    "accurately' within their n-ranges."
)
OVERVIEW_ALT = "PRBM error against deflection, every case and load level, with the printed claims: " + "; ".join(
    c.label.replace("\n", " ") for c in CLAIMS
)


def headline(rows) -> str:
    """The first sentence of the summary: the cases counted per verdict (the counts add up to the number of
    cases), then, of those, the ones that compare the PRBM with the FEM on a position (the overview's
    cases) and how far apart the two are."""
    counts = verdict_counts_line(rows)
    compared = [r for r in rows if not math.isnan(r.prbm_fem_length)]
    if not compared:
        return f"{counts}; none compares the PRBM with the FEM on a position."
    worst = max(compared, key=lambda r: r.prbm_fem_length)
    within = sum(r.prbm_fem_length <= 0.01 for r in compared)
    return (
        f"{counts}. {len(compared)} of the {len(rows)} compare the PRBM with the FEM on a position: the "
        f"PRBM is within 1 % of L of the FEM on {within} of them (a difference, not a claimed limit), "
        f"{sig(100 * worst.prbm_fem_length, 3)} % of L at most ({worst.case})."
    )


VOCABULARY = (
    "Verdicts, worst first: " + "; ".join(vocabulary_lines()) + ". A case's verdict is the worst of "
    "its rows; the first four make the exit status 1."
)


@dataclass(frozen=True)
class DomainStudy:
    """The deflection domains of [bapat2015, ch. 4] (exact, FEM-free), kept in ``folder`` and run again
    only when its figure is missing or a source it depends on (code or data) has changed; a task of
    ``run_cases``' pool, run beside the cases."""

    folder: Path
    label: str = "chapter-4 domain study"

    def __call__(self) -> None:
        stamp = self.folder / "sources.sha256"
        digest = cache.digest_of(cache.sources_of([Path(domain_study.__file__)]) + [domain_study.DATA])
        if (self.folder / "domains.png").is_file() and stamp.is_file() and stamp.read_text() == digest:
            return
        print("chapter-4 deflection domains (validation.sweep.domain_study) ...", flush=True)
        shutil.rmtree(self.folder, ignore_errors=True)  # hard links to the previous report's: never written through
        domain_study.run_study(self.folder)
        stamp.write_text(digest)


@dataclass
class DomainsAndAtlas:
    """The chapter-4 domain study, then the atlas page's atlas-only part (``atlas_page.prepare_static``:
    the coarse atlas built where none of the current code is found, its claims table reading the study's
    summary, its maps and refit), in one task of ``run_cases``' pool beside the cases: off the main
    process's path, which then only adds the cases' predicted-against-measured part (its levels worked
    out beside each case by ``PageWriter``, its scatter drawn in a figure process). The coarse atlas runs
    the elastica's compiled integrator (``compiled``): the pool starts the task once the elastica's primer
    has compiled it, rather than compile it a second time beside the primer."""

    stage: Path
    datasets: Path
    label: str = "chapter-4 domain study and atlas maps"
    compiled: tuple[str, ...] = ("elastica",)

    def __call__(self) -> None:
        DomainStudy(self.stage / DOMAINS)()
        atlas_page.prepare_static(self.stage, self.datasets)


def _last_costs(out: Path) -> dict[str, float]:
    """Each case's seconds (its run and its page) in the last report's ``timing.csv``, which orders
    this run's cases longest first; empty when there is none."""
    try:
        last = pd.read_csv(out / TIMING_CSV)
    except (OSError, ValueError, pd.errors.ParserError):
        return {}
    if not {"kind", "name", "wall"} <= set(last.columns):
        return {}
    work = last[last["kind"].isin(["case", "page"])]
    return {str(k): float(v) for k, v in work.groupby("name")["wall"].sum().items()}


def _write_tables(outcome, out: Path, pages: Sequence[PageLink] = ()) -> pd.DataFrame:
    """``results.csv`` (and ``.parquet``) and ``summary.csv`` (its rows of the cases whose ``pages`` carry
    one taken as they are); returns the summary."""
    table = outcome.table
    table.to_csv(out / "results.csv", index=False)
    try:
        table.astype(
            {
                "finding": "string",
                "message": "string",
                "source": "string",
                "applicability": "string",
                "verdict": "string",
            }
        ).to_parquet(out / "results.parquet")
    except ImportError:
        pass
    rows = {page.case: page.summary_row for page in pages if page.summary_row is not None}
    summ = summary(table, outcome.results, rows) if len(table) else pd.DataFrame()
    summ.to_csv(out / "summary.csv", index=False)
    return summ


def _command_time(started: float, before: float) -> str:
    """The whole command's wall seconds, from its start (``before``: its age when the report began,
    `command_age`: the imports and the argument parsing), or '' where it is unknown (not run as a command)."""
    if math.isnan(before):
        return ""
    return f"the command {before + time.perf_counter() - started:.1f} s since it started"


def _write_timing(
    timeline: list[Timed], out: Path, jobs: int, started: float, cpu: float, before: float = math.nan
) -> str:
    """``timing.csv`` (every piece of work) and ``timing.txt`` (the breakdown, headed by the whole
    run's wall and CPU seconds, this process and its workers, and the command's wall seconds from its
    first line: the start-up and imports before the report began, ``before`` seconds, count for whoever
    waits for it); returns the text."""
    times = os.times()
    total_cpu = times.user + times.system + times.children_user + times.children_system - cpu
    head = (
        f"report: {time.perf_counter() - started:.1f} s wall, {total_cpu:.1f} s CPU (this process and its "
        f"{jobs} worker(s)); load average {' '.join(f'{x:.1f}' for x in os.getloadavg())}"
    )
    command = _command_time(started, before)
    if command:
        head += f"\n{command} ({before:.1f} s of start-up and imports before the report began)"
    text = head + "\n" + breakdown(timeline, jobs)
    (out / TIMING_CSV).write_text(csv_text(timeline))
    (out / "timing.txt").write_text(text + "\n")
    return text


def screen_lines(timing: str, out: Path) -> list[str]:
    """What the report prints before its last line: the time breakdown's first line with where the rest
    is (``timing.txt``), its slowest cases, and the cases counted per verdict (``summary.csv``)."""
    lines = timing.splitlines()
    shown = [lines[0].replace("report: ", "time: ", 1) + f"; breakdown in {out / 'timing.txt'}"] if lines else []
    shown += [line.strip() for line in lines if line.strip().startswith("slowest cases:")][:1]
    summary_file = out / "summary.csv"
    if summary_file.is_file():
        verdicts = pd.read_csv(summary_file, usecols=["verdict"])["verdict"].dropna()
        shown.append(f"{counts_sentence([Verdict(v) for v in verdicts])} (verdicts: validation/run/verdict.py)")
    return shown


def build_report(out: Path, use_cache: bool = True, jobs: int = 2, cases: list[str] | None = None) -> int:
    """Run (or reuse) the cases and write the report (module docstring); prints where the time went."""
    started, times, before = time.perf_counter(), os.times(), command_age()
    cpu = times.user + times.system + times.children_user + times.children_system
    try:
        plotly_bundle()  # the charts' library, before anything runs
    except PlotlyMissing as exc:
        print_error(f"prbm-validate report: {exc}")
        return ExitStatus.FAILED
    with OutputSet(out, owned=OWNED, seed=REUSED, link=LINKED) as output:
        stage = output.path
        (stage / "cases").mkdir(exist_ok=True)
        install_plotly(stage)  # before the workers draw pages
        paths = find_case_files(cases or None)
        # the whole report: the chapter-4 deflection-domain study beside the sweep studies, run beside the cases
        extra = [] if cases else [DomainsAndAtlas(stage, out / atlas_page.DATASETS)]
        # the atlas page's measured levels beside the cases when it will be drawn (the whole report builds
        # an atlas; a report of chosen cases draws the page from a published one)
        measure = not cases or (out / atlas_page.DATASETS).is_dir()
        previous = out / atlas_page.FIGURES / atlas_page.MEASURED if measure else None
        outcome = run_cases(
            paths,
            use_cache=use_cache,
            jobs=jobs,
            progress=True,
            after=PageWriter(stage, previous),
            extra=extra,
            costs=_last_costs(out),
        )
        if not outcome.results and outcome.errors:  # rejected: no case could run
            for error in outcome.errors:
                print_error(error)
            return ExitStatus.BAD_INPUT
        pooled = time.perf_counter() - started  # cases, their pages and the domain study, on ``jobs`` processes
        timeline = outcome.timeline
        # the pictures (matplotlib's layout is slow) drawn in processes of their own beside the tables
        # and the index page, on the cores the finished workers left free: the overview as PNG and as
        # SVG, each in one (in one together on one core), then the atlas page's scatter in the first free
        processes = max(1, min(jobs, FIGURE_PROCESSES))
        with ProcessPoolExecutor(max_workers=processes) as figure_pool:
            with timed("main", "overview points", timeline):
                points = _overview_points(outcome)
                formats = [(f,) for f in OVERVIEW] if processes > 1 else [OVERVIEW]
                overview = [figure_pool.submit(plot_overview, points, stage / "overview.png", f) for f in formats]
            later = FigureProcess(figure_pool)  # the atlas page's scatter, drawn beside the index
            with timed("main", "pages not drawn in the workers", timeline):
                pages = _build_pages(outcome.results, outcome.table, stage, jobs, done=outcome.after)
            with timed("main", "tables (results.csv, summary.csv)", timeline):
                _write_tables(outcome, stage, pages)
            with timed("main", "atlas page", timeline):
                atlas_line, atlas_error = _atlas_page(outcome, stage, out, jobs, build=not cases, draw=later.draw)
            with timed("main", "index page", timeline):
                _write_index(outcome, pages, stage, published=out, atlas=atlas_line)
            with timed("main", "waiting for the figure processes", timeline):
                for picture in overview:
                    picture.result()
                failed = later.wait()
            if failed is not None and atlas_error is None:  # the index says so instead of linking the page
                atlas_line, atlas_error = _atlas_failed(failed)
                _write_index(outcome, pages, stage, published=out, atlas=atlas_line)
        page_errors = [page.error for page in pages if page.error] + ([atlas_error] if atlas_error else [])
        for error in outcome.errors:
            print_error(error)
        for line in outcome.unexpected_problems + page_errors:  # what makes the exit status 1, in words
            print(f"not ok: {line}")
        timing = _write_timing(timeline, stage, jobs, started, cpu, before)
        output.commit()
    for line in screen_lines(timing, out):
        print(line)
    command = _command_time(started, before)
    print(
        f"report: {out / 'index.html'} ({len(outcome.results)} cases, {time.perf_counter() - started:.1f} s, "
        f"of which {pooled:.1f} s the cases, their pages and the domain study on {jobs} process(es)"
        + (f"; {command}" if command else "")
        + ")"
    )
    if page_errors and outcome.exit_status == ExitStatus.OK:
        return ExitStatus.FAILED
    return outcome.exit_status


FIGURE_PROCESSES = 2  # the report's figure processes (at most ``jobs``): the overview's PNG and SVG side by side
OVERVIEW = ("png", "svg")  # the overview picture's formats, each drawn by a figure process


def _overview_points(outcome) -> list[OverviewPoint]:
    """``overview_points`` of every case, each case's as its page writer worked them out (``PageLink``)
    where it did, in the order of the results."""
    pages = getattr(outcome, "after", None) or {}
    known = {case: link.overview for case, link in pages.items() if getattr(link, "overview", None) is not None}
    if any(r.loaded.id not in known for r in outcome.results):
        return overview_points(outcome.results, outcome.table)
    return [point for r in outcome.results for point in known[r.loaded.id]]


@dataclass
class FigureProcess:
    """Pictures handed to the report's figure processes, drawn there while this process writes the
    tables and the index: ``draw`` (also ``atlas_page.write_page``'s) hands one over, ``wait`` waits for
    every picture handed over."""

    pool: ProcessPoolExecutor
    pending: list[Future] = field(default_factory=list)

    def draw(self, function: Callable[..., object], *args: object) -> None:
        self.pending.append(self.pool.submit(function, *args))

    def wait(self) -> BaseException | None:
        """Wait for every picture; returns the first failure (None: all drawn)."""
        failures = [future.exception() for future in self.pending]
        return next((failure for failure in failures if failure is not None), None)


def _atlas_failed(exc: BaseException) -> tuple[tuple[str, str], str]:
    """The index's line (html, markdown) and the error of an atlas page that could not be drawn."""
    error = f"atlas page: could not be drawn: {type(exc).__name__}: {exc}"
    return (f"<p class='bad'><b>PRBM validity atlas:</b> {html.escape(error)}</p>", error), error


def _atlas_page(
    outcome, stage: Path, published: Path, jobs: int, build: bool, draw: atlas_page.Draw = atlas_page.draw_now
) -> tuple[tuple[str, str], str | None]:
    """The PRBM validity atlas's page (``atlas_page``) in ``stage``, from the best atlas under the report's
    ``atlas/`` (else, with ``build``: the whole report, the coarse one built); returns the index's line
    (html, markdown) and the error that kept the page from being drawn (None: drawn or not asked for).
    ``draw``: how its scatter is drawn (``atlas_page.write_page``)."""
    pages = getattr(outcome, "after", None) or {}
    known = {case: link.measured for case, link in pages.items() if getattr(link, "measured", None)}
    try:
        page = atlas_page.build_page(
            stage,
            outcome.results,
            outcome.table,
            published / atlas_page.DATASETS,
            build=build,
            workers=jobs,
            known=known,
            draw=draw,
        )
    except Exception as exc:  # noqa: BLE001 - the atlas page is optional: its failure is reported, the report goes on
        return _atlas_failed(exc)
    if page is None:
        text = "not drawn: a report of chosen cases builds no atlas (the whole report, or prbm-validate atlas, does)"
        return (f"<p><b>PRBM validity atlas:</b> {html.escape(text)}</p>", text), None
    return (page.index_html, f"[{page.index_words}]({page.link}); {page.index_text}"), None


def _write_index(
    outcome, pages: list[PageLink], out: Path, published: Path | None = None, atlas: tuple[str, str] = ("", "")
) -> None:
    """``index.html`` and ``index.md`` written in ``out`` (the overview figure beside them: `plot_overview`),
    linking the other commands' pages found in ``published`` (the report's folder; default ``out``);
    ``atlas``: the line (html, markdown) about the atlas page, under the headline."""
    published = out if published is None else published
    table = outcome.table
    links = {page.case: page.link for page in pages}
    page_errors = [page.error for page in pages if page.error]
    drawn = {page.case: page.summary for page in pages if page.summary is not None}
    parts = by_case(table) if any(r.loaded.id not in drawn for r in outcome.results) else {}
    rows = [drawn.get(r.loaded.id) or summarise(r, rows_of(parts, table, r.loaded.id)) for r in outcome.results]
    items = _index_findings(outcome.results, table, pages)
    failed = outcome.failed_comparisons
    info = reproducibility()
    body_readings, md_readings = _readings_section(outcome.results, table, links)
    body = [
        "<h1>PRBM validation report</h1>",
        f"<p class='lead'>{html.escape(headline(rows))}</p>",
        atlas[0],
        f"<p><img id='overview' src='overview.png' alt='{html.escape(OVERVIEW_ALT, quote=True)}'></p>",
        f"<p class='caption'>{html.escape(OVERVIEW_CAPTION)} <a href='overview.svg'>The same picture as "
        "SVG</a>: click a dot to open its case.</p>",
        f"<h2>Key</h2><p class='caption vocabulary'>{html.escape(VOCABULARY)}</p><dl class='key'>"
        + "".join(f"<dt>{html.escape(term)}</dt><dd>{html.escape(meaning)}</dd>" for term, meaning in key_terms())
        + "</dl>",
        "<h2>Cases</h2><p class='caption'>One line a case: click a header to sort, the case for its page, a "
        "result to unfold it (hover: the whole sentence). Colour: PRBM error from green (at most 0.5 % of L) "
        "to red (10 % of L or more), whatever its verdict; a label above the number where a limit is claimed "
        "for it. Hover a verdict or a method for its reason, the FEM time for the other methods' times.</p>",
        summary_tables_html(rows, links),
        *body_readings,
        "<h2>Findings and their evidence</h2><p class='caption'>Printed numbers not reproduced, misprints, "
        "and readings of the source that decide the answer; one line a case, its findings and their evidence "
        "behind a click.</p>",
        findings_html(items, links),
    ]
    md = ["# PRBM validation report\n", headline(rows) + "\n"]
    md += [f"PRBM validity atlas: {atlas[1]}\n"] if atlas[1] else []
    md += [
        "![overview](overview.png)\n",
        OVERVIEW_CAPTION + "\n",
        VOCABULARY + "\n",
        summary_markdown(rows),
        *md_readings,
        "\n## Findings\n",
    ]
    md += [f"- {f.case}: {f.text}" + "".join(f"\n  - {e}" for e in f.evidence[:3]) for f in items]
    if len(failed):
        body.append(
            "<h2>Comparisons outside the claimed limit</h2><ul>"
            + "".join(
                f"<li class='bad'>{_link(links.get(r['case'], '#'), r['case'])} "
                + html.escape(
                    f"{METHOD_NAMES.get(r['method'], r['method'])} {r['quantity']} at {r['level_label']}: "
                    f"{sig(r['value'])} against printed {r['reference_label']} {sig(r['reference_value'])}"
                )
                + "</li>"
                for _, r in failed.iterrows()
            )
            + "</ul>"
        )
        md += [
            f"- **outside the claimed limit** {r['case']} {r['method']} {r['quantity']} at {r['level_label']}"
            for _, r in failed.iterrows()
        ]
    if outcome.errors:
        body.append(
            "<h2>Bad case files</h2><ul>" + "".join(f"<li>{html.escape(e)}</li>" for e in outcome.errors) + "</ul>"
        )
    if page_errors:
        body.append(
            "<h2>Pages that could not be drawn</h2><ul>"
            + "".join(f"<li class='bad'>{html.escape(e)}</li>" for e in page_errors)
            + "</ul>"
        )
    body.append(
        "<h2>Reproducibility</h2><details class='fold'><summary>machine, versions and code digest ("
        f"{len(info)} items)</summary>"
        + _html_table(pd.DataFrame(list(info.items()), columns=["item", "value"]))
        + "</details>"
    )
    body.append("<p>Files: <a href='results.csv'>results.csv</a>, <a href='summary.csv'>summary.csv</a></p>")
    body += _other_pages_html(published, out)
    md += ["\n## Reproducibility\n", _md_table(pd.DataFrame(list(info.items()), columns=["item", "value"]))]
    (out / "index.html").write_text(_page("PRBM validation report", "".join(body)))
    (out / "index.md").write_text("\n".join(md) + "\n")


def _index_findings(results: list[CaseResult], table: pd.DataFrame, pages: list[PageLink]) -> list[Finding]:
    """``findings`` of every case, in its order (by group, then case), each case's as its page worked
    them out; worked out here when a page did not."""
    drawn = {page.case: page.findings for page in pages if page.findings is not None}
    if any(r.loaded.id not in drawn for r in results):
        return findings(results, table)
    ordered = sorted(results, key=lambda r: (group_order(r.loaded.case.case.group), r.loaded.id))
    return [item for r in ordered for item in drawn[r.loaded.id]]


def _other_pages_html(published: Path, out: Path) -> list[str]:
    """The index's links to the other commands' pages and pictures found in ``published`` (and ``out``),
    each study's and the benchmark's pictures folded under one line."""
    body = []
    extra = [
        (f"{name}/{page}", label)
        for name, page, label in (
            ("stress", "index.html", "stress report (prbm-validate stress)"),
            ("bench", "headline.json", "benchmark headline (prbm-validate bench)"),
            ("bench", "bench.csv", "benchmark table"),
        )
        if (published / name / page).exists()
    ]
    if extra:
        body.append(
            "<h2>Other pages</h2><ul>"
            + "".join(f"<li><a href='{link}'>{label}</a></li>" for link, label in extra)
            + "</ul>"
        )
    studies: dict[str, Path] = {}
    for folder in (published, out):  # a study written in ``out`` over the published one of that name
        studies |= {
            p.name: p
            for p in (folder / "sweeps").glob("*")
            if p.is_dir() and not is_leftover(p) and list(p.glob("*.png"))
        }
    if studies:
        body.append("<h2>Sweep studies (prbm-validate sweep)</h2>")
        for _, study in sorted(studies.items()):
            pngs = sorted(study.glob("*.png"))
            pictures = "".join(_image(f"sweeps/{study.name}/{png.name}", png.name) for png in pngs)
            body.append(
                f"<details class='fold'><summary><b>{html.escape(study.name)}</b>: {len(pngs)} "
                f"picture(s)</summary>{pictures}</details>"
            )
    bench_plots = sorted((published / "bench").glob("*.png"))
    if bench_plots:
        body.append(
            f"<h2>Benchmark (prbm-validate bench)</h2><details class='fold'><summary>{len(bench_plots)} "
            "picture(s)</summary>"
            + "".join(_image(f"bench/{png.name}", png.name) for png in bench_plots)
            + "</details>"
        )
    return body
