"""The report names every kind of load in its sentences, and one page that cannot be drawn costs
only that page: it says why, the other pages and the index are written, the exit status is 1.

(A report of the uniform-load cantilever once stopped the whole report with KeyError 'distributed'
in the summary sentence, after every case had been computed.)
"""

from types import SimpleNamespace

import pandas as pd

from validation.case.loader import CASES_DIR, load_case
from validation.case.loads import load_unit
from validation.report import build
from validation.report.summary import level_phrase


def _stand_in(case):
    return SimpleNamespace(loaded=SimpleNamespace(case=case))


def test_distributed_and_self_weight_loads_have_units_and_phrases():
    uniform = load_case(CASES_DIR / "benchmarks" / "cantilever_uniform_load.toml").case
    load = uniform.loads[0]
    assert load.kind == "distributed"
    per_length = f"{uniform.unit('force')}/{uniform.unit('length')}"
    assert load_unit(load, uniform) == per_length
    last = uniform.n_levels() - 1
    assert level_phrase(_stand_in(uniform), last).endswith(per_length)

    weighed = load_case(CASES_DIR / "chapter9" / "test1a_self_weight.toml").case
    kinds = [ld.kind for ld in weighed.loads]
    assert load_unit(weighed.loads[kinds.index("self_weight")], weighed) == "x gravity"
    # the phrase follows the load that changes along the path (the applied force), in lbf
    assert level_phrase(_stand_in(weighed), 1).endswith("= 4 lbf")


def test_a_page_that_cannot_be_drawn_says_why_and_the_rest_goes_on(tmp_path, monkeypatch):
    (tmp_path / "cases").mkdir()

    def broken(result, part, out):
        raise KeyError("distributed")

    monkeypatch.setattr(build, "_case_page", broken)
    result = SimpleNamespace(loaded=SimpleNamespace(id="some_case", text="[case]\nid = 'some_case'\n"))
    part = pd.DataFrame({"wall_time": [0.1], "cached": [False], "value": [1.0]})
    page = build._page_job((result, part, tmp_path))
    assert page.case == "some_case" and page.link == "cases/some_case.html"
    assert page.error is not None and "KeyError" in page.error and "distributed" in page.error
    assert "could not be drawn" in (tmp_path / page.link).read_text()
    assert not (tmp_path / "cases" / "some_case.digest").exists()  # drawn again next time


def test_the_report_is_written_and_fails_when_a_page_cannot_be_drawn(tmp_path, monkeypatch):
    def broken(result, part, out):
        raise ValueError("planted drawing error")

    monkeypatch.setattr(build, "_case_page", broken)
    status = build.build_report(tmp_path, use_cache=True, jobs=1, cases=["cantilever_tip_load"])
    assert status == 1
    index = (tmp_path / "index.html").read_text()
    assert "Pages that could not be drawn" in index and "planted drawing error" in index
    assert (tmp_path / "summary.csv").exists()
