"""A case page is the same whichever storage pandas gives its text: the pages are drawn with
Python strings (``build.PAGE_STRINGS``, faster for their many small filters and sorts than pandas 3's
pyarrow-backed default), and the page, its Markdown and its one-line summary must equal the ones
drawn with pyarrow strings, on a case with references, findings and three methods."""

import pytest

from validation.case.loader import case_by_id
from validation.report import build
from validation.run.case_run import run_case


@pytest.mark.parametrize("case_id", ["bapat2015_test1a", "bapat2015_table3_3"])
def test_a_page_drawn_with_python_strings_equals_the_pyarrow_one(tmp_path, monkeypatch, case_id):
    result = run_case(case_by_id(case_id), use_cache=True)
    pages = {}
    for storage in ("python", "pyarrow"):
        out = tmp_path / storage
        (out / "cases").mkdir(parents=True)
        monkeypatch.setattr(build, "PAGE_STRINGS", storage)
        link = build.PageWriter(out)(result)
        assert link.error is None
        pages[storage] = ((out / link.link).read_text(), (out / link.link).with_suffix(".md").read_text(), link.summary)
    assert pages["python"] == pages["pyarrow"]
