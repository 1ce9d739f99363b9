"""The benchmark runs and writes its files (timings are measured there, never asserted here).

A smoke run, out of the default suite (marker ``bench``): ``pytest -m bench``."""
import json

import pandas as pd
import pytest

from validation.bench import run_bench

pytestmark = pytest.mark.bench


def test_bench_quick_writes_csv_json_and_plots(tmp_path):
    assert run_bench(tmp_path, quick=True, cases={"cantilever_tip_load": [0, 9], "no_such_case": None}) == 0
    headline = json.loads((tmp_path / "headline.json").read_text())
    assert any("no_such_case" in s for s in headline["skipped"])
    frame = pd.read_csv(tmp_path / "bench.csv")
    assert set(frame.columns) >= {"case", "method", "elements", "time_s", "error", "iterations", "peak_memory_mb"}
