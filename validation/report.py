"""Build the report an engineer reads: a summary page, a page per case, findings, reproducibility.

``prbm-validate report`` runs (or reuses the cached results of) every case and writes, under the
output folder: ``index.html`` and ``index.md`` (summary grouped by group, findings, machine and
versions), ``cases/<id>.html`` and ``.md`` (every output at every level for every method beside the
printed values, with errors, and plots), ``results.csv`` (and ``results.parquet``), and the FEM's
deformed configurations as VTU files for ParaView under ``vtu/<id>/``.
"""
from __future__ import annotations

import datetime as _dt
import hashlib
import html
import math
import platform
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path

import numpy as np
import pandas as pd

from validation.loader import find_case_files
from validation.runner import CaseResult, run_cases, summary

DEPENDENCIES = ["numpy", "scipy", "scikit-fem", "meshio", "pyvista", "pandas", "matplotlib", "pydantic",
                "tqdm", "openseespy", "pyarrow"]
METHOD_STYLE = {"fem": ("C0", "-"), "prbm": ("C1", "--"), "elastica": ("C2", ":"), "bcm": ("C4", "-.")}
REF_MARKER = {"PRBM": "s", "ANSYS": "^", "elliptic": "D", "measured": "o", "exact": "*", "BCM": "v",
              "chain": "P", "published": "X"}

CSS = """body{font-family:system-ui,sans-serif;margin:2em;max-width:1200px;color:#222}
table{border-collapse:collapse;margin:1em 0;font-size:13px}th,td{border:1px solid #ccc;padding:3px 6px;
text-align:right}th{background:#eee;cursor:pointer}td:first-child,th:first-child{text-align:left}
.bad{background:#fdd}.good{background:#dfd}.finding{background:#ffd}img{max-width:100%;border:1px solid #ddd}
code{background:#f4f4f4;padding:1px 3px}"""
SORT_JS = """document.querySelectorAll('th').forEach(th=>th.onclick=()=>{const t=th.closest('table'),
i=[...th.parentNode.children].indexOf(th),rows=[...t.querySelectorAll('tr')].slice(1),a=th.asc=!th.asc;
rows.sort((x,y)=>{let p=x.children[i].innerText,q=y.children[i].innerText,m=parseFloat(p),n=parseFloat(q);
return (isNaN(m)||isNaN(n)?p.localeCompare(q):m-n)*(a?1:-1)});rows.forEach(r=>t.appendChild(r))});"""


def _fmt(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (float, np.floating)):
        return f"{value:.6g}"
    return str(value)


def _html_table(frame: pd.DataFrame, row_class=None) -> str:
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in frame.columns)
    body = []
    for _, row in frame.iterrows():
        cls = row_class(row) if row_class else ""
        cells = "".join(f"<td>{html.escape(_fmt(v))}</td>" for v in row.values)
        body.append(f"<tr class='{cls}'>{cells}</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def _md_table(frame: pd.DataFrame) -> str:
    if frame.empty:
        return "_none_\n"
    lines = ["| " + " | ".join(map(str, frame.columns)) + " |", "|" + "---|" * len(frame.columns)]
    for _, row in frame.iterrows():
        lines.append("| " + " | ".join(_fmt(v).replace("|", "/") for v in row.values) + " |")
    return "\n".join(lines) + "\n"


def _page(title: str, body: str) -> str:
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
            f"<style>{CSS}</style></head><body>{body}<script>{SORT_JS}</script></body></html>")


def reproducibility() -> dict[str, str]:
    info = {"date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "python": sys.version.split()[0], "platform": platform.platform()}
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
        info["git commit"] = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                            text=True, check=True, cwd=Path(__file__).parent).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        info["git commit"] = "unknown"
    for name in DEPENDENCIES:
        try:
            info[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            info[name] = "not installed"
    info["command"] = "prbm-validate report"
    return info


def _level_axis(result: CaseResult) -> tuple[np.ndarray, str]:
    case = result.loaded.case
    if case.loads:
        load = case.loads[0]
        dim = {"force": "force", "moment": "moment", "displacement": "length", "rotation": "deg"}[load.kind]
        name = load.label or f"{load.kind} at {load.point}"
        return np.asarray(load.levels(), float), f"{name} [{case.unit(dim)}]"
    return np.arange(case.n_levels(), dtype=float), "load level"


def _plot_outputs(result: CaseResult, table: pd.DataFrame, folder: Path) -> list[str]:
    """One figure per case: a panel per output (value against load level), every method as a line,
    every printed column as markers."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    axis, label = _level_axis(result)
    outputs = list(table.dropna(subset=["quantity"]).groupby(["quantity", "point"], sort=False))
    if not outputs:
        return []
    ncols = min(3, len(outputs))
    nrows = -(-len(outputs) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.6 * ncols, 3.4 * nrows), squeeze=False)
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.1 / nrows ** 0.5, top=0.97, wspace=0.32,
                        hspace=0.45)
    for ax, ((quantity, point), part) in zip(axes.flat, outputs):
        for method, rows in part.drop_duplicates(["method", "level"]).groupby("method"):
            rows = rows.sort_values("level")
            color, style = METHOD_STYLE.get(method, ("k", "-"))
            ax.plot(axis[rows["level"].astype(int)], rows["value"], style, color=color, marker=".",
                    label=method)
        refs = part.dropna(subset=["reference_value"]).drop_duplicates(["reference_label", "level",
                                                                          "reference_value"])
        for ref_label, rows in refs.groupby("reference_label"):
            ax.plot(axis[rows["level"].astype(int)], rows["reference_value"], REF_MARKER.get(ref_label, "x"),
                    mfc="none", color="k", label=f"printed {ref_label}")
        ax.set_xlabel(label, fontsize=8)
        ax.set_ylabel(f"{quantity}{'@' + point if point else ''} [{part['unit'].iloc[0]}]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(outputs):]:
        ax.set_visible(False)
    name = f"{result.loaded.id}_outputs.png"
    fig.savefig(folder / name, dpi=80)
    plt.close(fig)
    return [name]


def normalise_shapes(shapes) -> list[list[np.ndarray]]:
    """Shapes as a list (per level) of lists of (n, 2) polylines.

    Adapters may give a dict {level: ...} or a list per level, and per level one array or a list of
    arrays, each (n, 2)/(n, >2) point rows or (2|3, n) coordinate rows (x, y[, theta])."""
    if isinstance(shapes, dict):
        shapes = [shapes[k] for k in sorted(shapes)]
    out = []
    for entry in shapes:
        lines = [entry] if isinstance(entry, np.ndarray) else list(entry)
        fixed = []
        for line in lines:
            line = np.asarray(line, float)
            if line.ndim != 2:
                continue
            if line.shape[0] in (2, 3) and line.shape[1] > 3:
                line = line[:2].T
            fixed.append(line[:, :2])
        out.append(fixed)
    return out


def _plot_shapes(result: CaseResult, folder: Path) -> str | None:
    """Deformed shapes: FEM beams as curves, PRB links dashed, measured tip points as markers."""
    shapes = {m: normalise_shapes(r.extras["shapes"]) for m, r in result.runs.items() if r.extras.get("shapes")}
    if not shapes:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 5))
    for method, per_level in shapes.items():
        color, style = METHOD_STYLE.get(method, ("k", "-"))
        for i, polylines in enumerate(per_level):
            for j, line in enumerate(polylines):
                line = np.asarray(line)
                if line.size:
                    ax.plot(line[:, 0], line[:, 1], style, color=color, lw=1,
                            label=method if i == 0 and j == 0 else None)
    case = result.loaded.case
    measured = {}
    for ref in case.references:
        if ref.label == "measured" and ref.quantity in ("x", "y"):
            measured.setdefault((ref.point, ref.level), {})[ref.quantity] = ref.value
    pts = [(v["x"], v["y"]) for v in measured.values() if "x" in v and "y" in v]
    if pts:
        ax.plot(*zip(*pts), "o", mfc="none", color="k", label="measured")
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.set_xlabel(f"x [{case.unit('length')}]")
    ax.set_ylabel(f"y [{case.unit('length')}]")
    ax.legend(fontsize=8)
    name = f"{result.loaded.id}_shapes.png"
    fig.savefig(folder / name, dpi=80, bbox_inches="tight")
    plt.close(fig)
    return name


def _plot_path(result: CaseResult, folder: Path) -> str | None:
    """Equilibrium path of a continuation run, limit points marked."""
    run = result.runs.get("fem")
    path = run.extras.get("path") if run else None
    if not path:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(path["displacement"], path["load"], "-", color="C0", label="FEM path")
    for k, (d, p) in enumerate(path.get("limit_points", [])):
        ax.plot([d], [p], "rv", label="limit point" if k == 0 else None)
    ax.set_xlabel(path.get("displacement_label", "control displacement"))
    ax.set_ylabel(path.get("load_label", "load"))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    name = f"{result.loaded.id}_path.png"
    fig.savefig(folder / name, dpi=80, bbox_inches="tight")
    plt.close(fig)
    return name


def _write_vtu(result: CaseResult, folder: Path) -> list[str]:
    run = result.runs.get("fem")
    shapes = normalise_shapes(run.extras["shapes"]) if run and run.extras.get("shapes") else None
    if not shapes:
        return []
    import meshio

    target = folder / result.loaded.id
    target.mkdir(parents=True, exist_ok=True)
    files = []
    for level, polylines in enumerate(shapes):
        points, cells = [], []
        for line in polylines:
            line = np.asarray(line, float)
            start = len(points)
            points.extend(line.tolist())
            cells.extend([[start + k, start + k + 1] for k in range(len(line) - 1)])
        if not cells:
            continue
        xyz = np.column_stack([np.asarray(points), np.zeros(len(points))])
        name = target / f"level_{level:03d}.vtu"
        meshio.write(name, meshio.Mesh(xyz, [("line", np.asarray(cells))]))
        files.append(str(name.relative_to(folder.parent)))
    return files


def glance(table: pd.DataFrame) -> pd.DataFrame:
    """Every output at every level in one row: each method's value, each printed column, and the
    differences an engineer asks about first (PRBM - FEM, each model - measured, FEM - exact)."""
    rows = table.dropna(subset=["quantity"])
    if rows.empty:
        return pd.DataFrame()
    key = ["quantity", "point", "level"]
    values = rows.drop_duplicates(key + ["method"]).pivot_table(index=key, columns="method", values="value",
                                                                  aggfunc="first")
    refs = rows.dropna(subset=["reference_label"]).drop_duplicates(key + ["reference_label"])
    printed = refs.pivot_table(index=key, columns="reference_label", values="reference_value", aggfunc="first")
    printed.columns = [f"printed {c}" for c in printed.columns]
    out = values.join(printed, how="left")
    fem_est = rows[rows["method"] == "fem"].drop_duplicates(key).set_index(key)["error_estimate"]
    if len(fem_est):
        out["fem ± (estimate)"] = fem_est
    if {"prbm", "fem"} <= set(out.columns):
        out["PRBM - FEM"] = out["prbm"] - out["fem"]
    for method in ("prbm", "fem"):
        if method in out.columns and "printed measured" in out.columns:
            out[f"{method.upper()} - measured"] = out[method] - out["printed measured"]
    if {"fem", "elastica"} <= set(out.columns):
        out["FEM - exact"] = out["fem"] - out["elastica"]
    labels = rows.drop_duplicates(key).set_index(key)["level_label"]
    out = out.reset_index()
    out.insert(3, "load", [labels.get((q, p, l), l) for q, p, l in zip(out["quantity"], out["point"], out["level"])])
    units = rows.drop_duplicates(["quantity"]).set_index("quantity")["unit"]
    out.insert(1, "unit", out["quantity"].map(units))
    return out.drop(columns=["level"])


def _prb_model(result: CaseResult) -> tuple[pd.DataFrame | None, str | None]:
    """The PRBM adapter's record of the model it built for each beam (mechanisms without hand-given
    links): beam, model, how its ends are held, pivots, springs, gamma, K_Theta and why."""
    run = result.runs.get("prbm")
    if run is None or not run.extras.get("prb_model"):
        return None, None
    rows = [{"beam": b["beam"], "model": b["model"], "ends": "-".join(b["ends"]),
             "pivots": "; ".join(f"({x:.4g}, {y:.4g})" for x, y in b["pivots"]),
             "springs": "; ".join(f"{k:.4g}" for k in b["springs"]), "gamma": b["gamma"], "K_theta": b["K_theta"],
             "why": b["reason"]} for b in run.extras["prb_model"]]
    return pd.DataFrame(rows), run.extras.get("lock")


def _case_page(result: CaseResult, table: pd.DataFrame, out: Path) -> tuple[str, str]:
    case = result.loaded.case
    cid = case.case.id
    folder = out / "cases"
    images = _plot_outputs(result, table, folder)
    for extra in (_plot_shapes(result, folder), _plot_path(result, folder)):
        if extra:
            images.insert(0, extra)
    vtus = _write_vtu(result, out / "vtu")
    cols = ["method", "quantity", "point", "level_label", "value", "unit", "error_estimate",
            "reference_label", "reference_value", "abs_error", "rel_error", "norm_error", "within_tolerance",
            "converged"]
    shown = table.dropna(subset=["quantity"])[cols].rename(columns={"level_label": "level"})
    runs = pd.DataFrame([dict(method=m, converged=r.converged, wall_time_s=r.wall_time,
                              message=r.message[:300]) for m, r in result.runs.items()])
    source = case.case.source.label() if case.case.source else ""
    findings = table.dropna(subset=["finding"]).drop_duplicates(["quantity", "point", "level",
                                                                 "reference_label"])
    head = (f"<p><a href='../index.html'>all cases</a></p><h1>{html.escape(case.case.title)}</h1>"
            f"<p><b>id</b> <code>{cid}</code> &middot; <b>group</b> {html.escape(case.case.group)} &middot; "
            f"<b>units</b> {case.case.units} &middot; <b>source</b> {html.escape(source)}</p>"
            f"<p>{html.escape(case.case.description)}</p>")
    if case.case.assumptions:
        head += "<h3>Assumptions</h3><ul>" + "".join(f"<li>{html.escape(a)}</li>"
                                                     for a in case.case.assumptions) + "</ul>"
    at_a_glance = glance(table)
    body = head + "<h2>Methods</h2>" + _html_table(runs)
    prb_model, prb_lock = _prb_model(result)
    if prb_model is not None:
        body += ("<h2>PRB model built from the geometry</h2>"
                 + (f"<p><b>Lock:</b> {html.escape(prb_lock)}</p>" if prb_lock else "") + _html_table(prb_model))
    if len(at_a_glance):
        body += ("<h2>At a glance</h2><p>Each method's value beside the printed columns; differences are "
                 "in the output's unit (FEM - exact uses the exact elastica where the case runs it; "
                 "'fem ± (estimate)' is the FEM's own Richardson error estimate).</p>" + _html_table(at_a_glance))
    if len(findings) or case.case.findings:
        body += "<h2>Findings</h2><ul>" + "".join(f"<li>{html.escape(f)}</li>" for f in case.case.findings) + "".join(
            f"<li>{html.escape(str(r['reference_label']))} {r['quantity']} level {r['level_label']}: "
            f"{html.escape(str(r['finding']))}</li>" for _, r in findings.iterrows()) + "</ul>"
    body += "<h2>Plots</h2>" + "".join(f"<p><img src='{name}' alt='{name}'></p>" for name in images)
    body += ("<h2>Every output</h2><p>rel_error is relative to the printed value; norm_error is the "
             "absolute error over the characteristic length (useful where a value is near zero).</p>")
    body += _html_table(shown, lambda r: "" if pd.isna(r["within_tolerance"])
                        else ("good" if r["within_tolerance"] else "bad"))
    if vtus:
        body += "<h2>ParaView</h2><ul>" + "".join(f"<li><a href='../{v}'>{v}</a></li>" for v in vtus) + "</ul>"
    (folder / f"{cid}.html").write_text(_page(case.case.title, body))
    md = [f"# {case.case.title}\n", f"`{cid}` · {case.case.group} · units {case.case.units} · {source}\n",
          case.case.description + "\n"]
    md += [f"- {a}" for a in case.case.assumptions]
    md += ["\n## Methods\n", _md_table(runs)]
    if prb_model is not None:
        md += ["\n## PRB model built from the geometry\n"] + ([f"Lock: {prb_lock}\n"] if prb_lock else []) \
            + [_md_table(prb_model)]
    if len(at_a_glance):
        md += ["\n## At a glance\n", _md_table(at_a_glance)]
    md += ["\n## Every output\n", _md_table(shown)]
    md += [f"\n![{name}]({name})" for name in images]
    (folder / f"{cid}.md").write_text("\n".join(md) + "\n")
    return cid, f"cases/{cid}.html"


def _page_job(args) -> tuple[str, str]:
    """Write one case page unless its digest (case text and results) is unchanged since last time."""
    result, part, out = args
    cid = result.loaded.id
    stable = part.drop(columns=["wall_time", "cached"])  # what a page shows, less the timings
    digest = hashlib.sha256((result.loaded.text + stable.to_csv(index=False)).encode()).hexdigest()
    stamp = out / "cases" / f"{cid}.digest"
    if stamp.exists() and stamp.read_text() == digest and (out / "cases" / f"{cid}.html").exists():
        return cid, f"cases/{cid}.html"
    page = _case_page(result, part, out)
    stamp.write_text(digest)
    return page


def _build_pages(results: list[CaseResult], table: pd.DataFrame, out: Path, jobs: int):
    tasks = [(r, table[table["case"] == r.loaded.id], out) for r in results]
    if jobs > 1 and len(tasks) > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=jobs) as pool:
            return list(pool.map(_page_job, tasks, chunksize=4))
    return [_page_job(t) for t in tasks]


def build_report(out: Path, use_cache: bool = True, jobs: int = 2, cases: list[str] | None = None) -> int:
    started = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    (out / "cases").mkdir(exist_ok=True)
    paths = find_case_files(cases or None)
    outcome = run_cases(paths, use_cache=use_cache, jobs=jobs, progress=True)
    table = outcome.table
    table.to_csv(out / "results.csv", index=False)
    try:
        table.astype({"finding": "string", "message": "string", "source": "string"}).to_parquet(
            out / "results.parquet")
    except ImportError:
        pass
    summ = summary(table) if len(table) else pd.DataFrame()
    links = dict(_build_pages(outcome.results, table, out, jobs))
    summ.to_csv(out / "summary.csv", index=False)

    failed = outcome.failed_comparisons
    finding_rows = table.dropna(subset=["finding"]).drop_duplicates(
        ["case", "quantity", "point", "level", "reference_label"])
    info = reproducibility()
    body = ["<h1>PRBM validation report</h1>",
            f"<p>{len(outcome.results)} cases, {len(table)} result rows, built in "
            f"{time.perf_counter() - started:.1f} s.</p>"]
    md = ["# PRBM validation report\n", f"{len(outcome.results)} cases.\n"]
    for group, part in summ.groupby("group", sort=True) if len(summ) else []:
        part = part.copy()
        part["case"] = [f"<a href='{links.get(c, '#')}'>{c}</a>" for c in part["case"]]
        body.append(f"<h2>{html.escape(group)}</h2>")
        body.append(_html_table(part.drop(columns="group"), lambda r: "bad" if r["failed"] else "")
                    .replace("&lt;a href=&#x27;", "<a href='").replace("&#x27;&gt;", "'>")
                    .replace("&lt;/a&gt;", "</a>"))
        md += [f"\n## {group}\n", _md_table(summ[summ["group"] == group].drop(columns="group"))]
    body.append("<h2>Findings: printed numbers not reproduced, and comparisons outside their tolerance</h2>")
    items = [f"<li><b>{r.loaded.id}</b>: {html.escape(f)}</li>" for r in outcome.results
             for f in r.loaded.case.case.findings]
    items += [f"<li><b>{r['case']}</b> {r['reference_label']} {r['quantity']} level {r['level_label']}: "
             f"{html.escape(str(r['finding']))}</li>" for _, r in finding_rows.iterrows()]
    items += [f"<li class='bad'><b>{r['case']}</b> {r['method']} {r['quantity']}@{r['point']} level "
              f"{r['level_label']}: {r['value']:.6g} vs printed {r['reference_label']} {r['reference_value']:.6g} "
              f"(rel {r['rel_error']:.3g}) outside the claimed tolerance</li>" for _, r in failed.iterrows()]
    body.append("<ul>" + "".join(items) + "</ul>" if items else "<p>none</p>")
    md.append("\n## Findings\n")
    md += [f"- {r.loaded.id}: {f}" for r in outcome.results for f in r.loaded.case.case.findings]
    md += [f"- {r['case']} {r['reference_label']} {r['quantity']} level {r['level_label']}: {r['finding']}"
           for _, r in finding_rows.iterrows()]
    md += [f"- **outside tolerance** {r['case']} {r['method']} {r['quantity']} level {r['level_label']}"
           for _, r in failed.iterrows()]
    if outcome.errors:
        body.append("<h2>Bad case files</h2><ul>" + "".join(f"<li>{html.escape(e)}</li>"
                                                              for e in outcome.errors) + "</ul>")
    body.append("<h2>Reproducibility</h2>" + _html_table(pd.DataFrame(list(info.items()),
                                                                       columns=["item", "value"])))
    body.append("<p>Files: <a href='results.csv'>results.csv</a>, <a href='summary.csv'>summary.csv</a></p>")
    extra = [(f"{name}/{page}", label) for name, page, label in
             (("stress", "index.html", "stress report (prbm-validate stress)"),
              ("bench", "headline.json", "benchmark headline (prbm-validate bench)"),
              ("bench", "bench.csv", "benchmark table"))
             if (out / name / page).exists()]
    if extra:
        body.append("<h2>Other pages</h2><ul>" + "".join(f"<li><a href='{link}'>{label}</a></li>"
                                                         for link, label in extra) + "</ul>")
    studies = sorted(p for p in (out / "sweeps").glob("*") if p.is_dir() and list(p.glob("*.png")))
    if studies:
        body.append("<h2>Sweep studies (prbm-validate sweep)</h2>")
        for study in studies:
            pictures = "".join(f"<p><img src='sweeps/{study.name}/{png.name}' alt='{png.name}'></p>"
                               for png in sorted(study.glob("*.png")))
            body.append(f"<h3>{html.escape(study.name)}</h3>{pictures}")
    bench_plots = sorted((out / "bench").glob("*.png"))
    if bench_plots:
        body.append("<h2>Benchmark (prbm-validate bench)</h2>" + "".join(
            f"<p><img src='bench/{png.name}' alt='{png.name}'></p>" for png in bench_plots))
    md += ["\n## Reproducibility\n", _md_table(pd.DataFrame(list(info.items()), columns=["item", "value"]))]
    (out / "index.html").write_text(_page("PRBM validation report", "".join(body)))
    (out / "index.md").write_text("\n".join(md) + "\n")
    for error in outcome.errors:
        print(f"error: {error}", file=sys.stderr)
    print(f"report: {out / 'index.html'} ({len(outcome.results)} cases, "
          f"{time.perf_counter() - started:.1f} s)")
    return outcome.exit_status
