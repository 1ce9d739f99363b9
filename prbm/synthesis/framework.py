"""Chapter-5 synthesis framework: a fixed-guided beam with one inflection point carrying a rigid coupler.

[bapat2015, §5.3], Fig. 5.9.  At precision position j (j = 2, 3, ...) the beam is the
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
Th3j + th1 (notes/seed-ch5-9.md section 3.3; only (160) reproduces the printed examples).
The fits g, c, K are eqs (41)-(43) at n1j (a free choice) and n2j = -1/tan(phi2j), phi2j = phi1j - gam_j
(150), phi1j = atan2(1, -n1j).

Unknowns: every R2j, Th2j, R3j, Th3j not given as a free choice, R5, th5, R6, and EI when energies or
forces are specified.  The equations must be as many as the unknowns (design tables 5.1-5.3); the
system is solved by ``least_squares`` from a grid of starts and every valid root (R > 0, Th3j > gam_j
and load ratios n2j inside the fits' range) is returned, the first ``max_roots`` found.

Angles are in degrees here, as in the dissertation's synthesis tables (chapters 3, 5, 6); the PRBM library they feed works in radians.
"""

from __future__ import annotations

import cmath
import itertools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from prbm.synthesis.dyads import DEG, SynthesisError
from prbm.synthesis.fixed_guided import pauly_midha


@dataclass
class _Framework:
    """The chapter-5 equations for given precision positions: the unknowns' names, the residual of
    eqs (160), (163), (164) (and (165) with energies, (166)-(167) with forces), bounds and guesses."""

    th1: float
    gam: list[float]
    phi1: list[float]
    phi2: list[float]
    n2: list[float]
    P1: list[tuple[float, float, float]]
    P2: list[tuple[float, float, float]]
    delta: list[complex]
    fixed: dict[str, float]
    names: list[str]
    energy: list[float] | None
    force: list[float] | None

    @property
    def js(self) -> list[int]:
        return list(range(2, 2 + len(self.delta)))

    @property
    def need_EI(self) -> bool:
        return self.energy is not None or self.force is not None

    def unpack(self, x: NDArray[np.float64]) -> dict[str, float]:
        v = dict(self.fixed)
        v.update(zip(self.names, x))
        for k in list(v):
            if k.startswith("Theta"):
                v[k + "_rad"] = v[k] * DEG
        return v

    def residual(self, x: NDArray[np.float64]) -> list[float]:
        v = self.unpack(x)
        EI = math.exp(v["EI"]) if self.need_EI else 1.0
        out = []
        e1 = cmath.exp(1j * self.th1)
        for i, j in enumerate(self.js):
            g1, c1, K1 = self.P1[i]
            g2, c2, K2 = self.P2[i]
            gam = self.gam[i]
            R2, R3 = v[f"R2_{j}"], v[f"R3_{j}"]
            T2, T3 = v[f"Theta2_{j}_rad"], v[f"Theta3_{j}_rad"]
            loop = (
                R2 * e1 * ((1 - g1) / g1 + cmath.exp(1j * T2))
                + R3 * e1 * ((1 - g2) / g2 * cmath.exp(1j * gam) + cmath.exp(1j * T3))
                + v["R5"] * cmath.exp(1j * v["Theta5_rad"]) * (cmath.exp(1j * gam) - 1)
                - v["R6"] * e1
                - self.delta[i]
            )
            out += [loop.real, loop.imag, (R2 / g1 + R3 / g2 - v["R6"]), T2 * c1 - (T3 - gam) * c2 - gam]
            if self.energy is not None:
                U = 0.5 * (g1 * g1 * K1 * EI / R2 * T2**2 + g2 * g2 * K2 * EI / R3 * (T3 - gam) ** 2)
                out.append(U / self.energy[i] - 1.0)
            if self.force is not None:
                out.append(self.force[i] * R2**2 / (EI * g1 * g1) * math.sin(self.phi1[i] - T2) - K1 * T2)
                out.append(self.force[i] * R3**2 / (EI * g2 * g2) * math.sin(self.phi2[i] - T3 + gam) - K2 * (T3 - gam))
        return out

    def jacobian(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """d residual / d x, analytically (the unknowns' angles in degrees, EI as its logarithm)."""
        v = self.unpack(x)
        col = {name: k for k, name in enumerate(self.names)}
        EI = math.exp(v["EI"]) if self.need_EI else 1.0
        rows: list[dict[str, float | complex]] = []
        e1 = cmath.exp(1j * self.th1)
        e5 = cmath.exp(1j * v["Theta5_rad"])
        for i, j in enumerate(self.js):
            g1, c1, K1 = self.P1[i]
            g2, c2, K2 = self.P2[i]
            gam = self.gam[i]
            R2, R3 = v[f"R2_{j}"], v[f"R3_{j}"]
            T2, T3 = v[f"Theta2_{j}_rad"], v[f"Theta3_{j}_rad"]
            eg, e2, e3 = cmath.exp(1j * gam), cmath.exp(1j * T2), cmath.exp(1j * T3)
            loop = {
                f"R2_{j}": e1 * ((1 - g1) / g1 + e2),
                f"Theta2_{j}": R2 * e1 * 1j * e2 * DEG,
                f"R3_{j}": e1 * ((1 - g2) / g2 * eg + e3),
                f"Theta3_{j}": R3 * e1 * 1j * e3 * DEG,
                "R5": e5 * (eg - 1),
                "Theta5": v["R5"] * 1j * e5 * (eg - 1) * DEG,
                "R6": -e1,
            }
            rows += [
                {k: d.real for k, d in loop.items()},
                {k: d.imag for k, d in loop.items()},
                {f"R2_{j}": 1 / g1, f"R3_{j}": 1 / g2, "R6": -1.0},
                {f"Theta2_{j}": c1 * DEG, f"Theta3_{j}": -c2 * DEG},
            ]
            if self.energy is not None:
                k2, k3 = g1 * g1 * K1 * EI, g2 * g2 * K2 * EI
                U = 0.5 * (k2 / R2 * T2**2 + k3 / R3 * (T3 - gam) ** 2)
                rows.append(
                    {
                        f"R2_{j}": -0.5 * k2 * T2**2 / R2**2 / self.energy[i],
                        f"Theta2_{j}": k2 / R2 * T2 * DEG / self.energy[i],
                        f"R3_{j}": -0.5 * k3 * (T3 - gam) ** 2 / R3**2 / self.energy[i],
                        f"Theta3_{j}": k3 / R3 * (T3 - gam) * DEG / self.energy[i],
                        "EI": U / self.energy[i],
                    }
                )
            if self.force is not None:
                F = self.force[i]
                s2, s3 = math.sin(self.phi1[i] - T2), math.sin(self.phi2[i] - T3 + gam)
                a2, a3 = F * R2**2 / (EI * g1 * g1), F * R3**2 / (EI * g2 * g2)
                rows.append(
                    {
                        f"R2_{j}": 2 * a2 / R2 * s2,
                        "EI": -a2 * s2,
                        f"Theta2_{j}": (-a2 * math.cos(self.phi1[i] - T2) - K1) * DEG,
                    }
                )
                rows.append(
                    {
                        f"R3_{j}": 2 * a3 / R3 * s3,
                        "EI": -a3 * s3,
                        f"Theta3_{j}": (-a3 * math.cos(self.phi2[i] - T3 + gam) - K2) * DEG,
                    }
                )
        J = np.zeros((len(rows), len(self.names)))
        for r, row in enumerate(rows):
            for name, d in row.items():
                if name in col:
                    J[r, col[name]] = d
        return J

    def bounds(self, scale: float) -> tuple[list[float], list[float]]:
        def low(n: str) -> float:
            return -30.0 if n == "EI" else -180.0 if n == "Theta5" else -89.0 if n.startswith("Theta") else 1e-6

        def high(n: str) -> float:
            return 40.0 if n == "EI" else 180.0 if n.startswith("Theta") else 200.0 * scale

        return [low(n) for n in self.names], [high(n) for n in self.names]

    def guess(self, scale: float, R6: float, R5f: float, th5: float, s: float, ang: float) -> list[float]:
        x0 = []
        for n in self.names:
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
                x0.append(math.log(max(abs(self.force[0]) if self.force else 1.0, 1e-3) * (R6 * scale) ** 2))
        return x0

    def solution(self, x: NDArray[np.float64]) -> dict[str, float] | None:
        """The root as named values (EI, Theta5 normalised), or None where it is not a mechanism."""
        v = self.unpack(x)
        ok = all(v[f"R2_{j}"] > 0 and v[f"R3_{j}"] > 0 for j in self.js) and v["R5"] > 0 and v["R6"] > 0
        ok &= all(-4 < n <= 10 for n in self.n2)
        if not ok:
            return None
        sol = {k: float(v[k]) for k in self.names + list(self.fixed)}
        sol["Theta5"] = (sol["Theta5"] + 180.0) % 360.0 - 180.0
        if self.need_EI:
            sol["EI"] = math.exp(v["EI"])
        return sol


def _framework(
    theta1: float,
    delta: list[complex],
    gamma: list[float],
    n1: list[float],
    fixed: dict[str, float],
    energy: list[float] | None,
    force: list[float] | None,
) -> _Framework:
    """The unknowns left by the free choices; a one-line error when equations and unknowns differ."""
    npos = len(delta)
    gam = [g * DEG for g in gamma]
    phi1 = [math.atan2(1.0, -n) for n in n1]
    phi2 = [p - g for p, g in zip(phi1, gam)]
    n2 = [-math.cos(p) / math.sin(p) for p in phi2]
    names = [
        f"{v}_{j}" for j in range(2, 2 + npos) for v in ("R2", "Theta2", "R3", "Theta3") if f"{v}_{j}" not in fixed
    ]
    names += ["R5", "Theta5", "R6"] + (["EI"] if energy is not None or force is not None else [])
    n_eq = npos * (4 + (1 if energy is not None else 0) + (2 if force is not None else 0))
    if n_eq != len(names):
        raise SynthesisError(
            f"{n_eq} equations but {len(names)} unknowns ({', '.join(names)}): "
            f"specify {len(names) - n_eq} more free choice(s)"
            if len(names) > n_eq
            else f"{n_eq} equations but {len(names)} unknowns: too many free choices"
        )
    return _Framework(
        th1=theta1 * DEG,
        gam=gam,
        phi1=phi1,
        phi2=phi2,
        n2=n2,
        P1=[pauly_midha(n) for n in n1],
        P2=[pauly_midha(n) for n in n2],
        delta=list(delta),
        fixed=fixed,
        names=names,
        energy=energy,
        force=force,
    )


def solve_framework(
    *,
    theta1: float,
    delta: list[complex],
    gamma: list[float],
    n1: list[float],
    fixed: dict[str, float] | None = None,
    energy: list[float] | None = None,
    force: list[float] | None = None,
    max_roots: int = 1,
) -> list[dict[str, float]]:
    """Roots of the chapter-5 equations; angles in degrees in and out.  ``fixed`` names free choices
    'R2_j', 'Theta2_j', 'R3_j', 'Theta3_j' (j = 2, 3, ...)."""
    problem = _framework(theta1, delta, gamma, n1, dict(fixed or {}), energy, force)
    scale = max(abs(d) for d in delta)
    bounds = problem.bounds(scale)
    roots: list[dict[str, float]] = []
    for start in itertools.product((2.0, 4.0, 8.0), (0.3, 1.0), range(-150, 180, 60), (0.3, 0.6), (10.0, 25.0)):
        x0 = np.clip(problem.guess(scale, *start), np.array(bounds[0]) + 1e-9, np.array(bounds[1]) - 1e-9)
        try:
            res = least_squares(
                problem.residual,
                x0,
                jac=problem.jacobian,
                bounds=bounds,
                xtol=1e-14,
                ftol=1e-14,
                gtol=1e-14,
                max_nfev=400,
            )
        except (ValueError, OverflowError, ZeroDivisionError):
            continue
        sol = problem.solution(res.x) if max(abs(r) for r in res.fun) <= 1e-9 else None
        if sol is not None and not any(
            abs(sol["R6"] - r["R6"]) < 1e-6 * sol["R6"] and abs(sol["R5"] - r["R5"]) < 1e-6 * sol["R6"] for r in roots
        ):
            roots.append(sol)
        if len(roots) >= max_roots:
            break
    if not roots:
        raise SynthesisError(
            "no fixed-guided beam with one inflection point reaches these precision positions "
            "with these free choices (no root of eqs 160, 163, 164"
            + (", 165" if energy else "")
            + (", 166, 167" if force else "")
            + ")"
        )
    return roots
