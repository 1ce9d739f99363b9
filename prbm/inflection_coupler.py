"""Fixed-guided segments with one inflection point each, joined by one rigid coupler (seed 000 ch. 5).

The fully-compliant "Type A" mechanisms of seed 000 section 5.5 (Examples 2 and 3): every segment j
is clamped at its root O_j and rigidly attached at its end E_j to one rigid coupler that carries the
coupler point P.  Each segment is the chapter-3/5 PRBM of a fixed-guided beam with one inflection
point (three pivots: two characteristic pivots and the instantaneous pin at the inflection point;
seed 000 eqs (131)-(152) = (83)-(104), ``prbm.inflection``).

Forward model (the seed's verification: "specifying the transverse deflection and rotation of the
rigid coupler", Tables 5.5-5.6).  The coupler is given its X motion and rotation gamma; its Y motion
is free and carries no external force.  For a trial Y the coupler pose fixes every segment end:

    E_j = P + (E_j0 - P_0) e^{i gamma},   z_j = (E_j - O_j) e^{-i theta1_j},
    a_j = Re z_j,  b_j = Im z_j,  theta0_j = gamma                       (the vector loop of eq 154)

with theta1_j = arg(E_j0 - O_j) the undeformed segment direction (eq 156).  The displacement-specified
problem of each segment (case 1: a, b, theta0 -> P, nP, M; ``solve_displacements``, eqs (143)-(152))
gives the end load (-nP, P) applied to the beam in its own frame; in the global frame
F_j = (-nP_j + i P_j) e^{i theta1_j} (eqs (171)-(172)).  The coupler receives -F_j from each segment, so
its free Y direction is in equilibrium when

    sum_j Im F_j = 0,                                                    (the Y-free condition)

one equation in Y, solved by a scan for a sign change and Brent's method.  The strain energy is the
PRBM springs' (eq 165, = (1/2) sum k_i Theta_i^2 per segment).  A segment with b < 0 is solved as
its mirror image (b, theta0 -> -b, -theta0), which flips P, M and the angles and keeps nP.

Validity: each segment's root must be valid in ``prbm.inflection`` (load ratios n, n2 inside the fits'
range -4 < n <= 10, 0 < l1 < l, Theta_i > 0); where a trial Y admits no valid root for some segment,
the residual is undefined there, and a pose with no valid Y is reported as not converged with the
reason (never a placeholder).
"""
from __future__ import annotations

import cmath
import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from prbm.inflection import InflectionBeam, solve_displacements
from prbm.result import PRBMResult

__all__ = ["GuidedSegment", "CouplerPose", "SegmentState", "segment_state", "coupler_y_force", "solve_y_free"]

MODEL = ("fixed-guided segments with one inflection point (seed 000 eqs (131)-(152)) on one rigid coupler, "
         "coupler X and rotation prescribed, Y free (seed 000 section 5.5)")


@dataclass(frozen=True)
class GuidedSegment:
    """One segment: root O (clamped), end E0 on the coupler in the unloaded pose (global, complex),
    bending stiffness EI; its length is |E0 - O| and its direction theta1 = arg(E0 - O)."""

    name: str
    root: complex
    end: complex
    EI: float
    family: str = "pauly-midha"

    @property
    def length(self) -> float:
        return abs(self.end - self.root)

    @property
    def theta1(self) -> float:
        return cmath.phase(self.end - self.root)


@dataclass(frozen=True)
class CouplerPose:
    """The coupler's motion from its unloaded pose: translation (dx, dy) of the point P0, rotation gamma (rad)."""

    point: complex
    dx: float
    dy: float
    gamma: float


@dataclass
class SegmentState:
    """One segment at one coupler pose: the end in its own frame, the PRBM loads, validity."""

    segment: GuidedSegment
    a: float
    b: float
    theta0: float
    valid: bool
    message: str
    P: float = math.nan          # transverse end force on the beam (segment frame)
    nP: float = math.nan         # axial (compressive +) end force on the beam
    moment: float = math.nan     # CCW end moment on the beam
    energy: float = math.nan     # PRBM spring energy
    l1: float = math.nan
    roots: int = 0
    extras: dict = field(default_factory=dict)

    @property
    def force(self) -> complex:
        """End force on the beam, global frame: (-nP + i P) e^{i theta1} (eqs 171-172)."""
        return complex(-self.nP, self.P) * cmath.exp(1j * self.segment.theta1)


def segment_end(seg: GuidedSegment, pose: CouplerPose) -> tuple[float, float, float]:
    """(a, b, theta0) of the segment end in its own frame for a coupler pose (the vector loop, eq 154)."""
    E = segment_tip(seg, pose.point + complex(pose.dx, pose.dy), pose.point, pose.gamma)
    z = (E - seg.root) * cmath.exp(-1j * seg.theta1)
    return z.real, z.imag, pose.gamma


def segment_state(seg: GuidedSegment, pose: CouplerPose, *, prefer="energy") -> SegmentState:
    """The chapter-3 case-1 problem (a, b, theta0 -> P, nP, M) of one segment at a coupler pose."""
    a, b, theta0 = segment_end(seg, pose)
    sign = -1.0 if b < 0 else 1.0
    beam = InflectionBeam(seg.length, seg.EI, seg.family)
    res = solve_displacements(beam, a=a, b=sign * b, theta0=sign * theta0, prefer=prefer)
    if not res.converged:
        return SegmentState(seg, a, b, theta0, False, f"segment '{seg.name}': {res.message}")
    o = res.outputs
    # eq (147)'s M opposes P (clockwise for P > 0): the CCW moment on the beam is -M; mirrored: P, M flip
    return SegmentState(seg, a, b, theta0, True, res.message, P=sign * float(o["P"]), nP=float(o["nP"]),
                        moment=-sign * float(o["M"]), energy=float(o["U"]), l1=float(o["l1"]),
                        roots=len(res.roots[0]),
                        extras={"Theta1": float(o["Theta1"]), "Theta2": float(o["Theta2"]), "n": float(o["n"]),
                                "n2": float(o["n2"])})


def coupler_y_force(segments: list[GuidedSegment], pose: CouplerPose) -> tuple[float, list[SegmentState]]:
    """sum_j Im F_j, the Y force the segments need from the coupler (NaN where a segment has no valid root)."""
    states = [segment_state(s, pose) for s in segments]
    if not all(st.valid for st in states):
        return math.nan, states
    return sum(st.force.imag for st in states), states


def solve_y_free(segments: list[GuidedSegment], point: complex, dx: float, gamma: float, *,
                 span: float | None = None, samples: int = 41) -> PRBMResult:
    """The coupler Y at which the Y force vanishes, for prescribed dx and gamma (rad).

    Scans dy over [-span, span] (default half the shortest segment) for a sign change of
    ``coupler_y_force`` between two valid samples, the one nearest dy = 0 first, then Brent's method.
    Outputs: dy, dx, gamma, strain_energy (sum of the segments' PRBM springs), Fx, moment (the
    coupler's prescribed-motion reactions: the load the mechanism needs at P, global, moment CCW about P).
    """
    t0 = time.perf_counter()
    span = span if span is not None else 0.5 * min(s.length for s in segments)
    grid = np.linspace(-span, span, samples)
    grid = grid[np.argsort(np.abs(grid))]  # nearest the unloaded Y first
    values = {}

    def f(dy: float) -> float:
        if dy not in values:
            values[dy] = coupler_y_force(segments, CouplerPose(point, dx, dy, gamma))[0]
        return values[dy]

    ordered = np.sort(grid)
    [f(float(y)) for y in ordered]
    brackets = [(float(y0), float(y1)) for y0, y1 in zip(ordered[:-1], ordered[1:])
                if np.isfinite(f(float(y0))) and np.isfinite(f(float(y1))) and f(float(y0)) * f(float(y1)) <= 0]
    wall = time.perf_counter() - t0
    if not brackets:
        valid = sum(np.isfinite(v) for v in values.values())
        reason = (f"no Y in [-{span:.4g}, {span:.4g}] balances the coupler: the Y force keeps one sign over the "
                  f"{valid} of {samples} trial Y with a valid PRBM root for every segment")
        return PRBMResult(False, reason, {}, {}, MODEL, wall, len(values), np.array([False]))
    y0, y1 = min(brackets, key=lambda br: abs(br[0] + br[1]))
    dy = brentq(f, y0, y1, xtol=1e-12 * span, rtol=1e-12) if f(y0) * f(y1) < 0 else (y0 if f(y0) == 0 else y1)
    force, states = coupler_y_force(segments, CouplerPose(point, dx, dy, gamma))
    scale = max(abs(st.force) for st in states)
    ok = abs(force) <= 1e-6 * max(scale, 1e-300)
    P = point + complex(dx, dy)
    # the coupler's equilibrium: the load it needs at P is what the segment ends receive from it
    Fx = sum(st.force.real for st in states)
    moment = sum(st.moment + _cross(segment_tip(st.segment, P, point, gamma) - P, st.force) for st in states)
    out = {"dx": np.asarray(dx), "dy": np.asarray(dy), "gamma": np.asarray(gamma),
           "strain_energy": np.asarray(sum(st.energy for st in states)), "Fx": np.asarray(Fx),
           "moment": np.asarray(moment)}
    message = (f"Y-free coupler: {len(brackets)} sign change(s) of the Y force in the scan; "
               + "; ".join(f"{st.segment.name}: {st.message}, n = {st.extras['n']:.3g}" for st in states))
    if not ok:
        message = f"Y force {force:.3g} left at the bracket (a jump between PRBM roots, not a root); " + message
    return PRBMResult(ok, message, out, {"segments": [s.name for s in segments]}, MODEL,
                      time.perf_counter() - t0, len(values), np.array([ok]),
                      extras={"states": states, "brackets": brackets, "span": span})


def segment_tip(seg: GuidedSegment, P: complex, point0: complex, gamma: float) -> complex:
    """The segment end E (global) with the coupler point at P and the coupler turned by gamma."""
    return P + (seg.end - point0) * cmath.exp(1j * gamma)


def _cross(r: complex, F: complex) -> float:
    """The planar cross product r x F."""
    return r.real * F.imag - r.imag * F.real
