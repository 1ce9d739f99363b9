"""The validation suite: every case file through every method it asks for, by the pytest plugin's
checks (validation/pytest_plugin.py; ``pytest cases/`` runs the same files as one item per method).

Each claimed tolerance (a reference with ``compare`` and ``tolerance``) must hold, unless the
reference records a known misprint or disagreement (``finding``). PRBM-to-FEM and model-to-
experiment errors are recorded by the runner without a threshold: they are the harness's findings.
No method may skip a case silently: it returns values, or says why it does not apply or failed.
"""
from __future__ import annotations

import pytest

from validation.api import validate
from validation.loader import find_case_files, load_case
from validation.pytest_plugin import comparison_failures
from validation.runner import requests_for

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
    failed = comparison_failures(result)
    assert not failed, f"{len(failed)} claimed comparison(s) fail:\n" + "\n".join(failed)
