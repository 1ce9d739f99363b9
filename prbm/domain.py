"""Characteristic deflection domains (seed 000 chapter 4): reachable end positions of a segment type,
found by sweeping its PRBM over load ratios and load levels, and the boundary curves of the cloud.

Procedure of section 4.2 / Fig. 4.1 (the flowchart is missing from the seed): apply a wide range of
end-load combinations, compute the end points, extract the lower and upper boundaries.  Here the
boundaries are, for each normalised transverse deflection b/l (binned), the smallest and largest
normalised end position a/l of the cloud.  ``fit_radius`` fits a PRBM circle (centre (1 - gamma) l
on the axis, or the clamp for the fixed-guided lower bound) to a boundary by least squares.  The
printed constants (gamma_l = 0.8053, gamma_u = 0.8829 for the straight fixed-pinned segment, eqs
110-111) depend on the unpublished extraction rule and are not expected to be reproduced exactly
(notes seed-ch2-4 section 6.2: the extreme-n trajectories give 0.8114 and 0.8817).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import least_squares

from prbm.fits import fit_family

__all__ = ["fixed_pinned_domain", "boundary_curves", "fit_radius"]


def fixed_pinned_domain(n_values=None, theta0_max_deg: float = 90.0, n_theta: int = 91,
                        family="pauly-midha") -> dict[str, np.ndarray]:
    """End points (a/l, b/l) of the straight fixed-pinned PRBM for n in n_values and PRB angles
    Theta from 0 up to min(theta0_max / c_theta, phi) (theta0 = c_theta Theta <= theta0_max, and
    Theta < phi, the force direction).  Vectorised: one (n, Theta) grid, no root finding (Theta is
    the parameter; the load follows from eq (47) and is returned as alpha^2 = P l^2/EI)."""
    fam = fit_family(family)
    if n_values is None:
        n_values = np.linspace(max(fam.lower, -4.0) + 1e-9, min(fam.upper, 10.0), 141)
    n = np.asarray(n_values, float)[:, None]
    gamma, c_theta, K = fam.parameters(n.ravel())
    gamma, c_theta, K = gamma[:, None], c_theta[:, None], K[:, None]
    phi = np.arctan2(1.0, -n)
    s = np.linspace(0.0, 1.0, n_theta)[None, :]
    Theta_max = np.minimum(math.radians(theta0_max_deg) / c_theta, phi * 0.999)
    Theta = s * Theta_max
    a = 1.0 - gamma * (1.0 - np.cos(Theta))
    b = gamma * np.sin(Theta)
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha2 = K * Theta / (np.sqrt(1 + n**2) * np.sin(phi - Theta))
    n_grid = np.broadcast_to(n, Theta.shape)
    return {"a": a.ravel(), "b": b.ravel(), "n": n_grid.ravel(), "Theta": Theta.ravel(),
            "alpha2": alpha2.ravel()}


def boundary_curves(a, b, bins: int = 60) -> dict[str, np.ndarray]:
    """Lower (min a) and upper (max a) boundary of a point cloud, per bin of b."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    edges = np.linspace(b.min(), b.max(), bins + 1)
    idx = np.clip(np.digitize(b, edges) - 1, 0, bins - 1)
    centres, lower, upper = [], [], []
    for i in range(bins):
        mask = idx == i
        if mask.any():
            centres.append(b[mask].mean())
            lower.append(a[mask].min())
            upper.append(a[mask].max())
    return {"b": np.array(centres), "lower": np.array(lower), "upper": np.array(upper)}


def fit_radius(a, b, *, centre: str = "prbm") -> float:
    """Least-squares gamma of a circle through boundary points (a, b) (normalised by l).

    centre='prbm': circle of radius gamma about ((1 - gamma), 0) (eqs 48-49);
    centre='clamp': circle of radius gamma about the fixed end (eq 117's gamma-bar_l).
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    if centre == "clamp":
        return float(np.mean(np.hypot(a, b)))

    def residual(g):
        return np.hypot(a - (1 - g[0]), b) - g[0]

    return float(least_squares(residual, [0.85]).x[0])
