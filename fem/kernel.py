"""Everything numba compiles (``cache=True``) for the FEM Newton corrector, in one module: the
corotational element loop, the scatter of element entries into solver storage, and the
load-control Newton corrector compiled whole.

One module on purpose: numba's cache is keyed on the source file of each compiled function only,
so a cached function calling a compiled function of another file keeps running the old machine
code after that file is edited (numba's "Notes on caching"). `tests/project/test_compiled_cache.py`
checks that no cached function calls into another module.

The mathematics is that of `corotational` (Crisfield 1991 ch. 7; Battini 2002 ch. 2), written
element by element so that one call does what took some thirty NumPy calls:

    chord       d = X2 + u_2 - X1 - u_1,  L = |d|,  c = d_x/L,  s = d_y/L
    chord angle beta = beta_prev + wrap(atan2(d_y, d_x) - beta_prev)
    local       u_bar = (L^2 - L0^2)/(L + L0),  theta_i = wrap(theta_i + beta0 - beta)
    forces      N = k_a u_bar,  [M1, M2] = k_b [theta_1, theta_2],  V = (M1 + M2)/L
                f = [-(cN + sV), -(sN - cV), M1, cN + sV, sN - cV, M2]
    tangent     K = E^T C E,  E = [r; z; e3; e6],  r = [-c, -s, 0, c, s, 0],  z = [s, -c, 0, -s, c, 0]
                C = [[k_a, V/L, 0, 0], [V/L, (k11+k12+k21+k22)/L^2 + N/L, -(k11+k21)/L, -(k12+k22)/L],
                     [0, -(k11+k12)/L, k11, k12], [0, -(k21+k22)/L, k21, k22]]

The numbers are those of the NumPy expressions to rounding; the first call compiles (a few
seconds) and writes the machine code to numba's cache beside this module, so later processes load it.

The load-control Newton corrector of `newton` compiled whole (`newton_load`), for the
common system: dead loads only (no followers, no forces toward points, no distributed loads), a
dense or banded tangent; with or without rigid links (their slaves placed by the master's rotation,
the constraint coefficients turned with it and the slaves' geometric tangent term, as
`assembly.System` has them).

One call runs every iteration of

    r(q) = J^T (f_int(q) - lambda f_ext),   K(q) dq = -r,   q <- q + dq

with the same steps, in the same order, as the NumPy corrector: the element loop above,
the scatter of the element forces and tangents into the full vector and into the solver's
storage (here column-major, as LAPACK reads it), the factorisation and back-substitution (a dense
tangent: LAPACK ``dgetrf``/``dgetrs``, scipy's own, called through ``scipy.linalg.cython_lapack``; a
banded one: `band_lu`/`band_solve`, LAPACK's ``dgbtf2``/``dgbtrs`` compiled here, the same operations
in the same order: bit for bit scipy's factors and solutions at the narrow bands RCM gives most
models (half-bandwidth 4 and 6 checked); at wider ones (8 and up) scipy's BLAS (OpenBLAS) updates
the columns with vector kernels and the two differ in the last bits), the rotation-limited correction, and the convergence tests
(residual, energy, negligible correction) and rotation-increment cut of `newton`. Norms and dot
products are BLAS ``ddot`` as in NumPy, so the numbers are those of the NumPy corrector (to rounding
where the band is wider).

It returns a status code; `newton` turns it into the same `NewtonOutcome` or `StepFailed`.

At the converged state it also does what the Python side did after it: the det-K sign confirmed on
the converged tangent when the iterate's factors said it is not positive, and the inertia test of the
stability check (a Cholesky of the shifted, Jacobi-scaled tangent in band storage), so that neither
leaves compiled code nor turns the tangent row-major.

The helpers only compiled code calls (``_factor``, ``_back_solve``, ``_det_sign``,
``_shifted_cholesky_fails``) are compiled with ``no_cpython_wrapper=True``: numba builds no
Python-callable wrapper for them (``band_lu``, ``band_solve`` and ``_evaluate`` keep theirs: the tests
call them).

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

import math

import llvmlite.binding as llvm
import numpy as np
from numba import njit, types
from numba.extending import get_cython_function_address

__all__ = ["element_kernel", "scatter", "scatter_add", "CompiledLayout", "newton_load", "CONVERGED",
           "NOT_FINITE", "NO_CONVERGENCE", "SINGULAR", "NON_FINITE_TANGENT", "ROTATION_TOO_LARGE"]


@njit(cache=True, inline="always")
def _wrap(a):
    """Angle in (-pi, pi]."""
    return math.atan2(math.sin(a), math.cos(a))


@njit(cache=True)
def element_kernel(X1, X2, p, L0, beta0, beta_prev, ka, kb, need_tangent,
                   f, K, N, M, L, beta, theta_bar, u_bar, jumped):
    """Into the given arrays: internal forces f (n,6), tangent K (n,6,6) (untouched when not
    needed), and the local state N (n,), M (n,2), L, beta, theta_bar (n,2), u_bar, jumped (n,) of
    all elements. (Outputs are passed in, not returned: returning arrays from numba costs more
    than the loop for small meshes.)"""
    n = L0.shape[0]
    CE = np.empty((4, 6))
    for e in range(n):
        dx = X2[e, 0] - X1[e, 0] + p[e, 3] - p[e, 0]
        dy = X2[e, 1] - X1[e, 1] + p[e, 4] - p[e, 1]
        Le = math.hypot(dx, dy)
        c, s = dx / Le, dy / Le
        b = beta_prev[e] + _wrap(math.atan2(dy, dx) - beta_prev[e])
        ub = (Le * Le - L0[e] * L0[e]) / (Le + L0[e])
        t1_raw = p[e, 2] + (beta0[e] - b)
        t2_raw = p[e, 5] + (beta0[e] - b)
        t1, t2 = _wrap(t1_raw), _wrap(t2_raw)
        jumped[e] = max(abs(t1_raw - t1), abs(t2_raw - t2)) > 1.0
        k11, k12, k21, k22 = kb[e, 0, 0], kb[e, 0, 1], kb[e, 1, 0], kb[e, 1, 1]
        Ne = ka[e] * ub
        M1 = k11 * t1 + k12 * t2
        M2 = k21 * t1 + k22 * t2
        V = (M1 + M2) / Le
        a = c * Ne + s * V
        bb = s * Ne - c * V
        f[e, 0], f[e, 1], f[e, 2], f[e, 3], f[e, 4], f[e, 5] = -a, -bb, M1, a, bb, M2
        N[e], M[e, 0], M[e, 1], L[e], beta[e] = Ne, M1, M2, Le, b
        theta_bar[e, 0], theta_bar[e, 1], u_bar[e] = t1, t2, ub
        if need_tangent:
            _tangent(K, CE, e, c, s, ka[e], Ne, V, Le, k11, k12, k21, k22)


@njit(cache=True, inline="always")
def _tangent(K, CE, e, c, s, ka, N, V, L, k11, k12, k21, k22):
    """K[e] = E^T C E with E = [r; z; e3; e6]: the products of the dense loops with the zero entries
    of E and C left out (adding an exact zero changes no bit, so the sums are those of the dense
    loops, term for term and in the same order)."""
    r = (-c, -s, 0.0, c, s, 0.0)
    z = (s, -c, 0.0, -s, c, 0.0)
    c01 = V / L
    c11 = (k11 + k12 + k21 + k22) / (L * L) + N / L
    c12, c13 = -(k11 + k21) / L, -(k12 + k22) / L
    c21, c31 = -(k11 + k12) / L, -(k21 + k22) / L
    # CE = C E, row by row (C[0] = [ka, c01, 0, 0], C[1] = [c01, c11, c12, c13],
    # C[2] = [0, c21, k11, k12], C[3] = [0, c31, k21, k22])
    ce0, ce1, ce2, ce3 = CE[0], CE[1], CE[2], CE[3]
    for j in range(6):
        e3 = 1.0 if j == 2 else 0.0
        e6 = 1.0 if j == 5 else 0.0
        ce0[j] = 0.0 + ka * r[j] + c01 * z[j] + 0.0 * e3 + 0.0 * e6
        ce1[j] = 0.0 + c01 * r[j] + c11 * z[j] + c12 * e3 + c13 * e6
        ce2[j] = 0.0 + 0.0 * r[j] + c21 * z[j] + k11 * e3 + k12 * e6
        ce3[j] = 0.0 + 0.0 * r[j] + c31 * z[j] + k21 * e3 + k22 * e6
    for i in range(6):
        ri, zi = r[i], z[i]
        if i == 2:
            for j in range(6):
                K[e, i, j] = 0.0 + ce2[j]
        elif i == 5:
            for j in range(6):
                K[e, i, j] = 0.0 + ce3[j]
        else:
            for j in range(6):
                K[e, i, j] = 0.0 + ri * ce0[j] + zi * ce1[j]


@njit(cache=True)
def scatter_add(target, source, factor, values, out):
    """out[target[j]] += values[source[j]] * factor[j], in the order of j (the assembly of element
    entries into solver storage through precomputed index maps)."""
    for j in range(target.shape[0]):
        out[target[j]] += values[source[j]] * factor[j]


def scatter(target, source, factor, values, size):
    """A new vector of length ``size``: zeros, then `scatter_add`."""
    out = np.zeros(size)
    scatter_add(target, source, factor, values, out)
    return out

CONVERGED, NOT_FINITE, NO_CONVERGENCE, SINGULAR, NON_FINITE_TANGENT, ROTATION_TOO_LARGE = range(6)
CONVERGED_JUMPED = 6   # converged, and some element's end rotations are 2 pi off its chord (`newton.accept_check`)



def _lapack(name: str, n_args: int):
    """scipy's LAPACK routine ``name`` as a function compiled code calls by symbol (so that numba
    can cache the machine code: the symbol is bound to the address again in every process)."""
    symbol = f"fem_lapack_{name}"
    llvm.add_symbol(symbol, get_cython_function_address("scipy.linalg.cython_lapack", name))
    return types.ExternalFunction(symbol, types.void(*[types.voidptr] * n_args))


_dgetrf = _lapack("dgetrf", 6)
_dgetrs = _lapack("dgetrs", 9)
_dpotrf = _lapack("dpotrf", 5)
_dpbtrf = _lapack("dpbtrf", 6)


class CompiledLayout:
    """Column-major storage indices of the reduced tangent for LAPACK (dense: A[i, j] at j n + i;
    banded: the LAPACK band, ab[kl + ku + i - j, j] at j (2 kl + ku + 1) + kl + ku + i - j), and
    how to turn it back into the row-major storage of `linear_solver.MatrixLayout`.
    ``applies(system)``: the system is one the compiled corrector handles."""

    @staticmethod
    def applies(system) -> bool:
        return (system.layout.kind in ("dense", "banded") and system.n > 0
                and len(system.fol_nodes) == 0 and len(system.pt_nodes) == 0
                and len(system.dist_follower) == 0)

    def __init__(self, layout, rows, cols):
        n = layout.n
        self.banded = layout.kind == "banded"
        if self.banded:
            self.kl, self.ku, self.ld = layout.kl, layout.ku, layout.nrow
            self.flat = cols * layout.nrow + (layout.kl + layout.ku + rows - cols)
        else:
            self.kl, self.ku, self.ld = 0, 0, n
            self.flat = cols * n + rows
        self.size, self.n = layout.size, n

    def row_major(self, data: np.ndarray) -> np.ndarray:
        """The storage of `MatrixLayout` (row-major) from the column-major one."""
        return np.ascontiguousarray(data.reshape(self.n, self.ld).T).ravel()


@njit(cache=True, no_cpython_wrapper=True)
def _factor(work, banded, n, kl, ku, ld, ipiv, ints, info):
    """LU of the column-major matrix in ``work`` (in place): a band by `band_lu`, a dense matrix by
    LAPACK dgetrf; info[0] > 0: an exactly zero pivot."""
    ints[0], ints[1], ints[2], ints[3] = n, kl, ku, ld
    if banded:
        info[0] = band_lu(work, n, kl, ku, ld, ipiv)
    else:
        _dgetrf(ints[0:].ctypes, ints[0:].ctypes, work.ctypes, ints[3:].ctypes, ipiv.ctypes, info.ctypes)


@njit(cache=True, no_cpython_wrapper=True)
def _back_solve(work, banded, ipiv, ints, info, x):
    """x <- K^-1 x with the factors `_factor` left in ``work`` (its n, kl, ku, ld in ``ints``)."""
    if banded:
        band_solve(work, ints[0], ints[1], ints[2], ints[3], ipiv, x)
        return
    trans = np.empty(1, np.uint8)
    trans[0] = 78     # 'N'
    ints[4] = 1
    _dgetrs(trans.ctypes, ints[0:].ctypes, ints[4:].ctypes, work.ctypes, ints[3:].ctypes,
            ipiv.ctypes, x.ctypes, ints[0:].ctypes, info.ctypes)


@njit(cache=True, error_model="numpy")
def band_lu(ab, n, kl, ku, ld, ipiv):
    """LU with partial pivoting of the column-major LAPACK band ``ab`` in place (A[i, j] at
    j ld + kl + ku + i - j, ld >= 2 kl + ku + 1): LAPACK's ``dgbtf2`` step for step (what ``dgbtrf``
    runs when the lower bandwidth is below its block size, always so for a beam mesh), compiled here
    because scipy's ``dgbtrf`` spends most of a small band's time in its BLAS calls (``idamax``,
    ``dswap``, ``dscal``, ``dger`` per column). ``ipiv`` 1-based as LAPACK's. Returns LAPACK's info:
    0, or the 1-based column of the first exactly zero pivot."""
    kv = ku + kl
    info = 0
    for j in range(ku + 1, min(kv, n)):            # zero the fill-in of the first columns
        for i in range(kv - j, kl):
            ab[j * ld + i] = 0.0
    ju = 0                                          # last column touched by the row swaps (0-based)
    for j in range(n):
        if j + kv < n:                              # fill-in of column j + kv
            for i in range(kl):
                ab[(j + kv) * ld + i] = 0.0
        km = min(kl, n - 1 - j)                     # subdiagonal entries of column j
        d = j * ld + kv                             # the diagonal entry
        jp, big = 0, abs(ab[d])
        for t in range(1, km + 1):                  # idamax: the first largest magnitude
            v = abs(ab[d + t])
            if v > big:
                jp, big = t, v
        ipiv[j] = jp + j + 1
        if ab[d + jp] != 0.0:
            ju = max(ju, min(j + ku + jp, n - 1))
            if jp != 0:                             # swap rows j and j + jp over columns j..ju
                for c in range(ju - j + 1):
                    a, b = d + jp + c * (ld - 1), d + c * (ld - 1)
                    ab[a], ab[b] = ab[b], ab[a]
            if km > 0:
                r = 1.0 / ab[d]
                for t in range(1, km + 1):
                    ab[d + t] *= r
                for c in range(1, ju - j + 1):      # rank-1 update of the band right of column j
                    y = ab[d + c * (ld - 1)]
                    if y != 0.0:
                        temp = -y
                        base = d + c * (ld - 1)
                        for t in range(1, km + 1):
                            ab[base + t] += ab[d + t] * temp
        elif info == 0:
            info = j + 1
    return info


@njit(cache=True, error_model="numpy")
def band_solve(ab, n, kl, ku, ld, ipiv, x):
    """x <- A^-1 x with the factors of `band_lu`: LAPACK's ``dgbtrs`` (no transpose, one right-hand
    side) step for step: the row swaps and L by columns, then U by ``dtbsv`` (upper, by columns). A zero
    pivot divides as LAPACK does (IEEE: inf or NaN, no exception); the corrector never solves with one."""
    kv = ku + kl
    if kl > 0:
        for j in range(n - 1):
            lm = min(kl, n - 1 - j)
            p = ipiv[j] - 1
            if p != j:
                x[p], x[j] = x[j], x[p]
            if x[j] != 0.0:
                temp = -x[j]
                d = j * ld + kv
                for t in range(1, lm + 1):
                    x[j + t] += ab[d + t] * temp
    for j in range(n - 1, -1, -1):
        if x[j] != 0.0:
            d = j * ld + kv
            x[j] = x[j] / ab[d]
            temp = x[j]
            for i in range(j - 1, max(0, j - kv) - 1, -1):
                x[i] -= temp * ab[d - (j - i)]


@njit(cache=True, no_cpython_wrapper=True)
def _det_sign(work, banded, n, kl, ku, ld, ipiv):
    """Sign of det K from the LU factors: signs of U's diagonal times the pivot parity; 0 when a
    pivot is zero or not finite."""
    sign = 1
    for j in range(n):
        d = work[j * ld + (kl + ku if banded else j)]
        if d == 0.0 or not math.isfinite(d):
            return 0
        if d < 0.0:
            sign = -sign
        if ipiv[j] - 1 != j:
            sign = -sign
    return sign


@njit(cache=True, no_cpython_wrapper=True)
def _shifted_cholesky_fails(K, banded, n, kl, ku, ldk, held, tol):
    """True when the Cholesky factorisation of  S A S + tol I  breaks down (a pivot not positive), A the
    symmetric tangent in the corrector's column-major storage ``K`` (leading dimension ``ldk``): entry
    (i, j) at j ldk + r, r = kl + ku + i - j in LAPACK's general band storage (``banded``, its upper
    triangle read) or r = i (dense, read as (A + A^T)/2). S = diag(1/sqrt|A_ii|) (1 where A_ii = 0),
    the row and column of DOF ``held`` (>= 0) replaced by a unit diagonal. By Sylvester's law of inertia: some
    eigenvalue of S A S is below -tol. The shifted matrix is written in LAPACK's symmetric upper
    storage, a band of half-bandwidth ku (dpbtrf) or the full matrix (dpotrf), and factorised by
    scipy's LAPACK, as `stability.eigenvalue_below` does (no factorisation loop of its own for numba to
    compile). Only `newton_load` calls it (no Python wrapper); the tests compile its ``py_func``."""
    w = ku if banded else n - 1
    base = kl + ku if banded else 0
    ld = w + 1 if banded else n          # entry (i, j), i <= j, at j ld + (w + i - j) (band) or j ld + i
    up = np.zeros(ld * n)
    d = np.empty(n)
    for j in range(n):
        a = abs(K[j * ldk + (base if banded else j)])
        d[j] = math.sqrt(a) if a != 0.0 else 1.0
    for j in range(n):
        for i in range(max(0, j - w), j + 1):
            if banded:
                a = K[j * ldk + base + i - j]
            else:
                a = 0.5 * (K[j * ldk + i] + K[i * ldk + j])
            a = a / (d[i] * d[j])
            if i == held or j == held:
                a = 1.0 if i == j else 0.0
            if i == j:
                a += tol
            up[j * ld + (w + i - j if banded else i)] = a
    uplo = np.empty(1, np.uint8)
    uplo[0] = 85      # 'U'
    ints = np.zeros(4, np.int32)
    ints[0], ints[1], ints[2] = n, w, ld
    if banded:
        _dpbtrf(uplo.ctypes, ints[0:].ctypes, ints[1:].ctypes, up.ctypes, ints[2:].ctypes, ints[3:].ctypes)
    else:
        _dpotrf(uplo.ctypes, ints[0:].ctypes, up.ctypes, ints[2:].ctypes, ints[3:].ctypes)
    return ints[3] > 0


@njit(cache=True)
def _evaluate(q, presc, lam, F_fixed, beta_prev, I0, C0, p_dofs, edofs, X1, X2, L0, beta0, ka, kb,
              springs, spring_k, ground, flat, valid_src, coef, K, u, f_int, f_ref, R, r, fr,
              fe, Ke, N, M, L, beta, theta_bar, u_bar, jumped, sp, links, links_X, I1, C1, C1w, pair,
              rows_full, cols_full):
    """Residual r, reduced reference load fr and tangent K (column-major storage) at q; returns
    F_scale = max(|lambda f_ref|, |f_int|). Every output array is filled in place.

    Rigid links (none: ``links`` has no rows), as `assembly.System.full_displacements` and
    ``evaluate`` treat them: ``links`` (n_s, 4) the slave and (root) master node and their rotation
    DOFs, ``links_X`` (n_s, 4) the two nodes' reference positions; the constraint map's second column
    (I1, C1) with its current coefficients C1w (the slaves' rows turn with the master); the tangent's
    entries weighted by the current coefficients of the two columns ``pair`` = 2 w1 + w2 of each
    reduced entry (full entry ``valid_src``, full row and column ``rows_full``, ``cols_full``), the
    slaves' geometric term -(R_s . (x_s - x_m)) among the full entries after the springs'."""
    n, nf = q.shape[0], u.shape[0]
    wide = links.shape[0] > 0
    for i in range(nf):
        k = I0[i]
        t0 = C0[i] * q[k] if k < n else C0[i] * 0.0
        if wide:
            k1 = I1[i]
            u[i] = t0 + (C1[i] * q[k1] if k1 < n else C1[i] * 0.0)
            C1w[i] = C1[i]
        else:
            u[i] = t0
    for j in range(p_dofs.shape[0]):
        u[p_dofs[j]] = presc[j]
    for t in range(links.shape[0]):      # slaves: x_s = x_m + R(theta_m) (X_s - X_m), theta_s = theta_m
        s, m, rs, rm = links[t, 0], links[t, 1], links[t, 2], links[t, 3]
        th = u[rm]
        d0x, d0y = links_X[t, 0] - links_X[t, 2], links_X[t, 1] - links_X[t, 3]
        cs, sn = math.cos(th), math.sin(th)
        rd0, rd1 = cs * d0x - sn * d0y, sn * d0x + cs * d0y
        u[2 * s] = u[2 * m] + rd0 - d0x
        u[2 * s + 1] = u[2 * m + 1] + rd1 - d0y
        u[rs] = th
        C1w[2 * s] = -rd1
        C1w[2 * s + 1] = rd0
    n_el = edofs.shape[0]
    p = np.empty((n_el, 6))
    for e in range(n_el):
        for j in range(6):
            p[e, j] = u[edofs[e, j]]
    tangent = n_el >= 0   # True, typed as a run-time bool like the Python callers' (one compiled variant)
    element_kernel(X1, X2, p, L0, beta0, beta_prev, ka, kb, tangent, fe, Ke, N, M, L, beta, theta_bar,
                   u_bar, jumped)
    f_int[:] = 0.0
    for e in range(n_el):
        for j in range(6):
            f_int[edofs[e, j]] += fe[e, j]
    if springs.shape[0]:
        sp[:] = 0.0
        for s in range(springs.shape[0]):
            m = spring_k[s] * (u[springs[s, 0]] - u[springs[s, 1]])
            sp[springs[s, 0]] += m
            sp[springs[s, 1]] += -m
        for i in range(nf):
            f_int[i] += sp[i]
    for i in range(nf):
        f_ref[i] = F_fixed[i]
    f_ref[ground] = 0.0
    f_int[ground] = 0.0
    for i in range(nf):
        R[i] = f_int[i] - lam * f_ref[i]
    r[:] = 0.0
    fr[:] = 0.0
    for i in range(nf):
        k = I0[i]
        if k < n:
            r[k] += C0[i] * R[i]
            fr[k] += C0[i] * f_ref[i]
        if wide:
            k1 = I1[i]
            if k1 < n:
                r[k1] += C1w[i] * R[i]
                fr[k1] += C1w[i] * f_ref[i]
    f_ext = lam * f_ref
    scale = max(math.sqrt(np.dot(f_ext, f_ext)), math.sqrt(np.dot(f_int, f_int)))
    K[:] = 0.0
    n_ke = n_el * 36
    ke = Ke.reshape(n_ke)       # the element tangents as one flat, row-major vector (a view)
    n_sp4 = n_ke + 4 * springs.shape[0]
    for j in range(flat.shape[0]):
        src = valid_src[j]
        if src < n_ke:
            v = ke[src]
        elif src < n_sp4:
            s = (src - n_ke) // 4
            v = spring_k[s] * (1.0 if (src - n_ke) % 4 in (0, 3) else -1.0)
        else:   # a slave's geometric term on its master's rotation
            t = src - n_sp4
            s, m = links[t, 0], links[t, 1]
            xs = links_X[t, 0] + u[2 * s] - links_X[t, 2] - u[2 * m]
            ys = links_X[t, 1] + u[2 * s + 1] - links_X[t, 3] - u[2 * m + 1]
            v = -(R[2 * s] * xs + R[2 * s + 1] * ys)
        if wide:
            a, b = rows_full[src], cols_full[src]
            K[flat[j]] += v * (C0[a] if pair[j] < 2 else C1w[a]) * (C0[b] if pair[j] % 2 == 0 else C1w[b])
        else:
            K[flat[j]] += v * coef[j]
    return scale


@njit(cache=True)
def newton_load(q, q_start, presc, lam, F_fixed, beta_prev, I0, C0, p_dofs, edofs, X1, X2, L0, beta0,
                ka, kb, springs, spring_k, ground, flat, valid_src, coef, banded, kl, ku, ld, rot,
                rtol, atol, floor, L_ref, maxiter, damp, max_rot_inc,
                K, u, f_int, f_ref, R, r, fr, fe, Ke, N, M, L, beta, theta_bar, u_bar, jumped, hist,
                links, links_X, I1, C1, C1w, pair, rows_full, cols_full, confirm_sign, inertia_tol):
    """Every iteration of the load-control corrector from q (updated in place). Returns
    (status, iterations, det sign of the last factorisation, F_scale, rotation increment, final,
    below); the evaluation at the final q is left in the output arrays. The sign: 2 when nothing was
    factorised (a failed first iteration); a run that converges before any correction factorises the
    tangent at its state for it (0: singular or not finite there). The rotation increment: of a
    ROTATION_TOO_LARGE cut, or of the converged state from q_start (CONVERGED, or CONVERGED_JUMPED
    when an element's end rotations jumped by about 2 pi).

    At a converged state (what `newton.det_sign` and `solver._even_crossing` would otherwise compute
    afterwards, here without leaving compiled code or turning the tangent row-major):
    ``confirm_sign``: a sign not positive from the factors of the iterate before convergence is
    confirmed by the same factorisation of the converged tangent a run that converges before any
    correction makes; ``final`` says the sign is of the converged state itself (that factorisation). ``inertia_tol`` (NaN: not
    asked): when the sign is not negative and some element is in compression, ``below`` is 1 when the
    Jacobi-scaled tangent has an eigenvalue below -inertia_tol (`_shifted_cholesky_fails`), else 0;
    -1 when not computed."""
    n, nf = q.shape[0], u.shape[0]
    work = np.empty(K.shape[0])
    ipiv = np.empty(max(n, 1), np.int32)
    ints = np.zeros(6, np.int32)
    info = np.zeros(1, np.int32)
    sp = np.empty(nf)
    dq = np.empty(n)
    has_rot = False
    for k in range(n):
        if rot[k]:
            has_rot = True
    dq_small = False
    sign = 2
    final = False   # the sign is of the converged state's own factors
    for it in range(maxiter + 1):
        scale = _evaluate(q, presc, lam, F_fixed, beta_prev, I0, C0, p_dofs, edofs, X1, X2, L0, beta0,
                          ka, kb, springs, spring_k, ground, flat, valid_src, coef, K, u, f_int, f_ref,
                          R, r, fr, fe, Ke, N, M, L, beta, theta_bar, u_bar, jumped, sp, links, links_X,
                          I1, C1, C1w, pair, rows_full, cols_full)
        rn = math.sqrt(np.dot(r, r))
        tol = rtol * scale + floor + atol
        hist[it] = rn / max(scale, 1e-300)
        if not math.isfinite(rn):
            return NOT_FINITE, it, sign, scale, 0.0, False, -1
        converged = (rn <= tol or dq_small) and (it > 0 or rn <= rtol * scale + atol)
        # the last factors' sign stands (positive, or not asked to be confirmed): done
        if converged and (n == 0 or sign == 1 or (sign != 2 and not confirm_sign)):
            break
        if not converged and it == maxiter:
            return NO_CONVERGENCE, it, sign, scale, 0.0, False, -1
        # the factorisation: of the correction, or (converged) for the sign at this state itself: before
        # any correction, or to confirm a sign not positive from the iterate before
        finite = True
        for j in range(K.shape[0]):
            if not math.isfinite(K[j]):
                finite = False
                break
            work[j] = K[j]
        if not finite:
            if converged:
                sign, final = 0, True
                break
            return NON_FINITE_TANGENT, it, sign, scale, 0.0, False, -1
        _factor(work, banded, n, kl, ku, ld, ipiv, ints, info)
        if info[0] > 0:
            if converged:
                sign, final = 0, True
                break
            return SINGULAR, it, sign, scale, 0.0, False, -1
        sign = _det_sign(work, banded, n, kl, ku, ld, ipiv)
        if converged:
            final = True
            break
        if sign == 0:
            return SINGULAR, it, 2, scale, 0.0, False, -1
        for k in range(n):
            dq[k] = -r[k]
        _back_solve(work, banded, ipiv, ints, info, dq)
        if damp > 0.0 and has_rot:
            big = 0.0
            for k in range(n):
                if rot[k]:
                    big = max(big, abs(dq[k]))
            if big > damp:
                for k in range(n):
                    dq[k] = dq[k] * (damp / big)
        if it > 0 and abs(np.dot(dq, r)) <= rtol ** 2 * scale * L_ref:
            break       # converged by the energy criterion
        dq_small = True
        for k in range(n):
            q[k] = q[k] + dq[k]
            if abs(dq[k]) > 1e-13 * (1.0 if rot[k] else L_ref):
                dq_small = False
        if has_rot:
            dth = 0.0
            for k in range(n):
                if rot[k]:
                    dth = max(dth, abs(q[k] - q_start[k]))
            limit = (2.0 if it == 0 else 4.0) * max_rot_inc
            if dth > limit:
                return ROTATION_TOO_LARGE, it + 1, sign, scale, dth, False, -1
    # converged (every other way out returned above): what `newton.accept_check` reads of the state
    status = CONVERGED
    for e in range(jumped.shape[0]):
        if jumped[e]:
            status = CONVERGED_JUMPED
    dth = 0.0
    for k in range(n):
        if rot[k]:
            dth = max(dth, abs(q[k] - q_start[k]))
    below = -1
    if inertia_tol == inertia_tol and 0 <= sign <= 1 and n > 0:
        compressed = False
        for e in range(N.shape[0]):
            if N[e] < 0.0:
                compressed = True
        if compressed:
            below = 1 if _shifted_cholesky_fails(K, banded, n, kl, ku, ld, -1, inertia_tol) else 0
    return status, it, sign, scale, dth, final, below
