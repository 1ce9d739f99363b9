"""The plain-script OpenSees peer of the benchmark (`validation.bench.opensees_script`).

The script's inputs are read from the case (no number of its own), and it must land where the harness's
adapter (``validation.methods.opensees``) lands on the same mesh: both run the same OpenSees model with
Newton stopped at NormDispIncr 1e-10, so each stops within that increment of the same discrete
equilibrium, and their displacements differ by at most twice it. A planted error in the script's model
(the load's sign, the beam's length, its stiffness off by a millionth) must break that agreement. The
runs need OpenSeesPy (the ``peer`` extra) and are skipped without it; the reading of the case is checked
without it.
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from validation.bench import headline as bench
from validation.bench.opensees_script import (
    NEWTON_TOLERANCE,
    SCRIPT,
    Member,
    ScriptJob,
    ScriptUnavailable,
    script_job,
    script_model,
)
from validation.case.loader import case_by_id
from validation.case.method_options import OpenSeesOptions
from validation.methods.base import RunStatus
from validation.run.runner import requests_for, run_method

AGREE = 2 * NEWTON_TOLERANCE  # two runs each within the Newton tolerance of one equilibrium
SINGLE_LEVEL = bench.BENCH_CASES[0]  # the cantilever, PL^2/EI = 10 in one level


def _cantilever():
    return bench._last_level_only(case_by_id("cantilever_tip_load").case)


def _both(case, bench_case, n: int) -> tuple[dict, ScriptJob]:
    """The adapter's values on the case at n elements, and the plain script's job on the same."""
    adapter = run_method(bench._at(case, bench_case, bench.PEER, n), bench.PEER)
    assert adapter.converged and adapter.values, adapter.message
    return adapter.values, bench._at(case, bench_case, SCRIPT, n)


def _worst(values: dict, job: ScriptJob) -> float:
    """The largest difference of the script's values from ``values`` (inf when it misses one)."""
    got = job.run().values
    return max((abs(got[r] - v) if r in got else math.inf) for r, v in values.items())


@pytest.mark.parametrize("n", [8, 16])
def test_the_script_gives_the_adapters_answer_on_the_single_level_cantilever(n):
    pytest.importorskip("openseespy.opensees")
    values, job = _both(_cantilever(), SINGLE_LEVEL, n)
    assert {r.quantity for r in values} == {"x", "y"}
    assert _worst(values, job) <= AGREE
    assert values[next(r for r in values if r.quantity == "y")] > 0.8  # PL^2/EI = 10: w/L = 0.81, a large deflection


def test_a_planted_error_in_the_script_breaks_the_agreement():
    """The load's sign flipped, the beam 1 % longer, its EI off by a millionth: each moves the tip by far
    more than the agreement allows (the last by about 1e-7 L, a thousand times it)."""
    pytest.importorskip("openseespy.opensees")
    values, job = _both(_cantilever(), SINGLE_LEVEL, 8)
    model = job.model
    assert model is not None and _worst(values, job) <= AGREE
    (root, (length, y)), beam = model.points, model.members[0]
    planted = {
        "load sign": replace(model, loads=tuple((p, -fx, -fy, -m) for p, fx, fy, m in model.loads)),
        "length": replace(model, points=(root, (1.01 * length, y))),
        "stiffness": replace(model, members=(replace(beam, EI=beam.EI * (1 + 1e-6)),)),
    }
    for what, wrong in planted.items():
        assert _worst(values, replace(job, model=wrong)) > 100 * AGREE, what


@pytest.mark.parametrize("index", range(1, len(bench.BENCH_CASES)), ids=[b.label for b in bench.BENCH_CASES[1:]])
def test_the_script_gives_the_adapters_answer_on_every_benchmark_case(index):
    """The ten-level cantilever, the roll-up by an end moment (whose Newton fails past ML/EI = pi in both,
    at the same load factor), Lee's frame (the limit load by displacement control), the composite beam of
    Test 1(a), Test 2 (hinges, a rigid coupler, a pinned link) and the parallel-guided mechanism (a rigid
    coupler on two beams), at 4 elements a beam."""
    pytest.importorskip("openseespy.opensees")
    bench_case = bench.BENCH_CASES[index]
    case = case_by_id(bench_case.case_id).case
    case = bench._last_level_only(case) if bench_case.single_level else case
    adapter = run_method(bench._at(case, bench_case, bench.PEER, 4), bench.PEER)
    job = bench._at(case, bench_case, SCRIPT, 4)
    run = job.run()
    assert adapter.values and set(run.values) == set(adapter.values)
    for r, v in adapter.values.items():  # a limit load (Lee's frame, P L^2/EI = 18.6): relative to it
        assert abs(run.values[r] - v) <= AGREE * max(1.0, abs(v)), r
    assert (run.converged, run.extras["iterations"]) == (adapter.converged, adapter.extras["iterations"])


def test_the_scripts_numbers_come_from_the_case():
    """The single-level cantilever read into the script: root and tip at 0 and L, EI and EA of the
    section, the tip load P L^2/EI = 10 along +y at load factor 1, one level; a longer, stiffer, reversed
    case gives the script those numbers, not its own."""
    case = bench._at(_cantilever(), SINGLE_LEVEL, bench.PEER, 8)  # the positions the bench reads
    model, names = script_model(case, tuple(requests_for(case, bench.PEER)), OpenSeesOptions())
    assert model.points == ((0.0, 0.0), (1.0, 0.0)) and names == {"root": 0, "tip": 1}
    assert model.members == (Member(0, 1, 1e10, 1.0),)
    assert model.supports == ((0, True),) and model.factors == (1.0,)
    assert model.loads == ((1, 0.0, 10.0, 0.0),) and model.readings == ((0, 1),)
    seg = case.segment.model_copy(update={"length": 2.5, "E": 3.0})
    load = case.loads[0].model_copy(update={"direction": (0.0, -1.0)})
    other = case.model_copy(update={"segment": seg, "loads": [load]})
    model, _ = script_model(other, tuple(requests_for(other, bench.PEER)), OpenSeesOptions())
    assert model.points[1] == (2.5, 0.0) and model.members[0].EI == 3.0
    assert model.loads == ((1, 0.0, -10.0, 0.0),)


def test_a_case_the_script_does_not_express_is_unavailable_with_no_numbers():
    """A curved beam (the arch), a follower load, a sprung joint: the job says "unavailable: ..." and
    its run gives no values (the bench then prints "plain script unavailable: ...")."""
    arch = case_by_id("arch_215_clamped_hinged").case
    with pytest.raises(ScriptUnavailable, match="curved beam"):
        script_model(arch, tuple(requests_for(arch, bench.PEER)), OpenSeesOptions())
    job = script_job(arch, 4)
    run = job.run()
    assert job.model is None and job.reason.startswith("unavailable: ")
    assert run.values == {} and run.status is RunStatus.NOT_APPLICABLE and run.message == job.reason
    assert bench._no_rows(SCRIPT, job.reason).startswith("plain script unavailable: ")
    follower = case_by_id("bapat2015_test2_follower").case
    with pytest.raises(ScriptUnavailable, match="turning with the structure"):
        script_model(follower, tuple(requests_for(follower, bench.PEER)), OpenSeesOptions())
