"""The report as an engineer reads it: headless Chromium at a 1366 x 900 window loads the index and every
case page of a small report (a segment case, a mechanism case and a user's case with no printed values)
and checks, in the page, that nothing is wider than the window, that the index is scrolled once (under
6000 px with every chapter expanded, the findings folded), that no plotly legend lies over a plot area,
and that no 'NaN' is shown. A screenshot of each page goes to the folder named by ``REPORT_SCREENSHOTS``
(a CI artefact), else to the test's temporary folder."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from tests.validation.test_report import window
from validation.report.build import build_report

WIDTH, HEIGHT = 1366, 900
INDEX_HEIGHT = 6000  # px at WIDTH: the index an engineer scrolls once
USER_CASE_ID = "layout_user_cantilever"
USER_CASE = f"""
[case]
id = "{USER_CASE_ID}"
title = "A user's cantilever with no printed values"
group = "user cases"
units = "in-lb"

[segment]
boundary = "fixed-free"
length = 10.0
E = 30e6
section = {{ kind = "rectangle", width = 0.5, thickness = 0.0625 }}

[[loads]]
kind = "force"
point = "tip"
direction = [0.0, 1.0]
values = [0.5, 1.0, 1.5]

[[outputs]]
quantity = "x"
[[outputs]]
quantity = "y"

[methods.fem]
[methods.prbm]
"""
CASES = ["cantilever_tip_load", "bapat2015_test2"]  # a segment, a mechanism
PAGES = ["index.html", *(f"cases/{case}.html" for case in CASES + [USER_CASE_ID])]
# one worker builds the report and runs the browser, the one Chromium of test_report.py and test_report_case_pages.py
pytestmark = pytest.mark.xdist_group("report")

# each plotly chart: its legend's box and the boxes of its plot areas (the subplots' background
# rectangles, else their drag areas, which cover the plot area exactly)
CHART_BOXES = """
const box = e => { const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; };
return [...document.querySelectorAll('.js-plotly-plot')].map(chart => {
  const legend = chart.querySelector('.legend');
  let areas = [...chart.querySelectorAll('.bglayer rect.bg')];
  if (!areas.length) areas = [...chart.querySelectorAll('.nsewdrag')];
  return [chart.id || '(no id)', legend ? box(legend) : null, areas.map(box)];
});"""


@pytest.fixture(scope="module")
def layout_report(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("layout")
    user = folder / f"{USER_CASE_ID}.toml"
    user.write_text(USER_CASE)
    build_report(folder / "report", use_cache=False, jobs=1, cases=CASES + [str(user)])
    return folder / "report"


@pytest.fixture(scope="module")
def browser(chromium):
    with window(chromium, WIDTH, HEIGHT) as driver:
        yield driver


@pytest.fixture(scope="module")
def shots(tmp_path_factory) -> Path:
    folder = Path(os.environ.get("REPORT_SCREENSHOTS") or tmp_path_factory.mktemp("screenshots"))
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def load(browser, report: Path, page: str, shots: Path):
    """The page loaded at WIDTH, its chapters (if folded) expanded, and its first screen saved."""
    path = report / page
    assert path.is_file(), f"{page} was not written"
    browser.get(path.as_uri())
    browser.execute_script("document.querySelectorAll('details.chapter').forEach(d => d.open = true)")
    assert browser.execute_script("return window.innerWidth") == WIDTH
    browser.save_screenshot(str(shots / (page.replace("/", "_").removesuffix(".html") + ".png")))
    return browser


def overlap(a, b) -> float:
    """The area two boxes (left, top, right, bottom) share."""
    return max(0.0, min(a[2], b[2]) - max(a[0], b[0])) * max(0.0, min(a[3], b[3]) - max(a[1], b[1]))


@pytest.mark.parametrize("page", PAGES)
def test_no_page_is_wider_than_the_window(layout_report, browser, shots, page):
    load(browser, layout_report, page, shots)
    width, window = browser.execute_script("return [document.documentElement.scrollWidth, window.innerWidth]")
    assert width <= window, f"{page}: {width} px wide in a {window} px window"


@pytest.mark.parametrize("page", PAGES)
def test_no_legend_lies_over_a_plot_area(layout_report, browser, shots, page):
    load(browser, layout_report, page, shots)
    for chart, legend, areas in browser.execute_script(CHART_BOXES):
        assert areas, f"{page}: chart {chart} has no plot area"
        if legend is None:
            continue
        covered = [overlap(legend, area) for area in areas]
        assert max(covered) <= 1.0, f"{page}: chart {chart}'s legend {legend} lies over its plot area {areas}"


@pytest.mark.parametrize("page", PAGES)
def test_no_page_shows_nan(layout_report, browser, shots, page):
    load(browser, layout_report, page, shots)
    text = browser.execute_script("return document.body.innerText")
    shown = [text[max(m.start() - 40, 0) : m.end() + 40] for m in re.finditer(r"\bnan\b", text, flags=re.I)]
    assert not shown, f"{page}: {shown}"


def test_the_index_is_scrolled_once(layout_report, browser, shots):
    load(browser, layout_report, "index.html", shots)
    height = browser.execute_script("return document.documentElement.scrollHeight")
    assert height < INDEX_HEIGHT, f"index.html is {height} px tall at {WIDTH} px"
    # the findings folded: one line a case, none open
    lines = browser.execute_script(
        "return [...document.querySelectorAll('details.casefindings')].map(d => [d.open, "
        "d.querySelector('summary').getBoundingClientRect().height])"
    )
    assert lines and not [line for line in lines if line[0] or line[1] > 30], lines


def test_the_first_screen_answers_and_cites_by_key(layout_report, browser, shots):
    load(browser, layout_report, "index.html", shots)
    lead, top, bottom, window = browser.execute_script(
        "const r = document.getElementById('overview').getBoundingClientRect();"
        "return [document.querySelector('p.lead').innerText, r.top, r.bottom, window.innerHeight]"
    )
    counted = re.match(r"(\d+) cases: ", lead)
    assert counted and int(counted.group(1)) == len(CASES) + 1, lead  # the answer, counted per verdict
    assert 0 <= top and bottom <= window, (top, bottom, window)  # the picture on the first screen
    text = browser.execute_script("return document.body.innerText")
    assert not re.findall(r"\bseed \d{3}\b", text, flags=re.I)  # sources by key ('[bapat2015]')
    # every result on one line of a readable width, the whole sentence on hover
    rows = browser.execute_script(
        "return [...document.querySelectorAll('table.summary td.sentence')].map(c => {"
        "const r = document.createRange(); r.selectNodeContents(c);"
        "return [c.getBoundingClientRect().width, new Set([...r.getClientRects()].map(b => Math.round(b.top))).size,"
        " c.title.startsWith(c.innerText)]})"
    )
    assert rows and all(width >= 250 and lines == 1 and whole for width, lines, whole in rows), rows
