"""The FEM's set-up and result shortcuts compute exactly what their plain definitions compute
(bit for bit: they exist for speed only)."""

import pickle

import numpy as np
import pytest

import fem
from fem.discretise import _arc_points, _first_member_ends, discretise


@pytest.mark.parametrize("n", [1, 2, 3, 7, 8, 64, 255, 1024])
def test_straight_member_points_are_those_of_linspace(n):
    for p0, p1 in (((0.0, 0.0), (1.0, 0.0)), ((0.3, -1.7), (2.9, 0.41)), ((-5.0, 2.0), (-5.0, -3.3))):
        P0, P1 = np.array(p0), np.array(p1)
        pts, _ = _arc_points(P0, P1, 0.0, n)
        expected = P0 + np.linspace(0.0, 1.0, n + 1)[:, None] * (P1 - P0)  # the definition
        assert np.array_equal(pts, expected)


def _frame(elements: int) -> fem.Model:
    model = fem.Model()
    for name, x, y in (("a", 0.0, 0.0), ("b", 0.0, 1.0), ("c", 1.2, 1.0), ("d", 1.2, 0.0)):
        model.add_node(name, x, y)
    section = fem.Section.from_EI(1e4, 1.0)
    for start, end in (("a", "b"), ("c", "b"), ("c", "d")):  # 'b' is the end of two members
        model.add_member(start, end, section, n_elements=elements)
    model.add_support("a", "fixed")
    model.add_support("d", "pinned")
    model.add_force("b", [0.5, 1.0], [0.0, -0.2])
    return model


@pytest.mark.parametrize("elements", [1, 5])
@pytest.mark.parametrize("hinged", [False, True])
def test_first_member_end_at_each_model_node_is_the_first_element_end_there(elements, hinged):
    model = _frame(elements)
    if hinged:  # the two members at 'b' turn on their own DOFs
        model.add_joint("b", [0, 1])
    d = discretise(model)
    expected = np.full(d.n_model_nodes, -1)
    for e in range(len(d.conn) - 1, -1, -1):  # the definition: the last write wins
        for side in (1, 0):
            if d.conn[e, side] < d.n_model_nodes:
                expected[d.conn[e, side]] = d.edofs[e, 3 * side + 2]
    assert np.array_equal(_first_member_ends(d.n_model_nodes, d.conn, d.edofs, d.member_elements), expected)
    assert (expected >= 0).all()


def test_field_series_sums_are_those_of_add_at_level_by_level():
    result = fem.solve(_frame(4))
    assert result.converged and result.n_levels == 2
    series = result.field_series()
    conn, N = result.connectivity, result.extra["element_axial_force"]
    n = result.mesh_positions.shape[1]
    count = np.bincount(conn.ravel(), minlength=n).astype(float)
    count[count == 0] = np.nan
    for k in range(result.n_levels):  # the definition: np.add.at on one level
        first, second = np.zeros(n), np.zeros(n)
        np.add.at(first, conn[:, 0], N[k])
        np.add.at(second, conn[:, 1], N[k])
        assert np.array_equal(series.nodal[k].axial_force, (first + second) / count, equal_nan=True)
        assert np.array_equal(series.nodal[k].axial_force, result.nodal_fields(k).axial_force, equal_nan=True)


def test_field_series_point_data_read_late_or_after_pickling_are_those_of_nodal_fields():
    model = fem.Model()  # a section that knows its stress: the stress branch too
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", 1.0, 0.0)
    model.add_member("root", "tip", fem.Section.rectangle(2e11, 0.02, 0.002), n_elements=6)
    model.add_support("root", "fixed")
    model.add_force("tip", [0.0, 0.0], [-0.5, -1.0])
    result = fem.solve(model)
    assert result.converged and result.n_levels == 2
    series = pickle.loads(pickle.dumps(result.field_series()))  # as the run cache stores it, unread
    for k in range(result.n_levels):
        one = result.nodal_fields(k)
        assert one.bending_stress is not None
        for name in ("displacement", "rotation", "curvature", "bending_moment", "axial_force", "bending_stress"):
            assert np.array_equal(getattr(series.nodal[k], name), getattr(one, name), equal_nan=True), (k, name)
    assert np.abs(series.nodal[1].bending_moment).max() > 0.0


@pytest.mark.parametrize("direction", [(1.0, 0.0), (0.3, -0.7), (3.0, 4.0), (-1e-3, 2e5)])
def test_support_direction_is_normalised_as_by_linalg_norm(direction):
    model = fem.Model()
    model.add_node("a", 0.0, 0.0)
    model.add_support("a", "slider", direction=direction)
    d = np.asarray(direction, dtype=float)
    assert model.supports[0].direction == tuple(float(v) for v in d / np.linalg.norm(d))  # the definition


@pytest.mark.parametrize("end", [(1.0, 0.0), (0.3, -1.7), (-2.9e3, 4.1e-2)])
def test_one_member_characteristic_length_is_the_mean_chord_of_the_arrays(end):
    model = fem.Model()
    model.add_node("a", 0.7, -0.2)
    model.add_node("b", *end)
    model.add_member("a", "b", fem.Section.from_EI(1e4, 1.0), n_elements=2)
    c = np.asarray(model.coords)
    chords = np.hypot(*(c[[1]] - c[[0]]).T)  # the definition for any number of members
    assert model.characteristic_length() == float(chords.sum() / len(chords))


def test_many_members_characteristic_length_is_the_mean_chord_of_the_arrays():
    """The multi-member path (differences of the stored float coordinates) against the definition on
    arrays, to the last bit, on random frames of two to nine members."""
    rng = np.random.default_rng(7)
    for trial in range(40):
        model = fem.Model()
        points = rng.normal(scale=10.0 ** rng.integers(-3, 4), size=(rng.integers(3, 8), 2))
        for k, (x, y) in enumerate(points):
            model.add_node(f"n{k}", x, y)
        ends = [(int(a), int(b)) for a, b in rng.integers(0, len(points), size=(rng.integers(2, 10), 2)) if a != b]
        for a, b in ends:
            model.add_member(f"n{a}", f"n{b}", fem.Section.from_EI(1e4, 1.0), n_elements=2)
        if len(model.members) < 2:
            continue
        c = np.asarray(model.coords)
        idx = np.array([(m.start, m.end) for m in model.members])
        chords = np.hypot(*(c[idx[:, 1]] - c[idx[:, 0]]).T)  # the definition
        assert model.characteristic_length() == float(chords.sum() / len(chords)), trial


def test_warm_start_guesses_of_all_levels_at_once_are_those_of_each_level():
    """The reduced unknowns and chord angles of every level's warm-start guess, worked out for all
    levels in one go (one bincount, each level's bins apart), equal those of each level alone bit for
    bit: a slider (two full DOFs feed its unknown), a rigid link (rows that feed nothing) and a
    released joint, on random full vectors. A mixed-up level offset or row would fail."""
    from fem.assembly import System
    from fem.warm_start import chord_angles, reduced_from_full

    m = fem.Model()
    for name, x, y in (("root", 0.0, 0.0), ("a", 1.0, 0.0), ("b", 1.3, 0.4), ("c", 2.2, 0.4)):
        m.add_node(name, x, y)
    section = fem.Section.from_EI(1e3, 1.0)
    m.add_member("root", "a", section, n_elements=3)
    m.add_member("b", "c", section, n_elements=4)
    m.add_rigid_link("a", "b")
    m.add_joint("b", k=1.5)
    m.add_support("root", "fixed")
    m.add_support("c", "slider", direction=(0.6, 0.8))
    m.add_force("c", [0.1, 0.2, 0.3], [0.0, -0.1, -0.2])
    d = discretise(m)
    system = System(m, d)
    U = np.random.default_rng(3).normal(scale=0.2, size=(5, d.n_full + 1))
    q_all, beta_all = reduced_from_full(d, U), chord_angles(d, U, system.X1, system.X2)
    assert q_all.shape == (5, d.n_red) and beta_all.shape == (5, len(d.L0))
    for k in range(5):
        assert np.array_equal(q_all[k], reduced_from_full(d, U[k]))
        assert np.array_equal(beta_all[k], chord_angles(d, U[k], system.X1, system.X2))
    p = U[2][d.edofs]  # the chord of each element in the deformed state, and its angle
    chord = system.X2 - system.X1 + p[:, 3:5] - p[:, 0:2]
    assert np.allclose(np.cos(beta_all[2]), chord[:, 0] / np.hypot(*chord.T), rtol=0, atol=1e-12)
    assert np.allclose(np.sin(beta_all[2]), chord[:, 1] / np.hypot(*chord.T), rtol=0, atol=1e-12)
    one = reduced_from_full(d, U[2])
    C, I = d.C[:, 0] * d.independent, d.I[:, 0]
    for j in range(d.n_red):  # the least-squares formula, unknown by unknown
        rows = I == j
        assert one[j] == pytest.approx((C[rows] * U[2][rows]).sum() / (C[rows] ** 2).sum(), rel=1e-12)


def test_warm_start_midpoints_lie_on_the_hermite_curve_of_the_coarse_elements():
    """The fine mesh's guess puts each new midpoint on the cubic Hermite curve through the coarse
    element's deformed ends, x_mid = (x1 + x2)/2 + L0/8 (t(phi_1) - t(phi_2)) (h10 = 1/8, h11 = -1/8 at
    s = 1/2, end tangents of length L0): the coarse nodes keep the coarse solution, and on a cantilever
    bent to ~50 degrees (PL^2/EI = 2) the midpoints are far closer to the converged fine solution
    than the midpoints of the coarse chords (x1 + x2)/2, which miss by the arc's sagitta on top of the
    coarse mesh's own error (measured: 0.11 of it, the coarse error). A correction of twice the size,
    or of the wrong sign, misses by about the sagitta again (ratio ~1 or ~2) and fails."""
    from fem.warm_start import guess_states

    def cantilever(n):
        m = fem.Model()
        m.add_node("root", 0.0, 0.0)
        m.add_node("tip", 1.0, 0.0)
        m.add_member("root", "tip", fem.Section.from_EI(1e6, 1.0), n_elements=n)
        m.add_support("root", "fixed")
        m.add_force("tip", [0.0], [-2.0])
        return m

    coarse = fem.solve(cantilever(8))
    fine = fem.solve(cantilever(16))
    assert coarse.converged and fine.converged
    d_fine = fine.extra["disc"]
    guess = guess_states(coarse, d_fine)[0]
    u_fine = np.asarray(fine.extra["u_full"], dtype=float)[0]
    chain = np.r_[d_fine.conn[0, 0], d_fine.conn[:, 1]]
    mids = chain[1::2]  # the fine nodes that are new midpoints
    ends = chain[0::2]

    def xy(u, nodes):  # deformed positions of fine-mesh nodes
        return d_fine.X[nodes] + np.stack([u[2 * nodes], u[2 * nodes + 1]], axis=1)

    hermite_miss = np.abs(xy(guess, mids) - xy(u_fine, mids)).max()
    chord_mid = (xy(guess, ends[:-1]) + xy(guess, ends[1:])) / 2
    chord_miss = np.abs(chord_mid - xy(u_fine, mids)).max()
    d_coarse = coarse.extra["disc"]
    coarse_chain = np.r_[d_coarse.conn[0, 0], d_coarse.conn[:, 1]]
    u_coarse = np.asarray(coarse.extra["u_full"], dtype=float)[0]
    coarse_xy = d_coarse.X[coarse_chain] + np.stack(
        [u_coarse[2 * coarse_chain], u_coarse[2 * coarse_chain + 1]], axis=1
    )
    assert np.array_equal(xy(guess, ends), coarse_xy)  # the coarse nodes keep the coarse solution
    assert chord_miss > 1e-3
    assert hermite_miss < 0.25 * chord_miss


def _bar_frame(refined: bool) -> fem.Model:
    """A beam whose tip carries a stiff straight bar (EI 1e6 times the beam's, as the harness models a
    pinned rigid link), the bar's far end loaded."""
    m = fem.Model()
    for name, x, y in (("root", 0.0, 0.0), ("tip", 1.0, 0.0), ("far", 1.0, 0.5)):
        m.add_node(name, x, y)
    m.add_member("root", "tip", fem.Section.from_EI(1e4, 1.0), n_elements=2)
    m.add_member("tip", "far", fem.Section.from_EI(1e10, 1e6), n_elements=1, refined=refined)
    m.add_support("root", "fixed")
    m.add_force("far", [0.0, 0.6], [0.0, -0.4])
    return m


def test_a_member_that_is_not_refined_keeps_its_elements_on_every_mesh():
    """`Model.add_member(refined=False)`: discretise's ``refine`` multiplies the elements of every other
    member and leaves this one's: the refined mesh is the mesh of the model written with the other
    members' elements doubled (the same nodes, the same elements); with ``refined`` (the default)
    the bar is split too."""
    m = _bar_frame(refined=False)
    assert [len(e) for e in discretise(m, refine=2).member_elements] == [4, 1]
    assert [len(e) for e in discretise(_bar_frame(refined=True), refine=2).member_elements] == [4, 2]
    doubled = _bar_frame(refined=False)
    doubled.members[0].n_elements = 4
    fine, plain = discretise(m, refine=2), discretise(doubled)
    assert np.array_equal(fine.X, plain.X) and np.array_equal(fine.conn, plain.conn)


def test_the_warm_start_keeps_the_nodes_of_a_member_that_is_not_refined():
    """The fine mesh's guess from the coarse solution (`warm_start.guess_states`): the bar's nodes keep
    the coarse states (no midpoint to add; to the rounding of (X + u) - X), and the error estimate's
    warm-started fine solve converges to the cold solve of the same mesh; a coarse result of another
    mesh family is refused."""
    from fem.warm_start import guess_states

    m = _bar_frame(refined=False)
    coarse = fem.solve(m, rtol=1e-12)
    fine = fem.solve(m, refine=2, rtol=1e-12)
    assert coarse.converged and fine.converged
    d_c, d_f = coarse.extra["disc"], fine.extra["disc"]
    guess = guess_states(coarse, d_f)
    u_c = np.asarray(coarse.extra["u_full"], dtype=float)
    far_c, far_f = d_c.conn[d_c.member_elements[1][0], 1], d_f.conn[d_f.member_elements[1][0], 1]
    dofs_c, dofs_f = [2 * far_c, 2 * far_c + 1, d_c.rot_dof[far_c]], [2 * far_f, 2 * far_f + 1, d_f.rot_dof[far_f]]
    assert np.allclose(guess[:, dofs_f], u_c[:, dofs_c], rtol=0, atol=1e-15)  # (X + u) - X: rounding only
    warm = fem.solve_with_error_estimate(m, rtol=1e-12)
    assert warm.converged
    # the same state to the corrector's rounding floor, which a bar 1e6 times stiffer raises to ~1e-7 L
    # (its forces' rounding, 4 eps EA, is the floor of the residual test)
    assert np.allclose(warm.result.positions, fine.positions, rtol=0, atol=1e-6)
    with pytest.raises(ValueError, match="half the elements"):
        guess_states(coarse, discretise(_bar_frame(refined=True), refine=3))


def _joint_link_slider(n: int = 3) -> fem.Model:
    """A curved beam and a straight one joined by a rigid link, a released joint with a spring, a
    slider: the constraint map's every kind of row."""
    m = fem.Model()
    for name, x, y in (("root", 0.0, 0.0), ("a", 1.0, 0.0), ("b", 1.3, 0.4), ("c", 2.2, 0.4)):
        m.add_node(name, x, y)
    section = fem.Section.from_EI(1e3, 1.0)
    m.add_member("root", "a", section, n_elements=n, curvature=0.4)
    m.add_member("b", "c", section, n_elements=n + 1)
    m.add_rigid_link("a", "b")
    m.add_joint("b", k=1.5)
    m.add_support("root", "fixed")
    m.add_support("c", "slider", direction=(0.6, 0.8))
    m.add_force("c", [0.1, 0.2, 0.3], [0.0, -0.1, -0.2])
    return m


@pytest.mark.parametrize(
    "model",
    [_joint_link_slider, lambda: _bar_frame(refined=False), lambda: _bar_frame(refined=True)],
    ids=["joint-link-slider", "bar kept", "bar split"],
)
def test_the_compiled_warm_start_gives_the_numpy_guess(model):
    """`warm_start.level_guesses` (compiled, `warm_kernel`) against its definition, the NumPy
    `guess_states` turned into reduced unknowns (`reduced_from_full`) and chord angles (`chord_angles`),
    on random coarse states of every level: a curved member, a rigid link, a released joint, a slider, a
    member that is not refined. The same arithmetic in the same order: equal to the last bits of the
    sines and cosines (C library against NumPy); a midpoint's Hermite term of the wrong sign, a level
    mixed up or a released rotation dropped fails by far more."""
    from types import SimpleNamespace

    from fem.assembly import System
    from fem.warm_start import chord_angles, guess_states, level_guesses, reduced_from_full

    m = model()
    d_c, d_f = discretise(m), discretise(m, refine=2)
    system = System(m, d_f)
    U_c = np.random.default_rng(7).normal(scale=0.3, size=(3, d_c.n_full + 1))
    U_c[:, -1] = 0.0  # the ground entry
    coarse = SimpleNamespace(extra={"disc": d_c, "u_full": U_c})
    got = level_guesses(coarse, d_f, system.X1, system.X2)
    U = guess_states(coarse, d_f)
    q, beta = reduced_from_full(d_f, U), chord_angles(d_f, U, system.X1, system.X2)
    assert got.q.shape == q.shape and got.beta.shape == beta.shape
    assert got.q.flags.c_contiguous and got.beta.flags.c_contiguous
    assert np.allclose(got.q, q, rtol=0, atol=1e-14)
    assert np.allclose(got.beta, beta, rtol=0, atol=1e-14)
    assert np.abs(q).max() > 0.05 and np.abs(beta - d_f.beta0).max() > 0.05  # a guess that moved
