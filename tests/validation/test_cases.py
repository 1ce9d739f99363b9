"""The validation suite: every case file through every method it asks for, by the pytest plugin's
checks (validation/pytest_plugin.py; ``pytest cases/`` runs the same files as one item per method).

A case fails (``validation.run.compare.case_verdict``) when any enforced check fails: a printed number
with a claimed tolerance, a finding (the printed value must still disagree and the explanation must
reproduce), an agreement between methods, or the automatic FEM-against-elastica check; when a method
it lists does not converge or does not apply, unless the case records that as the expected outcome;
or when a method gives values with no enforced check at a loaded level and the case does not say why.
"""

from __future__ import annotations

import pytest

from validation.run.api import validate
from validation.run.compare import case_verdict
from validation.case.loader import find_case_files, load_case
from validation.pytest_plugin import comparison_failures
from validation.run.runner import requests_for

CASE_FILES = find_case_files(None)


@pytest.mark.parametrize("path", CASE_FILES, ids=[p.stem for p in CASE_FILES])
def test_case(path):
    loaded = load_case(path)
    result = validate(loaded)
    for method, run in result.result.runs.items():
        wanted = requests_for(loaded.case, method)
        got = [r for r in wanted if r in run.values]
        if len(got) < len(wanted):
            assert run.message, f"{method} returned {len(got)}/{len(wanted)} outputs without saying why"
    failed = comparison_failures(result)  # the plugin's readable lines for the claimed comparisons
    problems = case_verdict(loaded.case, result.result.runs, result.results)
    assert not problems, (
        f"{len(problems)} problem(s):\n" + "\n".join(problems) + ("\n" + "\n".join(failed) if failed else "")
    )
