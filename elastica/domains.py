"""Exact characteristic deflection domains [bapat2015, ch. 4]: clouds of end positions of a
segment from the closed-form elliptic solutions, over the load grids the chapter prints.

Normalised as ``elastica.elliptic`` (l = EI = 1, so alpha^2 = P l^2/EI, positions a/l, b/l).

* ``fixed_pinned_cloud`` (section 4.4): initially straight fixed-pinned segment under P and nP,
  eqs (6), (7) with the corrected gamma, over n and theta0 (0 < theta0 < phi); the dissertation's grid is
  n = -4..10, theta0 = 1..90 deg.
* ``curved_fixed_pinned_cloud`` (section 4.5, and section 4.6's fixed-fixed segment with monotonic
  curvature, kappa0 = M l/EI (+ l/R_i), eqs 115, 119): eqs (8)-(11) over n, theta0 and kappa =
  M^2/(2 P EI) (eq 121; kappa0 = alpha sqrt(2 kappa)), limited by Su's maximum end angle (eq 112)

      theta0max = phi + acos(1 - kappa_F)  (kappa_F <= 2),  infinite for kappa_F > 2.

  Eq (112) is the condition that the curvature stays real along the beam: the first integral
  theta'^2 = 2P [lambda - (sin theta - n cos theta)] with sin theta - n cos theta = eta cos(theta - phi)
  must stay >= 0 for theta in [0, theta0], i.e. kappa/eta + cos(theta0 - phi) - 1 >= 0 when phi lies
  inside; so kappa in (112) is normalised by the resultant force F = eta P: kappa_F = M^2/(2 F EI)
  = kappa/eta (notes seed-ch2-4 section 6.5; the dissertation prints M^2/(2 P EI), which overstates theta0max
  for n != 0).  ``su_theta0_max`` takes kappa_F.
* ``fixed_guided_inflection_cloud`` (section 4.6, Figs 4.9-4.12): the straight fixed-fixed segment
  with one inflection point under P, nP and an opposing end moment M, by the Kimball-Tsai elliptic
  form (``fixed_guided_inflection_from_angle``) over n, theta0 and kappa in the range of eq (126),
  keeping the points whose load lies in the dissertation's P range.  The dissertation drew this cloud with Midha et
  al.'s PRBM (its Fig. 4.12); this is the exact one.
* ``kappa_min`` (eqs 123, 124) and ``kappa_range`` (the routine of section 4.6.1 / Fig. 4.16: theta0
  > 0: kappa_min with theta_i = theta0 + 5 deg, kappa_max with theta_i = 85 deg; theta0 < 0: kappa_min
  with theta_i = 5 deg), with phi = atan2(1, -n), and kappa normalised by F as in (120).

The clouds are computed on arrays, one expression over the whole grid (``fixed_pinned_arrays``,
``curved_fixed_pinned_arrays``, ``fixed_guided_inflection_arrays``: the formulas of
``elastica.elliptic``'s ``*_from_angle`` with scipy's elliptic integrals on arrays; the tests hold them
to the scalar functions point by point), not point by point in Python (~1.2 million points).

Each cloud function returns a ``DomainCloud``: the points (a, b, theta0, alpha, n, kappa), plus the
count of grid points left out and why (``excluded``: outside the formula's or Su's range).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipeinc, ellipkinc

__all__ = [
    "DomainCloud",
    "su_theta0_max",
    "fixed_pinned_cloud",
    "curved_fixed_pinned_cloud",
    "fixed_guided_inflection_cloud",
    "kappa_min",
    "kappa_range",
]

FloatArray = NDArray[np.float64]
Values = FloatArray | float  # a scalar or an array of them, combined elementwise


@dataclass(frozen=True)
class DomainCloud:
    """End points of a segment type over a load grid (normalised by l and EI; angles in rad)."""

    a: FloatArray
    b: FloatArray
    theta0: FloatArray
    alpha: FloatArray
    n: FloatArray
    kappa: FloatArray
    excluded: dict[str, int] = field(default_factory=dict)

    @property
    def size(self) -> int:
        return int(self.a.size)


def _phi(n: ArrayLike) -> FloatArray:
    """phi = atan2(1, -n), the direction of the end force (-nP, P) (rad)."""
    phi: FloatArray = np.arctan2(1.0, -np.asarray(n, float))
    return phi


def su_theta0_max(load_ratio: ArrayLike, kappa_force: ArrayLike) -> FloatArray:
    """Eq (112): the largest end angle (rad) of a curved fixed-pinned segment with monotonic curvature;
    kappa_force = M^2/(2 F EI), F = sqrt(1 + n^2) P (see the module docstring); inf for kappa_F > 2."""
    k = np.asarray(kappa_force, float)
    with np.errstate(invalid="ignore"):
        bound = _phi(load_ratio) + np.arccos(np.clip(1.0 - k, -1.0, 1.0))
    return np.where(k > 2.0, np.inf, bound)


def _grid(*axes: ArrayLike) -> list[FloatArray]:
    """Every combination of the axes' values, flat, the first axis outermost (the order of nested loops)."""
    return [g.ravel() for g in np.meshgrid(*(np.atleast_1d(np.asarray(a, float)) for a in axes), indexing="ij")]


Columns = tuple[ArrayLike, ArrayLike, ArrayLike, ArrayLike, ArrayLike, ArrayLike]


def _cloud(keep: NDArray[np.bool_], columns: Columns, excluded: dict[str, int]) -> DomainCloud:
    """The points where ``keep`` holds, columns (a, b, theta0, alpha, n, kappa)."""
    a, b, theta0, alpha, n, kappa = (np.broadcast_to(np.asarray(c, float), keep.shape)[keep] for c in columns)
    return DomainCloud(a=a, b=b, theta0=theta0, alpha=alpha, n=n, kappa=kappa, excluded=excluded)


def _asin_sqrt(x: FloatArray) -> FloatArray:
    """asin(sqrt(x)), NaN outside 0 <= x <= 1 + 1e-14 (``elastica.elliptic``'s rule, on arrays)."""
    inside = (x >= 0.0) & (x <= 1.0 + 1e-14)
    return np.where(inside, np.arcsin(np.sqrt(np.clip(x, 0.0, 1.0))), np.nan)


def _F(g: Values, t: FloatArray) -> FloatArray:
    """F(g, t), the incomplete elliptic integral of the first kind with modulus t, elementwise."""
    value: FloatArray = ellipkinc(g, t * t)
    return value


def _E(g: Values, t: FloatArray) -> FloatArray:
    """E(g, t), the incomplete elliptic integral of the second kind with modulus t, elementwise."""
    value: FloatArray = ellipeinc(g, t * t)
    return value


def fixed_pinned_arrays(theta0: Values, n: Values) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(a, b, alpha) of ``elastica.elliptic.fixed_pinned_from_angle`` (eqs 6, 7, corrected g) on arrays."""
    eta = np.hypot(1.0, n)
    lam = np.sin(theta0) - n * np.cos(theta0)
    t = np.sqrt((eta + lam) / (2.0 * eta))
    g = _asin_sqrt((eta - n) / (eta + lam))
    Kt, Et = _F(math.pi / 2, t), _E(math.pi / 2, t)
    Fg, Eg = _F(g, t), _E(g, t)
    alpha = (Kt - Fg) / np.sqrt(eta)
    bracket = Kt - Fg + 2.0 * (Eg - Et)
    root = np.sqrt(2.0 * eta * (eta + lam)) * np.cos(g)
    den = alpha * eta**2.5
    return (-n * eta * bracket + root) / den, (eta * bracket + n * root) / den, alpha


def curved_fixed_pinned_arrays(
    theta0: ArrayLike, n: ArrayLike, kappa: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(a, b, alpha) of ``elastica.elliptic.curved_fixed_pinned_from_angle`` on arrays: case A
    (lambda <= eta, eqs 8, 9 with eta^(5/2)) and case B (eqs 10, 11, NaN beyond 90 deg + atan n), each
    case's formulas evaluated on its own points only (the elliptic integrals are most of the cost)."""
    th, nn, kk = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (theta0, n, kappa)))
    eta = np.hypot(1.0, nn)
    s0 = np.sin(th) - nn * np.cos(th)
    lam = kk + s0
    case_a, beyond = lam <= eta, th > math.pi / 2 + np.arctan(nn)
    out = [np.full(th.shape, np.nan) for _ in range(3)]
    for pick, case in ((case_a, _case_a), (~case_a & ~beyond, _case_b)):
        for o, v in zip(out, case(eta[pick], nn[pick], s0[pick], lam[pick])):
            o[pick] = v
    return out[0], out[1], out[2]


def _case_a(
    eta: FloatArray, n: FloatArray, s0: FloatArray, lam: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(a, b, alpha) of case A (lambda <= eta, eqs 8, 9 with eta^(5/2))."""
    t = np.sqrt((eta + lam) / (2.0 * eta))
    g1, g2 = _asin_sqrt((eta - n) / (eta + lam)), _asin_sqrt((eta + s0) / (eta + lam))
    dF = _F(g2, t) - _F(g1, t)
    alpha = dF / np.sqrt(eta)
    bracket = dF + 2.0 * (_E(g1, t) - _E(g2, t))
    root = np.sqrt(2.0 * eta * (eta + lam)) * (np.cos(g1) - np.cos(g2))
    den = alpha * eta**2.5
    return (-n * eta * bracket + root) / den, (eta * bracket + n * root) / den, alpha


def _case_b(
    eta: FloatArray, n: FloatArray, s0: FloatArray, lam: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(a, b, alpha) of case B (lambda > eta, eqs 10, 11)."""
    r = np.sqrt(2.0 * eta / (eta + lam))
    p1, p2 = _asin_sqrt((eta - n) / (2.0 * eta)), _asin_sqrt((eta + s0) / (2.0 * eta))
    dF = _F(p2, r) - _F(p1, r)
    alpha = np.sqrt(2.0 / (lam + eta)) * dF
    bracket = lam / (eta + lam) * dF + _E(p1, r) - _E(p2, r)
    roots = np.sqrt(1.0 - (eta - n) / (eta + lam)) - np.sqrt(1.0 - (eta + s0) / (eta + lam))
    pre = np.sqrt(2.0 * (eta + lam)) / (alpha * eta**2)
    return pre * (-n * bracket + roots), pre * (bracket + n * roots), alpha


def fixed_guided_inflection_arrays(
    theta0: Values, n: Values, kappa: Values
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(a, b, alpha) of ``elastica.elliptic.fixed_guided_inflection_from_angle`` (the corrected
    Kimball-Tsai form) on arrays; NaN where its domain is left."""
    eta = np.hypot(1.0, n)
    s = np.sin(theta0) - n * np.cos(theta0)
    lam = kappa + s
    k = np.sqrt((eta + lam) / (2.0 * eta))
    g1 = _asin_sqrt(2.0 * eta * (lam + n) / ((lam + eta) * (eta + n)))
    g2 = _asin_sqrt(2.0 * eta * kappa / ((lam + eta) * (eta - s)))
    F12 = _F(g1, k) + _F(g2, k)
    E12 = _E(g1, k) + _E(g2, k)
    alpha = F12 / np.sqrt(eta)
    q1 = np.sqrt((eta - n) / (eta + n))
    q2 = np.sqrt((eta + s) / (eta - s))
    sl, sk, s2 = np.sqrt(lam + n), np.sqrt(kappa), np.sqrt(2.0 * eta)
    den = alpha * eta**2.5
    b = (eta * F12 - 2.0 * eta * E12 + s2 * (sl * (q1 + n) + sk * (q2 + n))) / den
    a = (-n * eta * F12 + 2.0 * n * eta * E12 + s2 * (-sl * (n * q1 - 1.0) - sk * (n * q2 - 1.0))) / den
    valid = (lam + n >= 0.0) & (eta - s > 0.0) & (lam + eta > 0.0) & (k < 1.0) & ~np.isnan(g1) & ~np.isnan(g2)
    return np.where(valid, a, np.nan), np.where(valid, b, np.nan), np.where(valid, alpha, np.nan)


def fixed_pinned_cloud(n_values: ArrayLike, theta0_values: ArrayLike) -> DomainCloud:
    """Section 4.4: eqs (6), (7) at every (n, theta0) with 0 < theta0 < phi(n)."""
    n, th = _grid(n_values, theta0_values)
    with np.errstate(invalid="ignore", divide="ignore"):
        a, b, alpha = fixed_pinned_arrays(th, n)
        keep = (th > 0.0) & (th < _phi(n)) & np.isfinite(a + b + alpha)
    return _cloud(keep, (a, b, th, alpha, n, 0.0), {"theta0 outside (0, phi)": int(keep.size - keep.sum())})


def curved_fixed_pinned_cloud(n_values: ArrayLike, theta0_values: ArrayLike, kappa_values: ArrayLike) -> DomainCloud:
    """Section 4.5: eqs (8)-(11) at every (n, theta0, kappa = M^2/(2 P EI)) within Su's bound (112)."""
    n, kappa, th = _grid(n_values, kappa_values, theta0_values)
    with np.errstate(invalid="ignore", divide="ignore"):
        within = th <= su_theta0_max(n, kappa / np.hypot(1.0, n))
        a, b, alpha = curved_fixed_pinned_arrays(th, n, kappa)
        valid = np.isfinite(a + b + alpha) & (alpha > 0.0)
    keep = within & valid
    return _cloud(
        keep,
        (a, b, th, alpha, n, kappa),
        {
            "beyond Su's theta0max (eq 112)": int((~within).sum()),
            "outside the elliptic form's range": int((within & ~valid).sum()),
        },
    )


def fixed_guided_inflection_cloud(
    n_values: ArrayLike,
    theta0_values: ArrayLike,
    kappa_values: ArrayLike,
    load_range: tuple[float, float] = (0.0, np.inf),
    first_quadrant: bool = True,
) -> DomainCloud:
    """Section 4.6, one inflection point: the Kimball-Tsai form at every (n, theta0, kappa), kept when
    alpha^2 = P l^2/EI lies in ``load_range`` (and, by default, the end in the first quadrant, as the
    routine of section 4.6.1)."""
    n, kappa, th = _grid(n_values, kappa_values, theta0_values)
    lo, hi = load_range
    with np.errstate(invalid="ignore", divide="ignore"):
        a, b, alpha = fixed_guided_inflection_arrays(th, n, kappa)
        valid = np.isfinite(a + b + alpha) & (alpha > 0.0)
        inside = (lo <= alpha**2) & (alpha**2 <= hi) & np.logical_or(not first_quadrant, (a >= 0.0) & (b >= 0.0))
    keep = valid & inside
    return _cloud(
        keep,
        (a, b, th, alpha, n, kappa),
        {
            "outside the elliptic form's range": int((~valid).sum()),
            "load or end outside the range asked": int((valid & ~inside).sum()),
        },
    )


def kappa_min(theta0: ArrayLike, load_ratio: ArrayLike, theta_i: ArrayLike) -> FloatArray:
    """Eq (123): kappa_min = cos(theta_i - phi) - cos(theta0 - phi), with kappa = M^2/(2 F EI)."""
    phi = _phi(load_ratio)
    return np.cos(np.asarray(theta_i, float) - phi) - np.cos(np.asarray(theta0, float) - phi)


def kappa_range(
    theta0: float, load_ratio: float, step: float = math.radians(5.0), theta_i_max: float = math.radians(85.0)
) -> tuple[float, float]:
    """The routine of section 4.6.1 (Fig. 4.16 is missing; as the text states it): for theta0 >= 0,
    kappa_min with theta_i = theta0 + step (eq 124), for theta0 < 0 with theta_i = step; kappa_max with
    theta_i = theta_i_max; both by eq (123)."""
    theta_i = theta0 + step if theta0 >= 0.0 else step
    return float(kappa_min(theta0, load_ratio, theta_i)), float(kappa_min(theta0, load_ratio, theta_i_max))
