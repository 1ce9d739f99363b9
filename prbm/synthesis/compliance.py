"""Compliance synthesis: torsional-spring constants from energies or torques at precision positions.

[bapat2015, §6.5].  With beta_i the angle of PRBM spring i, beta_i0 its angle in the
energy-free state and S the input (Theta2),

    U_j = 1/2 sum_i k_i (beta_ij - beta_i0)^2                                  (181)
    T_j = sum_i k_i (beta_ij - beta_i0) d beta_ij / dS                         (182)

Four-bar springs (183): beta1 = Theta2 (O2), beta2 = 180 - (Theta2 - Theta3) (A),
beta3 = Theta4 - Theta3 (B), beta4 = Theta4 (O4); with h3 = dTheta3/dTheta2 =
R2 sin(Theta4 - Theta2) / (R3 sin(Theta3 - Theta4)) and h4 = dTheta4/dTheta2 =
R2 sin(Theta3 - Theta2) / (R4 sin(Theta3 - Theta4)) the rates are 1, h3 - 1, h4 - h3, h4.
Slider-crank springs ([bapat2015, eq 196] with the slider spring f_k = 0): beta1 = Theta2 (O2),
beta2 = Theta3 - Theta2 (A), beta3 = Theta3 (slider pin); g3 = dTheta3/dTheta2 =
-R2 cos Theta2 / (R3 cos Theta3); rates 1, g3 - 1, g3.

Both (181) and (182) are linear in k: f = A k - b.  The spring constants solve the optimisation
(184)-(185): minimise F = sum_j f_j^2 over bounds on k, equal-spring groups (k1 = k2, ... as
parametrisation) and inequality constraints g(k) <= 0 (e.g. the stress of the segment realising a
spring, see ``prbm.synthesis.segments``), by SLSQP from several starts (the bounded linear least-squares
solution among them).  Section 6.6: a final F far from zero means the energies/torques do not
agree with the link rotations -- the result says so and in which direction to change them.

Angles are in degrees here, as in the dissertation's synthesis tables (chapters 3, 5, 6); the PRBM library they feed works in radians.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Callable, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import lsq_linear, minimize

from prbm.mechanisms import four_bar_rates, slider_crank_rate
from prbm.synthesis.dyads import DEG, FourBarDesign, SliderCrankDesign, four_bar_position, slider_position


def four_bar_springs(fb: FourBarDesign, theta2: float, theta3: float, theta4: float) -> tuple[np.ndarray, np.ndarray]:
    """(beta, d beta / d Theta2) of the four springs at O2, A, B, O4 (radians; eq. 183 and 182)."""
    t2, t3, t4 = theta2 * DEG, theta3 * DEG, theta4 * DEG
    h3, h4 = four_bar_rates(abs(fb.Z2), abs(fb.Z3), abs(fb.Z4), t2, t3, t4)  # the one copy, prbm.mechanisms
    beta = np.array([t2, math.pi - (t2 - t3), t4 - t3, t4])
    return beta, np.array([1.0, h3 - 1.0, h4 - h3, h4])


def slider_springs(sc: SliderCrankDesign, theta2: float, theta3: float) -> tuple[np.ndarray, np.ndarray]:
    """(beta, d beta / d Theta2) of the springs at O2, A and the slider pin (radians; eq. 196)."""
    t2, t3 = theta2 * DEG, theta3 * DEG
    g3 = slider_crank_rate(abs(sc.Z2), abs(sc.Z3), t2, t3)  # the one copy, prbm.mechanisms
    return np.array([t2, t3 - t2, t3]), np.array([1.0, g3 - 1.0, g3])


@dataclass
class Configuration:
    """One configuration where energy or torque is specified: link angles (deg) and a label."""

    label: str
    angles: tuple[float, ...]


def four_bar_configurations(
    fb: FourBarDesign, energy_free_theta2: float | None = None
) -> tuple[Configuration, list[Configuration]]:
    """(energy-free state, precision positions) of a four-bar.  The energy-free state is position 1
    unless an input angle Theta20 is given (then Theta30, Theta40 follow by position analysis)."""
    positions = [Configuration(f"P{j + 1}", fb.angles(j)) for j in range(len(fb.phi))]
    if energy_free_theta2 is None:
        return Configuration("P1 (energy-free)", positions[0].angles), positions
    t3, t4 = four_bar_position(fb, energy_free_theta2, positions[0].angles[1:])
    return Configuration("energy-free", (energy_free_theta2, t3, t4)), positions


def slider_configurations(
    sc: SliderCrankDesign, extra_x: Sequence[float] = ()
) -> tuple[Configuration, list[Configuration]]:
    """(energy-free = position 1, [P1, P2, then the slider at each extra displacement])."""
    t21, t31 = sc.angles(0)
    out = [Configuration(f"P{j + 1}", sc.angles(j)) for j in range(len(sc.phi))]
    x1 = abs(sc.Z11)
    for dx in extra_x:
        out.append(Configuration(f"slider +{dx:g}", slider_position(sc, x1 + dx, (t21, t31))))
    return Configuration("P1 (energy-free)", (t21, t31)), out


def springs_at(
    mech: FourBarDesign | SliderCrankDesign, config: Configuration
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    if isinstance(mech, SliderCrankDesign):
        return slider_springs(mech, *config.angles)
    return four_bar_springs(mech, *config.angles)


def design_rows(
    mech: FourBarDesign | SliderCrankDesign, free: Configuration, configs: list[Configuration], kind: str
) -> NDArray[np.float64]:
    """Row j of A with f_j = A_j k - b_j: 1/2 (beta - beta0)^2 for energy, (beta - beta0) beta' for torque."""
    beta0, _ = springs_at(mech, free)
    rows = []
    for c in configs:
        beta, rate = springs_at(mech, c)
        d = beta - beta0
        rows.append(0.5 * d * d if kind == "energy" else d * rate)
    return np.array(rows)


@dataclass
class SpringResult:
    """Spring constants and how they were obtained (scipy.optimize style)."""

    k: np.ndarray  # per spring, 0 where the PRBM has no spring
    success: bool
    message: str
    fun: float  # F = sum f_j^2 at the answer
    achieved: np.ndarray  # U_j or T_j with these springs
    target: np.ndarray
    nit: int = 0
    nfev: int = 0
    constraints: dict[str, float] = field(default_factory=dict)  # name -> g(k) (<= 0 is met)


class _Inequality(TypedDict):
    """An inequality constraint fun(x) >= 0 as ``scipy.optimize.minimize`` takes it."""

    type: str
    fun: Callable[[NDArray[np.float64]], float]


def _inequality(g: Callable[[NDArray[np.float64]], float], E: NDArray[np.float64]) -> _Inequality:
    """The constraint g(k) <= 0 on k = E x as ``minimize``'s inequality -g(E x) >= 0."""
    return {"type": "ineq", "fun": lambda x: -g(E @ x)}


def solve_springs(
    A: NDArray[np.float64],
    target: ArrayLike,
    *,
    springs: list[int],
    groups: list[list[int]] | None = None,
    bounds: tuple[float, float] = (0.0, np.inf),
    constraints: dict[str, Callable[[NDArray[np.float64]], float]] | None = None,
    ftol: float = 1e-10,
    rtol: float = 1e-6,
    label: str = "energy",
) -> SpringResult:
    """Minimise sum_j (A_j k - b_j)^2 (eq. 185) over the active springs (1-based joint numbers),
    with springs of one group equal, ``bounds`` on every k and ``constraints`` g(k) <= 0."""
    b = np.asarray(target, dtype=float)
    n_all = A.shape[1]
    groups = groups or [[s] for s in springs]
    grouped = {s for g in groups for s in g}
    if grouped != set(springs):
        missing = set(springs) ^ grouped
        raise ValueError(f"spring groups and active springs differ at spring(s) {sorted(missing)}")
    E = np.zeros((n_all, len(groups)))  # k = E x
    for col, g in enumerate(groups):
        for s in g:
            E[s - 1, col] = 1.0
    Ax = A @ E
    constraints = constraints or {}

    def objective(x: NDArray[np.float64]) -> float:
        f = Ax @ x - b
        return float(f @ f)

    def gradient(x: NDArray[np.float64]) -> NDArray[np.float64]:
        grad: NDArray[np.float64] = 2.0 * Ax.T @ (Ax @ x - b)
        return grad

    lo, hi = bounds
    start = lsq_linear(Ax, b, bounds=(lo, hi)).x
    starts = [start, np.full(len(groups), max(np.mean(np.abs(start)), 1.0)), np.clip(start * 3.0 + 1.0, lo, hi)]
    cons = [_inequality(g, E) for g in constraints.values()]
    best, nit, nfev = None, 0, 0
    for x0 in starts:
        res = minimize(
            objective,
            x0,
            jac=gradient,
            method="SLSQP",
            bounds=[(lo, None if hi == np.inf else hi)] * len(groups),
            constraints=cons,
            options={"ftol": 1e-16, "maxiter": 500},
        )
        nit += res.nit
        nfev += res.nfev
        feasible = all(c["fun"](res.x) >= -1e-9 for c in cons)
        if feasible and (best is None or res.fun < best.fun):
            best = res
    if best is None:
        k = E @ start
        return SpringResult(
            k,
            False,
            "no spring constants satisfy the constraints "
            f"({', '.join(constraints)}); relax them or change the specification",
            objective(start),
            A @ k,
            b,
            nit,
            nfev,
            {n: g(k) for n, g in constraints.items()},
        )
    k = E @ best.x
    achieved = A @ k
    fun = objective(best.x)
    scale = max(float(b @ b), 1e-300)
    ok = fun <= max(ftol, rtol**2 * scale)
    if ok:
        message = f"{label} specification met (F = {fun:.3g})"
    else:
        worst = int(np.argmax(np.abs(achieved - b)))
        direction = "lower" if achieved[worst] < b[worst] else "higher"
        message = (
            f"{label} specification cannot be met exactly: F = {fun:.4g}; the best springs give "
            f"{', '.join(f'{v:.4g}' for v in achieved)} for {', '.join(f'{v:.4g}' for v in b)} "
            f"(largest miss at entry {worst + 1}, {direction} than specified). Seed section 6.6: "
            f"check that the {label} agrees with the link rotations, then change the specification"
        )
    return SpringResult(k, ok, message, fun, achieved, b, nit, nfev, {n: g(k) for n, g in constraints.items()})
