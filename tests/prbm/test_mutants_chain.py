"""prbm.chain and bcm's rigid body: what the mutation run of session 6 found unchecked, each with a derivation.

* ``NodalLoads.plus`` adds every component (only f_y sums were ever used: f_x - other.f_x and m - other.m
  survived); ``lumped_uniform_load`` lumps an axial load q_x like a transverse one (q_x / weights
  survived): q L_i per element, half to each end node, total q_x l (its docstring; trapezoid rule).
* ``RigidBodyOnBeams.displacement`` is (R(phi) - I) r + (u, v): a point one unit above the reference,
  turned a quarter turn counter-clockwise, goes to one unit left of it, so it moves by (-1, -1); its
  v-component's cos(phi) - 1 term never showed at the small angles of the other tests.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bcm.mechanisms import BCMBeam, RigidBodyOnBeams
from prbm.chain import ChainBeam, NodalLoads, chain_from_tip, chain_tip, lumped_uniform_load


def test_nodal_loads_add_every_component():
    one = NodalLoads(np.array([1.0, 2.0]), np.array([3.0, 4.0]), np.array([5.0, 6.0]))
    two = NodalLoads(np.array([10.0, 20.0]), np.array([30.0, 40.0]), np.array([50.0, 60.0]))
    total = one.plus(two)
    assert list(total.fx) == [11.0, 22.0] and list(total.fy) == [33.0, 44.0] and list(total.m) == [55.0, 66.0]


def test_an_axial_uniform_load_is_lumped_like_a_transverse_one():
    beam = ChainBeam(2.0, 3.0, 4)  # elements of 0.5
    loads = lumped_uniform_load(beam, 0.8, -0.2)
    assert loads.fx == pytest.approx([0.2, 0.4, 0.4, 0.4, 0.2], rel=1e-15)  # 0.8 x 0.5, halves at the ends
    assert loads.fy == pytest.approx([-0.05, -0.1, -0.1, -0.1, -0.05], rel=1e-15)
    assert loads.fx.sum() == pytest.approx(0.8 * 2.0) and not loads.m.any()


def test_a_tip_moment_and_an_axial_pull_reach_the_march_through_plus():
    """Linear limit of eqs (32)-(33) on an exact chain: a tip moment m bends the beam to theta0 = m l/EI
    and b = m l^2/(2 EI); a tip pull adds nothing transverse (tension only reduces (31)'s amplification
    of a zero transverse load)."""
    L, EI, m = 2.0, 5.0, 1e-6
    beam = ChainBeam(L, EI, 8)
    loads = NodalLoads.at_tip(beam, fx=1e-6).plus(NodalLoads.at_tip(beam, m=m))
    r = chain_tip(beam, loads, steps=1)
    assert float(r["theta0"]) == pytest.approx(m * L / EI, rel=1e-6)
    assert float(r["b"]) == pytest.approx(m * L**2 / (2 * EI), rel=1e-6)


def test_a_body_point_turned_a_quarter_turn_moves_by_its_rotation():
    body = RigidBodyOnBeams([BCMBeam((0.0, 0.0), (1.0, 0.0), 1.0, 1e4)], (1.0, 0.0))
    q = np.array([0.0, 0.0, math.pi / 2])
    assert body.displacement((1.0, 1.0), q) == pytest.approx([-1.0, -1.0], abs=1e-15)
    assert body.position((1.0, 1.0), q) == pytest.approx([0.0, 0.0], abs=1e-15)
    q = np.array([0.3, -0.2, math.pi])  # half a turn plus a translation
    assert body.position((3.0, 0.5), q) == pytest.approx([1.0 - 2.0 + 0.3, -0.5 - 0.2], abs=1e-15)


def test_a_load_applied_in_one_step_that_the_solver_cannot_reach_is_reported():
    """P L^2/EI = 100 in one step from the straight chain: MINPACK's hybrid method stalls (its own
    words, on one line, after the step that failed); in 20 steps, each started from the last shape,
    it converges. The tip is then nearly along the force (b close to l) and within the beam's reach.
    (With 6 elements the 20-step answer lies 1.012 l from the root: stretched, reported as not converged.)"""
    beam = ChainBeam(1.0, 1.0, 8)
    loads = NodalLoads.at_tip(beam, 0.0, 100.0)
    one = chain_tip(beam, loads, steps=1)
    assert not one.converged and list(one.level_converged) == [False]
    assert (
        one.message.startswith("load step 1/1: The iteration is not making good progress") and "\n" not in one.message
    )
    many = chain_tip(beam, loads, steps=20)
    assert many.converged and many.message == "converged" and 0.95 < float(many["b"]) < 1.0
    assert math.hypot(float(many["a"]), float(many["b"])) < 1.0
    six = ChainBeam(1.0, 1.0, 6)
    stretched = chain_tip(six, NodalLoads.at_tip(six, 0.0, 100.0), steps=20)
    assert not stretched.converged and "beyond an inextensible beam's reach" in stretched.message


def test_function_evaluations_add_up_over_the_load_steps():
    # each step's hybrid solve evaluates the residual at least once (at its start) and its Jacobian at
    # least once (march_jacobian): 2 evaluations per step at the least, counted over all 10 steps
    beam = ChainBeam(2.0, 5.0, 8)
    r = chain_tip(beam, NodalLoads.at_tip(beam, 0.0, 1e-4, -3e-4), steps=10)
    assert r.nit >= 10 * 2


@pytest.mark.parametrize("inverse", [False, True])
def test_the_result_record_of_both_chain_solves(inverse):
    """What a Chain result carries besides the tip: the model's name and equations, the element count,
    one level's convergence, the wall time, and the deflected node positions ending at the tip (a, b)."""
    beam = ChainBeam(2.0, 5.0, 8)
    if inverse:
        r = chain_from_tip(beam, b=1e-4, theta0=2e-4, steps=2)
        model = "Chain Algorithm with tip displacement conditions, seed 000 eqs (26)-(40)"
    else:
        r = chain_tip(beam, NodalLoads.at_tip(beam, 0.0, 1e-4), steps=2)
        model = "Chain Algorithm, seed 000 eqs (26)-(40)"
    assert r.converged and r.message == "converged" and list(r.level_converged) == [True]
    assert r.model == model and r.constants == {"elements": 8}
    # the forward solve: >= 2 evaluations per step (residual and exact Jacobian, see above); the inverse
    # still differentiates by finite differences: 2N + 2 unknowns and the start, per step
    assert 0.0 < r.wall_time < 60.0 and r.nit >= (2 * (2 * 8 + 2 + 1) if inverse else 2 * 2)
    nodes = r.extras["nodes"]
    assert nodes.shape == (9, 2) and list(nodes[0]) == [0.0, 0.0]
    assert nodes[-1] == pytest.approx([float(r["a"]), float(r["b"])], abs=1e-15)


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: ChainBeam(0.0, 1.0), r"^ChainBeam: length must be finite and > 0, got 0\.0$"),
        (lambda: ChainBeam(math.inf, 1.0), r"^ChainBeam: length must be finite and > 0, got inf$"),
        (lambda: ChainBeam(1.0, 1.0, 0), r"^ChainBeam: elements must be >= 1, got 0$"),
        (lambda: ChainBeam(1.0, -2.0), r"^ChainBeam: EI must be finite and > 0, got -2\.0$"),
        (lambda: ChainBeam(1.0, math.nan), r"^ChainBeam: EI must be finite and > 0, got nan$"),
        (lambda: ChainBeam(1.0, (1.0, 2.0), 3), r"^ChainBeam: EI has 2 values for 3 elements$"),
        (lambda: ChainBeam(1.0, 1.0, 2, (0.0,)), r"^ChainBeam: 1 orientations for 2 elements$"),
        (
            lambda: chain_from_tip(ChainBeam(1.0, 1.0, 2), b=math.nan, theta0=0.1),
            r"^chain_from_tip: b, theta0, n must be finite, got nan, 0\.1, 0\.0$",
        ),
    ],
)
def test_bad_chain_input_names_the_field_and_the_value(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_a_chain_with_per_element_stiffness_and_orientation():
    """Two elements at 90 deg (a straight beam along +y, the chain's theta_i), EI = (2, 1): a tiny tip
    moment m turns element i by m L_i/EI_i (eq 33 with no force), so the tip turns by m (0.5/2 + 0.5/1)
    and moves along -x by m (0.5^2/(2*2) + 0.5 * 0.5/2 + 0.5^2/(2*1)) (eq 32 and the rigid turn of
    element 2 by element 1's rotation: the cantilever under a moment, piece by piece)."""
    m = 1e-7
    beam = ChainBeam(1.0, (2.0, 1.0), 2, (math.pi / 2, math.pi / 2))
    assert list(beam.stiffness()) == [2.0, 1.0] and beam.undeformed()[-1] == pytest.approx([0.0, 1.0], abs=1e-15)
    r = chain_tip(beam, NodalLoads.at_tip(beam, m=m), steps=1)
    assert float(r["theta0"]) == pytest.approx(m * (0.5 / 2.0 + 0.5 / 1.0), rel=1e-6)
    assert float(r["a"]) == pytest.approx(-m * (0.25 / 4.0 + 0.25 / 2.0 + 0.25 / 2.0), rel=1e-6)
    assert float(r["b"]) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("phi", [0.0, math.pi / 2, 2.0])
def test_the_generalised_moment_of_a_body_force_is_its_turned_arm_cross_the_force(phi):
    """Virtual work of a dead force F at body point p: d(p)/d(phi) . F = (R(phi) r) x F, r = p - reference
    (the moment about the reference of the force at the point's current place), plus any body moment;
    its terms in sin(phi) vanish at phi = 0, so a quarter turn and phi = 2 rad are needed to see them."""
    body = RigidBodyOnBeams([BCMBeam((0.0, 0.0), (1.0, 0.0), 1.0, 1e4)], (1.0, 0.0))
    r, F, M = np.array([1.0, 0.5]), np.array([2.0, 3.0]), 0.7
    c, s = math.cos(phi), math.sin(phi)
    turned = np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])
    g = body.external_force(np.array([0.1, -0.2, phi]), [((2.0, 0.5), tuple(F))], M)
    assert g == pytest.approx([2.0, 3.0, turned[0] * F[1] - turned[1] * F[0] + M], rel=1e-14, abs=1e-14)


def test_a_target_beyond_the_beams_reach_is_not_converged():
    # an inextensible beam of length l cannot put its tip 1.5 l from the root; the Chain Algorithm's
    # elements stretch (eq 34) until it "meets" b = 1.5 l (found by s6-audit): now reported, not converged
    beam = ChainBeam(1.0, 1.0, 4)
    r = chain_from_tip(beam, b=1.5, theta0=math.radians(60.0), steps=10)
    assert not r.converged and "beyond an inextensible beam's reach" in r.message and "b = 1.5" in r.message
    inside = chain_from_tip(beam, b=0.5, theta0=math.radians(40.0), steps=10)
    assert inside.converged and math.hypot(inside["a"], inside["b"]) < 1.0


def test_a_forward_chain_that_stretches_past_the_beams_length_is_not_converged():
    # two elements under P l^2/EI = 20 at the tip: the chords stretch (eq 34) until the tip is 1.25 l from the
    # root, which the forward solve used to return as converged; eight elements stay within reach
    coarse, fine = ChainBeam(1.0, 1.0, 2), ChainBeam(1.0, 1.0, 8)
    r = chain_tip(coarse, NodalLoads.at_tip(coarse, 0.0, 20.0, 0.0))
    assert not r.converged and "beyond an inextensible beam's reach" in r.message
    ok = chain_tip(fine, NodalLoads.at_tip(fine, 0.0, 20.0, 0.0))
    assert ok.converged and math.hypot(ok["a"], ok["b"]) < 1.0


def test_the_outboard_sums_of_eqs_26_to_28_take_the_loads_beyond_each_element():
    """Element i (nodes i to i+1) carries every load at nodes j >= i+1: (Fx, Fy) their sums and M their
    moment about node i+1, sum m_j + fy_j (x_j - x_i+1) - fx_j (y_j - y_i+1) (eqs 26-28), written here as
    the double loop of the equations, on loads at every node (interior axial forces and moments too)."""
    from prbm.chain import _outboard

    rng = np.random.default_rng(3)
    n = 6
    loads = NodalLoads(rng.normal(size=n + 1), rng.normal(size=n + 1), rng.normal(size=n + 1))
    nodes = rng.normal(size=(n + 1, 2))
    Fx, Fy, M = _outboard(loads, nodes)
    for i in range(n):
        out = range(i + 1, n + 1)
        assert Fx[i] == pytest.approx(sum(loads.fx[j] for j in out), rel=1e-12)
        assert Fy[i] == pytest.approx(sum(loads.fy[j] for j in out), rel=1e-12)
        x, y = nodes[i + 1]
        assert M[i] == pytest.approx(
            sum(loads.m[j] + loads.fy[j] * (nodes[j, 0] - x) - loads.fx[j] * (nodes[j, 1] - y) for j in out), rel=1e-12
        )


def test_scaled_loads_scale_every_component():
    loads = NodalLoads(np.array([1.0, -2.0]), np.array([3.0, 4.0]), np.array([-5.0, 6.0])).scaled(0.25)
    assert list(loads.fx) == [0.25, -0.5] and list(loads.fy) == [0.75, 1.0] and list(loads.m) == [-1.25, 1.5]


def test_the_unloaded_chain_starts_at_the_clamp():
    beam = ChainBeam(3.0, 1.0, 3, orientations=(0.0, math.pi / 2, math.pi))
    assert np.allclose(beam.undeformed(), [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], rtol=0, atol=1e-15)


def test_the_reach_message_gives_the_distance_in_beam_lengths():
    # two elements of a 2-unit beam under P l^2/EI = 40: the stretched chain's tip lies (a^2 + b^2)^0.5 / l
    # lengths from the root, the number the message prints
    beam = ChainBeam(2.0, 1.0, 2)
    r = chain_tip(beam, NodalLoads.at_tip(beam, 0.0, 10.0, 0.0))
    assert not r.converged
    reach = math.hypot(float(r["a"]), float(r["b"])) / 2.0
    assert reach > 1.0 and f"{reach:.4g} lengths from the root" in r.message


def test_the_forward_solve_returns_a_fixed_point_of_the_march():
    """The answer is the deflected chain that reproduces itself (X = G(X), eqs 26-40) to rounding, not to
    a loose solver tolerance: one more march from the returned nodes moves no node by 1e-13 l."""
    from prbm.chain import march

    beam = ChainBeam(2.0, 5.0, 8)
    loads = NodalLoads.at_tip(beam, -1.0, 4.0, 0.5).plus(lumped_uniform_load(beam, 0.3, 1.0))
    r = chain_tip(beam, loads)
    assert r.converged
    nodes = r.extras["nodes"]
    assert np.abs(march(beam, loads, nodes).nodes - nodes).max() < 1e-13 * beam.length


def test_a_displacement_step_the_solver_cannot_take_says_which_step_in_one_line():
    beam = ChainBeam(1.0, 1.0, 4)
    # the tip turned back on itself (theta0 = 3 rad) under a load ratio n = 5, in one step: MINPACK's hybrid
    # method stops without progress
    r = chain_from_tip(beam, b=0.3, theta0=3.0, n=5.0, steps=1)
    assert not r.converged
    assert r.message.startswith("displacement step 1/1: The iteration is not making good progress")
    assert "\n" not in r.message and "  " not in r.message


def test_the_inverse_solve_reports_the_end_conditions_it_met_and_its_axial_load():
    """chain_from_tip's outputs: the tip at height b with rotation theta0 as prescribed (its end
    conditions, met to the solver's tolerance), and nP = n P, the axial component of the tip force
    (-nP, P) it found (Table 3.1's load ratio)."""
    beam = ChainBeam(2.0, 5.0, 8)
    r = chain_from_tip(beam, b=0.4, theta0=0.3, n=2.0)
    assert r.converged
    assert float(r["b"]) == pytest.approx(0.4, abs=1e-9) and float(r["theta0"]) == pytest.approx(0.3, abs=1e-9)
    assert float(r["nP"]) == pytest.approx(2.0 * float(r["P"]), rel=1e-15) and float(r["P"]) != 0.0
