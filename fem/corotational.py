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

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import numpy as np

from .kernel import Beams, element_kernel, element_outputs
from .types import FloatArray

__all__ = ["element_state", "element_state_numpy", "wrap"]


def wrap(a: FloatArray) -> FloatArray:
    """Angle in (-pi, pi]."""
    return np.arctan2(np.sin(a), np.cos(a))


def element_state(
    beams: Beams, p: FloatArray, beta_prev: FloatArray, need_tangent: bool = True
) -> dict[str, FloatArray]:
    """Internal forces f (n,6), tangent K (n,6,6) and local state of all elements at the element
    displacements ``p`` (n,6), chord angles continued from ``beta_prev`` (n,), by the compiled
    `kernel.element_kernel` (the same formulas as `element_state_numpy`, element by element).

    Returns dict with f, K, N, M (n,2), L, beta, theta_bar (n,2), u_bar, jumped (`kernel.ElementState`;
    no K when ``need_tangent`` is false)."""
    out = element_outputs(len(beams.L0), bool(need_tangent))
    element_kernel(beams, np.ascontiguousarray(p, dtype=float), beta_prev, bool(need_tangent), out)
    state = out._asdict()
    if not need_tangent:
        del state["K"]
    return state


def element_state_numpy(
    beams: Beams, p: FloatArray, beta_prev: FloatArray, need_tangent: bool = True
) -> dict[str, FloatArray]:
    """Internal forces f (n,6), tangent K (n,6,6) and local state of all elements, vectorised NumPy.

    Returns dict with f, K, N, M (n,2), L, beta, theta_bar (n,2), u_bar, jumped.
    With V = (M1 + M2)/L:  f = [-(cN + sV), -(sN - cV), M1, cN + sV, sN - cV, M2].
    The tangent is written as K = E^T C E with E = [r; z; e3; e6] (n,4,6) and
    the symmetric 4x4 coefficients C that follow from expanding B^T k_l B
    (b_i = e_i - z/L) plus the geometric terms.
    """
    X1, X2, L0, beta0, ka, kb = beams.X1, beams.X2, beams.L0, beams.beta0, beams.ka, beams.kb
    dx = X2[:, 0] - X1[:, 0] + p[:, 3] - p[:, 0]
    dy = X2[:, 1] - X1[:, 1] + p[:, 4] - p[:, 1]
    L = np.hypot(dx, dy)
    c, s = dx / L, dy / L
    beta = beta_prev + wrap(np.arctan2(dy, dx) - beta_prev)
    u_bar = (L * L - L0 * L0) / (L + L0)
    theta_raw = p[:, 2::3] + (beta0 - beta)[:, None]
    theta_bar = wrap(theta_raw)
    jumped = np.abs(theta_raw - theta_bar).max(axis=1) > 1.0
    N = ka * u_bar
    M = np.matmul(kb, theta_bar[:, :, None])[:, :, 0]
    V = (M[:, 0] + M[:, 1]) / L
    a = c * N + s * V
    b = s * N - c * V
    f = np.column_stack([-a, -b, M[:, 0], a, b, M[:, 1]])
    out = dict(f=f, N=N, M=M, L=L, beta=beta, theta_bar=theta_bar, u_bar=u_bar, jumped=jumped)
    if need_tangent:
        n = len(L)
        E = np.zeros((n, 4, 6))
        E[:, 0, 0], E[:, 0, 1], E[:, 0, 3], E[:, 0, 4] = -c, -s, c, s  # r
        E[:, 1, 0], E[:, 1, 1], E[:, 1, 3], E[:, 1, 4] = s, -c, -s, c  # z
        E[:, 2, 2] = 1.0  # e3
        E[:, 3, 5] = 1.0  # e6
        k11, k12, k21, k22 = kb[:, 0, 0], kb[:, 0, 1], kb[:, 1, 0], kb[:, 1, 1]
        C = np.zeros((n, 4, 4))
        C[:, 0, 0] = ka
        C[:, 1, 1] = (k11 + k12 + k21 + k22) / (L * L) + N / L
        C[:, 0, 1] = C[:, 1, 0] = V / L
        C[:, 1, 2] = -(k11 + k21) / L
        C[:, 2, 1] = -(k11 + k12) / L
        C[:, 1, 3] = -(k12 + k22) / L
        C[:, 3, 1] = -(k21 + k22) / L
        C[:, 2:, 2:] = kb
        out["K"] = np.matmul(E.transpose(0, 2, 1), np.matmul(C, E))
    return out


def strain_energy(ka: FloatArray, kb: FloatArray, u_bar: FloatArray, theta_bar: FloatArray) -> FloatArray:
    """Element strain energies 1/2 (k_a u_bar^2 + theta_bar^T k_b theta_bar)."""
    bending: FloatArray = np.einsum("ei,eij,ej->e", theta_bar, kb, theta_bar)
    return 0.5 * (ka * u_bar**2 + bending)
