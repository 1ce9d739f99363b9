"""The report's page of the PRBM validity atlas (``validation.atlas``): ``atlas.html`` in the report folder.

The page shows what the atlas knows and how it compares with the cases, in this order:

* an introduction: what the atlas is (every PRBM segment model against the exact elastica over its input
  space; errors at equal load, in % of L; the split of an error into path and stiffness), which grid the
  page shows (``full``, built by hand with ``prbm-validate atlas``, else ``coarse``), its code version,
  and its points and build time from the dataset's ``atlas.json``;
* *Predicted against measured* (``validation.atlas.measured``): the atlas's expected PRBM error of every
  case level beside the PRBM-vs-FEM error the case measured, as a scatter, one sentence with the
  agreement numbers and the levels with the largest measured error, split into path and stiffness;
* *The seeds' claims, checked* (``validation.atlas.claims`` on ``cases/atlas/claims.toml``);
* a section per model: its error map and its 0.5/1/3/5 % regions in words (``validation.atlas.regions``);
* *Beyond the seeds: refit (gamma, K_Theta)* (``validation.atlas.refit``, fixed-pinned and curved).

What takes seconds is kept in ``atlas_figures/`` and done again only when what it depends on changes:
the claims, the maps and the refit depend only on the atlas (grid, code version, its rows), the claims
file and the code drawing them (``static.html`` and its digest); a case's measured levels (following
the PRBM along its line: about a second a level for the Chain Algorithm) on its PRBM and FEM values
and the code reading them (``measured.json``, by case).  The report works both out beside its cases, in
its pool's workers: the atlas-only part ahead (``prepare_static``), each case's measured levels where its
page is drawn (``case_measured``, handed to ``write_page`` as ``known``); the scatter is drawn in the
report's figure processes (``write_page``'s ``draw``).  The figures folder may hold hard links to the
previous report's files (the report's output set, ``validation.report.build``): a file is removed
before it is written again, never written through.

``find_atlas`` picks the dataset (the best one under the report's ``atlas/`` folder, else the coarse one
built, cached by code version); ``write_page`` writes the page; ``build_page`` does both and returns
the ``AtlasPage`` whose ``index_html`` is the report index's line.  Every text on the page is
HTML-escaped where it is written (``html.escape``; attribute values with ``quote=True``).
"""

from __future__ import annotations

import hashlib
import html
import json
import math
import shutil
import time
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Callable

import pandas as pd

from validation.atlas import claims as atlas_claims
from validation.atlas import dataset, map_figure, measured, refit, regions
from validation.atlas.models import MODELS
from validation.report.page import _fmt, _image, _link, _page

PAGE = "atlas.html"
FIGURES = "atlas_figures"  # the page's pictures and its cached atlas-only part
DATASETS = "atlas"  # the atlas datasets inside the report folder (``prbm-validate atlas``)
CLAIMS = dataset.ROOT / "cases" / "atlas" / "claims.toml"
MEASURED = "measured.json"  # in FIGURES: each case's measured levels, by what they depend on
LARGEST = 12  # levels shown in the table of the largest measured errors
REFIT_MODELS = (("fixed_pinned_pauly_midha", refit.FIXED_PINNED), ("curved_fixed_pinned", refit.CURVED))
VERDICT_CLASS = {
    "holds": "v-holds",
    "holds on part of its range": "v-part",
    "does not hold": "v-fails",
    "not testable": "v-untested",
}
CSS = """.scroll{overflow-x:auto;max-width:100%}.scroll table{margin:0}
table.wrap td,table.wrap th{text-align:left;white-space:normal;overflow-wrap:break-word}
table.wrap td.num{text-align:right;white-space:nowrap}table.wrap td.text{max-width:22em}
table.wrap td.id{max-width:13em;font:12px/1.35 monospace}
table.wrap td.quotes{min-width:6em;max-width:30em}
.v-holds{background:#dfd}.v-part{background:#ffd}.v-fails{background:#fdd}.v-untested{background:#eee}
.verdict{padding:1px 5px;border-radius:3px;white-space:nowrap}
.pair{display:flex;flex-wrap:wrap;gap:0.5em 1.5em;align-items:flex-start}
.pair>p{margin:0}.pair img.map{width:600px}.pair>.words{flex:1 1 24em;min-width:0;max-width:46em}
ul.regions{margin:0.3em 0;padding-left:1.2em;font-size:14px}ul.regions li{margin:0.2em 0}
td details{margin:0}td details summary{font-weight:400}td .quote{font-style:italic}
.prose{max-width:62em}nav.toc{font-size:13px;line-height:1.7}"""


@dataclass(frozen=True)
class AtlasPage:
    """What the page shows, for the report index: its link, grid, code version and agreement numbers."""

    link: str
    grid: str
    version: str
    agreement: dict = field(default_factory=dict)

    @property
    def index_words(self) -> str:
        return f"every PRBM segment model against the exact elastica ({self.grid} grid)"

    @property
    def index_text(self) -> str:
        """The agreement numbers in words (the index's line after its link)."""
        return agreement_words(self.agreement)

    @property
    def index_html(self) -> str:
        """The index's line: a link to the page and the agreement numbers in words."""
        link = _link(self.link, self.index_words)
        return f"<p><b>PRBM validity atlas:</b> {link}; {html.escape(self.index_text)}</p>"


def agreement_words(a: dict) -> str:
    """``measured.agreement`` in a sentence."""
    if not a.get("levels"):
        return "no case level has both an atlas prediction and a measured PRBM-vs-FEM error."
    rank = a.get("spearman", math.nan)
    return (
        f"predicted against measured PRBM error on {a['levels']} levels of {a['cases']} cases: "
        f"{100 * a['within_factor_2']:.0f} % within a factor 2 (or 0.25 % of L), "
        f"{100 * a['same_side_of_5_percent']:.0f} % on the same side of the 5 % validity limit"
        + (f", Spearman rank correlation {rank:.2f}." if math.isfinite(rank) else ".")
    )


def find_atlas(
    datasets: Path, build_into: Path | None = None, workers: int = 2, executor: str = "process"
) -> tuple[str, pd.DataFrame, Path] | None:
    """(grid, rows, the datasets' folder) of the best atlas of the current code under ``datasets``
    (``dataset.best_available``: the full one, else the coarse one); else the coarse atlas built under
    ``build_into`` (cached there by code version: a complete one is read, not built again, so that its
    manifest records only the runs that computed lines); None where neither is there and
    ``build_into`` is None."""
    found = dataset.best_available(datasets)
    if found is not None:
        return found[0], found[1], Path(datasets)
    if build_into is None:
        return None
    if not dataset.complete(build_into, "coarse"):
        dataset.build("coarse", out=build_into, executor=executor, workers=workers)
    frame = dataset.load(build_into, "coarse")
    if frame is None:
        raise RuntimeError(f"the coarse atlas built under {build_into} has no rows")
    return "coarse", frame, Path(build_into)


def manifest(datasets: Path, grid: str) -> dict:
    """The dataset's ``atlas.json`` (empty where it is missing or unreadable)."""
    try:
        return json.loads((dataset.folder(datasets, grid) / "atlas.json").read_text())
    except (OSError, ValueError):
        return {}


# ---- HTML pieces -------------------------------------------------------------------------------------


def _esc(value, digits: int = 3) -> str:
    return html.escape(_fmt(value, digits))


def _num(value, digits: int = 3) -> str:
    """A number's cell, right-aligned."""
    return f"<td class='num'>{_esc(value, digits)}</td>"


def _text(text: str) -> str:
    """A text's cell, wrapping."""
    return f"<td class='text'>{html.escape(text)}</td>"


def _breakable(name: str) -> str:
    """An identifier escaped, with a break allowed after each underscore."""
    return html.escape(name).replace("_", "_<wbr>")


def _table(columns: list[str], rows: list[list[str]], cls: str = "sortable wrap") -> str:
    """A table of cells already written as HTML (each escaped by its writer), in a box that scrolls on
    its own when it is wider than the page."""
    head = "".join(f"<th>{html.escape(c)}</th>" for c in columns)
    body = "".join(
        "<tr>" + "".join(cell if cell.startswith("<td") else f"<td>{cell}</td>" for cell in row) + "</tr>"
        for row in rows
    )
    return (
        f"<div class='scroll'><table class='{html.escape(cls, quote=True)}'><thead><tr>{head}</tr></thead>"
        f"<tbody>{body}</tbody></table></div>"
    )


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def _verdict(verdict: str) -> str:
    cls = VERDICT_CLASS.get(verdict, "v-untested")
    return f"<span class='verdict {cls}'>{html.escape(verdict)}</span>"


def _anchor(model: str) -> str:
    return "model-" + "".join(c if c.isalnum() or c in "-_" else "-" for c in model)


def _model_title(model: str) -> str:
    return MODELS[model].title if model in MODELS else model


# ---- sections ----------------------------------------------------------------------------------------


def _intro(grid: str, version: str, frame: pd.DataFrame, info: dict) -> str:
    runs = info.get("runs", [])
    built = ""
    if runs:
        seconds = sum(float(r.get("seconds", 0.0)) for r in runs)
        points = sum(int(r.get("points", 0)) for r in runs)
        last = runs[-1]
        built = (
            f" Built in {len(runs)} run(s): {points} points solved in {seconds:.1f} s "
            f"({last.get('executor', '?')}, {last.get('workers') or '?'} worker(s) in the last run)."
        )
    which = (
        "the full grid (at least 10^4 points a model, built by hand with prbm-validate atlas)"
        if grid == "full"
        else "the coarse grid (a few hundred points a model, built by the report because the full atlas of "
        "this code is not there: prbm-validate atlas builds it)"
    )
    lead = (
        "The atlas maps every PRBM segment model against the exact elastica over its whole input space, "
        "and tells where each model holds to 0.5, 1, 3 and 5 % of L."
    )
    text = (
        f"Along lines of growing load (the shape inputs fixed) the PRBM's tip is compared with the exact tip "
        f"at the same load: errors are at equal load, in % of the segment length L. An error splits in two: the "
        f"path error (the PRBM read where the exact tip is on its path: the same tip angle, or b for a guided "
        f"end) and the stiffness error (the load the PRBM needs to reach that point, against the exact load). "
        f"This page shows {which}: {len(frame)} points over {frame['model'].nunique()} models, code version "
        f"{version}.{built}"
    )
    return f"<p class='lead prose'>{html.escape(lead)}</p><p class='prose'>{html.escape(text)}</p>"


def _measured_key(result, rows: pd.DataFrame, code: bytes) -> str:
    """What a case's measured levels depend on: its PRBM run's atlas inputs and expected errors, its rows
    of the tidy table (the PRBM's and the FEM's values), its length, and the code that reads them."""
    run = result.runs.get("prbm")
    extras = {k: run.extras.get(k) for k in ("atlas_model", "atlas_inputs", "atlas_mirror")}
    segment = getattr(result.loaded.case, "segment", None)
    shown = rows[rows["method"].isin(["prbm", "fem"])][["method", "quantity", "point", "level", "value"]]
    text = (
        repr(sorted(run.expected_error.items()))
        + repr(extras)
        + repr(getattr(segment, "length", None))
        + shown.to_csv(index=False)
    )
    return hashlib.sha256(code + text.encode()).hexdigest()


@dataclass(frozen=True)
class CaseMeasured:
    """One case's measured levels (``measured.measured_levels``) and what they depend on (``_measured_key``):
    worked out where the case's page is drawn (a worker of the report's pool, beside the other cases) and
    handed to ``write_page``, which then follows no PRBM along its line on the report's serial path."""

    key: str
    levels: tuple[measured.MeasuredLevel, ...]

    def entry(self) -> dict:
        """The case's entry of ``measured.json``."""
        return {"key": self.key, "levels": [dict(lv.__dict__) for lv in self.levels]}


@lru_cache(maxsize=1)
def _measured_code() -> bytes:
    """The code the measured levels depend on: the modules reading them and the atlas's code version."""
    here = Path(__file__).parents[1] / "atlas"
    code = b"".join(p.read_bytes() for p in (here / "measured.py", here / "lines.py"))
    return code + dataset.code_version().encode()


def read_measured(path: Path) -> dict:
    """A report's ``measured.json`` (its cases' measured levels, by case); empty where it is missing or
    unreadable."""
    try:
        entries: dict = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return {}
    return entries


def case_measured(result, rows: pd.DataFrame, cached: dict) -> CaseMeasured | None:
    """The measured levels of one case from its rows of the tidy table (None: its PRBM run has no atlas
    model); read from ``cached`` (``measured.json``'s entries, by case) when its key is there (following
    a chain PRBM along its line takes a second a level)."""
    if _atlas_run(result) is None:
        return None
    key = _measured_key(result, rows, _measured_code())
    old = cached.get(result.loaded.id, {})
    if old.get("key") == key:
        return CaseMeasured(key, tuple(measured.MeasuredLevel(**d) for d in old["levels"]))
    return CaseMeasured(key, tuple(measured.measured_levels([result], rows)))


def _atlas_run(result):
    """The case's PRBM run when it has an atlas model (None: the case has no measured levels)."""
    run = result.runs.get("prbm")
    return run if run is not None and run.extras.get("atlas_model") else None


def _measured_frame(
    results, table: pd.DataFrame, cached: dict, known: dict[str, CaseMeasured] | None = None
) -> tuple[pd.DataFrame, dict]:
    """``measured.measured_levels`` of every case (a frame) and the cache to keep: a case in ``known``
    (worked out in this run from its rows, beside its page) is taken as it is; another whose key
    (``_measured_key``) is in ``cached`` is read from it (``case_measured``). Only the rows of the cases
    worked out here are split off the table."""
    known = known or {}
    todo = {r.loaded.id for r in results if r.loaded.id not in known and _atlas_run(r) is not None}
    rows = table[table["case"].isin(todo)] if todo and len(table) and "case" in table else table.iloc[0:0]
    by_case = dict(tuple(rows.groupby("case", sort=False))) if len(rows) else {}
    keep: dict[str, dict] = {}
    levels: list[measured.MeasuredLevel] = []
    for result in results:
        cid = result.loaded.id
        got = known.get(cid) or (case_measured(result, by_case[cid], cached) if cid in by_case else None)
        if got is None:
            continue
        keep[cid] = got.entry()
        levels += got.levels
    return measured.frame_of(levels), keep


Draw = Callable[..., object]  # draw(function, *args): call it now, or have another process call it


def draw_now(function: Callable[..., object], *args: object) -> None:
    """``write_page``'s default ``draw``: the picture drawn here, now."""
    function(*args)


def _measured_section(levels: pd.DataFrame, figures: Path, draw: Draw = draw_now) -> tuple[str, dict]:
    # ``agreement`` of an empty frame (object columns) cannot take isfinite: no level, nothing to agree on
    agree = measured.agreement(levels) if len(levels) else {"levels": 0}
    body = ["<h2 id='measured'>Predicted against measured</h2>"]
    if levels.empty:
        body.append(f"<p>{html.escape(agreement_words(agree))}</p>")
        return "".join(body), agree
    scatter = figures / "scatter.png"
    scatter.unlink(missing_ok=True)  # may be a hard link to the previous report's
    draw(measured.draw_scatter, levels, scatter)
    split = (
        "Split of the measured error: the path error is the PRBM read at the FEM's tip angle (b for a "
        "guided end), its distance from the FEM's tip in % of L; the stiffness error is the load the PRBM "
        "needs for that deflection against the case's load, in %; the locus error is the distance from "
        "the FEM's tip to the curve the PRBM's tip traces, in % of L."
    )
    worst = levels.sort_values("measured", ascending=False, na_position="last").head(LARGEST)
    notes = worst["why_no_split"].fillna("").astype(str)
    columns = [
        "case",
        "level",
        "model",
        "predicted (% of L)",
        "measured (% of L)",
        "path (% of L)",
        "stiffness (%)",
        "locus (% of L)",
    ] + (["no split because"] if notes.ne("").any() else [])
    rows = []
    for (_, r), note in zip(worst.iterrows(), notes):
        cid = str(r["case"])
        row = [
            _link(f"cases/{cid}.html", cid),
            _num(r["level"]),
            _text(_model_title(r["model"])),
            _num(r["predicted"]),
            _num(r["measured"]),
            _num(r["path"]),
            _num(r["stiffness"]),
            _num(r["locus"]),
        ]
        if len(columns) > 8:
            row.append(_text(note))
        rows.append(row)
    body += [
        "<div class='pair'>",
        _image(f"{FIGURES}/{scatter.name}", "predicted against measured PRBM error"),
        f"<div class='words'><p><b>{html.escape(_capital(agreement_words(agree)))}</b></p>"
        f"<p class='caption'>Predicted: the atlas's expected PRBM tip error at the level's inputs (the "
        f"shipped error maps); measured: the PRBM-vs-FEM tip distance at the same load. "
        f"{html.escape(split)}</p></div></div>",
        f"<h3>The {len(worst)} levels with the largest measured error</h3>",
        _table(columns, rows),
    ]
    return "".join(body), agree


DOMAIN_SUMMARY = Path("sweeps") / "chapter4_domains" / "summary.json"  # the report's chapter-4 domain study


def _claims_section(frame: pd.DataFrame, claims: list, report: Path) -> tuple[str, pd.DataFrame]:
    """The claims table: the atlas's claims checked, then the chapter-4 bound claims the report's domain
    study checked (``atlas_claims.domain_study_rows``; they are about a domain boundary, not an atlas column)."""
    checked = atlas_claims.check_claims(frame, claims)
    try:
        summary = json.loads((report / DOMAIN_SUMMARY).read_text())
    except (OSError, ValueError):
        summary = []
    domain = atlas_claims.domain_study_rows(summary)
    if len(domain):
        checked = pd.concat([checked, domain], ignore_index=True)
    columns = [
        "id",
        "model",
        "source",
        "bound & metric",
        "verdict",
        "holds where",
        "worst",
        "share within",
        "quote and note",
    ]
    rows = []
    for _, r in checked.iterrows():
        models = [m.strip() for m in str(r["model"]).split(",")]
        model_links = ", ".join(
            _link(f"#{_anchor(m)}", _model_title(m)) if m in MODELS else html.escape(m) for m in models
        )
        where = str(r.get("holds_where") or r.get("why") or "")
        share = r["share_within"]
        details = (
            f"<details><summary>quote</summary><p class='quote'>{html.escape(str(r['quote']))}</p>"
            f"<p>{html.escape(str(r['note']))}</p>"
            + (f"<p>{html.escape(str(r['why']))}</p>" if str(r.get("why") or "") else "")
            + "</details>"
        )
        rows.append(
            [
                f"<td class='id' id='claim-{html.escape(str(r['id']), quote=True)}'>{_breakable(str(r['id']))}</td>",
                f"<td class='text'>{model_links}</td>",
                _text(str(r["source"])),
                f"|{_breakable(str(r['metric']))}| &le; {_esc(r['bound'])}",
                _verdict(str(r["verdict"])),
                _text(where),
                _num(r["worst"]),
                f"<td class='num'>{html.escape('' if pd.isna(share) else f'{100 * share:.0f} %')}</td>",
                f"<td class='quotes'>{details}</td>",
            ]
        )
    counts = checked["verdict"].value_counts()
    tally = "; ".join(f"{v}: {int(counts[v])}" for v in atlas_claims.VERDICTS if v in counts)
    caption = (
        f"{len(checked)} printed claims (cases/atlas/claims.toml) read onto the atlas: |metric| <= bound "
        f"on the model's solved points inside the claim's range ({tally}). Metrics: tip_error, path_error "
        f"in % of L; locus_error_rel, path_error_rel in % of the deflection; stiffness_error in %. "
        f"'Holds where' is the largest stretch of the claim's axis from its low end on which every point "
        f"is within; 'worst' is the largest |metric|, 'share within' that of the measured points."
    )
    return (
        "<h2 id='claims'>The seeds' claims, checked</h2>"
        f"<p class='caption'>{html.escape(caption)}</p>" + _table(columns, rows)
    ), checked


def _model_sections(frame: pd.DataFrame, claims: list, checked: pd.DataFrame, figures: Path) -> str:
    body = []
    maps = map_figure.MapFigure()  # every map on one figure
    for name, m in MODELS.items():
        if not (frame["model"] == name).any():
            continue
        picture = figures / f"map_{name}.png"
        picture.unlink(missing_ok=True)
        maps.draw(frame, name, picture, claims)
        sentences = "".join(f"<li>{html.escape(regions.region_words(s))}</li>" for s in regions.summaries(frame, name))
        mine = checked[checked["model"].astype(str).str.split(", ").map(lambda ms: name in ms)]
        claimed = "".join(
            f"<li><a href='#claim-{html.escape(str(r['id']), quote=True)}'>{_breakable(str(r['id']))}"
            f"</a> {_verdict(str(r['verdict']))}</li>"
            for _, r in mine.iterrows()
        )
        points = int((frame["model"] == name).sum())
        body.append(
            f"<h2 id='{_anchor(name)}'>{html.escape(m.title)}</h2>"
            f"<p class='caption'>{html.escape(m.source)} &middot; load: {html.escape(m.load.label)} &middot; "
            f"{points} atlas rows</p><div class='pair'>"
            + f"<p><img class='map' src='{html.escape(f'{FIGURES}/{picture.name}', quote=True)}' "
            f"alt='{html.escape(f'error map of {m.title}', quote=True)}'></p>"
            + "<div class='words'><p>Tip error at equal load, regions (the worst line at each value of the map "
            f"axis):</p><ul class='regions'>{sentences}</ul>"
            + (f"<p>The seeds' claims on this model:</p><ul class='regions'>{claimed}</ul>" if claimed else "")
            + "</div></div>"
        )
    return "".join(body)


def _refit_section(frame: pd.DataFrame) -> str:
    tables, texts = [], []
    for name, kind in REFIT_MODELS:
        rows = frame[frame["model"] == name]
        if rows.empty:
            continue
        table = refit.refit_table(rows.dropna(axis=1, how="all"), kind)
        texts.append(
            refit.finding_text(table)
            if len(table)
            else f"{_model_title(name)}: no region of the atlas had points to refit."
        )
        if len(table):
            tables.append(table)
    body = [
        "<h2 id='refit'>Beyond the seeds: refit (gamma, K_Theta)</h2>",
        "<p class='caption'>One constant (gamma, K_Theta) per region, chosen to minimise the worst tip error "
        "(at equal load) on half of the region's atlas points; both it and the published n-fits are then "
        "judged on the other half (held out). Gain: the published worst over the refit worst (above 1: the "
        "refit is better).</p>",
    ]
    if tables:
        t = pd.concat(tables, ignore_index=True)
        columns = [
            "model",
            "region",
            "gamma",
            "K_Theta",
            "published gamma (mean)",
            "published K_Theta (mean)",
            "published worst (% of L)",
            "refit worst (% of L)",
            "gain",
            "fit / held-out points",
        ]
        rows = [
            [
                html.escape(str(r["model"])),
                _text(str(r["region"])),
                _num(r["gamma"], 4),
                _num(r["K_theta"], 4),
                _num(r["gamma_published"], 4),
                _num(r["K_theta_published"], 4),
                _num(r["published_worst"]),
                _num(r["refit_worst"]),
                _num(r["gain"]),
                _num(f"{r['fit_points']} / {r['test_points']}"),
            ]
            for _, r in t.iterrows()
        ]
        body.append(_table(columns, rows))
    body += [f"<p class='prose'>{html.escape(text)}</p>" for text in texts]
    return "".join(body)


# ---- the page ----------------------------------------------------------------------------------------


def _source_digest() -> bytes:
    here = Path(__file__)
    atlas = here.parents[1] / "atlas"
    return b"".join(
        p.read_bytes()
        for p in (
            here,
            atlas / "regions.py",
            atlas / "map_figure.py",
            atlas / "minor_ticks.py",
            atlas / "claims.py",
            atlas / "refit.py",
            atlas / "models.py",
        )
    )


def _static_digest(grid: str, version: str, frame: pd.DataFrame, claims_file: Path, report: Path) -> str:
    """What the atlas-only part of the page depends on: grid, version, rows, claims, the chapter-4 domain
    study's summary (its bound claims join the table), the code drawing it."""
    rows = pd.util.hash_pandas_object(frame[["line_id", "load", "tip_error"]], index=False).to_numpy()
    try:
        domain = (report / DOMAIN_SUMMARY).read_bytes()
    except OSError:
        domain = b""
    parts = [
        grid.encode(),
        version.encode(),
        str(len(frame)).encode(),
        rows.tobytes(),
        Path(claims_file).read_bytes(),
        domain,
        _source_digest(),
    ]
    return hashlib.sha256(b"\0".join(parts)).hexdigest()


def _static_part(frame: pd.DataFrame, grid: str, version: str, figures: Path, claims_file: Path) -> str:
    """The claims, the model sections and the refit: read from ``figures`` when its digest matches,
    else drawn again (the folder emptied first: its files may be hard links to the previous report's)."""
    digest = _static_digest(grid, version, frame, claims_file, figures.parent)
    stamp, cached = figures / "static.digest", figures / "static.html"
    try:
        if stamp.read_text() == digest and cached.is_file():
            names = json.loads((figures / "static.json").read_text())
            if all((figures / n).is_file() for n in names):
                return cached.read_text()
    except (OSError, ValueError):
        pass
    shutil.rmtree(figures, ignore_errors=True)
    figures.mkdir(parents=True)
    claims = atlas_claims.load_claims(claims_file)
    claims_html, checked = _claims_section(frame, claims, figures.parent)
    text = claims_html + _model_sections(frame, claims, checked, figures) + _refit_section(frame)
    cached.write_text(text)
    (figures / "static.json").write_text(json.dumps(sorted(p.name for p in figures.glob("map_*.png"))))
    stamp.write_text(digest)
    return text


def write_page(
    out: Path,
    grid: str,
    frame: pd.DataFrame,
    results=(),
    table: pd.DataFrame | None = None,
    datasets: Path | None = None,
    claims_file: Path = CLAIMS,
    known: dict[str, CaseMeasured] | None = None,
    draw: Draw = draw_now,
) -> AtlasPage:
    """``atlas.html`` (and its pictures under ``atlas_figures/``) in ``out`` from the atlas ``frame`` on
    ``grid``, with the cases' ``results`` and their tidy ``table`` (module docstring); ``datasets``: the
    folder holding the dataset (for its ``atlas.json``); ``known``: cases' measured levels this run
    already worked out from the same ``results`` and rows (``case_measured``, by case), taken as they
    are; ``draw``: how the scatter is drawn (``draw_now``, or handed to another process: the caller then
    waits for it)."""
    started = time.perf_counter()
    out = Path(out)
    figures = out / FIGURES
    info = manifest(datasets, grid) if datasets is not None else {}
    version = str(info.get("version") or dataset.code_version())
    cached = read_measured(figures / MEASURED)
    static = _static_part(frame, grid, version, figures, claims_file)  # first: it may empty the folder
    levels, keep = _measured_frame(list(results), table if table is not None else pd.DataFrame(), cached, known)
    (figures / MEASURED).unlink(missing_ok=True)  # may be a hard link
    (figures / MEASURED).write_text(json.dumps(keep))
    measured_html, agree = _measured_section(levels, figures, draw)
    toc = " &middot; ".join(
        [
            _link("#measured", "predicted against measured"),
            _link("#claims", "claims"),
            *(_link(f"#{_anchor(n)}", m.title) for n, m in MODELS.items() if (frame["model"] == n).any()),
            _link("#refit", "refit"),
        ]
    )
    body = (
        "<p><a href='index.html'>the report</a></p><h1>PRBM validity atlas</h1>"
        + _intro(grid, version, frame, info)
        + f"<nav class='toc'>{toc}</nav>"
        + measured_html
        + static
        + f"<p class='caption'>Page drawn in {time.perf_counter() - started:.1f} s.</p>"
    )
    (out / PAGE).unlink(missing_ok=True)
    (out / PAGE).write_text(_page("PRBM validity atlas", body, f"<style>{CSS}</style>"))
    return AtlasPage(PAGE, grid, version, agree)


def prepare_static(out: Path, datasets: Path, build: bool = True) -> None:
    """The atlas-only part of the page (claims, maps, regions, refit) drawn ahead into ``out/atlas_figures``
    with its digest, from the atlas found under ``datasets`` or (with ``build``) the coarse one built under
    ``out/atlas`` in this process: a task of the report's pool beside the cases (a pool worker cannot start
    processes of its own), so that ``write_page`` later finds it drawn and only adds the cases' part."""
    found = find_atlas(datasets, Path(out) / DATASETS if build else None, workers=1, executor="serial")
    if found is None:
        return
    grid, frame, where = found
    version = str(manifest(where, grid).get("version") or dataset.code_version())
    _static_part(frame, grid, version, Path(out) / FIGURES, CLAIMS)


def build_page(
    out: Path,
    results,
    table: pd.DataFrame,
    datasets: Path,
    build: bool = True,
    workers: int = 2,
    known: dict[str, CaseMeasured] | None = None,
    draw: Draw = draw_now,
) -> AtlasPage | None:
    """The atlas page of a report written in ``out``: the best atlas under ``datasets`` (the published
    report's ``atlas/``), else (with ``build``) the coarse atlas built under ``out/atlas`` (carried with
    the report's folder); None where there is none and ``build`` is False. ``known``, ``draw``: as
    ``write_page``."""
    found = find_atlas(datasets, Path(out) / DATASETS if build else None, workers=workers)
    if found is None:
        return None
    grid, frame, where = found
    return write_page(out, grid, frame, results, table, where, known=known, draw=draw)
