"""What the report's workers work out beside each case is what the main process would have worked out:
the whole table put together from the cases' rows (tabulated where each case ran, text in Python
strings) is the table tabulated in one process; ``summary.csv``'s rows, the overview's points and the
atlas page's measured levels that the page writer sends back are what the main process would work out
(the last taken as they are, not checked again); and the overview drawn as PNG and SVG by two
processes is the picture drawn by one."""

import re

import pandas as pd
import pytest

from validation.case.loader import find_case_files
from validation.atlas import measured
from validation.report import atlas_page, build
from validation.report.overview import overview_points, plot_overview
from validation.run.outcome import COLUMNS, run_cases, sorted_rows, summary, tabulate

CASES = ["cantilever_tip_load", "bapat2015_table3_3", "bapat2015_test1a", "seed003_slant_parallelogram"]


@pytest.fixture(scope="module")
def reported(tmp_path_factory):
    """The cases run as the report runs them: each case's page drawn by the page writer after it."""
    out = tmp_path_factory.mktemp("report")
    (out / "cases").mkdir()
    writer = build.PageWriter(out, out / "no_previous_measured.json")
    return run_cases(find_case_files(CASES), use_cache=True, jobs=1, after=writer), out


def test_the_table_put_together_from_the_cases_rows_is_the_one_tabulated_in_one_process(reported):
    outcome, _ = reported
    here = sorted_rows(pd.concat([tabulate(r) for r in outcome.results], ignore_index=True))
    pd.testing.assert_frame_equal(outcome.table, here, check_exact=True, check_column_type=True)
    assert list(outcome.table.columns) == COLUMNS and str(outcome.table["case"].dtype) == str(here["case"].dtype)


def test_the_summary_rows_of_the_page_writer_are_the_summarys(reported):
    outcome, _ = reported
    rows = {case: link.summary_row for case, link in outcome.after.items()}
    assert set(rows) == set(CASES) and all(row is not None for row in rows.values())
    expected = summary(outcome.table, outcome.results)
    pd.testing.assert_frame_equal(summary(outcome.table, outcome.results, rows), expected, check_exact=True)
    rows["cantilever_tip_load"] = {**rows["cantilever_tip_load"], "group": "another group"}  # not its row
    pd.testing.assert_frame_equal(summary(outcome.table, outcome.results, rows), expected, check_exact=True)


def test_the_overview_points_of_the_page_writer_are_overview_points(reported):
    outcome, _ = reported
    expected = overview_points(outcome.results, outcome.table)
    assert expected and build._overview_points(outcome) == expected


def test_the_measured_levels_of_the_page_writer_are_taken_as_they_are(reported, monkeypatch):
    outcome, _ = reported
    known = {case: link.measured for case, link in outcome.after.items() if link.measured is not None}
    assert known
    expected, keep = atlas_page._measured_frame(outcome.results, outcome.table, {})

    def not_again(*args):
        raise AssertionError("worked out again in the main process")

    monkeypatch.setattr(atlas_page, "_measured_key", not_again)
    monkeypatch.setattr(measured, "measured_levels", not_again)
    got, got_keep = atlas_page._measured_frame(outcome.results, outcome.table, {}, known)
    assert got.equals(expected) and got_keep == keep


def test_the_overview_drawn_by_two_processes_is_the_picture_drawn_by_one(reported, tmp_path):
    outcome, _ = reported
    points = overview_points(outcome.results, outcome.table)
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    plot_overview(points, tmp_path / "one" / "overview.png")
    for kind in build.OVERVIEW:
        plot_overview(points, tmp_path / "two" / "overview.png", (kind,))
    assert (tmp_path / "one" / "overview.png").read_bytes() == (tmp_path / "two" / "overview.png").read_bytes()

    def svg(folder):  # an SVG names its elements with random ids and carries the date it was drawn
        text = (tmp_path / folder / "overview.svg").read_text()
        return re.sub(r"[0-9a-f]{10}", "id", re.sub(r"<dc:date>[^<]*</dc:date>", "", text))

    assert svg("one") == svg("two")
