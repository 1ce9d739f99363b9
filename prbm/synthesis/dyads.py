"""Rigid-body synthesis of four-bar and slider-crank linkages with the standard dyad equations.

[bapat2015, §6.4], complex-number form (Erdman and Sandor).  Position 1 is the
reference; for every further precision position j the two dyads of a four-bar close the loops

    Z2 (e^{i phi_j} - 1) + Z5 (e^{i gamma_j} - 1) = delta_j          (179)  left dyad  O2-A-P
    Z4 (e^{i psi_j} - 1) + Z6 (e^{i gamma_j} - 1) = delta_j          (180)  right dyad O4-B-P

and for function generation the whole loop closes with

    Z2 (1 - e^{i phi_j}) + Z3 (1 - e^{i gamma_j}) + Z4 (e^{i psi_j} - 1) = 0     (178)

Z1 = O2->O4 (ground), Z2 = O2->A, Z3 = A->B, Z4 = O4->B, Z5 = A->P, Z6 = B->P;
Z2 + Z3 = Z1 + Z4 and Z3 = Z5 - Z6 [bapat2015, Figs 6.2, 6.3].  phi, gamma, psi are the rotations of
links 2, 3, 4 from position 1 and delta_j = P_j - P_1.

One dyad Z (e^{i a_j} - 1) + W (e^{i b_j} - 1) = delta_j at two or three positions is solved in
closed form for the usual sets of free choices:

* every rotation known (a_j and b_j): linear in Z, W (three positions), or W from a chosen Z
  (two positions);
* Z chosen, rotations b_j of W known (motion generation), a_j unknown: eliminating W between
  j = 2 and 3 leaves  -Z(e^{i b3} - 1) e^{i a2} + Z(e^{i b2} - 1) e^{i a3}
  = (delta3 + Z)(e^{i b2} - 1) - (delta2 + Z)(e^{i b3} - 1),  a triangle  p e^{ix} + q e^{iy} = c
  with at most two closures (branches);
* Z chosen, its rotations a_j known (prescribed timing), b_j unknown: with A_j = delta_j -
  Z(e^{i a_j} - 1), A2 e^{i b3} - A3 e^{i b2} = A2 - A3; one closure is the trivial b = 0
  (W infinite) and is discarded.

A triangle that does not close (|c| outside [||p| - |q||, |p| + |q|]) means the precision positions
are incompatible with the free choices: that is returned as a failed result with a message.

Angles are in degrees here, as in the dissertation's synthesis tables (chapters 3, 5, 6); the PRBM library they feed works in radians.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

DEG = math.pi / 180.0


def rot(angle_deg: float) -> complex:
    """e^{i angle}, angle in degrees."""
    return cmath.exp(1j * angle_deg * DEG)


def arg_deg(z: complex) -> float:
    return math.degrees(cmath.phase(z))


def polar(length: float, angle_deg: float) -> complex:
    return length * rot(angle_deg)


class SynthesisError(ValueError):
    """A specification with no solution; ``str()`` is the message for the designer."""


@dataclass
class Dyad:
    """One solved dyad: link Z with rotations a_j, coupler-side vector W with rotations b_j (deg).

    a and b include position 1 (a[0] = b[0] = 0)."""

    Z: complex
    W: complex
    a: list[float]
    b: list[float]
    branch: int = 0
    branches: int = 1

    def residual(self, deltas: list[complex]) -> float:
        return max(
            (abs(self.Z * (rot(a) - 1) + self.W * (rot(b) - 1) - d) for a, b, d in zip(self.a[1:], self.b[1:], deltas)),
            default=0.0,
        )


def triangle(p: complex, q: complex, c: complex, tol: float = 1e-12) -> list[tuple[float, float]]:
    """All (x, y) in radians with p e^{ix} + q e^{iy} = c (at most two)."""
    P, Q, C = abs(p), abs(q), abs(c)
    if min(P, Q, C) < tol:
        return []
    cosine = (Q * Q + C * C - P * P) / (2 * Q * C)
    if abs(cosine) > 1 + 1e-12:
        return []
    cosine = max(-1.0, min(1.0, cosine))
    out = []
    for sign in (1.0, -1.0):
        y = cmath.phase(c) - cmath.phase(q) + sign * math.acos(cosine)
        x = cmath.phase((c - q * cmath.exp(1j * y)) / p)
        out.append((x, y))
        if cosine in (1.0, -1.0):
            break
    return out


def _wrap(angle_deg: float) -> float:
    return (angle_deg + 180.0) % 360.0 - 180.0


def dyad_all_rotations(deltas: list[complex], a: list[float], b: list[float], Z: complex | None = None) -> Dyad:
    """Dyad with every rotation known (deg, positions 2..n).  Three positions: linear solve;
    two positions: W from the chosen Z."""
    if len(deltas) == 1:
        if Z is None:
            raise SynthesisError("two-position dyad with all rotations known needs the link vector as a free choice")
        eb = rot(b[0]) - 1
        if abs(eb) < 1e-12:
            raise SynthesisError("coupler rotation at position 2 is zero: the dyad equation has no solution for W")
        W = (deltas[0] - Z * (rot(a[0]) - 1)) / eb
        return Dyad(Z, W, [0.0, a[0]], [0.0, b[0]])
    if len(deltas) != 2:
        raise SynthesisError(f"{len(deltas) + 1} precision positions: only two or three are supported")
    M = np.array([[rot(a[0]) - 1, rot(b[0]) - 1], [rot(a[1]) - 1, rot(b[1]) - 1]])
    if abs(np.linalg.det(M)) < 1e-12:
        raise SynthesisError("the chosen rotations make the dyad equations singular (no unique dyad)")
    Zs, Ws = np.linalg.solve(M, np.array(deltas, dtype=complex))
    return Dyad(complex(Zs), complex(Ws), [0.0, *a], [0.0, *b])


def dyad_link_and_coupler_rotations(deltas: list[complex], Z: complex, b: list[float]) -> list[Dyad]:
    """Motion generation: Z chosen, rotations b_j of W known (three positions); every branch."""
    if len(deltas) != 2:
        raise SynthesisError(
            "a chosen link vector with known coupler rotations needs exactly three precision positions"
        )
    d2, d3 = deltas
    e2, e3 = rot(b[0]) - 1, rot(b[1]) - 1
    if abs(e2) < 1e-12 or abs(e3) < 1e-12:
        raise SynthesisError("a coupler rotation of zero leaves the dyad undetermined")
    roots = triangle(-Z * e3, Z * e2, (d3 + Z) * e2 - (d2 + Z) * e3)
    dyads = []
    for x, y in roots:
        a2, a3 = _wrap(math.degrees(x)), _wrap(math.degrees(y))
        W = (d2 - Z * (rot(a2) - 1)) / e2
        dyads.append(Dyad(Z, W, [0.0, a2, a3], [0.0, *b]))
    return _number(dyads)


def dyad_link_and_link_rotations(deltas: list[complex], Z: complex, a: list[float]) -> list[Dyad]:
    """Prescribed timing: Z chosen with its rotations a_j known; W and its rotations b_j unknown."""
    if len(deltas) != 2:
        raise SynthesisError("a chosen link vector with prescribed timing needs exactly three precision positions")
    A2 = deltas[0] - Z * (rot(a[0]) - 1)
    A3 = deltas[1] - Z * (rot(a[1]) - 1)
    dyads = []
    for x, y in triangle(A2, -A3, A2 - A3):
        b3, b2 = _wrap(math.degrees(x)), _wrap(math.degrees(y))
        if abs(rot(b2) - 1) < 1e-9 or abs(rot(b3) - 1) < 1e-9:
            continue  # the trivial closure b = 0 (W at infinity)
        dyads.append(Dyad(Z, A2 / (rot(b2) - 1), [0.0, *a], [0.0, b2, b3]))
    return _number(dyads)


def dyad_link_and_direction(delta: complex, Z: complex, a: float, direction_deg: float) -> Dyad:
    """Two positions: Z and its rotation a known, only the direction of W known (its length and
    rotation b unknown):  R_W e^{i theta_W} (e^{ib} - 1) = A,  e^{ib} - 1 = 2 i sin(b/2) e^{ib/2}."""
    A = delta - Z * (rot(a) - 1)
    if abs(A) < 1e-12:
        raise SynthesisError("the chosen link alone reaches the precision position: coupler rotation undefined")
    u = A / rot(direction_deg)  # = R_W (e^{ib} - 1), R_W real
    b = _wrap(2.0 * (arg_deg(u) - 90.0))  # arg(e^{ib} - 1) = b/2 + 90 (mod 180)
    eb = rot(b) - 1
    if abs(eb) < 1e-12:
        raise SynthesisError("no coupler rotation closes the dyad in the chosen direction")
    R = (u / eb).real
    if R <= 0:
        raise SynthesisError("the coupler vector would have to point opposite to the chosen direction")
    W = polar(R, direction_deg)
    return Dyad(Z, W, [0.0, a], [0.0, b])


def _number(dyads: list[Dyad]) -> list[Dyad]:
    for i, d in enumerate(dyads):
        d.branch, d.branches = i, len(dyads)
    return dyads


@dataclass
class FourBarDesign:
    """A synthesized four-bar at position 1 with its rotations at every precision position (deg)."""

    Z1: complex
    Z2: complex
    Z3: complex
    Z4: complex
    Z5: complex
    Z6: complex
    phi: list[float]
    gamma: list[float]
    psi: list[float]
    deltas: list[complex] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def angles(self, j: int) -> tuple[float, float, float]:
        """(Theta2, Theta3, Theta4) at precision position j (0-based), degrees."""
        return (arg_deg(self.Z2) + self.phi[j], arg_deg(self.Z3) + self.gamma[j], arg_deg(self.Z4) + self.psi[j])

    def loop_error(self) -> float:
        return abs(self.Z2 + self.Z3 - self.Z1 - self.Z4)

    def vectors(self) -> dict[str, complex]:
        return {f"Z{i}": getattr(self, f"Z{i}") for i in range(1, 7)}


def _pick(dyads: list[Dyad], branch: int | None, what: str) -> Dyad:
    if not dyads:
        raise SynthesisError(
            f"{what}: the precision positions cannot be reached with these free choices (the dyad loop does not close)"
        )
    if branch is None:  # default: the more compact dyad (the other closure folds the linkage)
        return min(dyads, key=lambda d: abs(d.W))
    if not 0 <= branch < len(dyads):
        raise SynthesisError(f"{what}: branch {branch} requested, {len(dyads)} exist")
    return dyads[branch]


def four_bar_from_dyads(left: Dyad, right: Dyad, deltas: list[complex]) -> FourBarDesign:
    """Assemble a four-bar from its left (Z2, Z5; phi, gamma) and right (Z4, Z6; psi, gamma) dyads."""
    if max(abs(g1 - g2) for g1, g2 in zip(left.b, right.b)) > 1e-6:
        raise SynthesisError("left and right dyads disagree on the coupler rotations")
    Z3 = left.W - right.W
    Z1 = left.Z + left.W - right.W - right.Z
    return FourBarDesign(
        Z1=Z1,
        Z2=left.Z,
        Z3=Z3,
        Z4=right.Z,
        Z5=left.W,
        Z6=right.W,
        phi=left.a,
        gamma=left.b,
        psi=right.a,
        deltas=list(deltas),
    )


def motion_generation(
    deltas: list[complex],
    gamma: list[float],
    *,
    Z2: complex | None = None,
    Z4: complex | None = None,
    phi: list[float] | None = None,
    psi: list[float] | None = None,
    branch_left: int | None = None,
    branch_right: int | None = None,
) -> FourBarDesign:
    """Motion generation (delta_j, gamma_j given).  Per dyad, either the link vector (Z2, Z4) or
    its rotations (phi, psi; three positions, or two positions with the link vector too)."""
    left = _side(deltas, gamma, Z2, phi, branch_left, "left dyad (Z2, Z5)")
    right = _side(deltas, gamma, Z4, psi, branch_right, "right dyad (Z4, Z6)")
    return four_bar_from_dyads(left, right, deltas)


def _side(
    deltas: list[complex],
    gamma: list[float],
    Z: complex | None,
    rotations: list[float] | None,
    branch: int | None,
    what: str,
) -> Dyad:
    if rotations is not None:
        return dyad_all_rotations(deltas, rotations, gamma, Z)
    if Z is None:
        raise SynthesisError(f"{what}: give the link vector or its rotations as free choices")
    if len(deltas) == 1:
        raise SynthesisError(f"{what}: two positions need the link rotation as a free choice")
    return _pick(dyad_link_and_coupler_rotations(deltas, Z, gamma), branch, what)


def path_generation_timed(
    deltas: list[complex],
    phi: list[float],
    *,
    Z2: complex | None = None,
    gamma: list[float] | None = None,
    Z4: complex | None = None,
    psi: list[float] | None = None,
    branch_left: int | None = None,
    branch_right: int | None = None,
) -> FourBarDesign:
    """Path generation with prescribed timing (delta_j, phi_j given).  Left dyad: Z2 chosen
    (gamma found) or gamma chosen; right dyad as in motion generation with the gamma found."""
    if gamma is not None:
        left = dyad_all_rotations(deltas, phi, gamma, Z2)
    else:
        if Z2 is None:
            raise SynthesisError("left dyad (Z2, Z5): give Z2 or the coupler rotations gamma as free choices")
        if len(deltas) == 1:
            raise SynthesisError("left dyad (Z2, Z5): two positions need gamma_2 as a free choice")
        left = _pick(dyad_link_and_link_rotations(deltas, Z2, phi), branch_left, "left dyad (Z2, Z5)")
    right = _side(deltas, left.b[1:], Z4, psi, branch_right, "right dyad (Z4, Z6)")
    return four_bar_from_dyads(left, right, deltas)


def path_generation(
    deltas: list[complex],
    *,
    phi: list[float],
    gamma: list[float] | None = None,
    Z2: complex | None = None,
    Z4: complex | None = None,
    psi: list[float] | None = None,
    branch_left: int | None = None,
    branch_right: int | None = None,
) -> FourBarDesign:
    """Path generation (only delta_j given): the input rotations phi_j are free choices, after
    which it is path generation with prescribed timing."""
    return path_generation_timed(
        deltas, phi, Z2=Z2, gamma=gamma, Z4=Z4, psi=psi, branch_left=branch_left, branch_right=branch_right
    )


def function_generation(
    phi: list[float],
    psi: list[float],
    *,
    theta2: float,
    theta3: float,
    R4: float,
    gamma2: float,
    branch: int | None = None,
    scan: int = 3600,
) -> FourBarDesign:
    """Function generation at three positions, eq. (178), with the dissertation's free choices (section 6.7
    Example 2): directions Theta21, Theta31 of Z2, Z3, length R4 and coupler rotation gamma2.

    For a trial gamma3 the two complex equations are linear in R2, R3 and Z4 (four reals); the
    remaining condition |Z4| = R4 is a scalar equation in gamma3, bracketed on a scan and solved by
    Brent's method.  Only roots with R2 > 0, R3 > 0 are kept."""
    if len(phi) != 2 or len(psi) != 2:
        raise SynthesisError("function generation is implemented for three precision positions")
    e2, e3 = rot(theta2), rot(theta3)

    def linear(g3: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        rows: list[list[float]] = []
        rhs: list[float] = []
        for p, s, g in ((phi[0], psi[0], gamma2), (phi[1], psi[1], g3)):
            c = [e2 * (1 - rot(p)), e3 * (1 - rot(g)), rot(s) - 1, 1j * (rot(s) - 1)]
            rows += [[v.real for v in c], [v.imag for v in c]]
            rhs += [0.0, 0.0]
        return np.array(rows), np.array(rhs)

    def solve(g3: float) -> tuple[NDArray[np.float64], float]:
        # homogeneous in (R2, R3, X4, Y4): the null vector, scaled afterwards to |Z4| = R4
        A, _ = linear(g3)
        _, sv, vt = np.linalg.svd(A)
        v = vt[-1]
        return v, sv[-1]

    def g(g3: float) -> float:
        A, _ = linear(g3)
        det: float = np.linalg.det(A)
        return det

    grid = np.linspace(-179.0, 179.0, scan)
    values = [g(x) for x in grid]
    roots: list[float] = []
    for x0, x1, v0, v1 in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if v0 == 0 or v0 * v1 < 0:
            r = brentq(g, x0, x1, xtol=1e-13)
            if abs(r) > 1e-6 and abs(r - gamma2) > 1e-6:
                roots.append(r)
    candidates: list[tuple[float, float, float, complex]] = []
    for g3 in roots:
        v, _ = solve(g3)
        Z4 = complex(v[2], v[3])
        scale = R4 / abs(Z4)
        R2, R3 = v[0] * scale, v[1] * scale
        Z4 = Z4 * scale
        if R2 < 0:
            R2, R3, Z4 = -R2, -R3, -Z4
        if R2 <= 0 or R3 <= 0:
            continue
        candidates.append((g3, R2, R3, Z4))
    if not candidates:
        raise SynthesisError(
            "function generation: no four-bar with positive link lengths meets the "
            "specified phi/psi pairs with these free choices"
        )
    pick = min(candidates, key=lambda c: abs(c[0])) if branch is None else candidates[branch]
    g3, R2, R3, Z4 = pick
    Z2, Z3 = polar(R2, theta2), polar(R3, theta3)
    Z1 = Z2 + Z3 - Z4
    # the coupler point is not specified in function generation: it is put at the middle of the coupler
    return FourBarDesign(
        Z1=Z1,
        Z2=Z2,
        Z3=Z3,
        Z4=Z4,
        Z5=Z3 / 2,
        Z6=-Z3 / 2,
        phi=[0.0, *phi],
        gamma=[0.0, gamma2, g3],
        psi=[0.0, *psi],
        notes=[
            f"{len(candidates)} solution(s) with positive link lengths; "
            f"gamma3 = {', '.join(f'{c[0]:.4f}' for c in candidates)} deg"
        ],
    )


def four_bar_position(fb: FourBarDesign, theta2: float, near: Sequence[float]) -> tuple[float, float]:
    """(Theta3, Theta4) for input angle theta2 (deg): circle intersection, the assembly closest to
    ``near`` = (Theta3, Theta4) of a reference configuration."""
    A = polar(abs(fb.Z2), theta2)
    O4 = fb.Z1
    R3, R4 = abs(fb.Z3), abs(fb.Z4)
    d = O4 - A
    D = abs(d)
    if D > R3 + R4 or D < abs(R3 - R4):
        raise SynthesisError(f"the linkage cannot assemble at Theta2 = {theta2:.4f} deg")
    x = (D * D + R3 * R3 - R4 * R4) / (2 * D)
    h = math.sqrt(max(R3 * R3 - x * x, 0.0))
    best: tuple[float, float, float] | None = None
    for s in (1.0, -1.0):
        B = A + (x + s * 1j * h) * d / D
        t3, t4 = arg_deg(B - A), arg_deg(B - O4)
        dist = abs(_wrap(t3 - near[0])) + abs(_wrap(t4 - near[1]))
        if best is None or dist < best[0]:
            best = (dist, t3, t4)
    assert best is not None  # set by the first intersection
    return best[1], best[2]


@dataclass
class SliderCrankDesign:
    """Crank Z2 (O2->A), coupler Z3 (A->slider pin C), slider axis along Theta1 through O2 (offset 0):
    Z2 + Z3 = Z11 at position 1; slider displacement delta_j along the axis [bapat2015, Figs 7.2-7.4]."""

    Z11: complex
    Z2: complex
    Z3: complex
    phi: list[float]
    gamma: list[float]
    deltas: list[complex]
    theta1: float = 0.0

    def angles(self, j: int) -> tuple[float, float]:
        return arg_deg(self.Z2) + self.phi[j], arg_deg(self.Z3) + self.gamma[j]

    def vectors(self) -> dict[str, complex]:
        return {"Z11": self.Z11, "Z2": self.Z2, "Z3": self.Z3}


def slider_crank_timed(
    delta: float,
    phi2: float,
    *,
    R2: float,
    theta3: float,
    theta1: float = 0.0,
    offset: float = 0.0,
    branch: int | None = None,
) -> SliderCrankDesign:
    """Two-position slider-crank path generation with prescribed timing [bapat2015, ch. 7, Example 1]:
    the slider pin moves delta along the axis while the crank turns phi2.  Free choices R2, Theta31.
    Unknowns Theta21, R3, gamma2 from the dyad  Z2 (e^{i phi2} - 1) + Z3 (e^{i gamma2} - 1) = delta e^{i theta1}
    and the offset condition Im[(Z2 + Z3) e^{-i theta1}] = offset: for a trial Theta21 the dyad is
    solved by ``dyad_link_and_direction``; the offset residual is then a scalar equation in Theta21."""
    axis = rot(theta1)

    def build(t21: float) -> tuple[Dyad, float]:
        d = dyad_link_and_direction(delta * axis, polar(R2, t21), phi2, theta3)
        return d, ((d.Z + d.W) / axis).imag - offset

    def g(t21: float) -> float:
        try:
            return build(t21)[1]
        except SynthesisError:
            return math.nan

    grid = np.linspace(-180.0, 180.0, 1441)
    vals = [g(t) for t in grid]
    roots: list[float] = []
    for x0, x1, v0, v1 in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if np.isfinite(v0) and np.isfinite(v1) and v0 * v1 < 0 and abs(v0 - v1) < 2 * R2 + 10 * abs(delta):
            roots.append(brentq(g, x0, x1, xtol=1e-13))
    sols: list[Dyad] = []
    for t21 in roots:
        d, res = build(t21)
        if abs(res) < 1e-8 and ((d.Z + d.W) / axis).real > 0:
            sols.append(d)
    if not sols:
        raise SynthesisError("slider-crank: no crank angle closes the loop with these free choices")
    if branch is None:
        d = min(sols, key=lambda s: abs(s.W))
    elif 0 <= branch < len(sols):
        d = sols[branch]
    else:
        raise SynthesisError(f"slider-crank: branch {branch} requested, {len(sols)} exist")
    return SliderCrankDesign(Z11=(d.Z + d.W), Z2=d.Z, Z3=d.W, phi=d.a, gamma=d.b, deltas=[delta * axis], theta1=theta1)


def slider_position(sc: SliderCrankDesign, x: float, near: tuple[float, float]) -> tuple[float, float]:
    """(Theta2, Theta3) with the slider pin at x along the axis from O2 (offset 0), closest to ``near``."""
    R2, R3 = abs(sc.Z2), abs(sc.Z3)
    C = x * rot(sc.theta1)
    D = abs(C)
    if D > R2 + R3 or D < abs(R2 - R3):
        raise SynthesisError(f"the slider-crank cannot assemble with the slider at {x:.4f}")
    a = (D * D + R2 * R2 - R3 * R3) / (2 * D)
    h = math.sqrt(max(R2 * R2 - a * a, 0.0))
    best: tuple[float, float, float] | None = None
    for s in (1.0, -1.0):
        A = (a + s * 1j * h) * C / D
        t2, t3 = arg_deg(A), arg_deg(C - A)
        dist = abs(_wrap(t2 - near[0])) + abs(_wrap(t3 - near[1]))
        if best is None or dist < best[0]:
            best = (dist, t2, t3)
    assert best is not None  # set by the first intersection
    return best[1], best[2]
