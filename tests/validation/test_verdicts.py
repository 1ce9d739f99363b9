"""One verdict vocabulary (``validation.run.verdict``): a row where no limit was claimed is 'no limit
claimed' whatever its error, a limit that fails is 'outside the claimed limit', the PRBM's 145 %
relative error of seed004_prbm_strip_moment is never 'within the claimed limit', the report's first
sentence counts every case once, and the old word 'agrees' appears nowhere in a report or its tables."""

from __future__ import annotations

import math
import re

import pandas as pd
import pytest

from validation.case.loader import case_by_id
from validation.report.build import build_report, headline
from validation.report.summary import CaseSummary, MethodState
from validation.run import tables
from validation.run.case_run import run_case
from validation.run.outcome import summary, tabulate
from validation.run.verdict import FAILING, ORDER, Verdict, counts_sentence, prbm_fem_verdict, row_verdict, worst

pytestmark = pytest.mark.xdist_group("verdicts")
CASES = ["seed004_prbm_strip_moment", "bapat2015_test2"]


def test_every_verdict_has_a_meaning_and_a_place_in_the_order():
    assert set(ORDER) == set(Verdict) and len(ORDER) == len(Verdict)
    assert all(v.meaning for v in Verdict)
    assert FAILING == {Verdict.FAILED, Verdict.NOT_CONVERGED, Verdict.OUTSIDE_LIMIT, Verdict.REFUSED}
    assert worst([Verdict.WITHIN, Verdict.NO_LIMIT]) is Verdict.NO_LIMIT
    assert worst([Verdict.NO_LIMIT, Verdict.OUTSIDE_LIMIT, Verdict.EXPECTED]) is Verdict.OUTSIDE_LIMIT


@pytest.mark.parametrize("error", [0.0, 0.01, 1.45, 4.5, 1e6])
def test_a_row_with_no_claimed_limit_is_no_limit_claimed_whatever_its_error(error):
    assert row_verdict(1.0 + error, None, compared=True, applicability="", run_state=None) is Verdict.NO_LIMIT
    assert row_verdict(1.0 + error, math.nan, compared=True, applicability="", run_state=None) is Verdict.NO_LIMIT
    assert row_verdict(1.0, None, compared=False, applicability="", run_state=None) is None  # values only


def test_a_failed_limit_is_outside_the_claimed_limit_even_outside_the_models_validity():
    assert row_verdict(2.0, False, compared=True, applicability="", run_state=None) is Verdict.OUTSIDE_LIMIT
    flagged = "PRB angle beyond the fit"
    assert row_verdict(2.0, False, compared=True, applicability=flagged, run_state=None) is Verdict.OUTSIDE_LIMIT
    assert row_verdict(2.0, True, compared=True, applicability=flagged, run_state=None) is Verdict.OUTSIDE_VALIDITY
    assert row_verdict(2.0, True, compared=True, applicability="", run_state=None) is Verdict.WITHIN
    assert row_verdict(2.0, True, compared=True, applicability="", run_state=None, kind="finding") is Verdict.FINDING
    assert (
        row_verdict(math.nan, False, compared=True, applicability="", run_state=Verdict.NOT_CONVERGED)
        is Verdict.NOT_CONVERGED
    )
    assert row_verdict(math.nan, False, compared=True, applicability="", run_state=Verdict.EXPECTED) is Verdict.EXPECTED


@pytest.fixture(scope="module")
def strip_moment() -> pd.DataFrame:
    return tabulate(run_case(case_by_id("seed004_prbm_strip_moment"), use_cache=False))


def test_the_prbm_strip_moment_is_never_within_a_limit(strip_moment):
    prbm = strip_moment[(strip_moment["method"] == "prbm") & strip_moment["reference_label"].notna()]
    big = prbm[prbm["rel_error"] > 1.0]
    assert len(big) and (big["rel_error"].max() > 1.4)  # the 145 % the issue names
    assert not (big["verdict"] == Verdict.WITHIN.value).any()
    assert set(big["verdict"]) <= {Verdict.NO_LIMIT.value, Verdict.OUTSIDE_LIMIT.value, Verdict.OUTSIDE_VALIDITY.value}
    assert prbm_fem_verdict(strip_moment) is not Verdict.WITHIN
    row = summary(strip_moment).iloc[0]
    assert row["verdict"] != Verdict.WITHIN.value and row["prbm_fem_verdict"] != Verdict.WITHIN.value


def test_within_needs_a_claimed_limit_that_holds_on_every_row(strip_moment):
    within = strip_moment[strip_moment["verdict"] == Verdict.WITHIN.value]
    assert len(within) and (within["within_tolerance"] == True).all()  # noqa: E712
    assert within["tolerance_rel"].notna().sum() + within["tolerance_abs"].notna().sum() >= len(within)
    no_limit = strip_moment[strip_moment["verdict"] == Verdict.NO_LIMIT.value]
    assert len(no_limit) and no_limit["within_tolerance"].isna().all()


def _row(case: str, verdict: Verdict) -> CaseSummary:
    return CaseSummary(
        group="g",
        case=case,
        title="t",
        verdict=verdict,
        reason="",
        methods=[MethodState("prbm", verdict, "")],
        sentence="s.",
        prbm_fem_length=0.02,
        prbm_fem_relative=0.1,
        fem_estimate=math.nan,
        checks=0,
        checks_passed=0,
        findings=0,
    )


def _counted(sentence: str) -> tuple[int, int]:
    """(the number of cases the sentence names, the sum of its per-verdict counts)."""
    head = re.match(r"(\d+) cases?: (.*?)(?:[.;]|$)", sentence)
    words = "|".join(re.escape(v.value) for v in Verdict)
    counts = [int(n) for n, _ in re.findall(rf"(\d+) ({words})", head.group(2))]
    return int(head.group(1)), sum(counts)


def test_the_first_sentence_counts_add_up_to_the_case_count():
    verdicts = [
        Verdict.WITHIN,
        Verdict.NO_LIMIT,
        Verdict.NO_LIMIT,
        Verdict.OUTSIDE_VALIDITY,
        Verdict.EXPECTED,
        Verdict.FINDING,
        Verdict.OUTSIDE_LIMIT,
    ]
    assert _counted(counts_sentence(verdicts)) == (7, 7)
    rows = [_row(f"c{i}", v) for i, v in enumerate(verdicts)]
    assert _counted(headline(rows)) == (7, 7)
    assert "agree" not in headline(rows)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    folder = tmp_path_factory.mktemp("verdict_report")
    status = build_report(folder, use_cache=False, jobs=1, cases=CASES)
    return folder, status


def test_a_built_report_and_its_tables_never_say_agrees(built):
    folder, _ = built
    files = [p for p in folder.rglob("*") if p.is_file() and p.suffix in (".html", ".md", ".csv", ".txt")]
    assert any(p.name == "index.html" for p in files)
    said = [p.name for p in files if re.search(r"\bagrees?\b", p.read_text(errors="replace"), flags=re.I)]
    assert not said, said
    results = pd.read_csv(folder / "results.csv")
    assert "verdict" in results and set(results["verdict"].dropna()) <= {v.value for v in Verdict}
    lead = re.search(r"<p class='lead'>(.*?)</p>", (folder / "index.html").read_text()).group(1)
    assert _counted(lead.replace("&#x27;", "'")) == (len(CASES), len(CASES))
    shown = pd.read_csv(folder / "summary.csv")
    assert set(shown["verdict"]) <= {v.value for v in Verdict} and len(shown) == len(CASES)


def test_the_comparisons_table_carries_the_verdict_column():
    result = run_case(case_by_id("seed004_prbm_strip_moment"), use_cache=True)
    tidy = tables.tables_of([result], tabulate(result))
    comparisons = tidy["comparisons"]
    assert "verdict" in comparisons and comparisons["verdict"].notna().all()
    assert not comparisons["verdict"].str.contains("agree").any()
