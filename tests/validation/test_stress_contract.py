"""``stress --long`` machinery (validation/stress/contract_run.py) and the PRBM's model applicability."""

import math

import pytest

from validation.stress import contract_run as stress_contract
from validation.stress.contract import Configuration, ContractResult
from validation.case.loader import load_case
from validation.methods.base import Request
from validation.run.runner import run_method
from validation.case.schema import Case


def test_every_category_runs_and_passes_on_an_executor(tmp_path):
    rows, summary = stress_contract.run_contract_stress(tmp_path, seed=3, count=6, executor="serial")
    assert summary["configurations"] == 6 and summary["compared_values"] > 50
    assert {r["category"] for r in rows} == set(stress_contract.CATEGORIES)
    assert all(r["passed"] for r in rows), [r["detail"] for r in rows if not r["passed"]]


def test_the_mechanism_check_fails_on_a_wrong_turn(monkeypatch):
    """The turned mechanism must give the segment's answer turned by phi: checked against phi + 10 deg it fails."""
    c = Configuration(
        boundary="fixed-free",
        units="SI",
        length=0.5,
        E=2e11,
        slenderness=100.0,
        kappa_L=0.0,
        load="oblique",
        magnitude=1e-5,
        angle_deg=70.0,
    )
    assert all(r.passed for r in stress_contract.mechanism_check(c, 35.0))
    real = stress_contract.mechanism_case
    monkeypatch.setattr(stress_contract, "mechanism_case", lambda c, phi: real(c, phi + 10.0))
    assert not all(r.passed for r in stress_contract.mechanism_check(c, 35.0))


def test_a_failure_is_shrunk_into_a_case_file(tmp_path, monkeypatch):
    planted = lambda category, c, phi=0.0: [ContractResult("fem", True, 1, ["planted"])]  # noqa: E731
    monkeypatch.setattr(stress_contract, "check", planted)
    rows, _ = stress_contract.run_contract_stress(tmp_path, seed=5, count=2, executor="serial")
    assert not any(r["passed"] for r in rows)
    files = sorted((tmp_path / "regressions").glob("*.toml"))
    assert files and all("kept as" in r["detail"] for r in rows)
    case = load_case(files[0]).case
    assert case.case.units == "dimensionless"  # shrunk to the plain unit system while it still fails


def _force_and_moment(M):
    return Case.model_validate(
        dict(
            case=dict(id="t", title="t", group="t", units="dimensionless"),
            segment=dict(boundary="fixed-free", length=1.0, E=1.0, section=dict(kind="inertia", I=1.0, A=1e6)),
            loads=[dict(kind="force", direction=[0.0, 1.0], values=[1.0]), dict(kind="moment", values=[M])],
            outputs=[dict(quantity="y")],
            methods={"prbm": {}},
        )
    )


@pytest.mark.parametrize("M, inflection", [(-0.3, True), (0.3, False), (-1.5, False)])
def test_the_prbm_warns_when_force_and_moment_give_an_inflection_point(M, inflection):
    """Seed 000 Table 2.1: P and M of one sense never inflect; of opposite sense (M = -0.3 P l) the
    moment changes sign between tip (M) and root (M + P a) and the monotonic model (eq 62) does not fit;
    with M = -1.5 P l the moment keeps its sign along the beam (opposite sense, still no inflection)."""
    run = run_method(_force_and_moment(M), "prbm")
    warned = "inflection point expected" in run.level_messages.get(0, "")
    assert warned == inflection
    assert math.isfinite(run.values[Request("y", "tip", 0)])
