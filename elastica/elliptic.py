"""Closed-form elliptic-integral solutions of [bapat2015, §2.1], with the dissertation's misprints corrected.

Every function is normalised: the flexible length l = 1 and EI = 1, so the load index is
alpha = sqrt(P l^2 / EI), positions are a/l and b/l, and moments are M l / EI. Angles are in rad.

Conventions ([bapat2015], checked against the shooting solver in ``elastica.shooting``): the clamp
is at the origin with the undeformed tangent along +x; the end force is (Fx, Fy) = (-nP, +P),
so n > 0 is compressive; theta_0 is the end slope, CCW positive. phi = atan2(1, -n) is the
direction of the end force. All segment types integrate

    EI theta'' = -P (cos(theta) + n sin(theta)),   first integral  theta'^2 = 2P [lambda - (sin(theta) - n cos(theta))],

with lambda = kappa + sin(theta_0) - n cos(theta_0) and kappa = theta'(l)^2 / (2P) = kappa_0^2 / (2 alpha^2).

F(g, t), E(g, t) are the incomplete elliptic integrals with *modulus* t (scipy takes m = t^2);
the dissertation prints the complete integrals without the sin^2 in the integrand (a misprint).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from typing import NamedTuple, ParamSpec, TypeVar

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipeinc, ellipkinc
from argcheck import checked

__all__ = [
    "EllipticTip",
    "pure_moment_tip",
    "cantilever_tip_load",
    "fixed_pinned_from_angle",
    "fixed_pinned_tip",
    "curved_fixed_pinned_from_angle",
    "curved_fixed_pinned_tip",
    "fixed_guided_inflection_from_angle",
    "fixed_guided_inflection_tips",
    "fixed_guided_monotonic_tip",
    "slfp_tip",
]


class EllipticTip(NamedTuple):
    """End of a segment (normalised by l and EI): position a, b; slope theta0 (rad); alpha = sqrt(Pl^2/EI).

    It answers the result protocol the libraries share (converged, status, message, iterations,
    wall_time): a closed form converges when its position is a real number; ``iterations`` is 0 (the
    bracketing root finds on theta0 are not counted) and ``wall_time`` is the public call's time."""

    a: float
    b: float
    theta0: float
    alpha: float
    kappa: float = 0.0
    wall_time: float = 0.0

    @property
    def converged(self) -> bool:
        return math.isfinite(self.a) and math.isfinite(self.b)

    @property
    def status(self) -> str:
        return "ok" if self.converged else "not converged"

    @property
    def message(self) -> str:
        return (
            "closed form (elliptic integrals)"
            if self.converged
            else "no real solution of the elliptic equations at these arguments"
        )

    @property
    def iterations(self) -> int:
        return 0


_P = ParamSpec("_P")
_Tips = TypeVar("_Tips", EllipticTip, list[EllipticTip])


def _timed(function: Callable[_P, _Tips]) -> Callable[_P, _Tips]:
    """Record the call's wall time on the EllipticTip (or each of a list) it returns."""

    @functools.wraps(function)
    def timed(*args: _P.args, **kwargs: _P.kwargs) -> _Tips:
        start = time.perf_counter()
        result = function(*args, **kwargs)
        elapsed = time.perf_counter() - start
        if isinstance(result, EllipticTip):
            return result._replace(wall_time=elapsed)
        return [tip._replace(wall_time=elapsed) for tip in result]

    return timed


def _F(g: float, t: float) -> np.float64:
    """F(g, t), the incomplete elliptic integral of the first kind with modulus t: a NumPy scalar, so
    the formulas built on it give inf or nan outside their domain instead of raising."""
    value: np.float64 = ellipkinc(g, t * t)
    return value


def _E(g: float, t: float) -> np.float64:
    """E(g, t), the incomplete elliptic integral of the second kind with modulus t (a NumPy scalar)."""
    value: np.float64 = ellipeinc(g, t * t)
    return value


def _phi(n: float) -> float:
    return math.atan2(1.0, -n)


def _asin_sqrt(x: float) -> float:
    if x < 0.0 or x > 1.0 + 1e-14:
        return math.nan
    return math.asin(math.sqrt(min(x, 1.0)))


@_timed
def pure_moment_tip(moment: float) -> EllipticTip:
    """Closed form for a straight cantilever under an end moment m = M l / EI (a circular arc).

    a = sin(m)/m, b = (1 - cos m)/m, theta_0 = m; m = 2 pi closes the full circle (a = b = 0).
    Source: notes/anchors.md section 2.2; [ananthasuresh_l18, 16:59-21:58].
    """
    m = moment
    if abs(m) < 1e-8:
        return EllipticTip(1.0 - m * m / 6.0, m / 2.0, m, 0.0)
    return EllipticTip(math.sin(m) / m, (1.0 - math.cos(m)) / m, m, 0.0)


# ---------------------------------------------------------------------------- section 2.1.1/2.1.2


def fixed_pinned_from_angle(theta0: float, load_ratio: float = 0.0) -> EllipticTip:
    """Initially straight fixed-pinned segment under P and nP, given theta_0 (explicit).

    [bapat2015, eqs 6, 7] (Howell), for 0 < theta_0 < phi:
        alpha = [F(t) - F(g, t)] / sqrt(eta),  t = sqrt((eta + lambda) / (2 eta)),
        b/l = {eta [F(t) - F(g,t) + 2(E(g,t) - E(t))] + n sqrt(2 eta (eta + lambda)) cos g} / (alpha eta^(5/2)),
        a/l = {-n eta [F(t) - F(g,t) + 2(E(g,t) - E(t))] + sqrt(2 eta (eta + lambda)) cos g} / (alpha eta^(5/2)),
    with lambda = sin theta_0 - n cos theta_0, eta = sqrt(1 + n^2).
    Correction (notes/seed-ch2-4.md section 2.2 and section 7 item 2): g = asin sqrt((eta - n)/(eta + lambda));
    the dissertation prints (eta + n), whose argument exceeds 1 for n > 0.
    For n = 0 this is section 2.1.1 (Bisshopp-Drucker), [bapat2015, eqs 4, 5]; eq (5) as printed gives
    the shortening 1 - a/l, not a/l (notes section 2.1): a/l = sqrt(2 sin theta_0)/alpha.
    """
    n = load_ratio
    eta = math.hypot(1.0, n)
    lam = math.sin(theta0) - n * math.cos(theta0)
    t = math.sqrt((eta + lam) / (2.0 * eta))
    g = _asin_sqrt((eta - n) / (eta + lam))
    Kt, Et = _F(math.pi / 2, t), _E(math.pi / 2, t)
    Fg, Eg = _F(g, t), _E(g, t)
    alpha = (Kt - Fg) / math.sqrt(eta)
    bracket = Kt - Fg + 2.0 * (Eg - Et)
    root = math.sqrt(2.0 * eta * (eta + lam)) * math.cos(g)
    den = alpha * eta**2.5
    return EllipticTip((-n * eta * bracket + root) / den, (eta * bracket + n * root) / den, theta0, alpha)


@_timed
@checked(positive=(), finite=("load",))
def cantilever_tip_load(load: float) -> EllipticTip:
    """Section 2.1.1: straight cantilever, transverse end load P (load = P l^2/EI > 0), n = 0.

    The dissertation omits the theta_0 equation; it is alpha = F(t) - F(g, t) (eq (6) with n = 0), solved here.
    """
    return fixed_pinned_tip(load, 0.0)


@_timed
@checked(positive=(), finite=("load", "load_ratio"))
def fixed_pinned_tip(load: float, load_ratio: float = 0.0) -> EllipticTip:
    """Section 2.1.2 with P (load = P l^2/EI) and n given: root-find theta_0 in (0, phi).

    A zero load gives the undeformed tip (1, 0, 0); a negative load the mirror image (about the
    axis) of the positive one: force (-nP, P) with P < 0 is the mirror of |P| with ratio -n."""
    if load == 0.0:
        return EllipticTip(1.0, 0.0, 0.0, 0.0)
    if load < 0.0:
        mirror = fixed_pinned_tip(-load, -load_ratio)
        return mirror._replace(b=-mirror.b, theta0=-mirror.theta0)
    n = load_ratio
    target = math.sqrt(load)
    phi = _phi(n)
    lo, hi = 1e-12, phi - 1e-9

    def f(th: float) -> float:
        return fixed_pinned_from_angle(th, n).alpha - target

    # alpha grows without bound as theta_0 -> phi; bracket on a geometric approach to phi
    with np.errstate(invalid="ignore", divide="ignore"):
        while f(hi) < 0.0:
            hi = phi - (phi - hi) * 1e-3
        th = float(brentq(f, lo, hi, xtol=1e-15, rtol=1e-15, maxiter=200))
    return fixed_pinned_from_angle(th, n)


# ---------------------------------------------------------------------------- section 2.1.3


def curved_fixed_pinned_from_angle(theta0: float, load_ratio: float, kappa: float) -> EllipticTip:
    """Initially curved fixed-pinned segment (Howell), given n, theta_0 (absolute) and kappa.

    kappa = kappa_0^2 / (2 alpha^2), kappa_0 = l/R_i (or the end curvature M l/EI + l/R_i).
    Case A, 0 < |lambda| < eta, [bapat2015, eqs 8, 9], alpha = [F(g2,t) - F(g1,t)]/sqrt(eta):
        g1 = asin sqrt((eta - n)/(eta + lambda)), g2 = asin sqrt((eta + sin th0 - n cos th0)/(eta + lambda)),
        t = sqrt((eta + lambda)/(2 eta)).
    Correction (notes/seed-ch2-4.md section 2.3, section 7 item 3): eq (9) needs eta^(5/2), not eta^2.
    Case B, lambda > eta, [bapat2015, eqs 10, 11] as printed (eta^2), with r = sqrt(2 eta/(eta + lambda)),
        psi_i = asin sqrt(.../(2 eta)), alpha = sqrt(2/(lambda + eta)) [F(psi2, r) - F(psi1, r)];
    valid for theta_0 <= 90 deg + atan(n) (principal branch of asin), nan beyond.
    """
    n = load_ratio
    eta = math.hypot(1.0, n)
    s0 = math.sin(theta0) - n * math.cos(theta0)
    lam = kappa + s0
    if lam <= eta:  # case A
        t = math.sqrt((eta + lam) / (2.0 * eta))
        g1 = _asin_sqrt((eta - n) / (eta + lam))
        g2 = _asin_sqrt((eta + s0) / (eta + lam))
        dF = _F(g2, t) - _F(g1, t)
        alpha = dF / math.sqrt(eta)
        bracket = dF + 2.0 * (_E(g1, t) - _E(g2, t))
        root = math.sqrt(2.0 * eta * (eta + lam)) * (math.cos(g1) - math.cos(g2))
        den = alpha * eta**2.5
        return EllipticTip((-n * eta * bracket + root) / den, (eta * bracket + n * root) / den, theta0, alpha, kappa)
    if theta0 > math.pi / 2 + math.atan(n):
        return EllipticTip(math.nan, math.nan, theta0, math.nan, kappa)
    r = math.sqrt(2.0 * eta / (eta + lam))  # case B
    p1 = _asin_sqrt((eta - n) / (2.0 * eta))
    p2 = _asin_sqrt((eta + s0) / (2.0 * eta))
    dF = _F(p2, r) - _F(p1, r)
    alpha = math.sqrt(2.0 / (lam + eta)) * dF
    bracket = lam / (eta + lam) * dF + _E(p1, r) - _E(p2, r)
    roots = math.sqrt(1.0 - (eta - n) / (eta + lam)) - math.sqrt(1.0 - (eta + s0) / (eta + lam))
    pre = math.sqrt(2.0 * (eta + lam)) / (alpha * eta**2)
    return EllipticTip(pre * (-n * bracket + roots), pre * (bracket + n * roots), theta0, alpha, kappa)


def _solve_theta0(residual: Callable[[float], float], lo: float, hi: float, samples: int = 400) -> list[float]:
    """All roots of ``residual(theta0)`` on [lo, hi] by sampling and Brent; nan samples are skipped."""
    grid = np.linspace(lo, hi, samples)
    with np.errstate(invalid="ignore", divide="ignore"):
        vals = np.array([residual(t) for t in grid])
    roots: list[float] = []
    for i in range(samples - 1):
        v0, v1 = vals[i], vals[i + 1]
        if np.isfinite(v0) and np.isfinite(v1) and v0 * v1 <= 0.0 and v0 != v1:
            with np.errstate(invalid="ignore", divide="ignore"):
                roots.append(float(brentq(residual, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15)))
    return roots


@_timed
def curved_fixed_pinned_tip(load: float, load_ratio: float, kappa0: float) -> EllipticTip:
    """Section 2.1.3 with P (load = P l^2/EI), n and end curvature kappa0 = l/R_i given.

    kappa = kappa0^2/(2 load) is fixed, so theta_0 follows from alpha(theta_0) = sqrt(load).
    Of several roots the one nearest the unloaded tip angle kappa0 is returned.
    """
    n, kappa, target = load_ratio, kappa0**2 / (2.0 * load), math.sqrt(load)

    def res(th: float) -> float:
        return curved_fixed_pinned_from_angle(th, n, kappa).alpha - target

    roots = _solve_theta0(res, 1e-9, 2.0 * math.pi - 1e-9, samples=800)  # nan outside the valid cases
    if not roots:
        raise ValueError("no theta_0 solves the curved fixed-pinned equations for these loads")
    return curved_fixed_pinned_from_angle(min(roots, key=lambda r: abs(r - kappa0)), n, kappa)


# ---------------------------------------------------------------------------- section 2.1.4


def fixed_guided_inflection_from_angle(theta0: float, load_ratio: float, kappa: float) -> EllipticTip:
    """Straight fixed-fixed segment with one inflection point (Kimball & Tsai), given n, theta_0, kappa.

    kappa = M^2 / (2 P EI) with M the end moment *opposing* P (clockwise for P > 0).
    [bapat2015, eqs 15, 16] are garbled as printed; this is the corrected form of
    notes/seed-ch2-4.md section 2.4 (and section 7 item 4), with s = sin th0 - n cos th0, lambda = kappa + s:
        alpha = [F(g1,k) + F(g2,k)] / sqrt(eta)            (printed: sqrt(2/eta))
        g1 = asin sqrt(2 eta (lambda + n) / ((lambda + eta)(eta + n)))   (printed: lambda + eta in the numerator)
        g2 = asin sqrt(2 eta kappa / ((lambda + eta)(eta - s))),   k = sqrt((eta + lambda)/(2 eta))
        b/l = {eta(F1+F2) - 2 eta(E1+E2) + sqrt(2 eta)[sqrt(lambda+n)(sqrt((eta-n)/(eta+n)) + n)
               + sqrt(kappa)(sqrt((eta+s)/(eta-s)) + n)]} / (alpha eta^(5/2))   (printed: -n, lambda+eta)
        a/l = {-n eta(F1+F2) + 2 n eta(E1+E2) + sqrt(2 eta)[-sqrt(lambda+n)(n sqrt((eta-n)/(eta+n)) - 1)
               - sqrt(kappa)(n sqrt((eta+s)/(eta-s)) - 1)]} / (alpha eta^(5/2)).
    Returns nan where the formula's domain (lambda + n >= 0, eta - s > 0, arguments <= 1) is left.
    """
    n = load_ratio
    eta = math.hypot(1.0, n)
    s = math.sin(theta0) - n * math.cos(theta0)
    lam = kappa + s
    nan = EllipticTip(math.nan, math.nan, theta0, math.nan, kappa)
    if lam + n < 0.0 or eta - s <= 0.0 or lam + eta <= 0.0:
        return nan
    k = math.sqrt((eta + lam) / (2.0 * eta))
    if k >= 1.0:
        return nan
    g1 = _asin_sqrt(2.0 * eta * (lam + n) / ((lam + eta) * (eta + n)))
    g2 = _asin_sqrt(2.0 * eta * kappa / ((lam + eta) * (eta - s)))
    if math.isnan(g1) or math.isnan(g2):
        return nan
    F12 = _F(g1, k) + _F(g2, k)
    E12 = _E(g1, k) + _E(g2, k)
    alpha = F12 / math.sqrt(eta)
    q1 = math.sqrt((eta - n) / (eta + n))
    q2 = math.sqrt((eta + s) / (eta - s))
    sl, sk, s2 = math.sqrt(lam + n), math.sqrt(kappa), math.sqrt(2.0 * eta)
    den = alpha * eta**2.5
    b = (eta * F12 - 2.0 * eta * E12 + s2 * (sl * (q1 + n) + sk * (q2 + n))) / den
    a = (-n * eta * F12 + 2.0 * n * eta * E12 + s2 * (-sl * (n * q1 - 1.0) - sk * (n * q2 - 1.0))) / den
    return EllipticTip(a, b, theta0, alpha, kappa)


@_timed
def fixed_guided_inflection_tips(load: float, load_ratio: float, opposing_moment: float) -> list[EllipticTip]:
    """Section 2.1.4 with loads given: P (load = P l^2/EI > 0), n and the opposing moment M l/EI > 0.

    kappa = M^2/(2P) is fixed; theta_0 solves alpha(theta_0) = sqrt(load). Several roots are
    possible (the dissertation notes that the load-specified form needs estimates); all are returned,
    sorted by |theta_0|. The formula sees theta_0 only through s = sin th0 - n cos th0, so every
    (a, b) comes twice, with the two theta_0 of equal s; the one nearer 0 is the branch connected
    to the unloaded beam in every case checked against ``elastica.shooting`` (tests).
    """
    n = load_ratio
    kappa = opposing_moment**2 / (2.0 * load)
    target = math.sqrt(load)

    def res(th: float) -> float:
        return fixed_guided_inflection_from_angle(th, n, kappa).alpha - target

    roots = _solve_theta0(res, -math.pi + 1e-6, math.pi - 1e-6, samples=1200)
    return [fixed_guided_inflection_from_angle(r, n, kappa) for r in sorted(roots, key=abs)]


@_timed
def fixed_guided_monotonic_tip(
    load: float, load_ratio: float, moment: float, initial_curvature: float = 0.0
) -> EllipticTip:
    """Section 2.1.4/2.1.5, monotonic curvature (no inflection): the curved fixed-pinned form.

    [bapat2015, eqs 14, 17]: kappa0 = M l/EI + l/R_i, with M the end moment in the same sense as the
    curvature (CCW for P > 0; Table 2.1: P and M of the same sign give no inflection point).
    """
    return curved_fixed_pinned_tip(load, load_ratio, moment + initial_curvature)


# ---------------------------------------------------------------------------- sections 2.1.6/2.1.7


@_timed
def slfp_tip(load: float, load_ratio: float, rigid_length: float, initial_curvature: float = 0.0) -> EllipticTip:
    """Small-length flexural pivot (flexible l = 1) carrying a rigid segment L = ``rigid_length`` (in l).

    [bapat2015, eqs 18-25] (Midha & Kuber): the flexible part is the curved fixed-pinned segment of
    section 2.1.3 with end curvature kappa0 = M l/EI + l/R_i, where the moment at the pivot end is
    M = F L sin(phi - theta_0), F = eta P; the end of the rigid segment is then
    (a + L cos theta_0, b + L sin theta_0). Correction (notes/seed-ch2-4.md section 2.6, section 7
    item 5): the lever is the rigid length L (printed as l in section 2.1.6); eq (19) uses eta^(5/2).
    ``load`` = P l^2/EI with l the flexible length; returns the end of the rigid segment (in l).
    """
    n, Lr, target = load_ratio, rigid_length, math.sqrt(load)
    eta, phi = math.hypot(1.0, n), _phi(load_ratio)

    def kappa_of(th: float) -> float:
        k0 = eta * load * Lr * math.sin(phi - th) + initial_curvature
        return k0 * k0 / (2.0 * load)

    def res(th: float) -> float:
        return curved_fixed_pinned_from_angle(th, n, kappa_of(th)).alpha - target

    roots = _solve_theta0(res, 1e-9, min(phi, math.pi / 2 + math.atan(n)) - 1e-9)
    if not roots:
        raise ValueError("no theta_0 solves the SLFP equations for these loads")
    th = roots[0]
    tip = curved_fixed_pinned_from_angle(th, n, kappa_of(th))
    return EllipticTip(tip.a + Lr * math.cos(th), tip.b + Lr * math.sin(th), th, tip.alpha, tip.kappa)
