"""Fixtures shared by the validation tests: the coarse PRBM error atlas, built once per test session, one
headless Chromium per worker, and the benchmark's timing cut to its minimum number of runs.

The coarse atlas of the current code takes a few CPU seconds to build; test_atlas.py (the shipped maps
against it, its lines read at once) and test_report_atlas.py (the atlas page drawn from it) read the same
one.  Under xdist the workers share it through the session's base folder (pytest-xdist's documented way
to run a session fixture once): the first worker to take the lock builds it, the other waits and reads it.

The report's browser tests (test_report.py, test_report_case_pages.py, test_report_layout.py: the xdist
group ``report``, one worker) share one headless Chromium, ``chromium``: a launch is about a CPU-second.
Each test takes it through ``test_report.window``, sized as it needs and with the console log of the pages
before it dropped.

The benchmark (``validation.bench.headline``) times each configuration as often as fits in a budget
(``TIME_BUDGET_S``, ``HEADLINE_BUDGET_S``: steadier best times on a shared machine); a test of what it
writes and how it exits asserts no timing (test_bench.py's docstring), so ``bench_minimum_runs`` sets
both budgets to zero: every configuration is timed its minimum ``repeats`` times, through the same code.
The tests of the budgets themselves (test_bench.py) set their own.
"""

from __future__ import annotations

import fcntl
import os
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def coarse_atlas(tmp_path_factory) -> Path:
    """The datasets folder holding the coarse atlas of the current code, built serially by the report's
    ``atlas_page.find_atlas`` (no published atlas to find, so it builds one under ``build_into``)."""
    from validation.report import atlas_page

    if os.environ.get("PYTEST_XDIST_WORKER"):  # this session's folder, shared by its workers only
        root = tmp_path_factory.getbasetemp().parent
    else:
        root = tmp_path_factory.mktemp("session")
    datasets = root / "coarse_atlas_datasets"
    with open(root / "coarse_atlas.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        found = atlas_page.find_atlas(root / "no_published_atlas", build_into=datasets, executor="serial")
    assert found is not None and found[0] == "coarse" and found[2] == datasets
    return datasets


@pytest.fixture
def bench_minimum_runs(monkeypatch):
    """``run_bench`` with each configuration timed its minimum number of runs (module docstring)."""
    from validation.bench import headline

    monkeypatch.setattr(headline, "TIME_BUDGET_S", 0.0)
    monkeypatch.setattr(headline, "HEADLINE_BUDGET_S", 0.0)


@pytest.fixture(scope="session")
def chromium():
    """The worker's one headless Chromium (``test_report.chromium_session``; module docstring), quit at
    the end of the session; a skip saying what is missing where there is none."""
    from tests.validation.test_report import chromium_session

    with chromium_session() as driver:
        yield driver
