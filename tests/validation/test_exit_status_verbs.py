"""The exit-status rule (validation/run/exit_status.py) on the verbs whose 0 and 1 are not covered
by tests/validation/test_exit_status.py: ``bench`` and ``stress`` each give 0 when everything ran and passed,
1 when a method did not converge or a check failed, 2 on bad input."""

from __future__ import annotations

import pytest

from validation.bench.headline import run_bench
from validation.cli.main import main
from validation.stress import checks as stress_checks
from validation.stress.checks import Check, run_stress

from tests.validation.test_exit_status import fake  # noqa: F401,F811  (the fake prbm adapter fixture)


@pytest.fixture
def tiny_bench_cases():
    """One level of the cantilever, coarse meshes only: the harness's exit logic, not the timing (each
    configuration timed its minimum number of runs: ``bench_minimum_runs``, tests/validation/conftest.py)."""
    return {"cantilever_tip_load": [0]}


@pytest.mark.usefixtures("bench_minimum_runs")
def test_bench_exits_0_when_every_method_converges(tmp_path, tiny_bench_cases, fake):  # noqa: F811
    assert run_bench(tmp_path, quick=True, cases=tiny_bench_cases, max_elements=4, plots=False) == 0


@pytest.mark.usefixtures("bench_minimum_runs")
def test_bench_exits_1_when_a_method_of_the_case_does_not_converge(tmp_path, tiny_bench_cases, fake, capsys):  # noqa: F811
    fake["behaviour"] = "not converged"
    assert run_bench(tmp_path, quick=True, cases=tiny_bench_cases, max_elements=4, plots=False) == 1
    assert "did not converge: cantilever_tip_load/prbm: no convergence at level 1" in capsys.readouterr().out


def test_bench_exits_2_on_an_unknown_case(tmp_path, capsys):
    assert run_bench(tmp_path, quick=True, cases={"no_such_case": None}, max_elements=4) == 2
    assert main(["bench", "--quick", "--no-such-option"]) == 2


def test_stress_exits_0_when_every_check_passes(tmp_path):
    assert run_stress(tmp_path) == 0


def test_stress_exits_1_when_a_check_fails(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(
        stress_checks, "bad_input_checks", lambda: [Check("bad input", "planted", False, "a planted failing check")]
    )
    assert run_stress(tmp_path) == 1
    assert "FAILED bad input: planted: a planted failing check" in capsys.readouterr().out


def test_stress_exits_2_on_bad_input(tmp_path):
    assert main(["stress", "--configurations", "many"]) == 2
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    assert main(["stress", "--out", str(blocker / "x")]) == 2
