"""The validation suite: every case file through every method it asks for.

A case fails (``validation.compare.case_verdict``) when any enforced check fails: a printed number
with a claimed tolerance, a finding (the printed value must still disagree and the explanation must
reproduce), an agreement between methods, or the automatic FEM-against-elastica check; when a method
it lists does not converge or does not apply, unless the case records that as the expected outcome;
or when a method gives values with no enforced check at a loaded level and the case does not say why.
"""
from __future__ import annotations

import pytest

from validation.compare import case_verdict
from validation.loader import find_case_files, load_case
from validation.runner import requests_for, run_case, tabulate

CASE_FILES = find_case_files(None)


@pytest.mark.parametrize("path", CASE_FILES, ids=[p.stem for p in CASE_FILES])
def test_case(path):
    loaded = load_case(path)
    result = run_case(loaded, use_cache=False)
    for method, run in result.runs.items():
        wanted = requests_for(loaded.case, method)
        got = [r for r in wanted if r in run.values]
        if len(got) < len(wanted):
            assert run.message, f"{method} returned {len(got)}/{len(wanted)} outputs without saying why"
    problems = case_verdict(loaded.case, result.runs, tabulate(result))
    assert not problems, f"{len(problems)} problem(s):\n" + "\n".join(problems)
