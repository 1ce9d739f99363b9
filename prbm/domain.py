"""Characteristic deflection domains [bapat2015, ch. 4]: reachable end positions of a segment type,
found by sweeping its PRBM over load ratios and load levels, and the boundary curves of the cloud.

Procedure of section 4.2 / Fig. 4.1 (the flowchart is missing from the dissertation): apply a wide range of
end-load combinations, compute the end points, extract the lower and upper boundaries.  Here the
boundaries are, for each normalised transverse deflection b/l (binned), the smallest and largest
normalised end position a/l of the cloud.  ``fit_radius`` fits a PRBM circle (centre (1 - gamma) l
on the axis, or the clamp for the fixed-guided lower bound) to a boundary by least squares.  The
printed constants (gamma_l = 0.8053, gamma_u = 0.8829 for the straight fixed-pinned segment, eqs
110-111) depend on the unpublished extraction rule and are not expected to be reproduced exactly
(notes seed-ch2-4 section 6.2: the extreme-n trajectories give 0.8114 and 0.8817).

Segment types (one function each; all sweep the PRBMs of ``prbm.segments`` with the PRB angle Theta as
the parameter, so no root finding: the load level follows from the spring equation and is returned):

* ``fixed_pinned_domain``: initially straight fixed-pinned, section 4.4.
* ``curved_fixed_pinned_domain``: initially curved fixed-pinned, section 4.5, per initial curvature
  kappa0 = l/R_i (eqs 53-61).
* ``fixed_guided_domain``: initially straight fixed-guided, end slope held at zero, two-spring PRBM
  (eq 63); section 4.6's segment without an end-angle degree of freedom.
* ``fixed_fixed_monotonic_domain``: fixed-fixed / fixed-guided with monotonic curvature, section 4.6:
  the curved fixed-pinned PRBM with kappa0 = M l/EI (115) (+ l/R_i, eq 119), with the moment bounds of
  section 4.6.1 (an opposing moment is kept only when kappa > 2, eq 125).
* ``slfp_domain``: small-length flexural pivot with a rigid segment, section 4.7 (eqs 71-82, 127).

Every domain function returns one dict: the swept points (``a``, ``b`` normalised by the segment
length, the sweep parameters per point, the load level), the boundary curves of the cloud from
``boundary_curves`` (``boundary_b``, ``boundary_lower``, ``boundary_upper``), and ``excluded``, the
number of grid points dropped because their load ratio n lies outside the fit family's published
range (never extrapolated), plus any other exclusion count named after its reason.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares

from prbm.fits import FitFamily, fit_family

__all__ = [
    "fixed_pinned_domain",
    "curved_fixed_pinned_domain",
    "fixed_guided_domain",
    "fixed_fixed_monotonic_domain",
    "slfp_domain",
    "boundary_curves",
    "fit_radius",
]

#: a swept domain (module docstring): the points' arrays, the boundary curves (arrays), the exclusion
#: counts (ints), and for the SLFP the arc's radius (a float) and pivot (x, y)
Domain: TypeAlias = dict[str, NDArray[np.float64] | int | float | tuple[float, float]]


def fixed_pinned_domain(
    n_values: ArrayLike | None = None,
    theta0_max_deg: float = 90.0,
    n_theta: int = 91,
    family: str | FitFamily = "pauly-midha",
) -> dict[str, NDArray[np.float64]]:
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
    return {"a": a.ravel(), "b": b.ravel(), "n": n_grid.ravel(), "Theta": Theta.ravel(), "alpha2": alpha2.ravel()}


def boundary_curves(a: ArrayLike, b: ArrayLike, bins: int = 60) -> dict[str, NDArray[np.float64]]:
    """Lower (min a) and upper (max a) boundary of a point cloud, per bin of b."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    edges = np.linspace(b.min(), b.max(), bins + 1)
    idx = np.clip(np.digitize(b, edges) - 1, 0, bins - 1)
    centres: list[float] = []
    lower: list[float] = []
    upper: list[float] = []
    for i in range(bins):
        mask = idx == i
        if mask.any():
            centres.append(b[mask].mean())
            lower.append(a[mask].min())
            upper.append(a[mask].max())
    return {"b": np.array(centres), "lower": np.array(lower), "upper": np.array(upper)}


def fit_radius(a: ArrayLike, b: ArrayLike, *, centre: str = "prbm") -> float:
    """Least-squares gamma of a circle through boundary points (a, b) (normalised by l).

    centre='prbm': circle of radius gamma about ((1 - gamma), 0) (eqs 48-49);
    centre='clamp': circle of radius gamma about the fixed end (eq 117's gamma-bar_l).
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    if centre == "clamp":
        return float(np.mean(np.hypot(a, b)))

    def residual(g: NDArray[np.float64]) -> NDArray[np.float64]:
        r: NDArray[np.float64] = np.hypot(a - (1 - g[0]), b) - g[0]
        return r

    return float(least_squares(residual, [0.85]).x[0])


def _default_n(fam: FitFamily) -> NDArray[np.float64]:
    """The load-ratio grid of ``fixed_pinned_domain``: 141 values over the fit range clipped to -4..10."""
    return np.linspace(max(fam.lower, -4.0) + 1e-9, min(fam.upper, 10.0), 141)


def _fit_range_n(fam: FitFamily, n_values: ArrayLike | None) -> tuple[NDArray[np.float64], int]:
    """(n inside the family's published range lower < n <= upper, number of n values dropped)."""
    n = np.atleast_1d(np.asarray(_default_n(fam) if n_values is None else n_values, float)).ravel()
    inside = (n > fam.lower) & (n <= fam.upper)
    return n[inside], int(np.count_nonzero(~inside))


def _with_boundaries(points: Mapping[str, ArrayLike], bins: int, **counts: int) -> Domain:
    """Flatten the swept grids, attach the boundary curves of the cloud and the exclusion counts."""
    flat = {key: np.ravel(value) for key, value in points.items()}
    if flat["a"].size:
        bc = boundary_curves(flat["a"], flat["b"], bins=bins)
    else:
        bc = {"b": np.empty(0), "lower": np.empty(0), "upper": np.empty(0)}
    out: Domain = {
        **flat,
        "boundary_b": bc["b"],
        "boundary_lower": bc["lower"],
        "boundary_upper": bc["upper"],
        **counts,
    }
    return out


def _curved_grid(
    kappa0: ArrayLike, n: NDArray[np.float64], fam: FitFamily, theta0_max_deg: float, n_theta: int
) -> dict[str, NDArray[np.float64]]:
    """Initially curved fixed-pinned PRBM (l = EI = 1) on the grid kappa0 x n x s, s in [0, 1].

    Geometry of eqs (53)-(57): a_i = sin(kappa0)/kappa0, b_i = (1 - cos kappa0)/kappa0,
    Theta_i = atan2(b_i, a_i - (1 - gamma)), rho = |(a_i - (1 - gamma), b_i)|; tip (59)-(60)
    a = 1 - gamma + rho cos Theta, b = rho sin Theta; theta0 = kappa0 + c_theta (Theta - Theta_i).
    Theta runs from Theta_i toward the force direction phi (taken on the branch within pi of Theta_i),
    at most until |theta0 - kappa0| = theta0_max and never reaching phi; the load follows from
    F rho l sin(phi - Theta) = rho K_Theta (EI/l) (Theta - Theta_i) (the assumption of
    ``curved_fixed_pinned_tip``) as alpha2 = P l^2/EI with F = P sqrt(1 + n^2).
    """
    k0 = np.asarray(kappa0, float).reshape(-1, 1, 1)
    nn = n.reshape(1, -1, 1)
    s = np.linspace(0.0, 1.0, n_theta).reshape(1, 1, -1)
    gamma, c_theta, K = (p.reshape(1, -1, 1) for p in fam.parameters(n))
    straight = np.abs(k0) < 1e-12
    k0_safe = np.where(straight, 1.0, k0)
    a_i = np.where(straight, 1.0, np.sin(k0_safe) / k0_safe)
    b_i = np.where(straight, 0.0, (1.0 - np.cos(k0_safe)) / k0_safe)
    Theta_i = np.arctan2(b_i, a_i - (1.0 - gamma))
    rho = np.hypot(a_i - (1.0 - gamma), b_i)
    phi = np.arctan2(1.0, -nn)
    phi = Theta_i + np.angle(np.exp(1j * (phi - Theta_i)))
    span = np.sign(phi - Theta_i) * np.minimum(math.radians(theta0_max_deg) / c_theta, np.abs(phi - Theta_i) * 0.999)
    Theta = Theta_i + s * span
    eta = np.sqrt(1.0 + nn**2)
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha2 = np.where(Theta == Theta_i, 0.0, K * (Theta - Theta_i) / (eta * np.sin(phi - Theta)))
    shape = Theta.shape
    return {
        "a": np.broadcast_to(1.0 - gamma + rho * np.cos(Theta), shape),
        "b": np.broadcast_to(rho * np.sin(Theta), shape),
        "theta0": np.broadcast_to(k0 + c_theta * (Theta - Theta_i), shape),
        "Theta": Theta,
        "alpha2": np.broadcast_to(alpha2, shape),
        "n": np.broadcast_to(nn, shape),
        "kappa0": np.broadcast_to(k0, shape),
    }


def curved_fixed_pinned_domain(
    curvature: ArrayLike,
    n_values: ArrayLike | None = None,
    theta0_max_deg: float = 90.0,
    n_theta: int = 91,
    family: str | FitFamily = "pauly-midha",
    bins: int = 60,
) -> Domain:
    """Characteristic deflection domain of an initially curved fixed-pinned segment [bapat2015, §4.5].

    curvature: kappa0 = l/R_i (dimensionless, CCW positive; eq 53), a scalar or an array of values.
    For one kappa0 this is the domain of that beam; for an array the cloud is the union, like the
    seed's Fig. 4.6 grid, in which kappa0 varies with the load (notes seed-ch2-4 section 6.3).
    Swept: n over n_values (default 141 values over -4 < n <= 10), force P > 0 (first quadrant, as the
    seed's theta0 in 1..90 deg), PRB angle from Theta_i until the force-induced end rotation
    |theta0 - kappa0| reaches theta0_max_deg or Theta reaches phi.  Model: eqs (53)-(61) as in
    ``prbm.segments.curved_fixed_pinned_tip`` (straight-beam gamma, c_theta, K_Theta at n: the dissertation
    gives no curvature dependence); as kappa0 -> 0 it becomes ``fixed_pinned_domain``.
    Not covered: P < 0 (the curved beam is not symmetric about its axis), the dissertation's elliptic
    (eqs 8-9) cloud and Su's theta0max (112), so gamma_l = 0.7431, gamma_u = 0.8148 (113-114) are
    not reproduced.  Load ratios outside the fit range are excluded (``excluded`` counts grid points).

    Returns a, b (normalised by l), theta0, Theta, alpha2 = P l^2/EI, n, kappa0 per point, the
    boundary curves and ``excluded``.
    """
    fam = fit_family(family)
    n, dropped = _fit_range_n(fam, n_values)
    n_kappa = np.atleast_1d(np.asarray(curvature, float)).size
    grid = _curved_grid(curvature, n, fam, theta0_max_deg, n_theta)
    return _with_boundaries(grid, bins, excluded=dropped * n_kappa * n_theta)


def fixed_guided_domain(
    n_values: ArrayLike | None = None,
    theta0_max_deg: float = 90.0,
    n_theta: int = 91,
    family: str | FitFamily = "pauly-midha",
    bins: int = 60,
) -> Domain:
    """Characteristic deflection domain of an initially straight fixed-guided segment, end slope held
    at zero, by the two-spring PRBM ([bapat2015, eq 63], [ananthasuresh_l18, 07:13-12:05]; section 4.6).

    Each half (l/2) is a fixed-pinned PRBM, so the middle link gamma l turns by Theta between two
    springs k = 2 gamma K_Theta EI/l: a = 1 - gamma (1 - cos Theta), b = gamma sin Theta (normalised
    by l), theta0 = 0, and (F l^2/EI) sin(phi - Theta) = 4 K_Theta Theta.  Swept: n over n_values,
    P > 0, Theta from 0 until the half-beam end rotation c_theta Theta reaches theta0_max_deg or
    Theta reaches phi.  The end moment that holds the slope is returned as moment = M l/EI
    (= -(2 gamma K_Theta Theta + (1 - gamma) alpha2 / 2), CCW positive, as ``fixed_guided_tip``).
    Not covered: the fixed-guided segment with one inflection point and a free end angle of
    Figs. 4.9-4.12 (Midha et al.'s PRBM with the kappa range of eq 126), so the dissertation's lower bound
    (116)/(117) and gamma_u = 0.9035 (118) are not reproduced; this is the theta0 = 0 slice.
    Since the geometry is the fixed-pinned one with the same gamma(n) and the same Theta cap, the
    cloud coincides with ``fixed_pinned_domain``'s (only the load differs, by a factor 4).

    Returns a, b, Theta, alpha2 = P l^2/EI, moment, n per point, the boundary curves, ``excluded``.
    """
    fam = fit_family(family)
    n, dropped = _fit_range_n(fam, n_values)
    gamma, c_theta, K = (p[:, None] for p in fam.parameters(n))
    nn = n[:, None]
    phi = np.arctan2(1.0, -nn)
    s = np.linspace(0.0, 1.0, n_theta)[None, :]
    Theta = s * np.minimum(math.radians(theta0_max_deg) / c_theta, phi * 0.999)
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha2 = 4.0 * K * Theta / (np.sqrt(1.0 + nn**2) * np.sin(phi - Theta))
    moment = -(2.0 * gamma * K * Theta + (1.0 - gamma) * alpha2 / 2.0)
    points = {
        "a": 1.0 - gamma * (1.0 - np.cos(Theta)),
        "b": gamma * np.sin(Theta),
        "Theta": Theta,
        "alpha2": alpha2,
        "moment": moment,
        "n": np.broadcast_to(nn, Theta.shape),
    }
    return _with_boundaries(points, bins, excluded=dropped * n_theta)


def fixed_fixed_monotonic_domain(
    moment_values: ArrayLike,
    n_values: ArrayLike | None = None,
    curvature: float = 0.0,
    theta0_max_deg: float = 90.0,
    n_theta: int = 91,
    family: str | FitFamily = "pauly-midha",
    kappa_monotonic: float = 2.0,
    bins: int = 60,
) -> Domain:
    """Characteristic deflection domain of a fixed-fixed (fixed-guided) segment with monotonic
    curvature [bapat2015, §4.6, Fig. 4.8], with the moment bounds of section 4.6.1.

    moment_values: end moments m = M l/EI (CCW positive, i.e. the same rotational sense as P > 0);
    curvature: l/R_i of an initially curved segment (eq 119).  The segment is the curved fixed-pinned
    PRBM with kappa0 = M l/EI + l/R_i (eqs 115, 119; Howell), swept as ``curved_fixed_pinned_domain``
    over (m, n, Theta), P > 0.  Moment bounds (section 4.6.1): a moment of the same sense as P gives
    monotonic curvature at any magnitude (Table 2.1); an opposing moment (m < 0) does so only when
    kappa = M^2/(2 F EI) > kappa_monotonic = 2 (eq 125; normalised by F = P sqrt(1 + n^2), not P,
    notes seed-ch2-4 section 6.5), otherwise the segment may have an inflection point and the point
    is excluded (count in ``excluded_inflection``).  Load ratios outside the fit range are excluded
    (``excluded``).  Not covered: the inflection-point configurations of Figs. 4.9-4.10 (the range
    0.1 <= kappa <= 1.8 of eq 126 belongs to them) and kappa_min of eq (123), whose values survive only
    in missing figures.

    Returns a, b, theta0, Theta, alpha2 = P l^2/EI, moment (m), kappa (M^2/(2 F EI)), n, kappa0 per
    point, the boundary curves, ``excluded`` and ``excluded_inflection``.
    """
    fam = fit_family(family)
    n, dropped = _fit_range_n(fam, n_values)
    m = np.atleast_1d(np.asarray(moment_values, float)).ravel()
    grid = _curved_grid(m + curvature, n, fam, theta0_max_deg, n_theta)
    moment = np.broadcast_to(m.reshape(-1, 1, 1), grid["a"].shape)
    F = grid["alpha2"] * np.sqrt(1.0 + grid["n"] ** 2)  # F l^2/EI
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = np.where(F > 0, moment**2 / (2.0 * np.where(F > 0, F, 1.0)), np.inf)
    keep = (moment >= 0.0) | (kappa > kappa_monotonic)
    points = {key: value[keep] for key, value in grid.items()}
    points.update(moment=moment[keep], kappa=kappa[keep])
    return _with_boundaries(
        points, bins, excluded=dropped * m.size * n_theta, excluded_inflection=int(np.count_nonzero(~keep))
    )


def slfp_domain(
    flexure_fraction: float,
    n_values: ArrayLike | None = None,
    curvature: float = 0.0,
    theta_max_deg: float = 90.0,
    n_theta: int = 91,
    bins: int = 60,
) -> Domain:
    """Characteristic deflection domain of a fixed-free segment made of a small-length flexural pivot
    (length l) and a rigid segment (length L), [bapat2015, §4.7] (eqs 71-82, 127).

    flexure_fraction = l/(l + L) (small: the model assumes l << L); curvature: kappa0 = l/R_i of the
    flexure (0 for the initially straight SLFP).  Positions are normalised by the segment length
    l + L.  Model as ``prbm.segments.slfp_tip``: pivot at the middle of the flexure (at the chord
    midpoint when curved, eqs 77-78), link R = L + l/2 (71), k = EI/l (72), theta0 - kappa0 =
    Theta - Theta_i (73), k (Theta - Theta_i) = F R sin(phi - Theta) (76, 79).  Swept: any n in
    n_values (default 141 values over -4..10; no fit is involved, so nothing is excluded), P > 0,
    Theta from Theta_i toward phi until |Theta - Theta_i| = theta_max_deg or Theta reaches phi.
    The domain is an arc of radius (l/2 + L) about the pivot (eq 127): a curve, not a region.
    Not covered: P < 0, and the Midha-Kuber elliptic solution the dissertation cites.

    Returns a, b, theta0, Theta, alpha2 = P (l + L)^2/EI, n per point, the boundary curves,
    ``radius`` (eq 127, normalised) and ``excluded`` (always 0).
    """
    lam = float(flexure_fraction)
    if not 0.0 < lam <= 1.0:
        raise ValueError("flexure_fraction = l/(l + L) must lie in (0, 1]")
    R = 1.0 - lam / 2.0
    n = np.atleast_1d(np.asarray(np.linspace(-4.0, 10.0, 141) if n_values is None else n_values, float))
    nn = n.ravel()[:, None]
    kappa0 = float(curvature)
    if abs(kappa0) < 1e-12:
        px, py, Theta_i = lam / 2.0, 0.0, 0.0
    else:
        px, py = lam / (2 * kappa0) * math.sin(kappa0), lam / (2 * kappa0) * (1 - math.cos(kappa0))
        a_i = lam / kappa0 * math.sin(kappa0) + (1.0 - lam) * math.cos(kappa0)
        b_i = lam / kappa0 * (1 - math.cos(kappa0)) + (1.0 - lam) * math.sin(kappa0)
        Theta_i = math.atan2(b_i - py, a_i - px)
    phi = np.arctan2(1.0, -nn)
    phi = Theta_i + np.angle(np.exp(1j * (phi - Theta_i)))
    span = np.sign(phi - Theta_i) * np.minimum(math.radians(theta_max_deg), np.abs(phi - Theta_i) * 0.999)
    Theta = Theta_i + np.linspace(0.0, 1.0, n_theta)[None, :] * span
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha2 = np.where(
            Theta == Theta_i, 0.0, (Theta - Theta_i) / (lam * R * np.sqrt(1.0 + nn**2) * np.sin(phi - Theta))
        )
    points = {
        "a": px + R * np.cos(Theta),
        "b": py + R * np.sin(Theta),
        "theta0": Theta - Theta_i + kappa0,
        "Theta": Theta,
        "alpha2": alpha2,
        "n": np.broadcast_to(nn, Theta.shape),
    }
    out = _with_boundaries(points, bins, excluded=0)
    out["radius"] = R
    out["pivot"] = (px, py)
    return out
