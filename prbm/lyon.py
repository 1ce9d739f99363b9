"""Lyon et al.'s PRBM of a fixed-guided segment with one inflection point [bapat2015, §2.3.4, eqs 64-70].

The inflection point is taken as a pin: the beam is two fixed-pinned segments, A (clamp to pin, length
l_A) and B (guided end E back to the pin, length l_B), each a Pauly-Midha PRBM (eqs 41-43) with PRB
angle theta_A, theta_B and spring k = gamma K_Theta EI / l_seg (68), under the end force F at angle
phi (global; psi = phi - 90 deg is the force angle from the beam normal, the reading under which eq
(66) is the fixed-pinned torque balance F gamma l sin(phi - Theta) = k Theta):

    theta_E = theta_A + beta - theta_B,  beta = C_A theta_A - C_B theta_B                    (64), (65)
    F gamma_A l_A [cos psi cos theta_A + sin psi sin theta_A] = k_A theta_A                      (66)
    F gamma_B l_B [cos(psi - theta_E) cos theta_B + sin(psi - theta_E) sin theta_B] = k_B theta_B  (67*)
    theta_A / theta_B = gamma_B K_B l_A / (gamma_A K_A l_B)   (equal spring torques)             (69)
    l_A + l_B = l                                                                            (70)

What the dissertation leaves open (its Fig. 2.19 is missing), and the reading taken here:

* C_A, C_B are not defined.  C = c_theta - 1 (eq 42) makes (64)-(65) theta_E = c_A theta_A - c_B theta_B,
  the slope compatibility at the inflection point that chapter 3 writes as eq (101).
* (67) is printed with cos(psi + theta_E): with theta_E from (64) that is not the moment of the end force
  about pivot B for any one sign convention of theta_E and theta_B (flipping theta_E fixes (67) but
  breaks (64)).  (67*) uses psi - theta_E, the statics of the chain below (as chapter 3's eq 96,
  phi_2 = phi_1 - theta_0); a finding recorded with the case file.
* The kinematics are not printed; the chain of the two PRBMs is used, as chapter 3's (103)-(104):
  a = (1-g_A) l_A + g_A l_A cos th_A + g_B l_B cos(th_E + th_B) + (1-g_B) l_B cos th_E, b likewise.
* Segment B's load ratio n_B follows from its force angle phi_B = phi - theta_E (as eq 94).
* The model has the end force as its only load: the equal-torque condition (69) takes the place of
  moment equilibrium, so the end moment is an output, M = -(r_E - r_pin) x F (zero moment at the pin).

Unknowns l_A, theta_A, theta_B; equations (66), (67*), (69); solved by Powell's hybrid method from the
symmetric guided-beam start (l_A = l/2, theta_A = theta_B).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import root

from prbm.fits import PAULY_MIDHA, load_ratio
from prbm.result import PRBMResult


def _state(
    x: Sequence[float] | NDArray[np.float64], F: float, phi: float, length: float, EI: float
) -> tuple[list[float], dict[str, float]]:
    lA, tA, tB = x
    lB = length - lA
    gA, cA, KA = PAULY_MIDHA.parameters(load_ratio(phi), "allow")
    thE = cA * tA
    for _ in range(50):  # theta_E depends on c_B(n_B(theta_E)): fixed point (c_theta varies slowly)
        gB, cB, KB = PAULY_MIDHA.parameters(load_ratio(phi - thE), "allow")
        new = cA * tA - cB * tB  # (64), (65)
        if abs(new - thE) < 1e-15:
            break
        thE = new
    kA, kB = gA * KA * EI / lA, gB * KB * EI / lB  # (68)
    res = [
        F * gA * lA * math.sin(phi - tA) - kA * tA,  # (66)
        F * gB * lB * math.sin(phi - thE - tB) - kB * tB,  # (67*)
        (kA * tA - kB * tB) / (kA + kB),
    ]  # (69)
    return res, {
        "lA": lA,
        "lB": lB,
        "gA": gA,
        "gB": gB,
        "cA": cA,
        "cB": cB,
        "KA": KA,
        "KB": KB,
        "thA": tA,
        "thB": tB,
        "thE": thE,
        "nB": load_ratio(phi - thE),
    }


def _kinematics(s: Mapping[str, float]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pin and end positions of the PRBM chain (chapter 3's eqs 103-104 form)."""
    lA, lB, gA, gB, tA, tB, thE = s["lA"], s["lB"], s["gA"], s["gB"], s["thA"], s["thB"], s["thE"]
    pin = np.array([(1 - gA) * lA + gA * lA * math.cos(tA), gA * lA * math.sin(tA)])
    end = (
        pin
        + gB * lB * np.array([math.cos(thE + tB), math.sin(thE + tB)])
        + (1 - gB) * lB * np.array([math.cos(thE), math.sin(thE)])
    )
    return pin, end


def lyon_from_tip(*, b: float, theta0: float, length: float, EI: float) -> PRBMResult:
    """Lyon et al.'s two-condition problem: the end height b and end angle theta0 (rad) given, the end
    force (magnitude F, angle phi) and the configuration (l_A, theta_A, theta_B) follow from (64)-(70)
    and the kinematics; the end moment is an output.  Outputs a, b, theta0, P, nP (n > 0 compressive),
    M (CCW), l_A, theta_A, theta_B, n_B.  Raises FitRangeError when the solution's n or n_B lies outside
    the Pauly-Midha fits."""
    t0 = time.perf_counter()
    if not (length > 0 and EI > 0 and math.isfinite(b) and math.isfinite(theta0)):
        raise ValueError(f"lyon_from_tip: need length, EI > 0 and finite b, theta0; got {length}, {EI}, {b}, {theta0}")

    def residual(x: NDArray[np.float64]) -> list[float]:
        lA, tA, tB, f, phi = x
        res, s = _state((lA, tA, tB), f * EI / length**2, phi, length, EI)
        _, end = _kinematics(s)
        return [r / (EI / length) for r in res[:2]] + [res[2], s["thE"] - theta0, (end[1] - b) / length]

    best = None
    t_start = math.asin(min(0.95, abs(b) / length))
    starts = [
        (lA, phi0, scale)
        for lA in (0.5, 0.25, 0.75)
        for scale in (4.0, 16.0)
        for phi0 in (math.pi / 2, math.pi / 3, 2 * math.pi / 3)
    ]
    for lA, phi0, scale in starts:  # f = F l^2/EI ~ 4 K Theta (guided beam), or stiffer
        sol = root(residual, [lA * length, t_start, t_start, scale * 2.65 * t_start, phi0], method="hybr", tol=1e-13)
        sol.x[4] = sol.x[4] % (2 * math.pi)  # the force angle, modulo a turn
        ok = sol.success and 0 < sol.x[0] < length and sol.x[3] > 0 and 0 < sol.x[4] < math.pi
        if ok and max(map(abs, residual(sol.x))) < 1e-9:  # a force F > 0 with P = F sin(phi) > 0
            best = sol
            break
    if best is None:
        return PRBMResult(
            False,
            "no solution of eqs (64)-(70) with F > 0 and P > 0 found from the starts tried",
            {},
            {},
            "Lyon et al. fixed-guided PRBM, seed 000 eqs (64)-(70)",
            time.perf_counter() - t0,
        )
    lA, tA, tB, f, phi = best.x
    F = f * EI / length**2
    _, s = _state((lA, tA, tB), F, phi, length, EI)
    PAULY_MIDHA.parameters(load_ratio(phi))
    PAULY_MIDHA.parameters(s["nB"])
    pin, end = _kinematics(s)
    Fx, Fy = F * math.cos(phi), F * math.sin(phi)
    r = end - pin
    out = {
        "a": end[0],
        "b": end[1],
        "theta0": s["thE"],
        "P": Fy,
        "nP": -Fx,
        "M": -(r[0] * Fy - r[1] * Fx),
        "l_A": lA,
        "theta_A": tA,
        "theta_B": tB,
        "n_B": s["nB"],
    }
    return PRBMResult(
        True,
        "converged",
        {k: np.float64(v) for k, v in out.items()},
        {"gamma_A": s["gA"], "gamma_B": s["gB"], "c_A": s["cA"], "c_B": s["cB"], "K_A": s["KA"], "K_B": s["KB"]},
        "Lyon et al. fixed-guided PRBM, seed 000 eqs (64)-(70)",
        time.perf_counter() - t0,
        int(best.nfev),
        np.array([True]),
    )


def lyon_tip(Fx: float, Fy: float, *, length: float, EI: float) -> PRBMResult:
    """End position, end angle and end moment of the fixed-guided segment under the end force (Fx, Fy)
    alone (global frame, x along the undeformed beam, Fy > 0: mirror the problem otherwise).  Unknowns
    l_A, theta_A, theta_B from (66), (67*), (69), started from the symmetric shape.  Outputs a, b,
    theta0 (rad), M (CCW, the moment the model's end carries), l_A, theta_A, theta_B, n_B.  Raises
    FitRangeError when n or n_B lies outside the Pauly-Midha fits."""
    t0 = time.perf_counter()
    if not (length > 0 and EI > 0 and math.isfinite(Fx) and math.isfinite(Fy)):
        raise ValueError(f"lyon_tip: need length > 0, EI > 0, finite forces; got {length}, {EI}, {Fx}, {Fy}")
    if Fy <= 0.0:
        raise ValueError(f"lyon_tip: Fy must be > 0 (mirror the problem), got {Fy}")
    F, phi = math.hypot(Fx, Fy), math.atan2(Fy, Fx)
    PAULY_MIDHA.parameters(load_ratio(phi))  # raises FitRangeError for n outside the fits
    start = min(1.0, F * length**2 / (EI * 4 * 2.65))  # small-angle Theta of the guided beam, (F l^2/EI) = 4 K Theta
    sol = root(lambda x: _state(x, F, phi, length, EI)[0], [0.5 * length, start, start], method="hybr", tol=1e-13)
    residual, s = _state(sol.x, F, phi, length, EI)
    ok = bool(sol.success) and max(abs(r) for r in residual) < 1e-9 * max(1.0, F * length) and 0.0 < s["lA"] < length
    PAULY_MIDHA.parameters(s["nB"])
    pin, end = _kinematics(s)
    r = end - pin
    out = {
        "a": end[0],
        "b": end[1],
        "theta0": s["thE"],
        "M": -(r[0] * Fy - r[1] * Fx),
        "l_A": s["lA"],
        "theta_A": s["thA"],
        "theta_B": s["thB"],
        "n_B": s["nB"],
    }
    message = "converged" if ok else f"not converged: {sol.message} (l_A = {s['lA']:.4g})"
    return PRBMResult(
        ok,
        message,
        {k: np.float64(v) for k, v in out.items()},
        {"gamma_A": s["gA"], "gamma_B": s["gB"], "c_A": s["cA"], "c_B": s["cB"], "K_A": s["KA"], "K_B": s["KB"]},
        "Lyon et al. fixed-guided PRBM, seed 000 eqs (64)-(70)",
        time.perf_counter() - t0,
        int(sol.nfev),
        np.array([ok]),
    )
