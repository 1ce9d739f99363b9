"""The benchmark runs and writes its files (timings are measured there, never asserted here)."""
import json

import pandas as pd

from validation.bench import run_bench


def test_bench_quick_writes_csv_json_and_plots(tmp_path):
    # an unknown case is bad input (exit status 2, validation/exit_status.py); the others still run
    assert run_bench(tmp_path, quick=True, cases={"cantilever_tip_load": [0, 9], "no_such_case": None}) == 2
    headline = json.loads((tmp_path / "headline.json").read_text())
    assert any("no_such_case" in s for s in headline["skipped"])
    frame = pd.read_csv(tmp_path / "bench.csv")
    assert set(frame.columns) >= {"case", "method", "elements", "time_s", "error", "iterations", "peak_memory_mb"}
