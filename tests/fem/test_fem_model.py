"""Model features of fem/ checked against exact (closed-form) solutions.

Rigid links, revolute joints with torsional springs, sliders, guided supports,
prescribed displacements/rotations, non-proportional load histories, layered
and tapered sections, reactions, member end forces, bending stress, VTU export.
Linear-theory references are used only with loads so small (w/L ~ 1e-7) that
the geometric nonlinearity is below the tolerance; cubic Hermite elements are
nodally exact for point loads on prismatic beams.
"""

from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import fem


def test_rigid_link_with_ground_spring_fixed_and_follower_force():
    L, k, F = 2.0, 3.0, 1.2
    m = fem.Model()
    m.add_node("O", 0.0, 0.0)
    m.add_node("A", L, 0.0)
    m.add_support("O", "pinned")
    m.add_joint("O", k_ground=k)
    m.add_rigid_link("O", "A")
    m.add_force("A", 0.0, -F * np.array([0.5, 1.0]))
    r = fem.solve(m)
    assert r.converged, r.message
    for lev, f in enumerate(F * np.array([0.5, 1.0])):
        theta = brentq(lambda t: k * t + f * L * np.cos(t), -np.pi / 2, 0.0, xtol=1e-15)
        assert abs(r.rotation("O", lev) - theta) < 1e-9
        assert np.allclose(r.position("A", lev), L * np.array([np.cos(theta), np.sin(theta)]), atol=1e-9)
        assert np.allclose(r.reaction("O", lev)[:2], [0.0, f], atol=1e-9)
        assert abs(r.strain_energy[lev] - 0.5 * k * theta**2) < 1e-9
    # follower force stays perpendicular to the bar: k theta = -F L exactly
    m.loads.clear()
    m.add_force("A", 0.0, -F, follower=True)
    r = fem.solve(m)
    assert r.converged, r.message
    assert abs(r.rotation("O") + F * L / k) < 1e-9


@pytest.mark.parametrize("listed", ["second", "both", "default"])
def test_joint_with_spring_between_members_pure_moment(listed):
    EI, L1, L2, k, M = 2.0, 1.0, 0.5, 4.0, 3.0
    m = fem.Model()
    m.add_node("O", 0.0, 0.0)
    m.add_node("B", L1, 0.0)
    m.add_node("C", L1 + L2, 0.0)
    s = fem.Section.from_EI(1e9, EI)
    m1 = m.add_member("O", "B", s, n_elements=40)
    m2 = m.add_member("B", "C", s, n_elements=20)
    m.add_support("O", "fixed")
    m.add_joint("B", members={"second": [m2], "both": [m1, m2], "default": None}[listed], k=k)
    m.add_moment("C", M)
    r = fem.solve(m)
    assert r.converged, r.message
    assert abs(r.rotation("B") - M * L1 / EI) < 1e-9  # node rotation = member 1 end
    assert abs(r.rotation("C") - M * (L1 / EI + 1 / k + L2 / EI)) < 1e-9
    assert abs(r.strain_energy[-1] - 0.5 * M**2 * ((L1 + L2) / EI + 1 / k)) < 1e-9
    kappa = M / EI
    B = np.array([np.sin(kappa * L1), 1 - np.cos(kappa * L1)]) / kappa
    a = kappa * L1 + M / k
    C = B + (np.array([np.sin(a + kappa * L2) - np.sin(a), np.cos(a) - np.cos(a + kappa * L2)]) / kappa)
    assert np.linalg.norm(r.position("C") - C) < 1e-4  # O(h^2) chord effect only


def test_ground_pivot_spring_single_member():
    """A member pinned to the ground through a torsional spring, end moment M."""
    EI, L, k, M = 2.0, 1.0, 5.0, 1.5
    m = fem.Model()
    m.add_node("O", 0.0, 0.0)
    m.add_node("A", L, 0.0)
    bar = m.add_member("O", "A", fem.Section.from_EI(1e9, EI), n_elements=10)
    m.add_support("O", "pinned")
    m.add_joint("O", members=[bar], k=k)
    m.add_moment("A", M)
    r = fem.solve(m)
    assert r.converged, r.message
    assert abs(r.rotation("O") - M / k) < 1e-9
    assert abs(r.rotation("A") - (M / k + M * L / EI)) < 1e-9
    assert abs(r.strain_energy[-1] - 0.5 * M**2 * (1 / k + L / EI)) < 1e-9


@pytest.mark.parametrize("angle_deg", [0.0, 30.0])
def test_pinned_slider_beam_small_load(angle_deg):
    EI, L, P = 1.0, 1.0, 1e-6
    c, s_ = np.cos(np.deg2rad(angle_deg)), np.sin(np.deg2rad(angle_deg))
    m = fem.Model()
    m.add_node("A", 0.0, 0.0)
    m.add_node("M", c * L / 2, s_ * L / 2)
    m.add_node("B", c * L, s_ * L)
    sec = fem.Section.from_EI(1e8, EI)
    m.add_member("A", "M", sec, n_elements=2)
    m.add_member("M", "B", sec, n_elements=2)
    m.add_support("A", "pinned")
    m.add_support("B", "slider", direction=(c, s_))
    m.add_force("M", P * s_, -P * c)
    r = fem.solve(m)
    assert r.converged, r.message
    d = r.position("M") - np.array([c, s_]) * L / 2
    w = -(d @ np.array([-s_, c]))
    assert abs(w / (P * L**3 / (48 * EI)) - 1) < 1e-6
    # the slider reaction is normal to its direction and carries P/2
    R = r.reaction("B")
    assert abs(R[:2] @ np.array([c, s_])) < 1e-12
    assert abs(np.linalg.norm(R[:2]) - P / 2) < 1e-6 * P  # geometric effect ~ w/L


def test_guided_support_small_load():
    EI, L, P = 1.0, 1.0, 1e-6
    m = fem.Model()
    m.add_node("A", 0.0, 0.0)
    m.add_node("B", L, 0.0)
    m.add_member("A", "B", fem.Section.from_EI(1e8, EI), n_elements=2)
    m.add_support("A", "fixed")
    m.add_support("B", "guided", direction=(0.0, 1.0))
    m.add_force("B", 0.0, P)
    r = fem.solve(m)
    assert abs(r.position("B")[1] / (P * L**3 / (12 * EI)) - 1) < 1e-6
    assert abs(r.rotation("B")) < 1e-15


def test_prescribed_rotation_non_proportional_levels():
    """Tip rotation prescribed up to the full circle and back; level 0 non-zero."""
    EI, L = 1.0, 1.0
    phis = np.array([np.pi / 2, 2 * np.pi, np.pi])
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e9, EI), n_elements=20)
    m.add_support("root", "fixed")
    m.prescribe("tip", "rz", phis)
    r = fem.solve(m)
    assert r.converged, r.message
    for k, phi in enumerate(phis):
        assert abs(r.rotation("tip", k) - phi) < 1e-12
        assert abs(r.reaction("tip", k)[2] - EI * phi / L) < 1e-6
        assert abs(r.strain_energy[k] - 0.5 * EI * phi**2 / L) < 1e-8
    assert np.linalg.norm(r.position("tip", 1)) < 1e-6 * L


def test_prescribed_displacement_reaction():
    EI, L, delta = 1.0, 1.0, 1e-7
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e8, EI), n_elements=1)
    m.add_support("root", "fixed")
    m.prescribe("tip", "uy", delta)
    r = fem.solve(m)
    assert abs(r.reaction("tip")[1] / (3 * EI * delta / L**3) - 1) < 1e-6


def test_layered_section_stiffness_and_stress():
    layers = [(200e3, 10.0, 1.0), (70e3, 10.0, 2.0)]
    sec = fem.Section.layers(layers)
    assert np.isclose(sec.EI, sum(E * w * h**3 / 12 for E, w, h in layers))
    assert np.isclose(sec.EA, sum(E * w * h for E, w, h in layers))
    L, P = 100.0, 1e-4
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", sec, n_elements=4)
    m.add_support("root", "fixed")
    m.add_force("tip", 0.0, P)
    r = fem.solve(m)
    assert abs(r.position("tip")[1] / (P * L**3 / (3 * sec.EI)) - 1) < 1e-6
    kappa_root = P * L / sec.EI
    sigma = max(E * kappa_root * h / 2 for E, _, h in layers)
    assert abs(r.max_bending_stress[-1] / sigma - 1) < 1e-6
    # member end forces: root moment equals P x_tip (statics)
    N, V, M = r.member_end_forces[-1, 0, 0]
    assert abs(abs(M) - P * r.position("tip")[0]) < 1e-9 * P * L


def test_rectangle_stress_and_tapered_member():
    E, w, h, L, P = 1000.0, 2.0, 0.5, 10.0, 1e-6
    sec = fem.Section.rectangle(E, w, h)
    assert np.isclose(sec.EI, E * w * h**3 / 12)
    EI0 = sec.EI
    taper = lambda xi: fem.Section.from_EI(sec.EA, EI0 * (1 - 0.5 * xi))
    exact = quad(lambda x: P * (L - x) ** 2 / (EI0 * (1 - 0.5 * x / L)), 0, L)[0]
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", L, 0.0)
    m.add_member("root", "tip", taper, n_elements=8)
    m.add_support("root", "fixed")
    m.add_force("tip", 0.0, P)
    est = fem.solve_with_error_estimate(m)
    w_fine = est.result.position("tip")[1]
    w_ext, w_err = est.extrapolated["positions"][-1, 1, 1], est.error["positions"][-1, 1, 1]
    assert abs(w_fine - exact) <= 1.5 * w_err + 1e-15
    assert abs(w_ext - exact) < 1e-3 * abs(w_fine - exact) + 1e-6 * exact


def test_bifurcation_detected_in_load_control():
    EI, L = 1.0, 1.0
    Pcr = np.pi**2 * EI / (4 * L**2)
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 0.0, L)
    m.add_member("root", "tip", fem.Section.from_EI(1e8, EI), n_elements=8)
    m.add_support("root", "fixed")
    m.add_force("tip", 0.0, -Pcr * np.array([0.9, 1.1]))
    r = fem.solve(m, initial_step=0.05)
    assert r.converged, r.message
    assert [c.kind for c in r.critical_points] == ["bifurcation"]
    # the det K sign change lies between the levels 0.9 Pcr and 1.1 Pcr
    assert 0.0 < r.critical_points[0].load_factor <= 1.0


def test_vtu_export(tmp_path):
    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e6, 1.0), n_elements=4)
    m.add_support("root", "fixed")
    m.add_force("tip", 0.0, [1.0, 2.0])
    r = fem.solve(m)
    paths = r.to_vtu(str(tmp_path / "cantilever"))
    assert len(paths) == 2
    import meshio

    mesh = meshio.read(paths[1])
    assert np.allclose(mesh.points[:, :2], r.mesh_positions[1])
    assert np.allclose(mesh.point_data["rotation"], r.mesh_rotations[1])
    assert (tmp_path / "cantilever.pvd").read_text().count("<DataSet") == 2


def test_fem_does_not_import_prbm_or_validation():
    src = Path(fem.__file__).parent
    for f in src.glob("*.py"):
        text = f.read_text()
        assert "import prbm" not in text and "from prbm" not in text
        assert "import validation" not in text and "from validation" not in text


def test_consistent_tangent_matches_finite_differences():
    """K = dr/dq (elements, springs, rigid link, follower force, slider, curved member)."""
    from fem.assembly import System
    from fem.discretise import discretise

    m = fem.Model()
    m.add_node("O", 0.0, 0.0)
    m.add_node("B", 1.0, 0.2)
    m.add_node("C", 1.5, 0.9)
    m.add_node("D", 2.0, 0.5)
    s = fem.Section.from_EI(50.0, 1.0)
    m.add_member("O", "B", s, n_elements=2)
    m.add_member("B", "C", s, n_elements=2, curvature=0.5)
    m.add_support("O", "pinned")
    m.add_joint("O", k_ground=2.0)
    m.add_joint("B", k=1.5)
    m.add_rigid_link("C", "D")
    m.add_support("C", "slider", direction=(0.6, 0.8))
    m.add_force("D", 0.3, -1.0, follower=True)
    m.add_force("B", 0.2, 0.1)
    sys_ = System(m, discretise(m))
    rng = np.random.default_rng(0)
    q = 0.3 * rng.normal(size=sys_.n)
    beta = sys_.disc.beta0.copy()
    loads = sys_.loads_at(-1, 0, 1.0)
    K = sys_.layout.to_dense(sys_.evaluate(q, beta, 1.3, *loads)["K"])
    h = 1e-6
    K_fd = np.empty_like(K)
    for j in range(sys_.n):
        e = np.zeros(sys_.n)
        e[j] = h
        rp = sys_.evaluate(q + e, beta, 1.3, *loads, need_K=False)["r"]
        rm = sys_.evaluate(q - e, beta, 1.3, *loads, need_K=False)["r"]
        K_fd[:, j] = (rp - rm) / (2 * h)
    assert np.abs(K - K_fd).max() < 1e-6 * np.abs(K).max()


def test_moment_on_one_side_of_a_hinge():
    """A torque on the released end of a beam at a pin acts on that beam only.

    Beam O-A (length L, EI) clamped at O, pinned at A to a rigid bar A-B that is pinned at B to
    ground: the bar holds A fixed in translation, so the beam is a clamped-pinned beam with an end
    moment M at A: end rotation theta_A = M L / (4 EI) (linear theory, tiny M)."""
    import numpy as np

    import fem

    L, EI, M = 1.0, 2.0, 1e-6
    m = fem.Model()
    m.add_node("O", 0.0, 0.0)
    m.add_node("A", L, 0.0)
    m.add_node("B", L, 1.0)
    beam = m.add_member("O", "A", fem.Section.from_EI(1e8, EI), n_elements=4)
    m.add_support("O", "fixed")
    m.add_support("B", "pinned")
    m.add_rigid_link("B", "A")  # the bar: carries A's node rotation, so the joint releases the beam
    m.add_joint("A", members=[beam])
    m.add_moment("A", [M], member=beam)
    r = fem.solve(m)
    assert r.converged
    # the torque reaches the clamp through the beam: carry-over moment M/2 at O
    assert np.isclose(r.reaction("O")[2], M / 2, rtol=1e-6)
    # the same torque on the node (the pin side, which nothing else holds) does not reach the beam
    m.loads[-1] = type(m.loads[-1])(m.loads[-1].node, "moment", m.loads[-1].values)
    r2 = fem.solve(m)
    assert r2.converged and abs(r2.reaction("O")[2]) < 1e-6 * M


@pytest.mark.parametrize(
    "bad", [0.0, -2, float("nan"), float("inf"), np.float64("nan"), np.array(-1.0), np.array(np.inf)]
)
def test_a_section_refuses_a_stiffness_that_is_not_finite_and_positive(bad):
    """EA and EI must be finite and > 0 whether given as Python numbers, numpy scalars or 0-d arrays
    (the plain-number check and the numpy one agree); the error names the field."""
    with pytest.raises(ValueError, match="EA must be finite and > 0"):
        fem.Section(bad, 1.0)
    with pytest.raises(ValueError, match="EI must be finite and > 0"):
        fem.Section(1.0, bad)
    for good in (2, 2.5, np.float64(3.0), np.array(4.0)):
        assert fem.Section(good, good).EA == good


def test_the_number_of_load_levels_is_the_common_length_of_the_histories():
    """`Model.n_levels`: 1 without loads; a single value counts at every level; histories of one length
    n > 1 (forces, moments, prescribed values, forces toward points, distributed loads alike) give n;
    two different lengths are refused, naming both."""
    model = fem.Model()
    model.add_node("a", 0.0, 0.0)
    model.add_node("b", 1.0, 0.0)
    model.add_member("a", "b", fem.Section.from_EI(1e3, 1.0), n_elements=2)
    assert model.n_levels == 1
    model.add_force("b", 0.0, 1.0)
    model.add_moment("b", [0.1, 0.2, 0.3])
    model.prescribe("a", "rz", [0.0, 0.0, 0.0])
    model.add_distributed([0.0, 0.1, 0.2], 0.0)
    model.add_pointed_force("b", [1.0, 2.0, 3.0], (2.0, 0.0))
    assert model.n_levels == 3
    model.add_force("a", [1.0, 2.0, 3.0, 4.0], 0.0)
    with pytest.raises(ValueError, match=r"different lengths: \[3, 4\]"):
        model.n_levels
