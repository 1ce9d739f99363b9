"""Feasible inflection-point locations of a fixed-guided beam by the PRBM vector loop ([bapat2015, §3.6],
eqs 105-107), and the approximate characteristic deflection domain they sweep.

The PRBM of the beam with one inflection point (Fig. 3.9, missing) is the vector loop (Fig. 3.10, missing)

    R1 = (1 - gamma) l1 along x,  R2 = gamma l1 at theta2,  R3 = gamma l2 at theta3,
    R4 = (1 - gamma) l2 at theta4,  R6 = b,  R7 = l,  R5 = l - a (the end's axial displacement),

closed by (105) theta3 = asin[(R6 - R2 sin theta2 - R4 sin theta4)/R3] and (106) R5 = R7 - [R1 + R2 cos
theta2 + R3 cos theta3 + R4 cos theta4], with (107) theta2 = Theta1, theta3 = Theta2 + theta0, theta4 =
theta0.  (107) is printed "theta2 = theta1; theta3 = theta2 + theta0": the PDF conversion lost the
capitals (PRB angles Theta1, Theta2), the reading under which the loop is chapter 3's eqs (103)-(104)
(notes seed-ch2-4 section 4.7).  The two constraints of the text:

 i) the orientation of Z3 exceeds the end angle, theta3 > theta0, i.e. Theta2 > 0;
ii) equal slopes at the inflection point: c_theta Theta1 = c_theta Theta2 + theta0 (eq 101 with
    theta10 = c_theta Theta1, theta20 = c_theta Theta2).

For a trial l1 the slope condition fixes Theta2 = Theta1 - theta0/c_theta, and (105) becomes one equation in
Theta1, g(Theta1) = R2 sin Theta1 + R3 sin(Theta1 - theta0/c_theta + theta0) + R4 sin theta0 - b = 0; l1
is feasible when it has a root with Theta1 > 0 and Theta2 > 0 (Fig. 3.11's flowchart is missing; this is
the algorithm the text states).  "Average PRBM parameters [33, 38, 40]" are used without values; the
defaults here are the Pauly-Midha constants at n = 0 (eqs 41, 42): gamma = 0.851892, c_theta = 1.238845.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from prbm.fits import PAULY_MIDHA

GAMMA_AVERAGE, C_THETA_AVERAGE, _ = PAULY_MIDHA.parameters(0.0)


@dataclass(frozen=True)
class LoopState:
    """One closed vector loop: the PRB angles (rad), the end position a (= l - R5) and feasibility."""

    l1: float
    feasible: bool
    reason: str
    Theta1: float = math.nan
    Theta2: float = math.nan
    a: float = math.nan


def loop_closure(
    *, length: float, b: float, theta0: float, l1: float, gamma: float = GAMMA_AVERAGE, c_theta: float = C_THETA_AVERAGE
) -> LoopState:
    """Close the loop of eqs (105)-(107) for end height b, end angle theta0 (rad) and inflection point at
    arc length l1; ``feasible`` is False (with the reason) when no root meets constraints i) and ii)."""
    if not (length > 0 and 0 < l1 < length and 0 < gamma <= 1 and c_theta > 0):
        raise ValueError(
            f"loop_closure: need length > 0, 0 < l1 < length, 0 < gamma <= 1, c_theta > 0; got "
            f"length={length}, l1={l1}, gamma={gamma}, c_theta={c_theta}"
        )
    l2 = length - l1
    R1, R2, R3, R4 = (1 - gamma) * l1, gamma * l1, gamma * l2, (1 - gamma) * l2
    shift = theta0 - theta0 / c_theta  # theta3 = Theta2 + theta0 = Theta1 + shift
    end = R4 * math.sin(theta0)

    def g(T1: float) -> float:  # (105) with (107), ii)
        return R2 * math.sin(T1) + R3 * math.sin(T1 + shift) + end - b

    lo = max(0.0, theta0 / c_theta)  # Theta1 > 0 and Theta2 = Theta1 - theta0/c_theta > 0 (constraint i)
    # the first sign change of g on a grid of Theta1 up to 90 deg, scanned upwards (g evaluated as the scan
    # reaches each node: the nodes past the first root meeting the constraints are never needed)
    grid = np.linspace(lo, math.pi / 2, 181).tolist()
    g_next = g(grid[0])
    for k in range(len(grid) - 1):
        g_here, g_next = g_next, g(grid[k + 1])
        if g_here == 0.0 or g_here * g_next < 0:
            T1 = grid[k] if g_here == 0.0 else brentq(g, grid[k], grid[k + 1], xtol=1e-14)
            T2 = T1 - theta0 / c_theta
            if T1 <= 0 or T2 <= 0:
                continue
            th3 = T2 + theta0
            R5 = length - (R1 + R2 * math.cos(T1) + R3 * math.cos(th3) + R4 * math.cos(theta0))  # (106)
            return LoopState(l1, True, "feasible", T1, T2, length - R5)
    return LoopState(
        l1, False, "no loop closure with Theta1 > 0 and Theta2 > 0 (theta3 > theta0) for Theta1 up to 90 deg"
    )


def feasible_l1(
    *,
    length: float,
    b: float,
    theta0: float,
    samples: int = 200,
    gamma: float = GAMMA_AVERAGE,
    c_theta: float = C_THETA_AVERAGE,
) -> list[LoopState]:
    """Fig. 3.11's sweep: the loop at ``samples`` trial l1 evenly inside (0, length)."""
    l1s = np.linspace(0.0, length, samples + 2)[1:-1]
    return [loop_closure(length=length, b=b, theta0=theta0, l1=float(x), gamma=gamma, c_theta=c_theta) for x in l1s]


def approximate_domain(
    *,
    length: float,
    theta0: float,
    b_values: Iterable[float],
    samples: int = 100,
    gamma: float = GAMMA_AVERAGE,
    c_theta: float = C_THETA_AVERAGE,
) -> NDArray[np.float64]:
    """Fig. 3.12's approximate characteristic deflection domain for one end angle: the end points (a, b)
    of every feasible (b, l1) pair, as an (m, 2) array."""
    points = [
        (s.a, b)
        for b in b_values
        for s in feasible_l1(length=length, b=float(b), theta0=theta0, samples=samples, gamma=gamma, c_theta=c_theta)
        if s.feasible
    ]
    return np.array(points, dtype=float).reshape(-1, 2)
