"""The report: every image and link resolves, and its tables say what the results say."""
import re

import pandas as pd

from validation.report import build_report
from validation.runner import summary


def test_report_links_resolve_and_tables_match(tmp_path):
    build_report(tmp_path, use_cache=False, jobs=1, cases=["cantilever_tip_load"])
    pages = [tmp_path / "index.html", *sorted((tmp_path / "cases").glob("*.html"))]
    assert len(pages) >= 2
    for page in pages:
        text = page.read_text()
        for target in re.findall(r"(?:src|href)='([^'#]+)'", text):
            assert (page.parent / target).resolve().exists(), f"{page.name}: broken link {target}"
    results = pd.read_csv(tmp_path / "results.csv")
    shown = pd.read_csv(tmp_path / "summary.csv")
    expected = summary(results)
    pd.testing.assert_frame_equal(shown.reset_index(drop=True), expected.reset_index(drop=True),
                                  check_dtype=False)
    case_page = (tmp_path / "cases" / "cantilever_tip_load.html").read_text()
    fem_rows = results[(results["method"] == "fem") & (results["quantity"] == "y") & (results["level"] == 9)]
    assert f"{fem_rows['value'].iloc[0]:.6g}" in case_page  # the page shows the computed value
    md = (tmp_path / "index.md").read_text()
    assert "cantilever_tip_load" in md and "Reproducibility" in md


def test_glance_differences_are_the_differences_of_the_values():
    from validation.loader import case_by_id
    from validation.report import glance
    from validation.runner import run_case, tabulate

    table = tabulate(run_case(case_by_id("cantilever_tip_load"), use_cache=False))
    view = glance(table)
    assert len(view) == 30  # x, y, rotation at 10 levels
    assert ((view["PRBM - FEM"] - (view["prbm"] - view["fem"])).abs() < 1e-12).all()
    assert ((view["FEM - exact"] - (view["fem"] - view["elastica"])).abs() < 1e-12).all()
    row = view[(view["quantity"] == "y") & (view["load"] == "9")].iloc[0]
    assert row["printed exact"] == 0.810609  # the reference from the case file, beside the methods
