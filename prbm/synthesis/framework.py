"""Chapter-5 synthesis framework: a fixed-guided beam with one inflection point carrying a rigid coupler.

Seed 000 (Bapat 2015) section 5.3, Fig. 5.9.  At precision position j (j = 2, 3, ...) the beam is the
three-pivot PRBM of chapter 3 (``prbm.synthesis.fixed_guided``) with R1j = (1 - g1j)/g1j R2j (158) and
R4j = (1 - g2j)/g2j R3j (159); the loop O -> E -> P1 -> Pj -> Ej -> O closes as

    R2j e^{i th1}[(1-g1j)/g1j + e^{i Th2j}] + R3j e^{i th1}[(1-g2j)/g2j e^{i gam_j} + e^{i Th3j}]
        + R5 e^{i th5}[e^{i gam_j} - 1] - R6 e^{i th1} = delta_j                       (160)
    R2j/g1j + R3j/g2j = R6                                                              (163)
    Th2j c1j = (Th3j - gam_j) c2j + gam_j                                               (164)

optionally with the energy (165) U_j = 1/2[g1j^2 K1j (EI/R2j) Th2j^2 + g2j^2 K2j (EI/R3j)(Th3j - gam_j)^2]
or the effecting force (166) (F_j R2j^2/(EI g1j^2)) sin(phi1j - Th2j) = K1j Th2j and
(167) (F_j R3j^2/(EI g2j^2)) sin(phi2j - Th3j + gam_j) = K2j (Th3j - gam_j).
Misprint followed: eqs (161)/(162) print cos/sin(Th3j + gam_j); the correct term, from (160), is
Th3j + th1 (../shared/notes/seed-ch5-9.md section 3.3; only (160) reproduces the printed examples).
The fits g, c, K are eqs (41)-(43) at n1j (a free choice) and n2j = -1/tan(phi2j), phi2j = phi1j - gam_j
(150), phi1j = atan2(1, -n1j).

Unknowns: every R2j, Th2j, R3j, Th3j not given as a free choice, R5, th5, R6, and EI when energies or
forces are specified.  The equations must be as many as the unknowns (design tables 5.1-5.3); the
system is solved by ``least_squares`` from a grid of starts and every valid root (R > 0, Th3j > gam_j
and load ratios n2j inside the fits' range) is returned, the first ``max_roots`` found.
"""
from __future__ import annotations

import cmath
import itertools
import math

import numpy as np
from scipy.optimize import least_squares

from prbm.synthesis.dyads import DEG, SynthesisError
from prbm.synthesis.fixed_guided import pauly_midha


def solve_framework(*, theta1: float, delta: list[complex], gamma: list[float], n1: list[float],
                    fixed: dict[str, float] | None = None, energy: list[float] | None = None,
                    force: list[float] | None = None, max_roots: int = 1) -> list[dict]:
    """Roots of the chapter-5 equations; angles in degrees in and out.  ``fixed`` names free choices
    'R2_j', 'Theta2_j', 'R3_j', 'Theta3_j' (j = 2, 3, ...)."""
    fixed = dict(fixed or {})
    npos = len(delta)
    js = list(range(2, 2 + npos))
    th1 = theta1 * DEG
    gam = [g * DEG for g in gamma]
    phi1 = [math.atan2(1.0, -n) for n in n1]
    phi2 = [p - g for p, g in zip(phi1, gam)]
    n2 = [-math.cos(p) / math.sin(p) for p in phi2]
    P1 = [pauly_midha(n) for n in n1]
    P2 = [pauly_midha(n) for n in n2]
    need_EI = energy is not None or force is not None
    names = [f"{v}_{j}" for j in js for v in ("R2", "Theta2", "R3", "Theta3") if f"{v}_{j}" not in fixed]
    names += ["R5", "Theta5", "R6"] + (["EI"] if need_EI else [])
    n_eq = npos * (4 + (1 if energy is not None else 0) + (2 if force is not None else 0))
    if n_eq != len(names):
        raise SynthesisError(f"{n_eq} equations but {len(names)} unknowns ({', '.join(names)}): "
                             f"specify {len(names) - n_eq} more free choice(s)" if len(names) > n_eq else
                             f"{n_eq} equations but {len(names)} unknowns: too many free choices")

    def unpack(x):
        v = dict(fixed)
        v.update(zip(names, x))
        for k in list(v):
            if k.startswith("Theta"):
                v[k + "_rad"] = v[k] * DEG
        return v

    def residual(x):
        v = unpack(x)
        EI = math.exp(v["EI"]) if need_EI else 1.0
        out = []
        for i, j in enumerate(js):
            g1, c1, K1 = P1[i]
            g2, c2, K2 = P2[i]
            R2, R3 = v[f"R2_{j}"], v[f"R3_{j}"]
            T2, T3 = v[f"Theta2_{j}_rad"], v[f"Theta3_{j}_rad"]
            e1 = cmath.exp(1j * th1)
            loop = (R2 * e1 * ((1 - g1) / g1 + cmath.exp(1j * T2))
                    + R3 * e1 * ((1 - g2) / g2 * cmath.exp(1j * gam[i]) + cmath.exp(1j * T3))
                    + v["R5"] * cmath.exp(1j * v["Theta5_rad"]) * (cmath.exp(1j * gam[i]) - 1)
                    - v["R6"] * e1 - delta[i])
            out += [loop.real, loop.imag, (R2 / g1 + R3 / g2 - v["R6"]), T2 * c1 - (T3 - gam[i]) * c2 - gam[i]]
            if energy is not None:
                U = 0.5 * (g1 * g1 * K1 * EI / R2 * T2 ** 2 + g2 * g2 * K2 * EI / R3 * (T3 - gam[i]) ** 2)
                out.append(U / energy[i] - 1.0)
            if force is not None:
                out.append(force[i] * R2 ** 2 / (EI * g1 * g1) * math.sin(phi1[i] - T2) - K1 * T2)
                out.append(force[i] * R3 ** 2 / (EI * g2 * g2) * math.sin(phi2[i] - T3 + gam[i]) - K2 * (T3 - gam[i]))
        return out

    scale = max(abs(d) for d in delta)
    lo = {"R": 1e-6, "Theta": -89.0, "EI": -30.0}
    hi = {"R": 200.0 * scale, "Theta": 180.0, "EI": 40.0}
    bounds = ([lo["EI"] if n == "EI" else (-180.0 if n == "Theta5" else lo[n.rstrip("_0123456789")[:5] if n.startswith("Theta") else "R"])
               for n in names],
              [hi["EI"] if n == "EI" else (180.0 if n == "Theta5" else hi["Theta" if n.startswith("Theta") else "R"])
               for n in names])
    roots = []
    for R6, R5f, th5, s, ang in itertools.product((2.0, 4.0, 8.0), (0.3, 1.0), range(-150, 180, 60),
                                                  (0.3, 0.6), (10.0, 25.0)):
        x0 = []
        for n in names:
            if n.startswith("R2_"):
                x0.append(R6 * scale * s * 0.85)
            elif n.startswith("R3_"):
                x0.append(R6 * scale * (1 - s) * 0.85)
            elif n.startswith("Theta"):
                x0.append(float(th5) if n == "Theta5" else ang + (5.0 if n.startswith("Theta3") else 0.0))
            elif n == "R5":
                x0.append(R5f * R6 * scale)
            elif n == "R6":
                x0.append(R6 * scale)
            else:  # log EI
                x0.append(math.log(max(abs(force[0]) if force else 1.0, 1e-3) * (R6 * scale) ** 2))
        x0 = np.clip(x0, np.array(bounds[0]) + 1e-9, np.array(bounds[1]) - 1e-9)
        try:
            res = least_squares(residual, x0, bounds=bounds, xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=400)
        except (ValueError, OverflowError, ZeroDivisionError):
            continue
        if max(abs(r) for r in res.fun) > 1e-9:
            continue
        v = unpack(res.x)
        ok = all(v[f"R2_{j}"] > 0 and v[f"R3_{j}"] > 0 for j in js) and v["R5"] > 0 and v["R6"] > 0
        ok &= all(-4 < n <= 10 for n in n2)
        if not ok:
            continue
        sol = {k: float(v[k]) for k in names + list(fixed)}
        sol["Theta5"] = (sol["Theta5"] + 180.0) % 360.0 - 180.0
        if need_EI:
            sol["EI"] = math.exp(v["EI"])
        if not any(abs(sol["R6"] - r["R6"]) < 1e-6 * sol["R6"] and abs(sol["R5"] - r["R5"]) < 1e-6 * sol["R6"]
                   for r in roots):
            roots.append(sol)
        if len(roots) >= max_roots:
            break
    if not roots:
        raise SynthesisError("no fixed-guided beam with one inflection point reaches these precision positions "
                             "with these free choices (no root of eqs 160, 163, 164"
                             + (", 165" if energy else "") + (", 166, 167" if force else "") + ")")
    return roots
