"""The comparison semantics fail when a number is wrong: references, findings, agreements, the
automatic FEM-against-elastica check and the case verdict, on small made-up runs (no solver).

The made-up numbers are inputs of the rule under test, not results of a solver."""

from __future__ import annotations

import math

import pandas as pd
import pytest
from pydantic import ValidationError

from validation.run.compare import (
    FEM_ESTIMATE_MULTIPLE,
    agreement_checks,
    axial_strain_bound,
    case_verdict,
    fem_elastica_checks,
    reference_check,
)
from validation.methods.base import MethodRun, Request
from validation.run.runner import CaseResult
from validation.run.outcome import tabulate
from validation.case.loader import LoadedCase
from validation.case.schema import Case


def _case(**extra) -> Case:
    data = {
        "case": {"id": "t", "title": "t", "group": "g", "units": "dimensionless"},
        "segment": {
            "boundary": "fixed-free",
            "length": 1.0,
            "E": 1.0,
            "section": {"kind": "inertia", "I": 1.0, "A": 1e6},
        },
        "loads": [{"kind": "force", "direction": [0.0, 1.0], "values": [0.0, 1.0, 2.0]}],
        "outputs": [{"quantity": "y"}],
        "methods": {"fem": {}, "elastica": {}, "prbm": {}},
    }
    for key, value in extra.items():
        if key == "case":
            data["case"] |= value
        else:
            data[key] = value
    return Case.model_validate(data)


def _ref(value=1.0, **extra) -> dict:
    return {
        "quantity": "y",
        "level": 1,
        "value": value,
        "label": "exact",
        "source": {"file": "x"},
        "compare": "elastica",
        "tolerance": {"abs": 0.01},
    } | extra


def _run(values: dict[int, float], estimate: float | None = None) -> MethodRun:
    run = MethodRun(values={Request("y", "tip", lv): v for lv, v in values.items()})
    if estimate is not None:
        run.error_estimate = {req: estimate for req in run.values}
    return run


def test_reference_fails_outside_its_tolerance():
    ref = _case(references=[_ref()]).references[0]
    assert reference_check(ref, 1.005, None).within
    assert not reference_check(ref, 1.1, None).within  # a 10 % error
    assert not reference_check(ref, -1.0, None).within  # a sign flip


def test_finding_asserts_both_halves():
    finding = {"text": "misprint: printed 5.41, computed 9.41", "computed": 9.41}
    ref = _case(references=[_ref(5.41, finding=finding)]).references[0]
    assert reference_check(ref, 9.41, None).within
    assert not reference_check(ref, 9.41 * 1.1, None).within  # the explanation no longer reproduces
    stale = reference_check(ref, 5.41, None)  # the printed value is met: stale finding
    assert not stale.within and "stale" in stale.detail


def test_finding_reproduced_by_other_inputs():
    finding = {"text": "mixed I", "reproduce_with": {"methods.elastica.I": 2.0}}
    ref = _case(references=[_ref(1.0, finding=finding)]).references[0]
    assert reference_check(ref, 0.9, reproduced=1.004).within
    assert not reference_check(ref, 0.9, reproduced=1.1).within
    assert not reference_check(ref, 0.9, reproduced=None).within  # the re-run gave nothing


def test_schema_rejects_a_finding_that_explains_nothing_and_a_bare_string():
    with pytest.raises(ValidationError, match="note"):
        _case(references=[_ref(finding={"text": "just a remark"})])
    with pytest.raises(ValidationError):
        _case(references=[_ref(finding="a remark")])
    with pytest.raises(ValidationError, match="compare"):
        _case(
            references=[
                {
                    k: v
                    for k, v in _ref(finding={"text": "x", "computed": 1.0}).items()
                    if k not in ("compare", "tolerance")
                }
            ]
        )


def test_agreement_uses_the_scale_of_the_quantity():
    case = _case(
        agreements=[
            {"method": "prbm", "against": "fem", "quantities": ["y"], "tolerance": {"rel": 0.05}, "basis": "made up"}
        ]
    )
    fem = _run({0: 0.0, 1: 1.0, 2: 2.0})
    ok = agreement_checks(case, case.agreements[0], {"prbm": _run({0: 0.001, 1: 1.04, 2: 2.02}), "fem": fem})
    assert all(c.within for c in ok.values()) and len(ok) == 3  # level 0: |0.001| on 1 % of 2.0
    bad = agreement_checks(case, case.agreements[0], {"prbm": _run({0: 0.0, 1: 1.1, 2: 2.0}), "fem": fem})
    assert not bad[Request("y", "tip", 1)].within


def test_agreement_against_a_printed_column():
    case = _case(
        references=[_ref(2.0, label="measured", compare=None, tolerance=None)],
        agreements=[
            {
                "method": "prbm",
                "against": "measured",
                "quantities": ["y"],
                "tolerance": {"rel": 0.04},
                "basis": "made up",
            }
        ],
    )
    got = agreement_checks(case, case.agreements[0], {"prbm": _run({1: 2.2})})
    assert list(got) == [Request("y", "tip", 1)] and not got[Request("y", "tip", 1)].within
    with pytest.raises(ValidationError, match="against"):
        _case(
            agreements=[
                {"method": "prbm", "against": "ANSYS", "quantities": ["y"], "tolerance": {"rel": 0.04}, "basis": "x"}
            ]
        )


def test_fem_held_to_the_elastica_within_its_estimate():
    case = _case()
    exact = _run({1: 1.0})
    stretch = axial_strain_bound(case, 1) * case.segment.length
    assert stretch == pytest.approx(1.0 / 1e6)  # |F| L / EA with F = 1, EA = 1e6
    near = 1.0 + 0.9 * FEM_ESTIMATE_MULTIPLE * 1e-4
    assert fem_elastica_checks(case, {"fem": _run({1: near}, 1e-4), "elastica": exact}, 1.0)[
        Request("y", "tip", 1)
    ].within
    far = 1.0 + 1.5 * FEM_ESTIMATE_MULTIPLE * 1e-4
    assert not fem_elastica_checks(case, {"fem": _run({1: far}, 1e-4), "elastica": exact}, 1.0)[
        Request("y", "tip", 1)
    ].within
    no_estimate = fem_elastica_checks(case, {"fem": _run({1: 1.0}), "elastica": exact}, 1.0)
    assert not no_estimate[Request("y", "tip", 1)].within


def _verdict(case: Case, runs: dict[str, MethodRun]) -> list[str]:
    result = CaseResult(LoadedCase(path=None, text="", case=case), runs=runs)
    return case_verdict(case, runs, tabulate(result))


def test_verdict_needs_a_check_at_a_loaded_level_for_every_method():
    case = _case(methods={"prbm": {}}, references=[_ref(0.0, level=0, compare="prbm")])
    problems = _verdict(case, {"prbm": _run({0: 0.0, 1: 1.0, 2: 2.0})})
    assert problems == ["prbm has values but no enforced check at a loaded level, and case.unchecked gives no reason"]
    excused = _case(
        methods={"prbm": {}},
        references=[_ref(0.0, level=0, compare="prbm")],
        case={"unchecked": {"prbm": "nothing printed"}},
    )
    assert _verdict(excused, {"prbm": _run({0: 0.0, 1: 1.0, 2: 2.0})}) == []


def test_verdict_on_a_method_that_fails():
    case = _case(
        methods={"prbm": {}}, outputs=[{"quantity": "y", "levels": [1]}], references=[_ref(1.0, compare="prbm")]
    )
    failing = MethodRun(values={}, converged=False, message="not applicable: x")
    assert any(p.startswith("prbm did not give every value") for p in _verdict(case, {"prbm": failing}))
    expected = _case(
        methods={"prbm": {}},
        outputs=[{"quantity": "y", "levels": [1]}],
        references=[_ref(1.0, compare="prbm")],
        case={"expected_failure": {"prbm": "why"}},
    )
    assert _verdict(expected, {"prbm": failing}) == []
    assert "expected to fail" in _verdict(expected, {"prbm": _run({1: 1.0})})[0]


def test_results_table_rows_carry_the_check():
    case = _case(
        methods={"prbm": {}, "fem": {}},
        outputs=[{"quantity": "y", "levels": [1]}],
        agreements=[
            {
                "method": "prbm",
                "against": "fem",
                "quantities": ["y"],
                "levels": [1],
                "tolerance": {"rel": 0.05},
                "basis": "made up",
            }
        ],
    )
    runs = {"prbm": _run({1: 1.2}), "fem": _run({1: 1.0})}
    table = tabulate(CaseResult(LoadedCase(path=None, text="", case=case), runs=runs))
    row = table[table["check"] == "agreement"].iloc[0]
    assert row["within_tolerance"] == False and row["tolerance_rel"] == 0.05  # noqa: E712
    assert row["source"] == "made up" and math.isclose(row["rel_error"], 0.2)
    assert isinstance(table, pd.DataFrame)


def test_one_beam_per_case():
    """No case gives a method its own I or EI: every difference in the table compares the same beam
    (a column that needs another I is a finding with ``reproduce_with``, or another case). A per-beam
    EI table of a mechanism must repeat the beams' own E I."""
    from validation.case.loader import find_case_files, load_case

    other = []
    for path in find_case_files(None):
        case = load_case(path).case
        for method, options in case.methods.items():
            for key in ("I", "EI"):
                given = (options or {}).get(key)
                if given is None:
                    continue
                if isinstance(given, dict) and case.mechanism is not None:
                    beams = {b.name: b for b in case.mechanism.beams}
                    own = {name: beams[name].section.stiffness(beams[name].E or case.mechanism.E)[1] for name in given}
                    if all(abs(given[name] - own[name]) <= 1e-3 * own[name] for name in given):
                        continue
                other.append((path.name, method, key))
    assert not other, other


def test_an_agreement_that_compares_nothing_fails_the_case():
    case = _case(
        methods={"prbm": {}, "fem": {}},
        outputs=[{"quantity": "y"}],
        agreements=[
            {"method": "prbm", "against": "fem", "quantities": ["x"], "tolerance": {"rel": 0.05}, "basis": "made up"}
        ],
        case={"unchecked": {"prbm": "x", "fem": "x"}},
    )
    problems = _verdict(case, {"prbm": _run({0: 0.0, 1: 1.0, 2: 2.0}), "fem": _run({0: 0.0, 1: 1.0, 2: 2.0})})
    assert len(problems) == 1 and "compares nothing" in problems[0]
