"""``prbm-validate audit``: a planted error fails a case that checks the planted method, and a planted
run never reaches the project's run cache (the runner stores every fresh run; a poisoned cache
would serve the planted values to the next ordinary run)."""

from __future__ import annotations

import os
from pathlib import Path

from validation.stress import audit

CASE = Path(__file__).resolve().parents[2] / "cases" / "seed004" / "strip_tip_force_prbm.toml"


def test_a_planted_error_is_caught_and_never_cached():
    cache = Path(os.environ["PRBM_VALIDATE_CACHE"])  # the test's private cache (conftest)
    [verdict] = audit.run_plant("prbm-outputs-x1.10", [CASE], jobs=1)
    assert verdict.failed and "prbm" in verdict.first_problem
    assert not cache.exists() or not any(cache.iterdir())
