"""The summary closes with the cases that have no PRBM-vs-FEM number, each with its one-line reason
(issue 20): a case with a length error or a relative error has a number; one with neither is counted
and listed, with the case's own reason (``case.no_prbm_fem``) or what its runs say."""

import math

from validation.run.verdict import Verdict
from validation.report.summary import (
    CaseSummary,
    MethodState,
    summary_markdown,
    summary_tables_html,
    without_prbm_fem,
    without_prbm_fem_line,
)


def _row(case, length=math.nan, relative=math.nan, reason="", methods=("prbm", "fem"), fem_validation=False):
    return CaseSummary(
        group="chapter 5",
        case=case,
        title="t",
        verdict=Verdict.NO_LIMIT,
        reason="",
        methods=[MethodState(m, Verdict.NO_LIMIT, "") for m in methods],
        sentence="s.",
        prbm_fem_length=length,
        prbm_fem_relative=relative,
        fem_estimate=math.nan,
        checks=0,
        checks_passed=0,
        findings=0,
        no_prbm_fem=reason,
        fem_validation=fem_validation,
    )


ROWS = [
    _row("with_length", length=0.002, relative=0.03),
    _row("relative_only", relative=2.0),
    _row("benchmark", reason="FEM-validation benchmark: a limit load checked against print", fem_validation=True),
    _row("no_prbm", methods=("fem",)),
]


def test_only_cases_with_neither_error_are_counted():
    assert [r.case for r in without_prbm_fem(ROWS)] == ["no_prbm", "benchmark"]  # other cases first
    assert without_prbm_fem_line(ROWS) == (
        "2 of 4 cases have no PRBM-vs-FEM number (1 other case, 1 FEM-validation benchmark), each with its reason:"
    )


def test_a_loading_reading_points_to_its_base_case():
    reading = _row("test1a_rope", methods=("fem",))
    reading.readings_of = "test1a"
    line = without_prbm_fem_line(ROWS + [reading])
    assert "1 loading reading of an experiment (its base case carries the number)" in line
    html = summary_tables_html(ROWS + [reading], {})
    assert (
        "test1a_rope</a>: a loading reading of test1a (FEM only): the PRBM-vs-FEM number is in the row of test1a"
        in html
    )


def test_the_closing_list_gives_each_reason_in_html_and_markdown():
    html = summary_tables_html(ROWS, {})
    closing = html[html.index("id='without-prbm-fem'") :]
    assert "benchmark</a>: FEM-validation benchmark: a limit load checked against print" in closing
    assert "no_prbm</a>: no PRBM in this case" in closing
    assert "with_length" not in closing and "relative_only" not in closing
    md = summary_markdown(ROWS)
    assert "- benchmark: FEM-validation benchmark: a limit load checked against print" in md
    assert "| relative_only | no limit claimed | s. | relative " in md  # the relative error stands in for % of L
    assert "none: FEM-validation benchmark" in md


def test_every_case_with_a_number_says_so():
    assert without_prbm_fem_line(ROWS[:2]) == "0 of 2 cases have no PRBM-vs-FEM number."
