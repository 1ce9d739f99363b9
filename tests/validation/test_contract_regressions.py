"""The shrunk stress-contract failures kept under cases/regressions/, re-run against the contract.

Each file was written by ``prbm-validate stress --long`` (``validation.stress.contract_run.
write_regression``) from a configuration that failed the quantity contract; its description carries the
configuration and a status: 'fixed' files failed before a fix and must pass the contract check now (the
check would fail again if the fix were undone); 'open' files record a failure not fixed yet and must
still fail (when one passes, the fix is in and the file's status and findings are to be updated).
"""

from pathlib import Path

import pytest

from validation.case.loader import load_case
from validation.stress.contract import Configuration
from validation.stress.contract_run import failures_of, regression_record

FOLDER = Path(__file__).resolve().parents[2] / "cases" / "regressions"
FILES = sorted(FOLDER.glob("contract_regression_*.toml"))


def test_there_are_regression_cases():
    assert FILES, f"no contract regressions in {FOLDER}"


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_regression_holds_its_status(path):
    loaded = load_case(path)
    record = regression_record(loaded.case.case.description)
    c = Configuration(**record["configuration"])
    failures = failures_of(record["category"], c, record["phi"])
    if record["status"] == "fixed":
        assert not failures, f"{path.name} was fixed and fails again: {failures}"
    else:
        assert failures, f"{path.name} (open) passes now: mark it 'fixed' and update its findings"
