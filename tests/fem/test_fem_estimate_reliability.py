"""The FEM's error estimate knows when it is not one (``fem.error_estimate.AsymptoticCheck``).

The Richardson estimate |u_2n - u_n|/3 bounds the error of u_2n only in the asymptotic range. On a
cantilever (L = 1, EI = 1, EA = 1e6) under a large inclined compressive tip force (135 deg) or a large
follower tip force (P L^2/EI = 2..10), the 2/4-element pair is not in it: before the check the tip x at
P L^2/EI = 6 was 11 x its estimate off the exact elastica, with status ok. Every expected number here is
the exact elastica (``elastica.solve_elastica``, shooting to rtol 1e-12), never an earlier FEM output:

- at 2 and 4 elements the FEM's value is within 3 x its estimate (plus the axial stretch P L/EA the
  inextensible elastica leaves out), or the FEM marks that estimate unreliable;
- with no refinement allowed (``max_refine = 2``) the 2-element run marks the estimates it cannot vouch
  for, and every one it does not mark holds; the value 11 x off is among the marked;
- the automatic FEM-against-elastica check records a marked value without judging it, and would judge
  (and fail) the same value unmarked;
- the tables and the report carry the mark, and the report's 'FEM error estimate' leaves it out;
- differences at round-off level are converged, not unreliable; the default 16 elements needs no
  extra mesh on these cases.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import elastica
import fem
from validation.case.loader import LoadedCase
from validation.case.schema import Case
from validation.cli.solve import solve_document
from validation.methods.base import Request
from validation.report.build import UNRELIABLE, glance
from validation.report.summary import estimate_text, summarise, summary_markdown, summary_tables_html
from validation.run.api import validate
from validation.run.compare import FEM_ESTIMATE_MULTIPLE, ROUND_OFF, fem_elastica_checks
from validation.run.outcome import fem_error_relative
from validation.run.runner import run_method
from validation.run import tables

LOADS = [2.0, 4.0, 6.0, 8.0, 10.0]  # P L^2/EI (L = 1, EI = 1)
EA = 1.0e6
KINDS = {
    "inclined": (135.0, False),  # a dead force at 135 deg: compressive, turned off the axis
    "follower": (90.0, True),
}  # a follower force, normal to the tip in the unloaded state
QUANTITIES = ("x", "y", "rotation")


def cantilever(kind: str, elements: int, **fem_options) -> Case:
    angle, follower = KINDS[kind]
    a = math.radians(angle)
    data = dict(
        case=dict(id=f"held_out_{kind}", title=f"cantilever, {kind} tip force", group="tests", units="dimensionless"),
        segment=dict(boundary="fixed-free", length=1.0, E=1.0, section=dict(kind="inertia", I=1.0, A=EA)),
        loads=[dict(kind="force", point="tip", direction=[math.cos(a), math.sin(a)], values=LOADS, follower=follower)],
        outputs=[dict(quantity=q, point="tip") for q in QUANTITIES],
        methods={"fem": dict(elements=elements, **fem_options), "elastica": {}},
    )
    return Case.model_validate(data)


def exact_tip(kind: str) -> dict[Request, float]:
    """The exact elastica's tip (x, y, rotation in degrees) at every level: the expected numbers."""
    angle, follower = KINDS[kind]
    a = math.radians(angle)
    out = {}
    for level, P in enumerate(LOADS):
        load = (P * math.cos(a), P * math.sin(a))
        tip = elastica.solve_elastica(
            1.0, 1.0, rtol=1e-12, atol=1e-12, **({"follower": (0.0, P)} if follower else {"force": load})
        )
        assert tip.converged, tip.message
        out.update(
            {
                Request("x", "tip", level): tip.x,
                Request("y", "tip", level): tip.y,
                Request("rotation", "tip", level): math.degrees(tip.theta),
            }
        )
    return out


def allowed(req: Request, estimate: float) -> float:
    """At most the automatic check's limit (`fem_elastica_checks`): 3 x the estimate, plus the axial strain
    P/EA and the round-off floor, each times the scale (L = 1; for the rotation, in degrees, its largest
    size 180)."""
    scale = 180.0 if req.quantity == "rotation" else 1.0
    return FEM_ESTIMATE_MULTIPLE * estimate + (LOADS[req.level] / EA + ROUND_OFF) * scale


def misses(run, exact) -> dict[Request, tuple[float, float]]:
    """Values off the exact elastica by more than the limit, with (true error, estimate)."""
    out = {}
    for req, want in exact.items():
        error = abs(run.values[req] - want)
        if error > allowed(req, run.error_estimate[req]):
            out[req] = (error, run.error_estimate[req])
    return out


@pytest.fixture(scope="module")
def exact():
    return {kind: exact_tip(kind) for kind in KINDS}


@pytest.mark.parametrize("elements", [2, 4])
@pytest.mark.parametrize("kind", list(KINDS))
def test_coarse_large_deflection_estimate_is_honest_or_marked(kind, elements, exact):
    """At 2 and 4 elements: within 3 x the estimate of the exact elastica, or marked unreliable."""
    run = run_method(cantilever(kind, elements), "fem")
    assert run.ok, run.message
    assert set(run.values) == set(exact[kind])
    wrong = {r: v for r, v in misses(run, exact[kind]).items() if r not in run.unreliable_estimate}
    assert not wrong, f"estimates neither honest nor marked unreliable (true error, estimate): {wrong}"


def test_without_refinement_the_run_marks_what_it_cannot_vouch_for(exact):
    """2 elements, no mesh past the 2/4 pair: the estimates that miss the exact elastica are marked,
    every unmarked one holds, and the run says so in its message."""
    run = run_method(cantilever("inclined", 2, max_refine=2), "fem")
    assert run.ok and run.extras["refine"] == 2, run.message
    off = misses(run, exact["inclined"])
    assert off, "the 2/4 pair must miss somewhere here (the exact tip x at P L^2/EI = 6 is 11 x its estimate off)"
    assert set(off) <= set(run.unreliable_estimate), {r: off[r] for r in set(off) - set(run.unreliable_estimate)}
    assert "estimate unreliable" in run.message
    assert all("asymptotic range" in why for why in run.unreliable_estimate.values())


def test_refined_until_asymptotic_then_honest(exact):
    """With refinement allowed the same 2-element run refines past the 2/4 pair and vouches for every
    estimate, each within 3 x of the exact elastica."""
    run = run_method(cantilever("inclined", 2), "fem")
    assert run.extras["refine"] > 2 and not run.unreliable_estimate, run.message
    assert not misses(run, exact["inclined"])


@pytest.mark.parametrize("kind", list(KINDS))
def test_default_mesh_needs_no_extra_mesh(kind, exact):
    """16 elements (the default): the 8/16/32 meshes are in the asymptotic range here, the values are
    those of the 32-element mesh and every estimate holds."""
    run = run_method(cantilever(kind, 16), "fem")
    assert run.extras["refine"] == 2 and not run.unreliable_estimate, run.message
    assert not misses(run, exact[kind])


def test_compare_rule_records_an_unreliable_estimate_without_judging_it(exact):
    """The automatic FEM-against-elastica check: a marked value is recorded with the reason and not
    judged (within None); the same value unmarked is judged, and fails (its estimate is no bound)."""
    case = cantilever("inclined", 2, max_refine=2)
    runs = {"fem": run_method(case, "fem"), "elastica": run_method(case, "elastica")}
    marked = runs["fem"].unreliable_estimate
    checks = fem_elastica_checks(case, runs, 1.0)
    assert marked and set(checks) == set(runs["fem"].values)
    for req, check in checks.items():
        if req in marked:
            assert check.within is None and check.tolerance is None and "unreliable" in check.detail
        else:
            assert check.within is True, (req, check)
    unmarked = fem_elastica_checks(case, {**runs, "fem": replace(runs["fem"], unreliable_estimate={})}, 1.0)
    off = misses(runs["fem"], exact["inclined"])
    assert off and all(unmarked[req].within is False for req in off)


@pytest.fixture(scope="module")
def marked_validation():
    return validate(cantilever("inclined", 2, max_refine=2))


def test_tables_carry_the_mark(marked_validation, tmp_path):
    """values and results: error_estimate_reliable False on the marked values, True on the other FEM
    values, empty where a method gives no estimate; written and read back the same; the marked rows'
    FEM-against-elastica comparisons are recorded, not judged."""
    v = marked_validation
    marked = v.result.runs["fem"].unreliable_estimate
    fem_rows = v.values[v.values["method"] == "fem"]
    flags = {
        Request(q, p, int(lv)): f
        for q, p, lv, f in zip(
            fem_rows["quantity"], fem_rows["point"], fem_rows["level"], fem_rows["error_estimate_reliable"]
        )
    }
    assert {r for r, f in flags.items() if f is False or f == False} == set(marked)  # noqa: E712
    assert all(bool(f) for r, f in flags.items() if r not in marked)
    assert v.values[v.values["method"] == "elastica"]["error_estimate_reliable"].isna().all()
    tables.write({"values": v.values}, tmp_path)
    for name in ("values.csv", "values.parquet"):
        back = tables.read(tmp_path / name, "values")
        assert back["error_estimate_reliable"].equals(v.values["error_estimate_reliable"]), name
    rows = v.results[(v.results["method"] == "fem") & (v.results["check"] == "fem-elastica")]
    not_judged = rows[rows["within_tolerance"].isna()]
    assert len(not_judged) == len(marked) and not_judged["message"].str.contains("unreliable").all()
    assert (rows["within_tolerance"].dropna() == True).all()  # noqa: E712


def test_report_shows_the_mark_and_leaves_it_out(marked_validation):
    """The report: the summary's 'FEM error estimate' is the largest reliable estimate with the count of
    unreliable ones beside it; the case page shows 'unreliable' in place of a marked estimate."""
    v = marked_validation
    row = summarise(v.result, v.results)
    marked = v.result.runs["fem"].unreliable_estimate
    assert row.fem_unreliable == len(marked) > 0
    assert f"{len(marked)} unreliable" in estimate_text(row) and f"{len(marked)} unreliable" in summary_markdown([row])
    assert f"{len(marked)} unreliable" in summary_tables_html([row], {})
    reliable = v.results[v.results["error_estimate_reliable"] != False]  # noqa: E712
    assert row.fem_estimate == fem_error_relative(reliable)
    if not math.isnan(row.fem_estimate):
        assert row.fem_estimate < fem_error_relative(v.results.assign(error_estimate_reliable=True))
    shown = glance(v.results).set_index(["quantity", "load"])["fem ± (estimate)"]
    assert (shown == UNRELIABLE).sum() == len(marked)


def test_round_off_differences_are_converged_not_unreliable():
    """A tip moment bends the cantilever into a circular arc (exact: constant curvature M/EI), whose
    tip rotation M L/EI every mesh gives to round-off; the reactions are the applied moment (exact
    equilibrium) to round-off in the internal forces: neither is judged unreliable nor refined for."""
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA=EA, EI=1.0), n_elements=16)
    m.add_support("root", "fixed")
    moments = np.array([1.0, 3.0, 6.0])
    m.add_moment("tip", moments)
    est = fem.solve_with_error_estimate(
        m, check=fem.AsymptoticCheck(fields=("rotations", "reactions", "strain_energy"))
    )
    assert est.reliable and est.refine == 2, est.message
    assert np.allclose(est.result.rotations[:, est.result.node_index("tip")], moments, rtol=1e-9)  # exact M L/EI
    for name in ("rotations", "reactions", "strain_energy"):
        assert not np.asarray(est.unreliable[name]).any(), name


def test_no_check_keeps_the_two_mesh_estimate():
    """check=None: the plain n/2n pair, nothing judged (every value reliable by declaration)."""
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA=EA, EI=1.0), n_elements=2)
    m.add_support("root", "fixed")
    P = np.array(LOADS)
    m.add_force("tip", P * math.cos(math.radians(135.0)), P * math.sin(math.radians(135.0)))
    plain = fem.solve_with_error_estimate(m, check=None)
    assert [r.n_elements for r in plain.results] == [2, 4] and plain.reliable
    checked = fem.solve_with_error_estimate(m, max_refine=2)
    assert [r.n_elements for r in checked.results] == [1, 2, 4] and not checked.reliable
    assert np.asarray(checked.unreliable["positions"]).any()


def test_solve_document_names_the_unreliable_estimate():
    """``prbm-validate solve``'s JSON gives the reason beside each estimate marked unreliable, and only there."""
    case = cantilever("inclined", 2, max_refine=2)
    run = run_method(case, "fem")
    loaded = LoadedCase(path=Path("<held-out case>"), text=case.model_dump_json(), case=case)
    outputs = {
        f"{name}@{level['level']}": value
        for level in solve_document(loaded, "fem", run)["levels"]
        for name, value in level["outputs"].items()
    }
    marked = {k for k in outputs if k.split("@")[1].startswith("tip:error_estimate_unreliable")}
    assert len(marked) == len(run.unreliable_estimate) > 0
    assert all("asymptotic range" in outputs[k] for k in marked)


def test_contract_regression_is_fixed_by_refining_not_by_skipping():
    """contract_regression_22f55021 (cases/regressions): the contract's 8-element FEM run on that guided
    beam now refines past the pre-asymptotic 8/16 pair and vouches for every estimate, so the contract
    judges every value against the exact elastica (none is skipped as unreliable) and passes."""
    from validation.case.loader import case_by_id
    from validation.stress.contract import Configuration, build_case, large_deflection_check
    from validation.stress.contract_run import regression_record

    record = regression_record(case_by_id("contract_regression_22f55021").case.case.description)
    c = Configuration(**record["configuration"])
    run = run_method(build_case(c, ("fem",), levels=4, fem_elements=8), "fem")
    assert run.extras["refine"] > 2 and not run.unreliable_estimate, run.message
    (result,) = [r for r in large_deflection_check(c) if r.method == "fem"]
    assert result.compared > 0 and not result.failures, result.failures


def test_reaction_round_off_of_a_stiff_bar_is_converged():
    """EA L^2/EI = 1e10 under a uniform transverse load: the root's force reactions are the load (exact
    equilibrium: R_x = 0, R_y = -q L) to the round-off of the internal forces, about eps EA = 2e-6 here,
    far above 1e-8 of the reaction; that is round-off, not a mesh that is not asymptotic: no extra mesh."""
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(EA=1e10, EI=1.0), n_elements=32)
    m.add_support("root", "fixed")
    q = np.array([1.0, 5.0, 10.0, 30.0])
    m.add_distributed(0.0 * q, q)
    est = fem.solve_with_error_estimate(m, check=fem.AsymptoticCheck(fields=("reactions",)), max_refine=2)
    assert est.reliable, est.message
    root = est.result.reactions[:, est.result.node_index("root")]
    assert np.allclose(root[:, :2], np.column_stack([0.0 * q, -q]), rtol=1e-6, atol=1e-4)  # exact equilibrium
