"""Exact characteristic deflection domains (seed 000 chapter 4): clouds of end positions of a
segment from the closed-form elliptic solutions, over the load grids the chapter prints.

Normalised as ``elastica.elliptic`` (l = EI = 1, so alpha^2 = P l^2/EI, positions a/l, b/l).

* ``fixed_pinned_cloud`` (section 4.4): initially straight fixed-pinned segment under P and nP,
  eqs (6), (7) with the corrected gamma, over n and theta0 (0 < theta0 < phi); the seed's grid is
  n = -4..10, theta0 = 1..90 deg.
* ``curved_fixed_pinned_cloud`` (section 4.5, and section 4.6's fixed-fixed segment with monotonic
  curvature, kappa0 = M l/EI (+ l/R_i), eqs 115, 119): eqs (8)-(11) over n, theta0 and kappa =
  M^2/(2 P EI) (eq 121; kappa0 = alpha sqrt(2 kappa)), limited by Su's maximum end angle (eq 112)

      theta0max = phi + acos(1 - kappa_F)  (kappa_F <= 2),  infinite for kappa_F > 2.

  Eq (112) is the condition that the curvature stays real along the beam: the first integral
  theta'^2 = 2P [lambda - (sin theta - n cos theta)] with sin theta - n cos theta = eta cos(theta - phi)
  must stay >= 0 for theta in [0, theta0], i.e. kappa/eta + cos(theta0 - phi) - 1 >= 0 when phi lies
  inside; so kappa in (112) is normalised by the resultant force F = eta P: kappa_F = M^2/(2 F EI)
  = kappa/eta (notes seed-ch2-4 section 6.5; the seed prints M^2/(2 P EI), which overstates theta0max
  for n != 0).  ``su_theta0_max`` takes kappa_F.
* ``fixed_guided_inflection_cloud`` (section 4.6, Figs 4.9-4.12): the straight fixed-fixed segment
  with one inflection point under P, nP and an opposing end moment M, by the Kimball-Tsai elliptic
  form (``fixed_guided_inflection_from_angle``) over n, theta0 and kappa in the range of eq (126),
  keeping the points whose load lies in the seed's P range.  The seed drew this cloud with Midha et
  al.'s PRBM (its Fig. 4.12); this is the exact one.
* ``kappa_min`` (eqs 123, 124) and ``kappa_range`` (the routine of section 4.6.1 / Fig. 4.16: theta0
  > 0: kappa_min with theta_i = theta0 + 5 deg, kappa_max with theta_i = 85 deg; theta0 < 0: kappa_min
  with theta_i = 5 deg), with phi = atan2(1, -n), and kappa normalised by F as in (120).

Each cloud function returns a ``DomainCloud``: the points (a, b, theta0, alpha, n, kappa), plus the
count of grid points left out and why (``excluded``: outside the formula's or Su's range).

Angles are in radians (degrees appear only in case files and reports).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from elastica.elliptic import (curved_fixed_pinned_from_angle, fixed_guided_inflection_from_angle,
                               fixed_pinned_from_angle)

__all__ = ["DomainCloud", "su_theta0_max", "fixed_pinned_cloud", "curved_fixed_pinned_cloud",
           "fixed_guided_inflection_cloud", "kappa_min", "kappa_range"]


@dataclass(frozen=True)
class DomainCloud:
    """End points of a segment type over a load grid (normalised by l and EI; angles in rad)."""

    a: np.ndarray
    b: np.ndarray
    theta0: np.ndarray
    alpha: np.ndarray
    n: np.ndarray
    kappa: np.ndarray
    excluded: dict[str, int] = field(default_factory=dict)

    @property
    def size(self) -> int:
        return int(self.a.size)


def _phi(n):
    return np.arctan2(1.0, -np.asarray(n, float))


def su_theta0_max(load_ratio, kappa_force):
    """Eq (112): the largest end angle (rad) of a curved fixed-pinned segment with monotonic curvature;
    kappa_force = M^2/(2 F EI), F = sqrt(1 + n^2) P (see the module docstring); inf for kappa_F > 2."""
    k = np.asarray(kappa_force, float)
    with np.errstate(invalid="ignore"):
        bound = _phi(load_ratio) + np.arccos(np.clip(1.0 - k, -1.0, 1.0))
    return np.where(k > 2.0, np.inf, bound)


def _cloud(rows: list[tuple], excluded: dict[str, int]) -> DomainCloud:
    data = np.array(rows, float).reshape(-1, 6)
    return DomainCloud(*(data[:, i] for i in range(6)), excluded=excluded)


def fixed_pinned_cloud(n_values, theta0_values) -> DomainCloud:
    """Section 4.4: eqs (6), (7) at every (n, theta0) with 0 < theta0 < phi(n)."""
    rows, outside = [], 0
    for n in np.atleast_1d(np.asarray(n_values, float)):
        phi = float(_phi(n))
        for th in np.atleast_1d(np.asarray(theta0_values, float)):
            if not 0.0 < th < phi:
                outside += 1
                continue
            tip = fixed_pinned_from_angle(float(th), float(n))
            if not np.isfinite(tip.a + tip.b + tip.alpha):
                outside += 1
                continue
            rows.append((tip.a, tip.b, th, tip.alpha, n, 0.0))
    return _cloud(rows, {"theta0 outside (0, phi)": outside})


def curved_fixed_pinned_cloud(n_values, theta0_values, kappa_values) -> DomainCloud:
    """Section 4.5: eqs (8)-(11) at every (n, theta0, kappa = M^2/(2 P EI)) within Su's bound (112)."""
    rows, beyond_su, invalid = [], 0, 0
    for n in np.atleast_1d(np.asarray(n_values, float)):
        eta = math.hypot(1.0, n)
        for kappa in np.atleast_1d(np.asarray(kappa_values, float)):
            limit = float(su_theta0_max(n, kappa / eta))
            for th in np.atleast_1d(np.asarray(theta0_values, float)):
                if th > limit:
                    beyond_su += 1
                    continue
                tip = curved_fixed_pinned_from_angle(float(th), float(n), float(kappa))
                if not (np.isfinite(tip.a + tip.b + tip.alpha) and tip.alpha > 0.0):
                    invalid += 1
                    continue
                rows.append((tip.a, tip.b, th, tip.alpha, n, kappa))
    return _cloud(rows, {"beyond Su's theta0max (eq 112)": beyond_su,
                         "outside the elliptic form's range": invalid})


def fixed_guided_inflection_cloud(n_values, theta0_values, kappa_values, load_range=(0.0, np.inf),
                                  first_quadrant: bool = True) -> DomainCloud:
    """Section 4.6, one inflection point: the Kimball-Tsai form at every (n, theta0, kappa), kept when
    alpha^2 = P l^2/EI lies in ``load_range`` (and, by default, the end in the first quadrant, as the
    routine of section 4.6.1)."""
    rows, invalid, out_of_range = [], 0, 0
    lo, hi = load_range
    for n in np.atleast_1d(np.asarray(n_values, float)):
        for kappa in np.atleast_1d(np.asarray(kappa_values, float)):
            for th in np.atleast_1d(np.asarray(theta0_values, float)):
                tip = fixed_guided_inflection_from_angle(float(th), float(n), float(kappa))
                if not (np.isfinite(tip.a + tip.b + tip.alpha) and tip.alpha > 0.0):
                    invalid += 1
                    continue
                if not lo <= tip.alpha**2 <= hi or (first_quadrant and (tip.a < 0.0 or tip.b < 0.0)):
                    out_of_range += 1
                    continue
                rows.append((tip.a, tip.b, th, tip.alpha, n, kappa))
    return _cloud(rows, {"outside the elliptic form's range": invalid,
                         "load or end outside the range asked": out_of_range})


def kappa_min(theta0, load_ratio, theta_i):
    """Eq (123): kappa_min = cos(theta_i - phi) - cos(theta0 - phi), with kappa = M^2/(2 F EI)."""
    phi = _phi(load_ratio)
    return np.cos(np.asarray(theta_i, float) - phi) - np.cos(np.asarray(theta0, float) - phi)


def kappa_range(theta0: float, load_ratio: float, step: float = math.radians(5.0),
                theta_i_max: float = math.radians(85.0)) -> tuple[float, float]:
    """The routine of section 4.6.1 (Fig. 4.16 is missing; as the text states it): for theta0 >= 0,
    kappa_min with theta_i = theta0 + step (eq 124), for theta0 < 0 with theta_i = step; kappa_max with
    theta_i = theta_i_max; both by eq (123)."""
    theta_i = theta0 + step if theta0 >= 0.0 else step
    return float(kappa_min(theta0, load_ratio, theta_i)), float(kappa_min(theta0, load_ratio, theta_i_max))
