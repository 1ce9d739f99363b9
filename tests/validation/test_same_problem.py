"""The same problem to the PRBM and the FEM (issue 20, part B), on configurations no case file contains.

* ``case.purpose = 'fem-validation'`` labels a benchmark of the FEM itself; the schema refuses it beside a
  PRBM, and the summary's one-line reason says so (``outcome.no_prbm_fem_reason``), as it gives every
  other case without a PRBM-vs-FEM number its reason;
* the FEM's inverse tip problem reports the tip x of its own solution (``inverse.tip_x``): the end
  position a for a prescribed b, theta0 and inflection location l1, the quantity of seed 000 section
  3.6's vector loop; expected value: the exact elastica solving the same problem (an independent method);
* the chapter-5 coupler PRBM answers per level: a level outside its fits has no value and says why,
  the others keep theirs (expected: two equal segments side by side translated without turning balance
  at the single segment's answer, tests/prbm/test_inflection_coupler.py's derivation);
* chapter 7's two-port Type 2 MA takes its input forces from ``ma.F_i`` when the case's load is the
  work-piece location, which must be the motion link 4 turned by ``location_deg`` gives that point.
"""

from __future__ import annotations

import cmath
import math

import pandas as pd
import pytest

from prbm.inflection_coupler import CouplerDrive, GuidedSegment, solve_coupler
from validation.case.loader import CaseError, load_case
from validation.methods.base import MethodRun, Request, RunStatus
from validation.run.outcome import no_prbm_fem_reason, summary, tabulate
from validation.run.case_run import run_case
from validation.run.runner import CaseResult, run_method

SEGMENT = """
[case]
id = "toy_{name}"
title = "toy"
group = "tests"
units = "dimensionless"
{info}

[segment]
boundary = "fixed-guided"
length = 1.0
E = 1.0
section = {{ kind = "inertia", I = 1.0, A = 1.0e6 }}

[[loads]]
kind = "force"
direction = [0.0, 1.0]
values = [{load}]

[[outputs]]
quantity = "{quantity}"
methods = {methods}

{options}
"""


def _case(tmp_path, name, info="", load="1.0", quantity="y", methods='["fem"]', options="[methods.fem]\nelements = 4"):
    path = tmp_path / f"{name}.toml"
    path.write_text(
        SEGMENT.format(name=name, info=info, load=load, quantity=quantity, methods=methods, options=options)
    )
    return path


def test_a_fem_validation_benchmark_runs_no_prbm(tmp_path):
    path = _case(
        tmp_path,
        "bench",
        info='purpose = "fem-validation"',
        methods='["fem", "prbm"]',
        options="[methods.fem]\n[methods.prbm]",
    )
    with pytest.raises(CaseError, match="purpose"):
        load_case(path)
    with pytest.raises(CaseError, match="purpose"):
        load_case(_case(tmp_path, "typo", info='purpose = "fem-only"'))
    assert load_case(_case(tmp_path, "ok", info='purpose = "fem-validation"')).case.case.purpose == "fem-validation"


def test_every_case_without_a_number_gets_its_reason_in_the_summary(tmp_path):
    bench = run_case(
        load_case(
            _case(tmp_path, "bench", info='purpose = "fem-validation"\nno_prbm_fem = "a limit load against print"')
        ),
        use_cache=False,
    )
    alone = run_case(load_case(_case(tmp_path, "alone")), use_cache=False)
    both = run_case(
        load_case(
            _case(
                tmp_path,
                "both",
                quantity="y",
                methods='["fem", "prbm"]',
                options="[methods.fem]\nelements = 4\n[methods.prbm]",
            )
        ),
        use_cache=False,
    )
    assert no_prbm_fem_reason(bench) == "FEM-validation benchmark: a limit load against print"
    assert no_prbm_fem_reason(alone) == "no PRBM in this case (the case states no reason)"
    results = [bench, alone, both]
    table = summary(pd.concat([tabulate(r) for r in results]), results).set_index("case")
    assert table.loc["toy_bench", "no_prbm_fem_reason"].startswith("FEM-validation benchmark")
    assert table.loc["toy_alone", "no_prbm_fem_reason"].startswith("no PRBM")
    assert pd.isna(table.loc["toy_both", "no_prbm_fem_reason"]) and table.loc["toy_both", "max_prbm_fem_per_length"] > 0


def test_a_refusing_prbm_is_named_with_its_message(tmp_path):
    loaded = load_case(_case(tmp_path, "refuse", methods='["fem", "prbm"]', options="[methods.fem]\n[methods.prbm]"))
    refused = MethodRun(
        values={}, converged=False, message="no state  within\nthe fits", status=RunStatus.NOT_APPLICABLE
    )
    result = CaseResult(loaded, {"fem": MethodRun(values={}), "prbm": refused})
    assert no_prbm_fem_reason(result) == "PRBM refuses: no state within the fits"
    stalled = MethodRun(values={}, converged=False, message="stopped at level 1")
    assert (
        no_prbm_fem_reason(CaseResult(loaded, {"fem": stalled, "prbm": MethodRun(values={})}))
        == "FEM gave no answer: stopped at level 1"
    )


INFLECTION = """
[case]
id = "toy_inflection"
title = "fixed-guided beam, b = 0.3 L, theta0 = 10 deg, zero moment at 0.55 L"
group = "tests"
units = "dimensionless"

[segment]
boundary = "fixed-guided"
length = 1.0
E = 1.0
section = { kind = "inertia", I = 1.0, A = 1.0e6 }

# start loads of the elastica's continuation only (rounded loads of this state), not applied
[[loads]]
kind = "force"
direction = [1.0, 0.0]
values = [20.0]
[[loads]]
kind = "force"
direction = [0.0, 1.0]
values = [10.0]
[[loads]]
kind = "moment"
values = [-1.3]

[[outputs]]
quantity = "x"
methods = ["fem", "elastica"]

[methods.fem]
inverse = { b = 0.3, theta0_deg = 10.0, l1 = 0.55, elements = 8, richardson = true, tip_x = true }
[methods.elastica]
problem = "inflection"
b = [0.3]
theta0 = [10.0]
l1 = [0.55]
"""


def test_fem_inverse_reports_the_end_position_of_the_exact_inflection_problem(tmp_path):
    """b = 0.3 L, theta0 = 10 deg, zero moment at 0.55 L (a configuration no case file holds): the FEM's
    tip x against the exact elastica's for the same three conditions."""
    path = tmp_path / "inflection.toml"
    path.write_text(INFLECTION)
    case = load_case(path).case
    fem, exact = run_method(case, "fem"), run_method(case, "elastica")
    assert fem.ok and exact.ok, (fem.message, exact.message)
    req = Request("x", "tip", 0)
    assert 0.9 < exact.values[req] < 1.0  # a real end position, shortened by bending
    estimate = fem.error_estimate[req]
    assert 0 < estimate < 1e-3
    assert fem.values[req] == pytest.approx(exact.values[req], abs=3 * estimate + 1e-6)


def test_tip_x_is_refused_where_x_is_prescribed_or_not_a_flag(tmp_path):
    inverse = "{ b = 0.3, theta0_deg = 20.0, a = 0.9, tip_x = true }"
    path = _case(tmp_path, "bad", quantity="x", options=f"[methods.fem]\ninverse = {inverse}")
    run = run_method(load_case(path).case, "fem")
    assert run.status is RunStatus.NOT_APPLICABLE and "prescribed" in run.message and "tip_x" in run.message
    inverse = "{ b = 0.3, theta0_deg = 20.0, l1 = 0.6, tip_x = 1 }"  # a flag, not a number: the schema's
    path = _case(tmp_path, "flag", quantity="x", options=f"[methods.fem]\ninverse = {inverse}")
    with pytest.raises(CaseError, match=r"methods\.fem\.inverse\.tip_x: .*valid boolean"):
        load_case(path)


TWINS = """
[case]
id = "toy_twins"
title = "two equal inflection segments on one coupler"
group = "tests"
units = "in-lb"

[mechanism]
E = 450000.0
nodes = [
  {{ name = "O1", x = -2.7273, y = -8.0178 }}, {{ name = "E1", x = -2.0811, y = -0.6320 }},
  {{ name = "O2", x = -1.7273, y = -8.0178 }}, {{ name = "E2", x = -1.0811, y = -0.6320 }},
  {{ name = "P", x = -1.5811, y = -0.6320 }},
]
beams = [
  {{ name = "s1", start = "O1", end = "E1", section = {{ kind = "rectangle", width = 1.5, thickness = 0.11478 }}, segment_type = "fixed-guided-inflection" }},
  {{ name = "s2", start = "O2", end = "E2", section = {{ kind = "rectangle", width = 1.5, thickness = 0.11478 }}, segment_type = "fixed-guided-inflection" }},
]
links = [ {{ name = "coupler", nodes = ["E1", "E2", "P"] }} ]
supports = [ {{ node = "O1", kind = "fixed" }}, {{ node = "O2", kind = "fixed" }} ]

[[loads]]
kind = "displacement"
point = "P"
direction = [1.0, 0.0]
values = [{shifts}]
[[loads]]
kind = "rotation"
point = "P"
body = "coupler"
values = [{turns}]

[[outputs]]
quantity = "dy"
point = "P"

[methods.prbm]
"""


def test_the_coupler_prbm_answers_the_levels_within_its_fits_and_says_why_not_elsewhere(tmp_path):
    """Level 1: translated without turning, the twins balance at the single segment's answer; level 2:
    turned 25 deg, the two ends 1 in apart need Y values 0.4 in apart, beyond what either reaches
    inside the fits: no value, the reason; all loaded levels outside: NotApplicable."""
    path = tmp_path / "twins.toml"
    path.write_text(TWINS.format(shifts="0.0, -1.0, -1.0", turns="0.0, 0.0, 25.0"))
    run = run_method(load_case(path).case, "prbm")
    seg = GuidedSegment("s1", complex(-2.7273, -8.0178), complex(-2.0811, -0.6320), 450000.0 * 1.5 * 0.11478**3 / 12)
    one = solve_coupler([seg], CouplerDrive(complex(-1.5811, -0.6320), 1 + 0j, -1.0, 0.0))
    assert run.values[Request("dy", "P", 1)] == pytest.approx(float(one.outputs["t"]), abs=1e-9)
    assert Request("dy", "P", 2) not in run.values
    assert run.level_converged == {0: True, 1: True, 2: False} and run.status is RunStatus.NOT_CONVERGED
    assert "disjoint" in run.level_messages[2]
    path.write_text(TWINS.format(shifts="0.0, -1.0", turns="0.0, 25.0"))
    assert run_method(load_case(path).case, "prbm").status is RunStatus.NOT_APPLICABLE


def _compliers(tmp_path, load: str, ma_extra: str, location: float = 3.0):
    text = open("cases/chapter7/example3.toml").read()
    start, end = text.index("[[loads]]"), text.index("[[outputs]]")
    text = text[:start] + load + "\n" + text[end:]
    text = text.replace('level_labels = ["F_i=10", "F_i=20", "F_i=40", "F_i=80"]', "")
    text = text.replace("location_deg = 5.0", f"location_deg = {location}").replace(
        "F_i = [10.0, 20.0, 40.0, 80.0], ", ma_extra
    )
    path = tmp_path / "compliers.toml"
    path.write_text(text)
    return load_case(path).case


def test_the_two_port_ma_takes_the_work_piece_location_as_its_load(tmp_path):
    """Link 4 turned 3 deg (not the case file's 5): the x displacement of IN is |O4 IN| (e^{i 3 deg} - 1)."""
    arm = complex(-1.7941, 2.5916) - complex(0.7745, 0.6004)
    dx = (arm * (cmath.exp(1j * math.radians(3.0)) - 1.0)).real
    held = _compliers(
        tmp_path,
        f'[[loads]]\nkind = "displacement"\npoint = "IN"\ndirection = [1.0, 0.0]\nvalues = [{dx}, {dx}]',
        "F_i = [10.0, 40.0], ",
    )
    forced = _compliers(
        tmp_path, '[[loads]]\nkind = "force"\npoint = "IN"\ndirection = [-0.6127, -0.7903]\nvalues = [10.0, 40.0]', ""
    )
    a, b = run_method(held, "prbm"), run_method(forced, "prbm")
    assert a.ok and b.ok, (a.message, b.message)
    assert a.values == b.values and len(a.values) == 2 * 2  # MA and T_c at two input forces
    wrong = _compliers(
        tmp_path,
        f'[[loads]]\nkind = "displacement"\npoint = "IN"\ndirection = [1.0, 0.0]\nvalues = [{1.1 * dx}, {1.1 * dx}]',
        "F_i = [10.0, 40.0], ",
    )
    run = run_method(wrong, "prbm")
    assert run.status is RunStatus.NOT_APPLICABLE and "location_deg" in run.message


TABLES = [
    "table3_3_case1_a_b_theta0",
    "table3_4_case2a_b_theta0_n0",
    "table3_5_case2b_b_theta0_n",
    "table3_6_case2c_b_theta0_l1",
    "table3_6_exact_inverse",
]


@pytest.mark.parametrize("name", TABLES)
def test_tables_3_3_to_3_6_give_the_fem_the_prbms_displacement_problem(name):
    """Seed 000 Tables 3.3-3.6 specify the tip (b, theta0 and a, n or l1) and ask for the loads: the FEM's
    inverse problem must be the PRBM's, level for level, and both must report the three tip loads."""
    case = load_case(f"cases/chapter3/{name}.toml").case
    prbm, inverse = case.methods["prbm"], case.methods["fem"]["inverse"]
    assert prbm["problem"] == "displacement"
    posed = {k: v for k, v in prbm.items() if k in ("a", "b", "theta0_deg", "n", "l1")}
    assert posed and {k: inverse.get(k) for k in posed} == posed
    for quantity in ("force_x", "force_y", "moment"):
        assert any(
            o.quantity == quantity and {"prbm", "fem"} <= set(o.methods or case.methods) for o in case.outputs
        ), quantity
