"""Which loading reading of each chapter-9 experiment puts the FEM nearest the measured points
(validation.run.readings_rank), held against the ranking each experiment's base case records.

The FEM runs on every reading of Tests 1(a)-(c) and 2 (the case files' own meshes, 16 elements and 32
for the Test 1 base cases, each with its Richardson estimate; no cache, a few seconds in all). The
measured points are the references labelled ``measured`` ([bapat2015, Tables 9.1-9.4]); the expected
ranking is not written here but read from the base case's finding ``Readings ranking (FEM): nearest A,
then B``, which gives the numbers and the reason. In short:

- Test 1(a): self-weight, then the base case (full transverse weight). The FEM travels 3-7 % less than
  the beam, so every reading that takes force away (friction, rope, follower) or stiffens the section
  (bonded) moves it further off; the beam's own weight adds travel.
- Test 1(c): friction, then the base case. The FEM travels up to 8 % more than the beam, so the uniform
  capstan loss of eq (211) comes nearest and the full force next.
- Test 1(b): friction nearest, for the reason of 1(c); the rope second is *not* a physical finding (its
  pulley distance is assumed), so there only the stability is claimed.
- Test 2: the two forces that turn with link 2 (perpendicular, follower) are the first two, as only
  they keep the P2-P3 errors near P1's; their order is *not* a physical finding (stability only).

What every case asserts beyond the order is its stability: the second reading is farther than the
nearest by more than the FEM's own error bound on the two rms distances (E_1 + E_2, from the Richardson
estimates), never a snapshot of the distances themselves.
"""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path

import pandas as pd
import pytest

from validation.run.api import validate
from validation.run.readings_rank import Ranking, Recorded, Status, rank_readings, recorded_ranking

CASES = Path(__file__).resolve().parents[2] / "cases" / "chapter9"
EXPERIMENTS = ("bapat2015_test1a", "bapat2015_test1b", "bapat2015_test1c", "bapat2015_test2")
# one worker for the module: the FEM runs (``_runs``, once per process) are computed once, not once per worker
pytestmark = pytest.mark.xdist_group("readings_rank")


@cache
def _runs() -> tuple[list, pd.DataFrame]:
    """The FEM on every reading of Tests 1 and 2: the case results and their rows."""
    runs = [validate(path, methods=["fem"], use_cache=False) for path in sorted(CASES.glob("test[12]*.toml"))]
    return [v.result for v in runs], pd.concat([v.results for v in runs], ignore_index=True)


@cache
def _rankings() -> dict[str, Ranking]:
    return {r.experiment: r for r in rank_readings(*_runs())}


@pytest.mark.parametrize("experiment", EXPERIMENTS)
def test_the_recorded_nearest_reading_holds(experiment):
    ranking = _rankings()[experiment]
    assert ranking.recorded is not None, f"{experiment} records no 'Readings ranking (FEM)' finding"
    first, second = ranking.readings[:2]
    assert all(r.levels >= 3 for r in ranking.readings), "a reading measured at fewer than 3 levels"
    assert first.case == ranking.recorded.nearest, ranking.line()
    assert second.case == ranking.recorded.second, ranking.line()
    assert math.isfinite(ranking.bound), f"no FEM error estimate on the first two readings: {ranking.line()}"
    assert second.rms - first.rms > first.estimate + second.estimate, ranking.line()
    assert ranking.status is Status.HOLDS


def test_every_experiment_is_ranked_in_its_case_units_and_in_percent_of_L():
    rankings = _rankings()
    assert set(rankings) == set(EXPERIMENTS)
    length = _runs()[1].groupby("case")["scale"].first()  # each case's characteristic length L
    for ranking in rankings.values():
        assert [r.rms for r in ranking.readings] == sorted(r.rms for r in ranking.readings)
        for r in ranking.readings:
            assert r.unit == "in"
            assert r.rms_pct_L == pytest.approx(100 * r.rms / length[r.case])


def test_a_reading_that_becomes_nearer_fails_the_recorded_ranking():
    """Plant the measured points' error on the second reading: move its FEM values onto the measurements
    at every level; it becomes the nearest (rms 0) and the recorded ranking must stop holding."""
    results, table = _runs()
    second = _rankings()["bapat2015_test1c"].readings[1].case
    planted = table.copy()
    rows = (planted["case"] == second) & (planted["reference_label"] == "measured")
    planted.loc[rows, "value"] = planted.loc[rows, "reference_value"]
    ranking = next(r for r in rank_readings(results, planted) if r.experiment == "bapat2015_test1c")
    assert ranking.nearest.case == second
    assert ranking.status is Status.DIFFERS
    assert "no longer holds" in ranking.line()


def test_an_order_within_the_fem_error_bound_is_not_separated():
    """Widen the first reading's estimate past the margin: the same order, but no longer separated; and
    an estimate marked unreliable gives no bound at all."""
    results, table = _runs()
    ranking = _rankings()["bapat2015_test1b"]
    first = ranking.nearest.case
    for change in ({"error_estimate": 10 * ranking.margin}, {"error_estimate_reliable": False}):
        planted = table.copy()
        rows = (planted["case"] == first) & (planted["reference_label"] == "measured")
        for column, value in change.items():
            planted.loc[rows, column] = value
        again = next(r for r in rank_readings(results, planted) if r.experiment == "bapat2015_test1b")
        assert again.nearest.case == first and not again.separated
        assert again.status is Status.NOT_SEPARATED


def test_the_recorded_ranking_is_read_from_the_finding():
    findings = [
        "something else",
        "Readings ranking (FEM): nearest a_b-1, then c_d; why ...",
        "Readings ranking (FEM): nearest x, then y",
    ]
    assert recorded_ranking(findings) == Recorded("a_b-1", "c_d")
    assert recorded_ranking(["no ranking here"]) is None
