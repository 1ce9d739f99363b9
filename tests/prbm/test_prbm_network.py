"""The general PRB network and the builder, against independent derivations and the notes' numbers.

* a straight beam by rule (any orientation): dead, follower and prescribed-motion tips against the
  one-pivot virtual-work equations K Theta = P gamma L cos Theta, = P gamma L, = M;
* the parallel-guided mechanism (seed 004): 8 K_Theta Theta = f cos Theta (virtual work on the
  parallelogram with four springs 2 gamma K_Theta EI/L; derived here), at an arbitrary orientation;
* the slant parallelogram of seed 003: the PRBM column of notes/seed-003-004.md sec. 2.2;
* the circular-guided mechanism of seed 003: the lock, and T = gamma K_Theta (EI/L) beta with
  gamma = L_AB/L_OA (notes sec. 4.1 option (a): 4.4808 N mm at beta = 0.1);
* stability: a pinned link with a torsion spring k under an axial thrust P is stable iff P l < k;
* arc length: the bistable four-bar of chapter 6 Example 2 under an input torque, through its limit
  point, every traced state on eq (182) written out here;
* one copy: the network's four-bar and slider-crank springs against eqs (181), (182), (196) written
  out here, for every four-bar of chapters 6, 7 and 9.
"""

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import prbm
from prbm import builder as pb
from validation.case.loader import load_case
from validation.methods.base import Request
from validation.run.runner import run_method
from validation.case.method_options import options_of

ROOT = Path(__file__).resolve().parents[2]
GAMMA, K_THETA = 0.85, 2.65


def _rot(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _beam_geometry(angle: float, L: float = 2.0, EI: float = 3.0):
    tip = _rot((L, 0.0), angle)
    return pb.Geometry(
        nodes=(pb.Node("O", 0.0, 0.0), pb.Node("T", float(tip[0]), float(tip[1]))),
        beams=(pb.Beam("b", "O", "T", EI),),
        supports=(pb.Support("O", "fixed"),),
    )


@pytest.mark.parametrize("angle", [0.0, 0.7, -2.3])
def test_fixed_free_beam_by_rule_dead_follower_couple_and_prescribed(angle):
    L, EI = 2.0, 3.0
    model = pb.build(_beam_geometry(angle, L, EI))
    (record,) = model.beams
    K = GAMMA * K_THETA * EI / L
    assert record.model == "fixed-free" and record.springs[0] == pytest.approx(K, rel=1e-12)
    assert np.allclose(record.pivots[0], _rot(((1 - GAMMA) * L, 0.0), angle))
    P = np.array([0.5, 1.5, 3.0])
    n = _rot((0.0, 1.0), angle)  # transverse to the beam

    def tip(theta):
        return _rot(((1 - GAMMA) * L + GAMMA * L * math.cos(theta), GAMMA * L * math.sin(theta)), angle)

    dead = prbm.solve(model.network, [prbm.Force("T", tuple(P * n[0]), tuple(P * n[1]))], 3)
    follower = prbm.solve(model.network, [prbm.Force("T", tuple(P * n[0]), tuple(P * n[1]), follower=True)], 3)
    couple = prbm.solve(model.network, [prbm.Couple(model.node_body["T"], tuple(P))], 3)
    for i, p in enumerate(P):
        theta = brentq(lambda t: K * t - p * GAMMA * L * math.cos(t), 0.0, 1.6)
        assert np.allclose(dead.position("T", i), tip(theta), atol=1e-10)
        assert dead.rotation(model.node_body["T"], i) == pytest.approx(theta, abs=1e-10)
        assert np.allclose(follower.position("T", i), tip(p * GAMMA * L / K), atol=1e-10)
        assert np.allclose(couple.position("T", i), tip(p / K), atol=1e-10)
    # prescribed transverse travel of the tip (beam along x): the force received is K Theta / (gamma L cos Theta)
    if angle == 0.0:
        dy = (0.2, 0.6, 1.2)
        held = prbm.solve(model.network, [prbm.PrescribedDisplacement("T", "y", dy)], 3)
        for i, d in enumerate(dy):
            theta = math.asin(d / (GAMMA * L))
            force = -held.states[i].lam[-1]
            assert force == pytest.approx(K * theta / (GAMMA * L * math.cos(theta)), rel=1e-9)


def _parallel_guided(angle: float, spacing: float = 0.5):
    nodes = {"G1": (0.0, 0.0), "G2": (0.0, spacing), "C1": (1.0, 0.0), "C2": (1.0, spacing), "M": (1.0, spacing / 2)}
    nodes = {k: _rot(v, angle) for k, v in nodes.items()}
    section = 1.0
    return pb.Geometry(
        nodes=tuple(pb.Node(k, float(v[0]), float(v[1])) for k, v in nodes.items()),
        beams=(pb.Beam("lower", "G1", "C1", section), pb.Beam("upper", "G2", "C2", section)),
        links=(pb.RigidLink("coupler", ("C1", "M", "C2")),),
        supports=(pb.Support("G1", "fixed"), pb.Support("G2", "fixed")),
    )


@pytest.mark.parametrize("angle", [0.0, 1.1])
def test_parallel_guided_against_virtual_work(angle):
    model = pb.build(_parallel_guided(angle))
    assert [b.model for b in model.beams] == ["fixed-guided", "fixed-guided"]
    assert all(k == pytest.approx(2 * GAMMA * K_THETA) for b in model.beams for k in b.springs)
    assert model.network.mobility() == 1
    f = np.array([2.0, 8.0, 16.0])
    d = _rot((0.0, 1.0), angle)
    res = prbm.solve(model.network, [prbm.Force("M", tuple(f * d[0]), tuple(f * d[1]))], 3)
    assert res.converged
    for i, fi in enumerate(f):
        theta = brentq(lambda t: 8 * K_THETA * t - fi * math.cos(t), 0.0, 1.5)
        expected = _rot((GAMMA * (math.cos(theta) - 1.0), GAMMA * math.sin(theta)), angle)
        assert np.allclose(res.displacement("M", i), expected, atol=1e-10)
        assert abs(res.rotation(model.node_body["M"], i)) < 1e-12
        assert res.states[i].stable
        assert res.strain_energy(i) == pytest.approx(4 * 0.5 * 2 * GAMMA * K_THETA * theta**2, rel=1e-9)


def test_parallel_guided_case_runs_the_prbm_built_from_geometry():
    case = load_case(ROOT / "cases/seed004/parallel_guided.toml").case
    assert not case.methods["prbm"]  # no PRBM-specific input
    run = run_method(case, "prbm")
    assert run.converged, run.message
    assert [b["model"] for b in run.extras["prb_model"]] == ["fixed-guided", "fixed-guided"]
    assert "fixed-guided" in run.message
    theta = brentq(lambda t: 8 * K_THETA * t - 16.0 * math.cos(t), 0.0, 1.5)
    assert run.values[Request("dy", "M", 7)] == pytest.approx(GAMMA * math.sin(theta), rel=1e-9)


# notes/seed-003-004.md sec. 2.2, column "PRBM gamma = 0.85, K_Theta = 2.65": (Delta X, Delta Y) in mm;
# here dx = Delta Y, dy = -Delta X
SLANT_PRBM = [
    (0.00315, 0.03162),
    (0.01524, 0.15780),
    (0.02659, 0.28419),
    (0.03719, 0.41076),
    (0.04705, 0.53750),
    (0.05615, 0.66440),
    (0.06450, 0.79143),
    (0.07209, 0.91857),
    (0.07892, 1.04581),
    (0.08499, 1.17313),
    (0.09030, 1.30050),
]


def test_slant_parallelogram_reproduces_the_notes_prbm_column():
    case = load_case(ROOT / "cases/seed003/slant_parallelogram.toml").case
    run = run_method(case, "prbm")
    assert run.converged, run.message
    for level, (dX, dY) in enumerate(SLANT_PRBM):
        assert run.values[Request("dx", "M", level)] == pytest.approx(dY, abs=6e-6)
        assert run.values[Request("dy", "M", level)] == pytest.approx(-dX, abs=6e-6)


def test_circular_guided_lock_is_detected_and_the_notes_workaround_applied():
    case = load_case(ROOT / "cases/seed003/circular_guided.toml").case
    run = run_method(case, "prbm")
    assert run.converged, run.message
    assert "zero mobility" in run.extras["lock"] and "gamma = |G A|/L = 0.8720" in run.extras["lock"]
    (record,) = run.extras["prb_model"]
    assert record["pivots"] == [[3.2, 0.0]] and record["gamma"] == pytest.approx(21.8 / 25.0)
    EI = 73000.0 * 5.1 * 0.25**3 / 12.0
    for level in range(10):
        beta = 0.01 * (level + 1)
        T = 21.8 / 25.0 * K_THETA * EI / 25.0 * beta
        assert run.values[Request("moment", "B", level)] == pytest.approx(T, rel=1e-7)
    assert run.values[Request("moment", "B", 9)] == pytest.approx(4.4808, abs=1e-4)  # notes sec. 4.1 (a)


def test_a_lock_without_the_workaround_raises():
    # the beam's far body is pinned to the ground at two points off the beam's line: it cannot move
    geo = pb.Geometry(
        nodes=(pb.Node("O", 0.0, 0.0), pb.Node("A", 5.0, 0.0), pb.Node("G1", 5.0, 2.0), pb.Node("G2", 6.0, 2.0)),
        beams=(pb.Beam("b", "O", "A", 1.0),),
        links=(pb.RigidLink("body", ("A", "G1", "G2")),),
        supports=(pb.Support("O", "fixed"), pb.Support("G1", "pinned"), pb.Support("G2", "pinned")),
    )
    with pytest.raises(prbm.LockedNetwork, match="zero mobility"):
        pb.build(geo)


def test_four_bar_of_a_fixed_pinned_beam_and_slfp_by_rule():
    # a fixed-pinned beam as the input link of a four-bar: pivot (1 - gamma) L from the clamp
    geo = pb.Geometry(
        nodes=(pb.Node("C", 0.0, 0.0), pb.Node("A", 0.0, 4.0), pb.Node("B", 3.0, 5.0), pb.Node("O4", 4.0, 0.0)),
        beams=(pb.Beam("seg", "C", "A", 2.0),),
        links=(pb.RigidLink("coupler", ("A", "B")), pb.RigidLink("link4", ("O4", "B"))),
        joints=(pb.Joint("A", ("seg", "coupler")), pb.Joint("B", ("coupler", "link4"))),
        supports=(pb.Support("O4", "pinned", member="link4"), pb.Support("C", "fixed")),
    )
    model = pb.build(geo)
    (record,) = model.beams
    assert record.model == "fixed-pinned"
    assert record.pivots[0] == pytest.approx((0.0, (1 - GAMMA) * 4.0))
    assert record.springs[0] == pytest.approx(GAMMA * K_THETA * 2.0 / 4.0)
    assert model.network.mobility() == 1
    # short flexures joining long links become SLFPs, K = EI/l
    geo = pb.Geometry(
        nodes=(
            pb.Node("G", 0.0, 0.0),
            pb.Node("E", 0.0, 0.2),
            pb.Node("F", 0.0, 5.0),
            pb.Node("H", 4.0, 5.2),
            pb.Node("I", 4.0, 5.0),
            pb.Node("J", 4.0, 0.2),
            pb.Node("K", 4.0, 0.0),
        ),
        beams=(
            pb.Beam("f1", "G", "E", 1.0),
            pb.Beam("f2", "F", "H", 1.0),
            pb.Beam("f3", "I", "J", 1.0),
            pb.Beam("f4", "J", "K", 1.0),
        ),
        links=(pb.RigidLink("l2", ("E", "F")), pb.RigidLink("l3", ("H", "I"))),
        supports=(pb.Support("G", "fixed"), pb.Support("K", "fixed")),
    )
    model = pb.build(geo, pb.Rules(beams={"f2": pb.BeamRule(model="slfp")}))
    kinds = {b.beam: b.model for b in model.beams}
    assert kinds["f1"] == "slfp" and kinds["f2"] == "slfp"
    assert next(b for b in model.beams if b.beam == "f1").springs[0] == pytest.approx(1.0 / 0.2)


def test_stability_of_a_pinned_link_under_axial_thrust():
    l, k = 2.0, 3.0
    net = prbm.Network(
        ["link"],
        {"O": (prbm.GROUND, (0.0, 0.0)), "T": ("link", (l, 0.0))},
        pins=[prbm.Pin("link", prbm.GROUND, (0.0, 0.0))],
        springs=[prbm.TorsionSpring("link", prbm.GROUND, k)],
        origins={"link": (0.0, 0.0)},
    )
    res = prbm.solve(net, [prbm.Force("T", (-0.9 * k / l, -1.1 * k / l), (0.0, 0.0))], 2)
    assert res.converged
    assert res.states[0].stable is True and res.states[1].stable is False
    assert res.states[0].min_reduced_eigenvalue == pytest.approx(k - 0.9 * k, rel=1e-9)
    assert res.states[1].min_reduced_eigenvalue == pytest.approx(k - 1.1 * k, rel=1e-9)


def _eq182(fb, theta2, free):
    """Input torque of eq (182) with the deflections of eq (183), written out (the reference)."""
    t3, t4 = fb.angles(theta2)
    h3 = fb.R2 * np.sin(t4 - theta2) / (fb.R3 * np.sin(t3 - t4))
    h4 = fb.R2 * np.sin(t3 - theta2) / (fb.R4 * np.sin(t3 - t4))
    wrap = lambda x: (x + np.pi) % (2 * np.pi) - np.pi  # noqa: E731
    d1 = theta2 - free[0]
    d3a, d4 = wrap(t3 - free[1]), wrap(t4 - free[2])
    d = (d1, wrap(d3a - d1), wrap(d4 - d3a), d4)
    k1, k2, k3, k4 = fb.springs
    T = k1 * d[0] + k2 * d[1] * (h3 - 1) + k3 * d[2] * (h4 - h3) + k4 * d[3] * h4
    U = 0.5 * sum(k * x**2 for k, x in zip(fb.springs, d))
    return T, U


def test_bistable_four_bar_traced_through_its_limit_point():
    # chapter 6 Example 2: k2 = 979.9148 in-lb/rad at A, position 1 energy-free
    fb = prbm.FourBar(
        -4.504 - 2.1j, -2.094 + 2.496j, -9.305 - 3.387j, -6.895 + 1.209j, springs=(0.0, 979.9148, 0.0, 0.0)
    )
    free = fb.theta_free
    res = prbm.trace(fb.network(), [prbm.Couple("link2", (100.0,))], steps=60, ds=0.04, t_max=10.0)
    lf = res.load_factor
    theta2 = free[0] + np.array([s.q[2] for s in res.states])
    T = np.array([_eq182(fb, t, free)[0] for t in theta2])
    assert np.allclose(lf * 100.0, T, rtol=1e-8, atol=1e-8 * np.max(np.abs(T)))
    peak = int(np.argmax(lf))
    assert 0 < peak < len(lf) - 1 and lf[-1] < lf[peak]  # the path went over the limit point
    stable = np.array([s.stable for s in res.states])
    assert stable[:peak].all() and not stable[peak + 1 : peak + 5].any()  # and lost stability there


def _case_four_bars():
    for path in sorted((ROOT / "cases").glob("chapter[679]/*.toml")):
        options = tomllib.loads(path.read_text()).get("methods", {}).get("prbm", {})
        links = options.get("links", {})
        if not {"r1", "r2", "r3", "r4"} <= set(links):
            continue
        Z = {k: complex(*v) for k, v in links.items()}
        sp = options.get("springs", {})
        springs = tuple(float(sp.get(f"k{i}", 0.0)) for i in range(1, 5))
        if not any(springs):
            springs = (3.0, 1.0, 2.0, 5.0)  # springs from eq (186) in the case: any values test the same code
        fb = prbm.FourBar(Z["r1"], Z["r2"], Z["r3"], Z["r4"], Z.get("r5", 0j), springs=springs)
        ef = options.get("energy_free")
        if ef:
            t20 = math.radians(ef["theta2"])
            t3, t4 = (float(v) for v in fb.angles(t20))
            fb.theta_free = (
                t20,
                math.radians(ef.get("theta3", math.degrees(t3))),
                math.radians(ef.get("theta4", math.degrees(t4))),
            )
        yield pytest.param(fb, id=path.stem)


@pytest.mark.parametrize("fb", list(_case_four_bars()))
def test_network_four_bar_equals_eqs_181_182(fb):
    free = fb.theta_free
    theta2 = fb.theta_ref[0] + np.radians([-10.0, 0.0, 7.0, 15.0])
    T_ref, U_ref = _eq182(fb, theta2, free)
    assert np.allclose(fb.input_torque(theta2), T_ref, rtol=1e-9, atol=1e-12 * np.max(np.abs(T_ref)))
    assert np.allclose(fb.strain_energy(theta2), U_ref, rtol=1e-9, atol=1e-12 * np.max(U_ref))
    torques = 0.5 * T_ref[2:]
    res = fb.positions_under_torque(torques)
    assert res.converged
    got = _eq182(fb, res["theta2"], free)[0]
    assert np.allclose(got, torques, rtol=1e-9)


def test_network_slider_crank_equals_eq_196():
    R2, R3, t2, off = 2.0, 3.0, 1.2, 0.4
    t3 = math.pi - math.asin((off - R2 * math.sin(t2)) / R3)
    sc = prbm.SliderCrank(R2, R3, t2, t3, offset=off, springs=(3.0, 1.0, 2.0), f_k=5.0)
    th = t2 + np.linspace(-0.3, 0.3, 7)
    t3s = sc.theta3(th)
    g3 = -R2 * np.cos(th) / (R3 * np.cos(t3s))
    d2, d3 = th - t2, t3s - t3
    x = R2 * np.cos(th) + R3 * np.cos(t3s)
    eq196 = (
        3.0 * d2
        + 1.0 * (d3 - d2) * (g3 - 1)
        + 2.0 * d3 * g3
        + 5.0 * (x - sc.x_ref) * R2 * np.cos(th) * (np.tan(t3s) - np.tan(th))
    )
    assert np.allclose(sc.compliance_torque(th), eq196, rtol=1e-9, atol=1e-12)


# notes/seed-003-004.md sec. 2.1, column "T_elastica [N mm]" (axially extensible, solve_bvp and shooting)
CIRCULAR_EXACT = [0.5159, 1.0318, 1.5478, 2.0638, 2.5799, 3.0960, 3.6123, 4.1286, 4.6450, 5.1616]


def test_elastica_mechanism_reproduces_the_circular_guided_reference():
    case = load_case(ROOT / "cases/seed003/circular_guided.toml").case
    run = run_method(case, "elastica")
    assert run.converged, run.message
    for level, T in enumerate(CIRCULAR_EXACT):
        assert run.values[Request("moment", "B", level)] == pytest.approx(T, abs=6e-5)


def test_parallel_guided_fem_error_is_its_own_estimate_against_the_exact_mechanism():
    case = load_case(ROOT / "cases/seed004/parallel_guided.toml").case
    load = case.loads[0].model_copy(update={"ramp": None, "values": [2.0, 8.0, 16.0]})
    case = case.model_copy(update={"loads": [load], "level_labels": None})  # three of its levels
    fem, exact = run_method(case, "fem"), run_method(case, "elastica")
    assert fem.converged and exact.converged, (fem.message, exact.message)
    for req, value in fem.values.items():
        if req.quantity in ("dx", "dy", "strain_energy"):
            error = abs(value - exact.values[req])
            assert 0.9 * fem.error_estimate[req] <= error <= 1.05 * fem.error_estimate[req], req


def test_a_body_carried_by_one_beam_rides_on_its_prb_link():
    # beam O-E (L = 2, EI = 3) clamped at O; a rigid body E-Q welded at E, held by nothing else; force at Q
    L, EI = 2.0, 3.0
    geo = pb.Geometry(
        nodes=(pb.Node("O", 0.0, 0.0), pb.Node("E", L, 0.0), pb.Node("Q", L + 0.5, 0.4)),
        beams=(pb.Beam("b", "O", "E", EI),),
        links=(pb.RigidLink("body", ("E", "Q")),),
        supports=(pb.Support("O", "fixed"),),
    )
    model = pb.build(geo)
    (record,) = model.beams
    assert record.model == "fixed-free" and "rides on the PRB link" in record.reason
    assert model.network.mobility() == 1
    K = GAMMA * K_THETA * EI / L
    pivot = np.array([(1 - GAMMA) * L, 0.0])
    arm = np.array([L + 0.5, 0.4]) - pivot
    F = np.array([-0.3, 1.2])
    res = prbm.solve(model.network, [prbm.Force("Q", (F[0],), (F[1],))], 1)

    def moment(theta):  # K Theta = (Q(Theta) - pivot) x F
        a = _rot(arm, theta)
        return K * theta - (a[0] * F[1] - a[1] * F[0])

    theta = brentq(moment, 0.0, 1.5)
    assert np.allclose(res.position("Q", 0), pivot + _rot(arm, theta), atol=1e-10)


def test_a_beam_pinned_to_the_ground_and_clamped_to_a_link_is_fixed_pinned_from_the_clamp():
    # chapter 6 Example 2's input segment: O2 pinned to the ground, F clamped to the coupler
    case = load_case(ROOT / "cases/chapter6/example2.toml").case
    from validation.methods import prbm_network

    model = pb.build(prbm_network.geometry(case.mechanism))
    (record,) = model.beams
    O2, F = np.array([0.0, 0.0]), np.array([-2.4609, 2.9328])
    assert record.model == "fixed-pinned" and record.ends == ("pinned", "clamped")
    assert np.allclose(record.pivots[0], F + (1 - GAMMA) * (O2 - F))
    assert model.network.mobility() == 1


def test_compliant_slider_crank_by_rule_against_virtual_work():
    # a fixed-pinned beam as the crank (clamp C), a coupler A-S, the slider S on a ground line along x;
    # the slider is pushed by dx: the force it needs is dU/dTheta2 / (dx/dTheta2) (virtual work, eq 196)
    L, EI, angle = 3.0, 2.0, math.radians(70.0)
    C = np.array([0.5, -0.2])
    A = C + L * np.array([math.cos(angle), math.sin(angle)])
    S = np.array([C[0] + 4.0, C[1] + 0.3])
    geo = pb.Geometry(
        nodes=(pb.Node("C", *C), pb.Node("A", *A), pb.Node("S", *S)),
        beams=(pb.Beam("crank", "C", "A", EI),),
        links=(pb.RigidLink("coupler", ("A", "S")),),
        joints=(pb.Joint("A", ("crank", "coupler")),),
        supports=(pb.Support("C", "fixed"), pb.Support("S", "slider", direction=(1.0, 0.0))),
    )
    model = pb.build(geo)
    assert [b.model for b in model.beams] == ["fixed-pinned"] and model.network.mobility() == 1
    K = GAMMA * K_THETA * EI / L
    O2 = C + (1 - GAMMA) * L * np.array([math.cos(angle), math.sin(angle)])
    t3 = math.atan2(S[1] - A[1], S[0] - A[0])
    sc = prbm.SliderCrank(
        GAMMA * L, float(np.linalg.norm(S - A)), angle, t3, offset=float(S[1] - O2[1]), springs=(K, 0.0, 0.0)
    )
    dx = (-0.2, 0.15, 0.4)
    res = prbm.solve(model.network, [prbm.PrescribedDisplacement("S", "x", dx)], 3)
    assert res.converged
    for i, d in enumerate(dx):
        theta2 = sc.theta2_at(d)
        t3i = float(sc.theta3(theta2))
        dx_dtheta = GAMMA * L * math.cos(theta2) * (math.tan(t3i) - math.tan(theta2))
        force = -res.states[i].lam[-1]
        assert force == pytest.approx(K * (theta2 - angle) / dx_dtheta, rel=1e-8)
        assert res.position("S", i)[1] == pytest.approx(S[1], abs=1e-12)


def test_the_rotation_of_a_free_beam_end_is_not_the_prb_link_angle():
    # quantity contract: rotation = change of the tangent angle at the point; the PRB link's angle is not it
    from validation.methods import prbm_network
    from validation.methods.base import MethodRun, NotApplicable

    case = load_case(ROOT / "cases/seed004/parallel_guided.toml").case
    mech = case.mechanism.model_copy(
        update={
            "links": [],
            "supports": case.mechanism.supports[:1],
            "beams": case.mechanism.beams[:1],
            "nodes": [n for n in case.mechanism.nodes if n.name in ("G1", "C1")],
        }
    )
    load = case.loads[0].model_copy(update={"point": "C1"})
    one = case.model_copy(update={"mechanism": mech, "loads": [load]})
    values = prbm_network.run_mechanism(one, [Request("dy", "C1", 0)], options_of("prbm", {}), MethodRun(values={}))
    # a free end under one transverse dead force: n = 0 is defined, so the builder takes the Pauly-Midha
    # fits there (seed 000 eqs 41, 43 at n = 0: gamma = 0.851892, K_Theta = 2.648834) and eq (47)
    gamma0, K0 = 0.851892, 2.648834
    theta = brentq(lambda t: gamma0 * K0 * t - 2.0 * gamma0 * math.cos(t), 0.0, 1.5)
    assert values[Request("dy", "C1", 0)] == pytest.approx(gamma0 * math.sin(theta), rel=1e-9)
    with pytest.raises(NotApplicable, match="end slope"):
        prbm_network.run_mechanism(one, [Request("rotation", "C1", 0)], options_of("prbm", {}), MethodRun(values={}))
