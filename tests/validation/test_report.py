"""The report: every image and link resolves, its tables say what the results say, the summary
reads in words and short numbers, and it works in a real browser (headless Chromium)."""

import html
import contextlib
import math
import os
import re
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from validation.case.loader import case_by_id
from validation.methods.base import MethodRun, RunStatus
from validation.report.build import build_report, glance
from validation.report.charts import outputs_chart
from validation.report.paraview import MAX_FRAMES, frames_shown
from validation.run.verdict import Verdict, run_verdict
from validation.report.overview import OverviewPoint, model_style, overview_points, plot_overview
from validation.report.summary import CaseSummary, MethodState, round_numbers, summary_tables_html
from validation.run.case_run import run_case
from validation.run.outcome import summary, tabulate

REPORT_CASES = ["cantilever_tip_load", "follower_tip_load", "bapat2015_test2"]
# one worker for the whole module, so the report (``built_report``, module scope) is built once, not once per worker
pytestmark = pytest.mark.xdist_group("report")


@pytest.fixture(scope="module")
def built_report(tmp_path_factory) -> Path:
    """One report of two benchmark segments (one with the PRBM) and a mechanism case with findings."""
    folder = tmp_path_factory.mktemp("report")
    build_report(folder, use_cache=False, jobs=1, cases=REPORT_CASES)
    return folder


def test_report_links_resolve_and_tables_match(built_report):
    tmp_path = built_report
    pages = [tmp_path / "index.html", *sorted((tmp_path / "cases").glob("*.html"))]
    assert len(pages) >= 2
    for page in pages:
        text = page.read_text()
        for target in re.findall(r"(?:src|href)='([^'#]+)'", text):
            assert (page.parent / target).resolve().exists(), f"{page.name}: broken link {target}"
    results = pd.read_csv(tmp_path / "results.csv")
    shown = pd.read_csv(tmp_path / "summary.csv")
    expected = summary(results)
    pd.testing.assert_frame_equal(shown.reset_index(drop=True), expected.reset_index(drop=True), check_dtype=False)
    case_page = (tmp_path / "cases" / "cantilever_tip_load.html").read_text()
    fem_rows = results[(results["method"] == "fem") & (results["quantity"] == "y") & (results["level"] == 9)]
    assert f"{fem_rows['value'].iloc[0]:.6g}" in case_page  # the page shows the computed value
    md = (tmp_path / "index.md").read_text()
    assert "cantilever_tip_load" in md and "Reproducibility" in md


def test_glance_differences_are_the_differences_of_the_values():
    table = tabulate(run_case(case_by_id("cantilever_tip_load"), use_cache=False))
    view = glance(table)
    assert len(view) == 30  # x, y, rotation at 10 levels
    assert ((view["PRBM - FEM"] - (view["prbm"] - view["fem"])).abs() < 1e-12).all()
    assert ((view["FEM - exact"] - (view["fem"] - view["elastica"])).abs() < 1e-12).all()
    row = view[(view["quantity"] == "y") & (view["load"] == "9")].iloc[0]
    assert row["printed exact"] == 0.810609  # the reference from the case file, beside the methods


def _glance_by_pivot_and_join(table: pd.DataFrame) -> pd.DataFrame:
    """The at-a-glance table by the pandas formulation it replaces: per (quantity, point, level) the
    first value of each method and of each printed label, as two frames indexed by the sorted keys
    with a number, the printed one left-joined on the methods' rows."""
    key_names = ["quantity", "point", "level"]
    rows = [r for r in table.itertuples(index=False) if not pd.isna(r.quantity)]

    def spread(label_of, value_of, prefix=""):
        first = {}
        for r in rows:
            if not pd.isna(label_of(r)):
                first.setdefault((r.quantity, r.point, r.level), {}).setdefault(label_of(r), value_of(r))
        labels = sorted(
            {c for part in first.values() for c in part if not all(pd.isna(p.get(c, np.nan)) for p in first.values())}
        )
        keys = sorted(k for k, part in first.items() if any(not pd.isna(part.get(c, np.nan)) for c in labels))
        index = (
            pd.MultiIndex.from_tuples(keys, names=key_names)
            if keys
            else pd.MultiIndex.from_arrays([[], [], []], names=key_names)
        )
        return pd.DataFrame(
            {prefix + c: np.array([first[k].get(c, np.nan) for k in keys], float) for c in labels}, index=index
        )

    out = spread(lambda r: r.method, lambda r: r.value).join(
        spread(lambda r: r.reference_label, lambda r: r.reference_value, "printed "), how="left"
    )
    estimates = {}
    for r in rows:
        if r.method == "fem":
            estimates.setdefault((r.quantity, r.point, r.level), r.error_estimate)
    if estimates:
        out["fem ± (estimate)"] = [estimates.get(k, np.nan) for k in out.index]
    for name, left, right in (
        ("PRBM - FEM", "prbm", "fem"),
        ("PRBM - measured", "prbm", "printed measured"),
        ("FEM - measured", "fem", "printed measured"),
        ("FEM - exact", "fem", "elastica"),
    ):
        if {left, right} <= set(out.columns):
            out[name] = out[left] - out[right]
    loads, units = {}, {}
    for r in rows:
        loads.setdefault((r.quantity, r.point, r.level), r.level_label)
        units.setdefault(r.quantity, r.unit)
    out = out.reset_index()
    out.insert(3, "load", [loads.get(k, k[2]) for k in zip(out["quantity"], out["point"], out["level"])])
    out.insert(1, "unit", out["quantity"].map(units))
    return out.drop(columns=["level"])


def test_glance_is_the_pivot_of_the_results_on_tables_no_case_has():
    """glance (built in one go, issue 15) equals the pivot-and-join formulation, frame and dtypes, on
    random result tables: missing values and labels, NaN or float levels, printed labels with no
    method value, empty tables.

    Every third table is tiny (1-4 rows: often no method value at all, the empty frame's dtypes); the others
    are up to 79 rows over the same 60 keys, so two methods (or two FEM estimates) often share a key and a
    wrong difference column, sign or first-of-duplicates shows.  Planted errors (a sign flip or a factor 1.1
    on PRBM - FEM or FEM - exact, the last FEM estimate instead of the first, float empty key columns) are
    each caught by 7 or more of these 80 tables (seeds 15, 1 and 2)."""
    rng = np.random.default_rng(15)
    columns = [
        "quantity",
        "point",
        "level",
        "method",
        "value",
        "reference_label",
        "reference_value",
        "error_estimate",
        "level_label",
        "unit",
    ]
    pick = lambda options: options[rng.integers(len(options))]  # noqa: E731
    nan_or = lambda p: math.nan if rng.random() < p else float(rng.uniform(-2.0, 2.0))  # noqa: E731
    for trial in range(80):
        rows = [
            {
                "quantity": pick(["x", "y", "rotation", None]),
                "point": pick(["tip", "", "A"]),
                "level": int(rng.integers(5)),
                "method": pick(["fem", "prbm", "elastica", "bcm", None]),
                "value": nan_or(0.3),
                "reference_label": pick([None, "measured", "ANSYS", "exact"]),
                "reference_value": nan_or(0.3),
                "error_estimate": nan_or(0.5),
                "level_label": pick([None, "P = 1 N", "2 N"]),
                "unit": pick(["mm", "deg", None]),
            }
            for _ in range(int(rng.integers(1, 80 if trial % 3 else 5)))
        ]
        table = pd.DataFrame(rows, columns=columns)
        if trial % 2:
            table["level"] = table["level"].astype(float)
        if table["quantity"].isna().all():
            continue
        pd.testing.assert_frame_equal(glance(table), _glance_by_pivot_and_join(table), check_exact=True)


def test_summary_reads_in_words_and_short_numbers(built_report):
    index = (built_report / "index.html").read_text()
    tables = re.findall(r"<table class='summary sortable'>.*?</table>", index, flags=re.S)
    assert len(tables) == 2  # chapter 9, benchmarks
    headers = {h for t in tables for h in re.findall(r"<th>(.*?)</th>", t)}
    assert "PRBM vs FEM, max % of L" in headers and "FEM time" in headers
    assert not [h for h in headers if "_" in h or re.fullmatch(r"[a-z]+", h)], headers  # no code identifiers
    generated = "".join(tables) + "".join(re.findall(r"<ul class='evidence'>.*?</ul>", index, flags=re.S))
    shown = re.sub(r"<[^>]+>", " ", generated)  # cell text, not attributes (data-value keeps the raw number)
    numbers = re.findall(r"(?<![\w.])\d[\d.]*(?:e[+-]?\d+)?", shown)
    assert numbers
    too_long = [n for n in numbers if len(re.sub(r"^[0.]+", "", n.split("e")[0]).replace(".", "")) > 4]
    assert not too_long, too_long


def test_summary_numbers_and_sentence_say_what_the_results_say(built_report):
    expected = summary(pd.read_csv(built_report / "results.csv")).set_index("case")
    index = (built_report / "index.html").read_text()
    for case in ("cantilever_tip_load", "bapat2015_test2"):
        row = re.search(rf">{case}</a></td>(.*?)</tr>", index, flags=re.S).group(1)
        pct = 100 * expected.loc[case, "max_prbm_fem_per_length"]
        assert f"{pct:.3g} %</td>" in row  # the colour-scaled cell
        assert f"PRBM within {pct:.3g} % of L of the FEM" in row  # the one-sentence result
        page = (built_report / "cases" / f"{case}.html").read_text()
        assert re.search(rf"<p class='lead'><b>PRBM within {re.escape(f'{pct:.3g}')} % of L", page)
    cantilever = re.search(r">cantilever_tip_load</a></td>(.*?)</tr>", index, flags=re.S).group(1)
    results = pd.read_csv(built_report / "results.csv")
    enforced = results[(results["case"] == "cantilever_tip_load") & results["within_tolerance"].notna()]
    assert len(enforced) > 31  # the 31 printed numbers and the checks between methods
    verdicts = summary(results).set_index("case")["verdict"]
    assert f">{html.escape(verdicts['cantilever_tip_load'])}<" in cantilever
    assert f"{len(enforced)} of {len(enforced)}" in cantilever
    test2 = re.search(r">bapat2015_test2</a></td>(.*?)</tr>", index, flags=re.S).group(1)
    assert f">{html.escape(verdicts['bapat2015_test2'])}<" in test2
    assert verdicts["bapat2015_test2"] == "no limit claimed"  # its points against the measured: no limit


def test_output_chart_draws_the_values_against_the_load_with_units():
    """The outputs chart's numbers are the results' (7 significant digits) against the case's load levels
    (cantilever_tip_load: PL^2/EI = 1..10, notes/anchors.md section 2.1), one legend entry per method."""
    result = run_case(case_by_id("cantilever_tip_load"), use_cache=False)
    table = tabulate(result)
    chart = outputs_chart("outputs", np.arange(1.0, 11.0), "force at tip [EI/L^2]", table)
    titles = {k: v["title"]["text"] for k, v in chart.layout.items() if k.startswith("yaxis")}
    panel = next(k for k, t in titles.items() if t == "y position at tip [L]")
    suffix = panel.removeprefix("yaxis")
    fem = next(t for t in chart.data if t["name"] == "FEM" and t["yaxis"] == f"y{suffix}")
    rows = table[(table["method"] == "fem") & (table["quantity"] == "y")].drop_duplicates("level").sort_values("level")
    assert fem["y"] == pytest.approx(rows["value"].tolist(), rel=1e-6)
    assert fem["x"] == pytest.approx(list(range(1, 11)))
    assert chart.layout[f"xaxis{suffix}"]["title"]["text"] == "force at tip [EI/L^2]"
    exact = next(t for t in chart.data if t["name"] == "printed: exact" and t["yaxis"] == f"y{suffix}")
    assert exact["y"][-1] == 0.810609  # the case file's printed value at PL^2/EI = 10
    legend = [t["name"] for t in chart.data if t["showlegend"]]
    assert sorted(legend) == sorted(set(t["name"] for t in chart.data))  # each name once in the legend
    assert {"FEM", "PRBM", "exact elastica"} <= set(legend)


def test_one_number_of_a_whole_case_is_no_panel_of_the_outputs_chart(built_report):
    """Test 2 asks for the mechanism's degrees of freedom (one count of the PRBM, printed 1 in seed 000
    section 9.3) beside the coupler point's dx and dy at the design torques: the chart draws dx and dy
    against the torque and no 'dof' panel (a point at the first torque would say the count belongs to
    it); the page's table still gives the count. A case whose only output is such a number draws no chart."""
    page = (built_report / "cases" / "bapat2015_test2.html").read_text()
    spec = re.search(r"<div id='outputs'.*?const f=(.*?);Plotly\.newPlot\('outputs'", page, flags=re.S).group(1)
    titles = re.findall(r'"text":"([^"]*\[[^"]*\])"', spec)
    assert {"x displacement at P [in]", "y displacement at P [in]"} <= set(titles)
    assert not [t for t in titles if t.startswith("degrees of freedom")]
    assert re.search(r"<td>prbm</td><td>dof</td><td></td><td>P0 \(unloaded\)</td><td>1</td><td>count</td>", page)
    table = tabulate(run_case(case_by_id("bapat2015_test3_specimen1"), use_cache=False))
    assert set(table["quantity"].dropna()) == {"dof"}
    assert outputs_chart("outputs", np.arange(1.0), "load level", table) is None


def test_a_continuation_writes_and_draws_its_limit_points_and_a_few_dozen_frames():
    """A continuation of hundreds of steps: its ParaView series keeps evenly spaced steps, the first, the
    last and every turning point of the load (a limit point), not every step."""
    load = np.concatenate([np.linspace(0, 3, 150), np.linspace(3, 2, 100), np.linspace(2, 9, 150)])
    kept = frames_shown(load)
    assert kept[0] == 0 and kept[-1] == len(load) - 1
    assert {149, 249} <= set(kept)  # the load's maximum and minimum
    assert len(kept) <= MAX_FRAMES + 2
    assert frames_shown(np.arange(12.0)) == list(range(12))  # a short series: every frame


def test_overview_axes_are_the_fem_deflection_and_the_prbm_error():
    result = run_case(case_by_id("cantilever_tip_load"), use_cache=False)
    table = tabulate(result)
    points = {p.level: p for p in overview_points([result], table)}
    assert sorted(points) == list(range(10))
    fem = table[table["method"] == "fem"].drop_duplicates(["quantity", "level"]).set_index(["quantity", "level"])
    prbm = table[table["method"] == "prbm"].drop_duplicates(["quantity", "level"]).set_index(["quantity", "level"])
    for level in (0, 9):  # the tip moves most (L = 1); the error is the larger of |dx| and |dy|
        x, y = fem.loc[("x", level), "value"], fem.loc[("y", level), "value"]
        assert points[level].deflection == pytest.approx(((x - 1.0) ** 2 + y**2) ** 0.5, rel=1e-9)
        error = max(abs(prbm.loc[(q, level), "value"] - fem.loc[(q, level), "value"]) for q in ("x", "y"))
        assert points[level].error_percent == pytest.approx(100 * error, rel=1e-9)


def test_overview_gives_every_model_its_own_look(tmp_path, monkeypatch):
    """The overview tells its PRBM models apart by colour and marker: the report's 16 models (and up to
    100) each get a (colour, marker) of their own; tab10 alone gave the 11th model the 1st's colour."""
    import matplotlib.axes

    drawn = []
    scatter = matplotlib.axes.Axes.scatter

    def recording(self, *args, **kwargs):
        drawn.append((tuple(kwargs["color"]), kwargs.get("marker", "o")))
        return scatter(self, *args, **kwargs)

    monkeypatch.setattr(matplotlib.axes.Axes, "scatter", recording)
    points = [OverviewPoint(f"case{k}", 0, 0.1 * (1 + k % 5), 1.0 + k, f"model {k:02d}") for k in range(16)]
    plot_overview(points, tmp_path / "overview.png")
    assert len(drawn) == 16 and len(set(drawn)) == 16
    assert len({model_style(k) for k in range(100)}) == 100


def test_run_verdict_reads_the_state_of_a_run():
    assert run_verdict(MethodRun(values={}))[0] is None  # it gave its values: rows decide
    refused = MethodRun(
        values={}, converged=False, message="not applicable: no PRBM for a closed ring", status=RunStatus.NOT_APPLICABLE
    )
    assert run_verdict(refused) == (Verdict.REFUSED, "no PRBM for a closed ring")
    assert run_verdict(MethodRun(values={}, converged=False, message="error: ValueError: x"))[0] is Verdict.FAILED
    assert run_verdict(MethodRun(values={}, converged=False, message="Newton stalled"))[0] is Verdict.NOT_CONVERGED
    assert run_verdict(refused, expected="a ring")[0] is Verdict.EXPECTED


def _chromium(scratch):
    """A headless Chromium driven by selenium, or a skip saying what is missing. Its profile and its
    temporary files (the singleton socket folder it would otherwise leave in /tmp) go to ``scratch``
    (a short path: a unix socket's path has at most 107 characters, which pytest's tmp_path under a
    worker of pytest-xdist can pass)."""
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed")
    binary = shutil.which("chromium") or shutil.which("chromium-browser")
    driver_path = shutil.which("chromedriver")
    if not binary or not driver_path:
        pytest.skip("Chromium or chromedriver is absent (Debian: apt-get install chromium chromium-driver)")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = binary
    for flag in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--disable-component-update",
        "--no-first-run",
        "--window-size=1280,800",
        f"--user-data-dir={scratch / 'profile'}",
    ):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(driver_path, env={**os.environ, "TMPDIR": str(scratch)}), options=options)


@contextlib.contextmanager
def chromium_session():
    """A headless Chromium (``_chromium``, 1280 x 800) in a scratch profile, quit and its profile removed
    afterwards (or a skip saying what is missing); ``window`` sizes it for a test."""
    scratch = Path(tempfile.mkdtemp(prefix="chromium-"))
    try:
        browser = _chromium(scratch)
    except BaseException:
        shutil.rmtree(scratch, ignore_errors=True)
        raise
    try:
        yield browser
    finally:
        browser.quit()
        shutil.rmtree(scratch, ignore_errors=True)


@contextlib.contextmanager
def window(browser, width: int = 1280, height: int = 800):
    """``browser`` (the worker's one Chromium, ``chromium`` in tests/validation/conftest.py) sized ``width`` x
    ``height`` (by default the size it starts at), on a blank page, the console log of the pages loaded
    before read and dropped: as a new session at that size would be."""
    browser.set_window_size(width, height)
    browser.get("about:blank")
    browser.get_log("browser")
    yield browser


def test_report_in_a_real_browser(built_report, chromium):
    with window(chromium) as browser:
        pages = [built_report / "index.html", *sorted((built_report / "cases").glob("*.html"))]
        for page in pages:
            browser.get(page.as_uri())
            broken = browser.execute_script(
                "return [...document.images].filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.src)"
            )
            assert broken == [], f"{page.name}: images that do not load: {broken}"
            errors = [e for e in browser.get_log("browser") if e["level"] == "SEVERE"]
            assert errors == [], f"{page.name}: console errors {errors}"
            # every chart drawn by plotly.js: its axes titled with units, a legend entry per method
            charts = browser.execute_script(
                "return [...document.querySelectorAll('div.chart')].map(c => [c.id, "
                "c.querySelectorAll('svg.main-svg').length, "
                '[...c.querySelectorAll(\'.g-xtitle, .g-ytitle, [class*="g-x"][class*="title"], '
                '[class*="g-y"][class*="title"]\')].map(t => t.textContent), '
                "[...c.querySelectorAll('.legend .traces .legendtext')].map(t => t.textContent)])"
            )
            for chart_id, svgs, titles, legend in charts:
                assert svgs > 0, f"{page.name}: chart {chart_id} not drawn"
                assert titles and all("[" in t for t in titles if t), f"{page.name} {chart_id}: {titles}"
                assert legend, f"{page.name}: chart {chart_id} has no legend"
            if page.name == "cantilever_tip_load.html":
                by_id = {c[0]: c for c in charts}
                assert {"FEM", "PRBM", "exact elastica", "printed: exact [notes/anchors.md §2.1]"} <= set(
                    by_id["outputs"][3]
                )
                assert {"FEM", "PRBM", "exact elastica"} <= set(by_id["shapes"][3])
        browser.get((built_report / "index.html").as_uri())
        # the first screen shows the picture of the whole validation
        top, bottom, height = browser.execute_script(
            "const r = document.getElementById('overview').getBoundingClientRect();"
            "return [r.top, r.bottom, window.innerHeight]"
        )
        assert 0 <= top and bottom <= height, (top, bottom, height)
        # sorting a column: click the FEM-time header of the benchmarks table (two cases), twice
        column, table = "FEM time", 1
        index = browser.execute_script(
            "return [...document.querySelectorAll('table.summary')[arguments[1]].tHead.rows[0].cells]"
            ".findIndex(c => c.innerText.trim() === arguments[0])",
            column,
            table,
        )
        assert index > 0
        read = (
            "return [...document.querySelectorAll('table.summary')[arguments[1]].tBodies[0].rows]"
            ".map(r => r.cells[arguments[0]].dataset.value)"
        )
        click = "document.querySelectorAll('table.summary')[arguments[1]].tHead.rows[0].cells[arguments[0]].click()"
        for order in (sorted, lambda v: sorted(v, reverse=True)):
            browser.execute_script(click, index, table)
            values = [float(v) for v in browser.execute_script(read, index, table)]
            assert len(values) == 2 and values[0] != values[1] and values == order(values)


def test_messages_in_the_summary_keep_four_significant_digits():
    text = "no convergence between t = 0.209595 and 0.3 at theta20 = 15.86, EI 1.0172526e-5, r1..r4"
    assert (
        round_numbers(text) == "no convergence between t = 0.2096 and 0.3 at theta20 = 15.86, EI 1.017e-05, r1..r4"
    )  # the input, not output, rounded


def test_an_absent_prbm_fem_number_shows_the_case_reason():
    row = CaseSummary(
        group="chapter 9",
        case="x",
        title="t",
        verdict=Verdict.WITHIN,
        reason="",
        methods=[MethodState("prbm", Verdict.WITHIN, "")],
        sentence="s.",
        prbm_fem_length=math.nan,
        prbm_fem_relative=math.nan,
        fem_estimate=math.nan,
        checks=0,
        checks_passed=0,
        findings=0,
        no_prbm_fem="geometry not in the seed",
    )
    cell = re.search(r"<td class='absent'[^>]*>(.*?)</td>", summary_tables_html([row], {})).group(1)
    assert cell == "geometry not in the seed"
    without = summary_tables_html([CaseSummary(**{**row.__dict__, "no_prbm_fem": ""})], {})
    assert "no FEM in this case" in without
