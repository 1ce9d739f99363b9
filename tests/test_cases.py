"""The validation suite: every case file through every method it asks for.

Each claimed tolerance (a reference with ``compare`` and ``tolerance``) must hold, unless the
reference records a known misprint or disagreement (``finding``). PRBM-to-FEM and model-to-
experiment errors are recorded by the runner without a threshold: they are the harness's findings.
No method may skip a case silently: it returns values, or says why it does not apply or failed.
"""
from __future__ import annotations

import pytest

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
    table = tabulate(result)
    claimed = table[table["within_tolerance"].notna() & table["finding"].isna()]
    failed = claimed[claimed["within_tolerance"] == False]  # noqa: E712
    report = failed[["method", "quantity", "point", "level", "value", "reference_label", "reference_value",
                     "rel_error", "abs_error", "tolerance_rel", "tolerance_abs", "message"]]
    assert failed.empty, f"{len(failed)} claimed comparison(s) fail:\n{report.to_string()}"
