"""The case summary (``validation.run.outcome.summary``) reads the same from a results table in memory
and from its CSV read back (``prbm-validate report`` writes results.csv and summary.csv; a user
recomputes the second from the first). Quantities with no point (strain energy, an input torque) are
written as an empty cell and read back as NaN; they must still count in the PRBM-to-FEM error."""

from __future__ import annotations

import math

import pandas as pd
import pytest

from validation.case.loader import case_by_id
from validation.run.api import run_case
from validation.run.outcome import summary, tabulate


@pytest.fixture(scope="module")
def table_and_result():
    result = run_case(case_by_id("bapat2015_ch6_ex2"), use_cache=False)
    return tabulate(result), result


def test_a_pointless_quantity_counts_in_the_prbm_fem_error(table_and_result):
    table, result = table_and_result
    energy = table[(table["quantity"] == "strain_energy") & table["method"].isin(["prbm", "fem"])]
    wide = energy.drop_duplicates(["method", "level"]).pivot(index="level", columns="method", values="value").dropna()
    assert len(wide) and (energy["point"] == "").all()
    scale = wide["fem"].abs().max()
    by_hand = ((wide["prbm"] - wide["fem"]).abs() / wide["fem"].abs().clip(lower=0.01 * scale)).max()
    row = summary(table, [result]).iloc[0]
    assert row["max_prbm_fem_rel"] >= by_hand > 0


def test_the_summary_reads_the_same_from_the_csv(table_and_result, tmp_path):
    table, result = table_and_result
    table.to_csv(tmp_path / "results.csv", index=False)
    back = pd.read_csv(tmp_path / "results.csv")
    assert back["point"].isna().any()  # the empty cells come back as NaN
    live, read = summary(table, [result]).iloc[0], summary(back, [result]).iloc[0]
    for column in ("max_prbm_fem_rel", "max_prbm_fem_per_length", "fem_error_est_rel"):
        a, b = float(live[column]), float(read[column])
        assert (math.isnan(a) and math.isnan(b)) or b == pytest.approx(a, rel=1e-6), column
    assert live["methods"] == read["methods"] and live["checks"] == read["checks"]
