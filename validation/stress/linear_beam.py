"""Linear (small-deflection) theory of a straight or circular-arc segment: the contract's reference.

Written from the textbook unit-load (Castigliano / Maxwell-Mohr) method, independent of every
solver in this repository. The segment starts at the origin along +x with constant initial
curvature kappa (straight when kappa = 0); arc length s in [0, L], tangent angle psi(s) = kappa s,

    x(s) = sin(kappa s)/kappa,   y(s) = (1 - cos(kappa s))/kappa          (x = s, y = 0 if straight).

A tip load f = (F_x, F_y, M) (CCW moment) gives the bending moment and the axial force

    M(s) = M + (x_t - x(s)) F_y - (y_t - y(s)) F_x = g(s) . f,   g = (-(y_t - y), x_t - x, 1),
    N(s) = F_x cos psi + F_y sin psi = t(s) . f,                t = (cos psi, sin psi, 0),

so by Castigliano's second theorem (Timoshenko & Gere, Mechanics of Materials, energy methods;
thin curved bar) the tip displacement (u_x, u_y, theta) of the cantilever is u = C f with

    C = int_0^L [ g g^T / EI + t t^T / EA ] ds.

For a straight beam this is the textbook cantilever: u_y = F L^3/3EI + M L^2/2EI,
theta = F L^2/2EI + M L/EI, u_x = F_x L/EA (Gere & Timoshenko, Table of beam deflections).
For a quarter circle of radius R under F_y: theta = F_y R^2 (pi/2 - 1)/EI.

A root that is pinned instead of clamped adds a rigid rotation phi of the whole segment about the
origin, u += phi (-y_t, x_t, 1), and the condition that the root carries no moment,
M + x_t F_y - y_t F_x = 0. Each tip freedom i has either its load f_i given (applied load, zero if
nothing acts) or its motion u_i given (held at 0 by the boundary, or prescribed); the linear system
gives the other. The strain energy is (1/2) f . u (the root does no work).

The integrals are evaluated by Gauss-Legendre quadrature (the integrands are trigonometric
polynomials of low degree in s, so 24 points are exact to rounding).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FREEDOMS = ("ux", "uy", "rz")


@dataclass(frozen=True)
class LinearTip:
    """Linear tip response: motion (u_x, u_y, theta [rad]) and total tip load (F_x, F_y, M), the
    root reaction (R_x, R_y, M_root) and the strain energy."""

    motion: np.ndarray
    load: np.ndarray
    reaction: np.ndarray
    strain_energy: float
    tip: tuple[float, float]


def arc_point(s, kappa: float):
    """(x, y, psi) at arc length s of the unloaded segment."""
    s = np.asarray(s, float)
    if kappa == 0.0:
        return s, np.zeros_like(s), np.zeros_like(s)
    return np.sin(kappa * s) / kappa, (1.0 - np.cos(kappa * s)) / kappa, kappa * s


GAUSS_24 = np.polynomial.legendre.leggauss(24)  # once: numpy solves an eigenproblem for the rule on each call


def flexibility(length: float, kappa: float, EI: float, EA: float = np.inf) -> np.ndarray:
    """The 3x3 tip flexibility C of the cantilever (clamped at s = 0), u = C f."""
    nodes, weights = GAUSS_24
    s = 0.5 * length * (nodes + 1.0)
    w = 0.5 * length * weights
    x, y, psi = arc_point(s, kappa)
    xt, yt, _ = arc_point(length, kappa)
    g = np.stack([-(yt - y), xt - x, np.ones_like(s)])  # (3, n)
    t = np.stack([np.cos(psi), np.sin(psi), np.zeros_like(s)])  # (3, n)
    C = (g * w) @ g.T / EI
    if np.isfinite(EA):
        C = C + (t * w) @ t.T / EA
    return C


def solve_tip(
    length: float,
    kappa: float,
    EI: float,
    EA: float,
    *,
    root_pinned: bool,
    given_load: dict[str, float],
    given_motion: dict[str, float],
) -> LinearTip:
    """Linear response with, for each tip freedom, either its load or its motion given.

    ``given_motion`` (freedom -> u_x, u_y [length] or theta [rad]) wins over ``given_load``
    (freedom -> F_x, F_y or M); a freedom in neither carries no load."""
    C = flexibility(length, kappa, EI, EA)
    xt, yt, _ = arc_point(length, kappa)
    xt, yt = float(xt), float(yt)
    rigid = np.array([-yt, xt, 1.0])
    n = 7 if root_pinned else 6  # unknowns: u (3), f (3), phi
    A = np.zeros((n, n))
    rhs = np.zeros(n)
    A[:3, :3] = np.eye(3)  # u - C f - phi rigid = 0
    A[:3, 3:6] = -C
    if root_pinned:
        A[:3, 6] = -rigid
        A[6, 3:6] = rigid  # no moment at the pinned root: M + x_t F_y - y_t F_x = 0
    for i, name in enumerate(FREEDOMS):
        row = 3 + i
        if name in given_motion:
            A[row, i] = 1.0
            rhs[row] = given_motion[name]
        else:
            A[row, 3 + i] = 1.0
            rhs[row] = given_load.get(name, 0.0)
    sol = np.linalg.solve(A, rhs)
    u, f = sol[:3], sol[3:6]
    reaction = -np.array([f[0], f[1], f[2] + xt * f[1] - yt * f[0]])
    return LinearTip(motion=u, load=f, reaction=reaction, strain_energy=0.5 * float(f @ u), tip=(xt, yt))
