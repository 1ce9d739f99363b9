"""2-D corotational Euler-Bernoulli beam element, vectorised over elements.

Crisfield (1991), Non-linear Finite Element Analysis of Solids and
Structures, vol. 1, ch. 7; Battini (2002), Co-rotational beam elements in
instability problems, PhD thesis KTH, ch. 2.

Element DOFs  p = [u1, v1, theta1, u2, v2, theta2]  (global, theta accumulated).

    chord       d = X2 + u_2 - X1 - u_1,  L = |d|,  c = d_x/L,  s = d_y/L
    chord angle beta = beta_prev + wrap(atan2(d_y, d_x) - beta_prev)   (continuous)
    local       u_bar   = L - L0 = (L^2 - L0^2)/(L + L0)
                theta_i = wrap(theta_i + beta0 - beta)        (relative to the chord)
    forces      q = [N, M1, M2] = k_l [u_bar, theta_1, theta_2],  k_l = diag(k_a, k_b)
    B           r = [-c, -s, 0, c, s, 0],   z = [s, -c, 0, -s, c, 0]
                B = [r;  e3 - z/L;  e6 - z/L]
    internal    f = B^T q
    tangent     K = B^T k_l B + (N/L) z z^T + ((M1 + M2)/L^2)(r z^T + z r^T)

Only the relative angle is wrapped.  ``jumped`` flags elements where the
wrap was active (|theta_i + beta0 - beta| > pi): two neighbouring rotations
differ by about 2 pi, a spurious equilibrium that the solver rejects.
"""
from __future__ import annotations

import numpy as np

__all__ = ["element_state", "wrap"]


def wrap(a):
    """Angle in (-pi, pi]."""
    return np.arctan2(np.sin(a), np.cos(a))


def element_state(X1, X2, p, L0, beta0, beta_prev, ka, kb, need_tangent=True):
    """Internal forces f (n,6), tangent K (n,6,6) and local state of all elements.

    Returns dict with f, K, N, M (n,2), L, beta, theta_bar (n,2), u_bar, jumped.
    """
    d = X2 - X1 + p[:, 3:5] - p[:, 0:2]
    L = np.hypot(d[:, 0], d[:, 1])
    c, s = d[:, 0] / L, d[:, 1] / L
    beta = beta_prev + wrap(np.arctan2(d[:, 1], d[:, 0]) - beta_prev)
    u_bar = (L * L - L0 * L0) / (L + L0)
    theta_raw = p[:, [2, 5]] + (beta0 - beta)[:, None]
    theta_bar = wrap(theta_raw)
    jumped = np.any(np.abs(theta_raw - theta_bar) > 1.0, axis=1)
    N = ka * u_bar
    M = np.einsum("eij,ej->ei", kb, theta_bar)
    zero = np.zeros_like(c)
    r = np.column_stack([-c, -s, zero, c, s, zero])
    z = np.column_stack([s, -c, zero, -s, c, zero])
    zL = z / L[:, None]
    b1 = -zL.copy()
    b1[:, 2] += 1.0
    b2 = -zL.copy()
    b2[:, 5] += 1.0
    f = r * N[:, None] + b1 * M[:, 0:1] + b2 * M[:, 1:2]
    out = dict(f=f, N=N, M=M, L=L, beta=beta, theta_bar=theta_bar, u_bar=u_bar, jumped=jumped)
    if need_tangent:
        K = (ka[:, None, None] * r[:, :, None] * r[:, None, :]
             + kb[:, 0, 0, None, None] * b1[:, :, None] * b1[:, None, :]
             + kb[:, 0, 1, None, None] * b1[:, :, None] * b2[:, None, :]
             + kb[:, 1, 0, None, None] * b2[:, :, None] * b1[:, None, :]
             + kb[:, 1, 1, None, None] * b2[:, :, None] * b2[:, None, :]
             + (N / L)[:, None, None] * z[:, :, None] * z[:, None, :])
        rz = r[:, :, None] * z[:, None, :]
        K += ((M[:, 0] + M[:, 1]) / (L * L))[:, None, None] * (rz + rz.transpose(0, 2, 1))
        out["K"] = K
    return out


def strain_energy(ka, kb, u_bar, theta_bar):
    """Element strain energies 1/2 (k_a u_bar^2 + theta_bar^T k_b theta_bar)."""
    return 0.5 * (ka * u_bar**2 + np.einsum("ei,eij,ej->e", theta_bar, kb, theta_bar))
