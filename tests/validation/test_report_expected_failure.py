"""The report shows a failure the case records as expected (``case.expected_failure``) as an expected
failure, with the case's reason, never as 'did not converge'; an unexpected one stays 'did not converge'."""

from __future__ import annotations

from tests.validation.test_exit_status import fake, write  # noqa: F401  (the fake prbm adapter fixture)
from tests.validation.test_foundation import GOOD

from validation.case.loader import load_case
from validation.run.verdict import Verdict
from validation.report.summary import summarise
from validation.run.outcome import tabulate
from validation.run.case_run import run_case

REASON = "the toy model stops at level 1 (a stated limit point)"


def summary_of(tmp_path, text):
    result = run_case(load_case(write(tmp_path, "toy.toml", text)), use_cache=False)
    return summarise(result, tabulate(result))


def test_expected_failure_is_shown_as_expected_with_its_reason(tmp_path, fake):  # noqa: F811
    fake["behaviour"] = "not converged"
    expecting = GOOD.replace('group = "tests"', f'group = "tests"\nexpected_failure = {{ prbm = "{REASON}" }}')
    assert expecting != GOOD
    shown = summary_of(tmp_path, expecting)
    assert shown.verdict is Verdict.EXPECTED and REASON in shown.reason
    assert [s.verdict for s in shown.methods] == [Verdict.EXPECTED]


def test_unexpected_failure_stays_failed(tmp_path, fake):  # noqa: F811
    fake["behaviour"] = "not converged"
    shown = summary_of(tmp_path, GOOD)
    assert shown.verdict is Verdict.NOT_CONVERGED and "no convergence at level 1" in shown.reason
