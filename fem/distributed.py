"""Consistent nodal loads of a uniform distributed load on corotational elements, and their load stiffness.

A load of intensity q (force per unit *reference* length, a 2-vector) acts along an element of
reference length L0 whose current chord is d = x2 - x1 (length L, unit normal n = perp(d)/L).
Within the element the corotational interpolation places the centre line at

    x(xi) = x1 + xi d + w(xi) n,   w(xi) = L [(xi - 2 xi^2 + xi^3) thb1 + (xi^3 - xi^2) thb2],

(cubic Hermite transverse displacement relative to the chord, thb_i = theta_i + beta0 - beta the
local end rotations, Crisfield 1991 sec. 7.2), so the work of a dead load is

    W = integral q . x ds = L0 [ q . (x1 + x2)/2 + (g . d)(theta1 - theta2)/12 ],   g = (q_y, -q_x)

(L n = perp(d), q . perp(d) = g . d; the chord angle cancels from thb1 - thb2). Its gradient gives
the consistent nodal loads

    f_1 = L0 (q/2 - g A/12),   f_2 = L0 (q/2 + g A/12),   m_1 = -m_2 = L0 (g . d)/12,   A = theta1 - theta2,

which for a straight element reduce to the textbook q L/2 and +-q_n L^2/12. The load stiffness
K_q = d f / d p is symmetric for a dead load (it is the Hessian of W):

    d f_1/d theta1 = -L0 g/12,  d f_2/d theta1 = +L0 g/12  (theta2: opposite signs),
    d m_1/d x2 = +L0 g/12,  d m_1/d x1 = -L0 g/12          (m_2: opposite signs).

A follower load turns with the element chord: q = R(beta - beta0) q0 (e.g. a pressure stays normal
to the beam). Then dq/d beta = perp(q) = -g, dg/d beta = q, d beta/d x2 = -d beta/d x1 = n/L, which
adds to the dead-load terms

    d f_1/d x2 = L0 (-g/2 - q A/12) n^T / L,   d f_2/d x2 = L0 (-g/2 + q A/12) n^T / L,
    d m_1/d x2 = L0 (q . d) n^T / (12 L)       (d/d x1 = -d/d x2; m_2 = -m_1),

an unsymmetric (non-conservative) load stiffness. Element DOFs are p = [u1, v1, theta1, u2, v2, theta2]
as in `corotational`; every array carries the element axis first.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import numpy as np

from .kernel import Beams
from .types import FloatArray

__all__ = ["element_loads"]


def element_loads(
    beams: Beams, p: FloatArray, beta: FloatArray, q_dead: FloatArray, q_follower: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Consistent nodal loads f (n, 6) and load stiffness K_q = df/dp (n, 6, 6) of all elements
    (`kernel.Beams`: their reference geometry) at element displacements ``p`` (n, 6) and chord angles
    ``beta`` (n,).

    ``q_dead``: (n, 2) dead intensities in the global frame; ``q_follower``: (n, 2) follower
    intensities in the reference frame, turned by the chord rotation beta - beta0 (both per unit
    reference length; zero rows for unloaded elements).
    """
    X1, X2, L0, beta0 = beams.X1, beams.X2, beams.L0, beams.beta0
    d = np.column_stack([X2[:, 0] - X1[:, 0] + p[:, 3] - p[:, 0], X2[:, 1] - X1[:, 1] + p[:, 4] - p[:, 1]])
    L = np.hypot(d[:, 0], d[:, 1])
    n_hat = np.column_stack([-d[:, 1], d[:, 0]]) / L[:, None]
    phi = beta - beta0
    cs, sn = np.cos(phi), np.sin(phi)
    q_turned = np.column_stack(
        [cs * q_follower[:, 0] - sn * q_follower[:, 1], sn * q_follower[:, 0] + cs * q_follower[:, 1]]
    )
    q = q_dead + q_turned
    g = np.column_stack([q[:, 1], -q[:, 0]])
    A = p[:, 2] - p[:, 5]
    gd = np.einsum("ei,ei->e", g, d)
    f = np.empty((len(L0), 6))
    f[:, 0:2] = L0[:, None] * (q / 2 - g * A[:, None] / 12)
    f[:, 3:5] = L0[:, None] * (q / 2 + g * A[:, None] / 12)
    f[:, 2] = L0 * gd / 12
    f[:, 5] = -f[:, 2]

    K = np.zeros((len(L0), 6, 6))
    # dead-load (conservative) part: every load turns the same way here, with g of the total q
    c = (L0 / 12)[:, None] * g
    for row, sign in ((slice(0, 2), -1.0), (slice(3, 5), 1.0)):  # forces w.r.t. theta1, theta2
        K[:, row, 2] = sign * c
        K[:, row, 5] = -sign * c
    K[:, 2, 0:2], K[:, 2, 3:5] = -c, c  # m1 w.r.t. x1, x2
    K[:, 5, 0:2], K[:, 5, 3:5] = c, -c  # m2 = -m1
    # follower part: the turning of q with the chord
    if np.any(q_follower):
        qd = np.einsum("ei,ei->e", q_turned, d)
        gt = np.column_stack([q_turned[:, 1], -q_turned[:, 0]])
        w = (L0 / L)[:, None]
        df1 = w * (-gt / 2 - q_turned * A[:, None] / 12)  # (n, 2): d f_1 / d beta * L0 / L
        df2 = w * (-gt / 2 + q_turned * A[:, None] / 12)
        dm1 = L0 * qd / (12 * L)
        for row, vec in ((slice(0, 2), df1), (slice(3, 5), df2)):
            block = vec[:, :, None] * n_hat[:, None, :]
            K[:, row, 3:5] += block
            K[:, row, 0:2] -= block
        K[:, 2, 3:5] += dm1[:, None] * n_hat
        K[:, 2, 0:2] -= dm1[:, None] * n_hat
        K[:, 5, 3:5] -= dm1[:, None] * n_hat
        K[:, 5, 0:2] += dm1[:, None] * n_hat
    return f, K
