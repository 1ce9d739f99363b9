"""The compiled element kernel against the vectorised NumPy element (the same derivation written
twice, Crisfield 1991 ch. 7), and its tangent against central differences of its own forces.

Compiled code and NumPy or LAPACK agree to within bounds of their rounding, stated in each test, never
to the last bit (the C library's sine is not NumPy's, a BLAS kernel depends on the CPU); rounding
bounds from Higham 2002 (N. J. Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., SIAM)."""

from dataclasses import replace
import numpy as np
import pytest

from fem.corotational import element_state, element_state_numpy
from scipy.linalg.lapack import dgbtrf, dgbtrs

from fem.kernel import Band, Beams, band_lu, band_solve, scatter

EPS = float(np.finfo(float).eps)  # machine epsilon
# one worker for the module: the kernels called here with arguments no case passes (other sizes, layouts) are
# compiled once, by one worker, when the compiled cache is cold (about half a CPU-second each in the other)
pytestmark = pytest.mark.xdist_group("fem_kernel")


def _random_elements(rng, n):
    X1 = rng.normal(size=(n, 2))
    ang = rng.uniform(-np.pi, np.pi, n)
    L0 = rng.uniform(0.2, 2.0, n)
    X2 = X1 + L0[:, None] * np.column_stack([np.cos(ang), np.sin(ang)])
    p = 0.3 * rng.normal(size=(n, 6))
    p[:, 2::3] *= 5.0  # rotations beyond pi, where the wrap acts
    ka = rng.uniform(1.0, 1e3, n)
    EI = rng.uniform(0.5, 2.0, n)
    kb = (EI / L0)[:, None, None] * np.array([[4.0, 2.0], [2.0, 4.0]]) + rng.normal(scale=0.1, size=(n, 2, 2))
    beta_prev = ang + rng.normal(scale=0.2, size=n)
    return Beams(X1=X1, X2=X2, L0=L0, beta0=ang, ka=ka, kb=kb), p, beta_prev


def test_kernel_equals_the_numpy_element_on_random_states():
    args = _random_elements(np.random.default_rng(1), 200)
    got, ref = element_state(*args), element_state_numpy(*args)
    assert ref["jumped"].any() and not ref["jumped"].all()  # both branches of the wrap are exercised
    for key in ("f", "K", "N", "M", "L", "beta", "theta_bar", "u_bar"):
        np.testing.assert_allclose(got[key], ref[key], rtol=1e-12, atol=1e-12 * np.abs(ref[key]).max(), err_msg=key)
    np.testing.assert_array_equal(got["jumped"], ref["jumped"])


def test_kernel_tangent_is_the_derivative_of_its_forces():
    beams, p, _ = _random_elements(np.random.default_rng(2), 5)
    p[:, 2::3] *= 0.1  # away from the wrap discontinuity
    beta_prev = element_state(beams, p, beams.beta0)["beta"]
    K = element_state(beams, p, beta_prev)["K"]
    h = 1e-6
    for j in range(6):
        dp = np.zeros_like(p)
        dp[:, j] = h
        fp = element_state(beams, p + dp, beta_prev, False)["f"]
        fm = element_state(beams, p - dp, beta_prev, False)["f"]
        np.testing.assert_allclose(K[:, :, j], (fp - fm) / (2 * h), rtol=1e-6, atol=1e-6 * np.abs(K).max())


def test_scatter_sums_repeated_targets_like_bincount():
    rng = np.random.default_rng(3)
    target = rng.integers(0, 7, 50)
    source = rng.integers(0, 30, 50)
    factor = rng.normal(size=50)
    values = rng.normal(size=30)
    expected = np.bincount(target, weights=values[source] * factor, minlength=9)
    assert scatter(target, source, factor, values, 9) == pytest.approx(expected, rel=1e-14, abs=1e-14)


def _compressed_column(load: float, kind: str = "auto", elements: int = 12, follower: bool = False):
    """The system of a straight cantilever (EA = 1e4, EI = 1, L = 1) of ``elements`` elements under the
    axial compression ``load`` at its tip (a follower force with ``follower``), with the tangent stored
    ``kind`` ('banded', 'dense' or the solver's choice)."""
    import fem
    from fem.assembly import System
    from fem.discretise import discretise

    m = fem.Model()
    m.add_node("root", 0.0, 0.0)
    m.add_node("tip", 1.0, 0.0)
    m.add_member("root", "tip", fem.Section.from_EI(1e4, 1.0), n_elements=elements)
    m.add_support("root", "fixed")
    m.add_force("tip", -load, 0.0, follower=follower)
    return System(m, discretise(m), solver_kind=kind)


def test_the_inertia_threshold_is_the_stability_checks_zero_eigenvalue():
    """`System.inertia_tol`: `stability.zero_eigenvalue` (1, n) where `solver._even_crossing` makes its
    test (dead loads, n <= DENSE_LIMIT), NaN (the corrector makes none) under a follower load or past
    DENSE_LIMIT unknowns."""
    from fem.stability import DENSE_LIMIT, zero_eigenvalue

    system = _compressed_column(4.0, "banded")
    assert system.inertia_tol == zero_eigenvalue(1.0, system.n) > 0.0
    assert np.isnan(_compressed_column(1.0, follower=True).inertia_tol)
    large = _compressed_column(1.0, elements=DENSE_LIMIT // 3 + 1)
    assert large.n > DENSE_LIMIT and np.isnan(large.inertia_tol)


@pytest.mark.parametrize("kind", ["banded", "dense"])
@pytest.mark.parametrize("held", [None, 7])
def test_cholesky_inertia_agrees_with_the_lowest_eigenvalue(kind, held):
    """eigenvalue_below(K, tol) is 'lowest scaled eigenvalue < -tol' (Sylvester), checked on the
    straight cantilever under axial compression past its first (and second) buckling loads
    (P_cr = pi^2 EI / 4 L^2, 9 pi^2 EI / 4 L^2), with thresholds just either side of lambda_min."""
    from fem.stability import eigenvalue_below, lowest_modes

    for load in (1.0, 4.0, 30.0):  # below, between, beyond the first two
        system = _compressed_column(load, kind)
        assert system.layout.kind == kind
        loads = system.loads_at(-1, 0, 1.0)
        d = system.disc
        q = np.zeros(system.n)  # the straight state: u = -P x / EA
        for node in range(len(d.X)):
            k = d.I[2 * node, 0]
            if k < system.n:
                q[k] = -load * d.X[node, 0] / 1e4
        K = system.evaluate(q, system.disc.beta0.copy(), 1.0, *loads)["K"]
        lam_min = lowest_modes(system, K, held, count=1)[0][0]
        if held is None:  # holding a DOF stiffens the column
            assert (lam_min < 0) == (load > np.pi**2 / 4)
        for tol in (-0.999 * lam_min, -1.001 * lam_min, 1e-12):
            assert eigenvalue_below(system, K, held, tol) == (lam_min < -tol), (load, tol, lam_min)


@pytest.mark.parametrize("kind", ["banded", "dense"])
def test_corrector_confirms_the_sign_and_tests_the_inertia_as_python_would(kind):
    """At a converged state the compiled corrector does what `newton.det_sign` and
    `solver._even_crossing` did after it, with the same answers as `linear_solver` and
    `stability.eigenvalue_below` (LAPACK on the row-major tangent) at that state. On the column of the
    test above (buckling loads pi^2/4 and 9 pi^2/4): a sign that is not positive from the iterate before
    convergence is confirmed on the converged tangent (stepping back from 4 to 1 starts from a tangent
    with det < 0 and ends at a stable state, det > 0); a positive one is taken as it is (from 1 to 4;
    the inertia test sees the eigenvalue below zero), a state converged before any correction keeps its
    own (final) sign; the inertia test, thresholds either side of the lowest eigenvalue, agrees with the
    eigenvalues at loads 1, 4 and 30 (none, one, two below zero); not asked (NaN), not made (-1)."""
    from fem.newton import det_sign, newton
    from fem.options import SolveOptions
    from fem.stability import eigenvalue_below, lowest_modes, zero_eigenvalue

    def column(load):
        system = _compressed_column(load, kind)
        assert system.compiled is not None
        return system

    def solved(system, q, tol=np.nan):
        system.inertia_tol = tol
        return newton(system, q.copy(), 1.0, system.disc.beta0.copy(), system.loads_at(-1, 0, 1.0), SolveOptions())

    zero = np.zeros(column(1.0).n)
    states = {load: solved(column(load), zero).q for load in (1.0, 4.0, 30.0)}
    for load in (1.0, 4.0, 30.0):  # from the unloaded state: the positive sign stands
        system = column(load)
        out = solved(system, zero)
        assert out.ev.inertia_below == -1 and out.factor.det_sign == 1 and not out.factor.final
        K = out.ev["K"]
        lam_min = lowest_modes(system, K, None, count=1)[0][0]
        assert (lam_min < 0) == (load > np.pi**2 / 4)
        for tol in (-0.999 * lam_min, -1.001 * lam_min, zero_eigenvalue(1.0, system.n)):
            below = solved(system, zero, tol).ev.inertia_below
            assert below == int(lam_min < -tol) == int(eigenvalue_below(system, K, None, tol)), (load, tol)
    system = column(1.0)  # from the state at 4: det < 0 at the start, > 0 at the end
    out = solved(system, states[4.0], zero_eigenvalue(1.0, system.n))
    assert out.iterations > 0 and out.factor.final
    assert out.factor.det_sign == system.layout.factor(out.ev["K"]).det_sign == 1
    assert det_sign(system, out.ev, out.factor) == 1 and out.ev.inertia_below == 0
    system = column(4.0)  # converged at the start: its own factorisation, det < 0
    out = solved(system, states[4.0], zero_eigenvalue(1.0, system.n))
    assert out.iterations == 0 and out.factor.final
    assert out.factor.det_sign == system.layout.factor(out.ev["K"]).det_sign == -1
    assert out.ev.inertia_below == -1  # lost stability already: no inertia test


def _gamma(k: int) -> float:
    """gamma_k = k u / (1 - k u), u = eps/2 the unit roundoff: the relative error of k roundings
    [Higham 2002, ch. 3]."""
    u = EPS / 2
    return k * u / (1 - k * u)


def _random_band(rng, n, kl, ku, singular_column=None):
    """A random n x n matrix of bandwidths kl, ku in LAPACK's band storage (2 kl + ku + 1 rows)."""
    ab = np.zeros((2 * kl + ku + 1, n))
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            ab[kl + ku + i - j, j] = rng.normal()
    if singular_column is not None:  # an all-zero column: an exactly zero pivot there
        ab[:, singular_column] = 0.0
    return ab


def _dense(ab, n, kl, ku):
    """The n x n matrix of LAPACK band storage ``ab`` (A[i, j] at row kl + ku + i - j)."""
    A = np.zeros((n, n))
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            A[i, j] = ab[kl + ku + i - j, j]
    return A


def _plu(lu, ipiv, n, kl, ku):
    """(perm, L, U) with A[perm] = L U from a band LU in LAPACK's storage (``dgbtrf``'s output: U's
    kl + ku superdiagonals, each column's multipliers below it, ``ipiv`` 0-based). LAPACK keeps L as a
    product of row swaps and eliminations; each later swap is applied here to the earlier columns'
    multipliers (as ``dgetrf`` stores them), which only moves numbers."""
    kv = kl + ku
    perm, L, U = np.arange(n), np.eye(n), np.zeros((n, n))
    for j in range(n):
        p = ipiv[j]
        if p != j:
            perm[[j, p]] = perm[[p, j]]
            L[[j, p], :j] = L[[p, j], :j]
        for i in range(max(0, j - kv), j + 1):
            U[i, j] = lu[kv + i - j, j]
        for i in range(j + 1, min(n, j + kl + 1)):
            L[i, j] = lu[kv + i - j, j]
    return perm, L, U


@pytest.mark.parametrize("seed", range(6))
def test_band_lu_is_lapack_dgbtrf_and_dgbtrs_to_rounding(seed):
    """The compiled band LU and solve of the Newton corrector (LAPACK's ``dgbtf2`` and ``dgbtrs`` step for
    step) against scipy's LAPACK, on random bands (every pivot case: rows swapped or not, fill-in beyond
    ku, a zero pivot). Not to the last bit: LAPACK's BLAS (``dger``) may fuse the multiply-add of the
    rank-1 update that the compiled loop rounds twice, and which kernel it runs depends on the CPU.
    With gamma_k = k u / (1 - k u), u = eps/2 [Higham 2002, ch. 3]:

    * info and pivots equal LAPACK's. An all-zero column stays exactly zero on either path (its
      updates add zeros), so its zero pivot is exact; the other pivots compare magnitudes that differ
      by rounding only (a tie within an ulp: probability ~eps on these Gaussian entries).
    * Our factors' backward error, componentwise: |A[perm] - L U| <= (gamma_{kl+2} + gamma_n) |L| |U|
      [Higham 2002, ch. 9]: an entry is at most kl + 1 products in a band of lower bandwidth kl, one
      more rounding for the reciprocal pivot ``dgbtf2`` scales by; gamma_n for forming L U here.
    * The factors equal LAPACK's to first order: both factorise A[perm] + E_k, |E_k| bounded as above,
      and A = L U perturbed gives L^-1 dL + dU U^-1 = L^-1 dA U^-1 (strictly lower plus upper), so with
      G = |L^-1| |E_1 - E_2| |U^-1|: |dL| <= |L| tril(G, -1), |dU| <= triu(G) |U|; twice that for the
      second-order terms and the rounding of forming the bound.
    * The solve's backward error: |b - A x| <= perm^T (gamma_{kl+2} + 3 gamma_w + gamma_w^2) |L| |U| |x|
      + gamma_{n+1} (|A| |x| + |b|), w = kl + ku + 2 the longest row of L or U plus the division
      [Higham 2002, ch. 9], the last term for forming the residual; LAPACK's solution lies within
      |A^-1| (Skeel's condition) times the two residual bounds, twice that for forming |A^-1|.

    These are ~1e-14 relative: a planted error of 1e-6 (or 1e-12) in a multiplier, an update or the
    solve, a wrong sign, a wrong pivot or a row left unswapped fails."""
    rng = np.random.default_rng(seed)
    for trial in range(60):
        n, kl, ku = int(rng.integers(1, 30)), int(rng.integers(0, 6)), int(rng.integers(0, 6))
        zero = int(rng.integers(0, n)) if trial % 10 == 9 else None
        ab = _random_band(rng, n, kl, ku, zero)
        A = _dense(ab, n, kl, ku)
        lu, piv, info = dgbtrf(ab.copy(), kl, ku)
        flat = ab.T.copy().ravel()  # column-major, as the corrector stores it
        ipiv = np.empty(n, np.int32)
        assert band_lu(flat, n, kl, ku, 2 * kl + ku + 1, ipiv) == info, trial
        np.testing.assert_array_equal(ipiv, piv + 1, err_msg=str(trial))
        ours = flat.reshape(n, -1).T
        perm, L, U = _plu(ours, ipiv - 1, n, kl, ku)
        LU = np.abs(L) @ np.abs(U)
        factor_bound = (_gamma(kl + 2) + _gamma(n)) * LU
        assert np.all(np.abs(A[perm] - L @ U) <= factor_bound), trial
        if zero is not None:
            assert info > 0
            continue
        _, L_ref, U_ref = _plu(lu, piv, n, kl, ku)
        G = np.abs(np.linalg.inv(L_ref)) @ (2 * factor_bound) @ np.abs(np.linalg.inv(U_ref))
        assert np.all(np.abs(L - L_ref) <= 2 * np.abs(L_ref) @ np.tril(G, -1)), trial
        assert np.all(np.abs(U - U_ref) <= 2 * np.triu(G) @ np.abs(U_ref)), trial
        b = rng.normal(size=n)
        x = b.copy()
        band_solve(flat, n, kl, ku, 2 * kl + ku + 1, ipiv, x)
        x_ref = dgbtrs(lu, kl, ku, b, piv)[0]
        w = kl + ku + 2
        solve = _gamma(kl + 2) + 3 * _gamma(w) + _gamma(w) ** 2
        residual_bound = np.empty(n)
        residual_bound[perm] = solve * (LU @ np.maximum(np.abs(x), np.abs(x_ref)))
        residual_bound += _gamma(n + 1) * (np.abs(A) @ np.abs(x) + np.abs(b))
        assert np.all(np.abs(b - A @ x) <= residual_bound), trial
        assert np.all(np.abs(x - x_ref) <= 2 * np.abs(np.linalg.inv(A)) @ (2 * residual_bound)), trial


@pytest.mark.parametrize("moment", [1.0, 3.0, 6.0, 7.0])
def test_the_compiled_corrector_s_acceptance_facts_are_the_numpy_ones(moment):
    """The compiled load-control corrector reports, with a converged state, whether an element's end
    rotations jumped by about 2 pi and the largest rotation increment from its start (what
    `newton.accept_check` reads); they equal the NumPy formulation on the evaluation it returns, and
    `accept_check` rejects or accepts the state alike with them or without. A roll-up in one step of
    4 elements: M L/EI = 6 and 7 land on 2 pi-jumped states, 1 and 3 do not."""
    import fem
    from fem import solver
    from fem.newton import StepFailed, accept_check, newton
    from fem.options import SolveOptions

    opts = SolveOptions()
    model = fem.Model()
    model.add_node("root", 0.0, 0.0)
    model.add_node("tip", 1.0, 0.0)
    model.add_member("root", "tip", fem.Section.from_EI(1e4, 1.0), n_elements=4)
    model.add_support("root", "fixed")
    model.add_moment("tip", [moment])
    system = solver._prepare(model, opts, None)
    assert system.compiled is not None
    q0, beta0 = np.zeros(system.n), system.disc.beta0.copy()
    out = newton(system, q0, 1.0, beta0, system.loads_at(-1, 0, 1.0), opts, q_start=q0)
    rot = system.disc.red_is_rotation
    jumped = bool(out.ev["el"]["jumped"].any())
    assert out.accept == (jumped, float(np.abs(out.q[rot] - q0[rot]).max()))
    assert jumped == (moment > 2 * np.pi * 0.9)
    outcomes = []
    for known in (None, out.accept):
        for cap in (np.pi, 0.5 * moment):  # the increment within the cap, and beyond it
            try:
                accept_check(
                    system, out.q, q0, out.ev, replace(opts, max_rotation_increment=cap), out.iterations, known
                )
                outcomes.append("accepted")
            except StepFailed as exc:
                outcomes.append((str(exc), exc.cut))
    assert outcomes[:2] == outcomes[2:]
    reason = "rotation jump of about 2 pi" if jumped else "rotation increment"
    assert (outcomes[0] == "accepted") == (not jumped)
    assert all(reason in o[0] for o in outcomes[int(not jumped) : 2]), outcomes


def _compiled_evaluation(system, q, beta, loads):
    """`kernel._evaluate` at q: (u, r, K in row-major storage, second constraint column, F_scale)."""
    from fem import kernel as cn

    d, c = system.disc, system.compiled
    work = cn.work_arrays(n=system.n, nf=d.n_full + 1, size=c.size, maxiter=0, links=True)
    el = cn.element_outputs(len(d.L0))
    F_fixed, _, presc = loads
    load = cn.Load(lam=1.0, F_fixed=F_fixed, presc=np.asarray(presc, float))
    scale = cn._evaluate(q, beta, load, system.beams, system.dofs, system.couplings, system.storage, work, el)
    return work.u, work.r, c.row_major(work.K), work.C1w, scale


@pytest.mark.parametrize(("elements", "kind"), [(2, "dense"), (2, "banded"), (24, "banded")])
def test_the_compiled_evaluation_with_rigid_links_is_the_numpy_one(elements, kind):
    """Rigid links in the compiled corrector: a beam, a rigid link from its end to a node off the line,
    a second beam from there to a pin, a joint spring and a dead load. The slaves placed by their
    masters' rotation, the constraint coefficients turned with them, the residual, the tangent with
    the slaves' geometric term and the force scale equal `assembly.System.evaluate`'s to rounding
    (`_same_evaluations`) at random states (dense and banded storage at 2 elements a beam, banded at 24)."""
    import fem
    from fem import solver
    from fem.options import SolveOptions

    model = fem.Model()
    for name, x, y in (("root", 0.0, 0.0), ("a", 1.0, 0.0), ("b", 1.4, 0.3), ("c", 2.4, 0.5)):
        model.add_node(name, x, y)
    section = fem.Section.from_EI(1e3, 1.0)
    model.add_member("root", "a", section, n_elements=elements)
    model.add_member("b", "c", section, n_elements=elements)
    model.add_rigid_link("a", "b")
    model.add_support("root", "fixed")
    model.add_support("c", "pinned")
    model.add_joint("b", k=2.0)
    model.add_force("b", [0.3], [-0.7])
    model.add_moment("a", [0.2])
    system = solver._prepare(model, SolveOptions(solver=kind), None)
    assert system.width == 2 and system.compiled is not None
    assert system.layout.kind == kind
    _same_evaluations(system, system.loads_at(-1, 0, 1.0), np.random.default_rng(elements), 5)


def _same_evaluations(system, loads, rng, count: int) -> None:
    """The compiled evaluation equals `System.evaluate` at ``count`` random states to within the rounding
    in which the two differ. Both run the same compiled element kernel and add the same terms in the same
    order; they differ in the sine and cosine that turn a slave about its master (the C library's in
    compiled code, NumPy's own vectorised ones: each within a few ulps, not always the same) and in
    the two 2-norms of F_scale (``ddot`` of two BLAS builds, whose kernels depend on the CPU). With
    eps the machine epsilon, d0 the slaves' arms and L the elements' lengths (dead loads here):

    * u and the turned constraint column C1: R(theta) d0 moves by a few ulps of the sine and cosine
      times the components of d0, plus the roundings of adding it to the master's position:
      dx = 8 eps (max|d0| + max|u|);
    * r = C^T (f_int - lam f_ref): the forces move by the stiffness (|K_el| and spring row sums,
      assembled) times dx, the coefficients by dx times |R|; plus the roundings of sums of different
      terms, 16 eps times the largest term;
    * K: an element's K_el = E^T C E (16 products an entry, `corotational.element_state_numpy`) has
      direction cosines E that turn by dx / l and coefficients C that move by at most max|K| dx / l
      (l the shortest element or arm): 32 max|K| dx / l; the slaves' geometric term
      -(R_s . (x_s - x_m)) moves by |R| dx + tol_r max|d0|; plus 16 eps max|K|;
    * F_scale: each 2-norm of nf terms within gamma_nf ~ nf eps/2 relative [Higham 2002, ch. 3],
      and |f_int| moves by at most sqrt(nf) tol_r.

    These are 1e-12 of each quantity's scale or less: a relative error of 1e-6 in one element's force
    or stiffness, a wrong sign or a mixed-up row fails."""
    d = system.disc
    nf = d.n_full + 1
    arm = np.abs(d.X[d.slaves] - d.X[d.masters]).max()
    shortest = min(d.L0.min(), np.hypot(*(d.X[d.slaves] - d.X[d.masters]).T).min())
    for _ in range(count):
        q = rng.normal(scale=0.1, size=system.n)
        beta = system.disc.beta0 + rng.normal(scale=0.05, size=len(system.disc.beta0))
        ev = system.evaluate(q, beta, 1.0, *loads, need_K=True)
        u, r, K, C1, scale = _compiled_evaluation(system, q, beta, loads)
        el = ev["el"]
        dx = 8 * EPS * (arm + np.abs(ev["u"]).max())
        rows = np.bincount(d.edofs.ravel(), weights=np.abs(el["K"]).sum(axis=2).ravel(), minlength=nf)
        rows += np.bincount(d.springs.ravel(), weights=np.repeat(2 * np.abs(d.spring_k), 2), minlength=nf)
        R = np.abs(ev["R_full"]).max()
        tol_r = (rows.max() + R) * dx + 16 * EPS * max(np.abs(el["f"]).max(), R)
        K_max = max(np.abs(el["K"]).max(), np.abs(ev["K"]).max())
        tol_K = 32 * K_max * dx / shortest + R * dx + tol_r * arm + 16 * EPS * K_max
        np.testing.assert_allclose(u, ev["u"], rtol=0, atol=dx)
        np.testing.assert_allclose(C1, ev["C"][:, 1], rtol=0, atol=dx)
        np.testing.assert_allclose(r, ev["r"], rtol=0, atol=tol_r)
        np.testing.assert_allclose(K, ev["K"], rtol=0, atol=tol_K)
        assert abs(scale - ev["F_scale"]) <= nf * EPS * ev["F_scale"] + np.sqrt(nf) * tol_r


def test_every_compiled_fem_function_is_compiled_once():
    """numba compiles a function once per combination of argument types and array layouts, each a few
    seconds of every cold start (the report's, the suite's): the FEM's runs -- a cantilever with its
    warm-started refined solve, Test 1(a) (a zero first level), Test 2 (rigid links, released joints)
    -- reach every kernel with one signature each (a strided row among the arguments, say, would add a
    second). Run in a fresh process, so that no other test's direct calls count."""
    import json
    import subprocess
    import sys

    code = (
        "import json\n"
        "from numba.core.registry import CPUDispatcher\n"
        "import fem.kernel, fem.numbering\n"
        "from validation.case.loader import case_by_id\n"
        "from validation.run.runner import run_method\n"
        "for cid in ('cantilever_tip_load', 'bapat2015_test1a', 'bapat2015_test2'):\n"
        "    assert run_method(case_by_id(cid).case, 'fem').converged, cid\n"
        "print(json.dumps({f'{m.__name__}.{k}': len(v.signatures) for m in (fem.kernel, fem.numbering)\n"
        "                  for k, v in vars(m).items() if isinstance(v, CPUDispatcher) and v.signatures}))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    counts = json.loads(out.stdout.strip().splitlines()[-1])
    assert counts.get("fem.kernel.newton_load") == 1, counts  # the entry points called from Python
    assert all(n == 1 for n in counts.values()), counts


@pytest.mark.parametrize("prescribed", [True, False])
def test_the_compiled_evaluation_of_linked_chains_sliders_and_prescribed_masters_is_the_numpy_one(prescribed):
    """Configurations no case file has: a chain of two rigid links (the second slave's root master is the
    first master), a slider support at the far end, a prescribed rotation of a link master, a spring to
    ground and two load levels: the compiled evaluation equals `assembly.System.evaluate` to rounding
    (`_same_evaluations`) at random states of both levels (without the prescribed rotation, a moment
    there: the slaves' geometric term then reaches the master's free rotation)."""
    from fem import solver
    from fem.options import SolveOptions

    model = _linked_chain(prescribed)
    system = solver._prepare(model, SolveOptions(), None)
    assert system.width == 2 and system.compiled is not None and len(system.links) == 2
    assert set(system.links[:, 1].tolist()) == {model.node("a")}
    rng = np.random.default_rng(11)
    for level in (0, 1):
        _same_evaluations(system, system.loads_at(level - 1, level, 1.0), rng, 4)


@pytest.mark.parametrize("prescribed", [True, False])
def test_a_linked_chain_solves_alike_with_the_compiled_and_the_numpy_corrector(monkeypatch, prescribed):
    """The same model solved end to end by the compiled corrector and by the NumPy one (the compiled
    layout refused): the same steps and iterations, positions and rotations equal to rounding."""
    import fem
    from fem.kernel import CompiledLayout

    compiled = fem.solve(_linked_chain(prescribed))
    monkeypatch.setattr(CompiledLayout, "applies", staticmethod(lambda system: False))
    numpy_run = fem.solve(_linked_chain(prescribed))
    assert compiled.converged and numpy_run.converged
    assert (compiled.steps, compiled.iterations) == (numpy_run.steps, numpy_run.iterations)
    assert np.allclose(compiled.mesh_positions, numpy_run.mesh_positions, rtol=0, atol=1e-12)
    assert np.allclose(compiled.mesh_rotations, numpy_run.mesh_rotations, rtol=0, atol=1e-12)


def _linked_chain(prescribed: bool):
    """Two beams joined by a chain of two rigid links (the second slave's root master is the first
    master), a slider at the far end, a joint spring to ground, and a prescribed rotation of the master
    (or a moment on it)."""
    import fem

    model = fem.Model()
    for name, x, y in (("root", 0.0, 0.0), ("a", 1.0, 0.0), ("b", 1.3, 0.3), ("c", 1.5, -0.2), ("d", 2.5, -0.2)):
        model.add_node(name, x, y)
    section = fem.Section.from_EI(2e3, 1.5)
    model.add_member("root", "a", section, n_elements=5)
    model.add_member("c", "d", section, n_elements=6)
    model.add_rigid_link("a", "b")
    model.add_rigid_link("b", "c")  # c's root master is a
    model.add_support("root", "fixed")
    model.add_support("d", "slider", direction=(0.8, -0.6))
    model.add_joint("c", k=3.0, k_ground=0.5)
    if prescribed:
        model.prescribe("a", "rz", [0.1, 0.25])
    else:
        model.add_moment("a", [0.3, 0.6])
    model.add_force("d", [0.2, 0.4], [-0.3, -0.1])
    return model


@pytest.mark.parametrize("seed", range(4))
def test_shifted_cholesky_sees_every_eigenvalue_below_minus_tol(seed):
    """The compiled inertia test of the stability check (`kernel._shifted_cholesky_fails`) against the
    eigenvalues of the same matrix from LAPACK's dsyevd (numpy eigvalsh): S A S with S = diag(1/sqrt|A_ii|)
    (1 where A_ii = 0), the held DOF's row and column replaced by a unit diagonal, has an eigenvalue
    below -tol exactly when the test fails. Random symmetric matrices in the corrector's column-major
    storages (LAPACK's general band; dense, plus an antisymmetric part it must cancel by reading
    (A + A^T)/2), with one to three eigenvalues shifted below zero, thresholds 0.1 % either side of the
    lowest eigenvalue.
    (Only the corrector calls the helper; its Python source is compiled here.)"""
    from numba import njit

    from fem.kernel import _shifted_cholesky_fails

    shifted_cholesky_fails = njit(_shifted_cholesky_fails.py_func)

    rng = np.random.default_rng(seed)
    for trial in range(40):
        n, w = int(rng.integers(2, 30)), int(rng.integers(1, 6))
        w = min(w, n - 1)
        B = np.zeros((n, n))
        for j in range(n):
            for i in range(max(0, j - w), j + 1):
                B[i, j] = B[j, i] = rng.normal()
        B += np.diag(rng.uniform(2.0 * w, 4.0 * w, n))  # diagonally dominant: positive definite
        B[np.diag_indices(n)] -= np.where(rng.random(n) < 0.1, 4.0 * w + 3.0, 0.0)  # some made negative
        if trial % 7 == 3:
            B[:, n // 2] = B[n // 2, :] = 0.0  # a zero diagonal: scaled by 1
        held = int(rng.integers(0, n)) if trial % 3 == 0 else -1
        d = np.sqrt(np.abs(np.diag(B)))
        d[d == 0.0] = 1.0
        A = B / np.outer(d, d)
        if held >= 0:
            A[held, :] = A[:, held] = 0.0
            A[held, held] = 1.0
        lowest = np.linalg.eigvalsh(A)[0]
        band = np.zeros((3 * w + 1, n))  # kl = ku = w
        for j in range(n):
            for i in range(max(0, j - w), min(n, j + w + 1)):
                band[2 * w + i - j, j] = B[i, j]
        skew = rng.normal(scale=0.5, size=(n, n))
        dense = B + skew - skew.T
        storages = [(band.T.ravel(), True, 3 * w + 1), (dense.T.ravel(), False, n)]  # column by column
        for tol in (-0.999 * lowest, -1.001 * lowest) if abs(lowest) > 1e-6 else (1e-3,):
            expected = lowest < -tol
            for K, banded, ldk in storages:
                kl = w if banded else 0
                band = Band(banded=banded, kl=kl, ku=kl, ld=ldk)
                assert shifted_cholesky_fails(K, band, n, held, tol) == expected, (trial, tol, ldk)


@pytest.mark.parametrize("elements", [1, 2, 8, 200])
def test_a_beams_band_is_stored_banded_at_any_size(elements):
    """`MatrixLayout`'s choice (``kind="auto"``): a cantilever's tangent, RCM-numbered, has a half-band of
    5 (two nodes of 3 DOFs), banded from 3 unknowns to 600 (`validation.bench.solver_choice` measures the
    compiled band LU as fast as LAPACK's dense LU at 6 unknowns and faster from 12 up)."""
    system = _compressed_column(1.0, elements=elements)
    assert system.layout.bw <= 5 and system.layout.kind == "banded"


def test_a_wide_band_is_stored_dense_up_to_300_unknowns_and_sparse_beyond():
    """The same choice for a band wider than max(8, n / 6): a full matrix is stored dense at 20 and at
    290 unknowns, sparse at 310."""
    from fem.linear_solver import MatrixLayout

    for n, kind in ((20, "dense"), (290, "dense"), (310, "sparse")):
        rows, cols = np.divmod(np.arange(n * n), n)
        assert MatrixLayout(n, rows, cols).kind == kind
