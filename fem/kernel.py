"""Compiled (numba, ``cache=True``) per-iteration kernels: the corotational element loop and the
scatter of element entries into solver storage.

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

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["element_kernel", "scatter", "scatter_add"]


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
