"""End forces that turn as the structure deflects, on the one-spring PRBMs of [bapat2015] and
[ananthasuresh_l18]: a follower force,
a rope to a fixed point, a force at a fixed angle to the line to a fixed point.

A load law gives the unit direction u of the force at a pose of the loaded point (``TipPose``: its
position z and the rotation of the end tangent from the unloaded pose):

    dead:               u = u0
    follower:           u = u0 e^{i theta0}                 (keeps its angle to the end tangent)
    toward a point D:   u = e^{i alpha} (D - z)/|D - z|     (a rope over a pulley at D for alpha = 0;
                                                             alpha = -90 deg keeps it perpendicular to
                                                             the line to D, clockwise from it)

Fixed-pinned segment (``fixed_pinned_turning_tip``).  At equilibrium the beam carries, at that state,
a dead end force F u.  The dissertation's fixed-pinned PRBM of a dead end force ([bapat2015, eqs 41-49]: the
n-fits gamma, c_theta, K_Theta at n = -u_x/u_y; (F l^2/EI) sin(phi - Theta) = K_Theta Theta (46)-(47);
a = l - gamma l (1 - cos Theta) (48); b = gamma l sin Theta (49); theta0 = c_theta Theta (44)) places
the tip; the turning load is in equilibrium when the law at that tip gives back the same u:

    r(psi) = arg( law(tip(F e^{i psi})) e^{-i psi} ) = 0,                                    (*)

one equation in the force's direction angle psi, solved by Brent's method on the sign change of r
nearest to the direction at the unloaded tip (scanned both ways in steps of ``step``).  So the fits
are evaluated at the load ratio of the force that acts at equilibrium, and every root satisfies the
PRBM equilibrium about the characteristic pivot (spring k = gamma K_Theta EI/l, eq 45),
k Theta = gamma l (F_y cos Theta - F_x sin Theta) with (F_x, F_y) = F u.  A root that needs a load ratio outside the fits' range raises
``FitRangeError``.  As F -> 0 the answer tends to the dead force u(unloaded tip): tip deflection
F_perp l^3 gamma/(K_Theta EI), the linear beam's F_perp l^3/(3 EI) times 3 gamma/K_Theta.

Four-bar input link (``input_angle_under_turning_forces``).  Link 2 of a PRB four-bar turns about the
characteristic pivot O2 (the origin of the four-bar's frame); its end A = R2 e^{i theta2} is the
segment tip, whose end tangent has turned by c_theta (theta2 - theta20) (eq 44 with Theta = theta2 -
theta20).  With one degree of freedom, virtual work on theta2 gives the equilibrium

    dU/dtheta2 (eq 182) = T + sum Im( conj(A) F u(A, c_theta (theta2 - theta20)) ),          (**)

the spring torque against the couple T plus the moment about O2 of the forces at A, whatever their law
(a follower force is not conservative, but the static balance is this virtual-work balance at the
current state).  Solved by Brent's method on the first sign change from theta20 in the direction the
load turns link 2.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import cmath
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from prbm.fits import FitRangeError, fit_family
from prbm.result import Levels, PRBMResult
from prbm.segments import fixed_pinned_tip

__all__ = [
    "TipPose",
    "DeadDirection",
    "FollowerDirection",
    "TowardPoint",
    "fixed_pinned_turning_tip",
    "input_angle_under_turning_forces",
]


@dataclass(frozen=True)
class TipPose:
    """The loaded point z (complex, the model's frame) and its end tangent's rotation from the
    unloaded pose (rad)."""

    z: complex
    rotation: float


class LoadLaw(Protocol):
    def direction(self, pose: TipPose) -> complex:
        """The force's unit direction (complex) at this pose."""


class InputLink(Protocol):
    """What ``input_angle_under_turning_forces`` reads of a PRB four-bar (``prbm.mechanisms.FourBar``): the
    input link's length R2 and the spring torque that holds the linkage at input angles theta2 (rad)."""

    R2: float

    def input_torque(self, theta2: NDArray[Any]) -> NDArray[np.float64]:
        """The torque on the input link holding the linkage at each of the angles theta2."""


def _unit(u: complex, what: str) -> complex:
    size = abs(u)
    if not (size > 0.0 and math.isfinite(size)):
        raise ValueError(f"{what}: the direction must be a finite non-zero vector, got {u}")
    return u / size


@dataclass(frozen=True)
class DeadDirection:
    """A force of fixed direction ``u0``."""

    u0: complex

    def direction(self, pose: TipPose) -> complex:
        return _unit(self.u0, "DeadDirection")


@dataclass(frozen=True)
class FollowerDirection:
    """A force that keeps its angle to the end tangent: ``u0`` in the unloaded pose, turned with it."""

    u0: complex

    def direction(self, pose: TipPose) -> complex:
        if not math.isfinite(pose.rotation):
            raise ValueError(
                "FollowerDirection: the end tangent's rotation is not available (a fit family without c_theta)"
            )
        return _unit(self.u0, "FollowerDirection") * cmath.exp(1j * pose.rotation)


@dataclass(frozen=True)
class TowardPoint:
    """A force pulling from the loaded point toward the fixed ``point``, turned by ``angle`` (rad, CCW)."""

    point: complex
    angle: float = 0.0

    def direction(self, pose: TipPose) -> complex:
        line = complex(self.point) - pose.z
        if abs(line) <= 1e-12 * max(abs(pose.z), abs(self.point), 1.0):
            raise ValueError(
                "TowardPoint: the loaded point is at the point the force pulls toward (direction undefined)"
            )
        return cmath.exp(1j * self.angle) * line / abs(line)


@dataclass(frozen=True)
class _SegmentModel:
    length: float
    EI: float
    family: str
    extrapolate: str

    def tip(self, F: float, psi: float) -> PRBMResult:
        """The fixed-pinned PRBM under the dead end force F e^{i psi} (eqs 41-49)."""
        s, c = math.sin(psi), math.cos(psi)
        if abs(s) < 1e-12:
            raise FitRangeError(
                f"end force along the segment (direction {math.degrees(psi):.3f} deg): n infinite, outside every n-fit"
            )
        return fixed_pinned_tip(
            F * s, -c / s, length=self.length, EI=self.EI, family=self.family, extrapolate=self.extrapolate
        )


def _pose(res: PRBMResult) -> TipPose:
    o = res.outputs
    return TipPose(complex(float(o["a"]), float(o["b"])), float(o["theta0"]))


def _mismatch(model: _SegmentModel, F: float, psi: float, law: LoadLaw) -> float:
    """r(psi) of (*): the law's direction at the PRBM tip against psi (rad); nan outside the fits."""
    try:
        res = model.tip(F, psi)
    except FitRangeError:
        return math.nan
    return cmath.phase(law.direction(_pose(res)) * cmath.exp(-1j * psi))


def _nearest_root(
    r: Callable[[float], float], start: float, step: float, span: float
) -> tuple[tuple[float, float] | None, bool]:
    """(the bracket of the sign change of r nearest to ``start``, scanned both ways, or None; whether a
    scanned point fell outside the fits (r = nan))."""
    r0 = r(start)
    if r0 == 0.0:
        return (start, start), False
    outside = not math.isfinite(r0)
    last = {+1: (start, r0), -1: (start, r0)}
    for k in range(1, int(span / step) + 1):
        for side in (+1, -1):
            x = start + side * k * step
            rx = r(x)
            x_prev, r_prev = last[side]
            last[side] = (x, rx)
            if not (math.isfinite(rx) and math.isfinite(r_prev)):
                outside |= not math.isfinite(rx)
                continue
            if abs(rx) < math.pi / 2 and abs(r_prev) < math.pi / 2 and (rx == 0.0 or (rx > 0) != (r_prev > 0)):
                return ((x_prev, x) if side > 0 else (x, x_prev)), outside
    return None, outside


def _segment_level(
    model: _SegmentModel, F: float, law: LoadLaw, step: float, span: float
) -> tuple[PRBMResult | None, float, str]:
    """(result at equilibrium or None, psi, message) of one load level; raises FitRangeError when the
    only directions left unscanned are outside the fits."""
    if F < 0.0:  # a negative magnitude: the force F u = |F| (-u)
        F, law = -F, _Reversed(law)
    psi0 = cmath.phase(law.direction(TipPose(complex(model.length, 0.0), 0.0)))
    if F == 0.0:
        return None, psi0, "no load"

    def r(psi: float) -> float:
        return _mismatch(model, F, psi, law)

    bracket, outside = _nearest_root(r, psi0, step, span)
    if bracket is None:
        if outside:
            raise FitRangeError(
                f"turning end force |F| = {F:g}: no equilibrium direction inside the n-fits' range (seed 000 eqs 41-43)"
            )
        return None, math.nan, f"turning end force |F| = {F:g}: no equilibrium direction found"
    lo, hi = bracket
    psi = lo if lo == hi else brentq(r, lo, hi, xtol=1e-14)
    return model.tip(F, psi), psi, "converged"


@dataclass(frozen=True)
class _Reversed:
    law: LoadLaw

    def direction(self, pose: TipPose) -> complex:
        return -self.law.direction(pose)


def fixed_pinned_turning_tip(
    F: ArrayLike,
    law: LoadLaw,
    *,
    length: float,
    EI: float,
    family: str = "pauly-midha",
    extrapolate: str = "raise",
    step: float = math.radians(0.5),
    span: float = math.pi,
) -> PRBMResult:
    """Tip of an initially straight fixed-pinned (fixed-free) segment under the end force F u, u given by
    ``law`` at the deflected tip (see the module docstring, eq (*)).  F: magnitude per level (a negative
    value reverses the law's direction).  Outputs per level: a, b, theta0 (rad), Theta (rad), Fx, Fy (the
    force acting at equilibrium), n; constants gamma, c_theta, K_theta, k at that n."""
    t0 = time.perf_counter()
    if not (length > 0 and EI > 0 and math.isfinite(length) and math.isfinite(EI)):
        raise ValueError(f"fixed_pinned_turning_tip: length and EI must be finite and > 0, got {length}, {EI}")
    model = _SegmentModel(float(length), float(EI), family, extrapolate)
    levels = np.atleast_1d(np.asarray(F, float))
    if not np.all(np.isfinite(levels)):
        raise ValueError(f"fixed_pinned_turning_tip: F must be finite, got {F!s}")
    keys = ("a", "b", "theta0", "Theta", "Fx", "Fy", "n", "gamma", "c_theta", "K_theta", "k")
    rows, ok, messages = [], [], []
    for f in levels.tolist():
        res, psi, message = _segment_level(model, f, law, step, span)
        messages.append(message)
        ok.append(res is not None or f == 0.0)
        rows.append(_row(model, res, f, psi))
    table: dict[str, Levels] = {k: np.array([row[k] for row in rows]) for k in keys}
    constants: dict[str, Any] = {k: table.pop(k) for k in ("gamma", "c_theta", "K_theta", "k")}
    constants["family"] = fit_family(family).name
    all_ok = all(ok)
    failures = "; ".join(m for m, level_ok in zip(messages, ok) if not level_ok)
    return PRBMResult(
        all_ok,
        "converged" if all_ok else failures,
        table,
        constants,
        "fixed-pinned under a turning end force, seed 000 eqs (41)-(49) at the equilibrium load ratio",
        time.perf_counter() - t0,
        0,
        np.array(ok),
    )


def _row(model: _SegmentModel, res: PRBMResult | None, F: float, psi: float) -> dict[str, float]:
    if res is None:
        nan = math.nan
        unloaded = F == 0.0
        return {
            "a": model.length if unloaded else nan,
            "b": 0.0 if unloaded else nan,
            "theta0": 0.0 if unloaded else nan,
            "Theta": 0.0 if unloaded else nan,
            "Fx": 0.0 if unloaded else nan,
            "Fy": 0.0 if unloaded else nan,
            "n": nan,
            "gamma": nan,
            "c_theta": nan,
            "K_theta": nan,
            "k": nan,
        }
    o, c = res.outputs, res.constants
    magnitude = abs(F)
    return {
        "a": float(o["a"]),
        "b": float(o["b"]),
        "theta0": float(o["theta0"]),
        "Theta": float(o["Theta"]),
        "Fx": magnitude * math.cos(psi),
        "Fy": magnitude * math.sin(psi),
        "n": float(o["n"]),
        "gamma": float(c["gamma"]),
        "c_theta": float(c["c_theta"]),
        "K_theta": float(c["K_theta"]),
        "k": float(c["k"]),
    }


def input_angle_under_turning_forces(
    fourbar: InputLink,
    forces: Sequence[tuple[float, LoadLaw]],
    *,
    theta20: float,
    c_theta: float,
    torque: float = 0.0,
    span: float = math.radians(120),
) -> float:
    """Input angle theta2 (rad) of the PRB four-bar ``fourbar`` (O2 at the origin of its frame) where the
    spring torque balances the couple ``torque`` plus the moment about O2 of the forces F u at the end A
    of link 2, u = law(A, c_theta (theta2 - theta20)) for each (F, law) (eq (**)).  The first root from
    theta20 in the direction the load turns link 2; nan if none within ``span``."""
    R2 = fourbar.R2

    def load_moment(t: float) -> float:
        A = R2 * cmath.exp(1j * t)
        pose = TipPose(A, c_theta * (t - theta20))
        return sum((A.conjugate() * F * law.direction(pose)).imag for F, law in forces)

    def unbalanced_grid(ts: NDArray[np.float64]) -> NDArray[np.float64]:
        r: NDArray[np.float64] = (
            np.asarray(fourbar.input_torque(ts), float) - torque - np.array([load_moment(t) for t in ts.tolist()])
        )
        return r

    def unbalanced(t: float) -> float:
        return float(unbalanced_grid(np.array([t]))[0])

    start = -unbalanced(theta20)
    if start == 0.0:
        return theta20
    grid = theta20 + math.copysign(1.0, start) * np.linspace(0.0, span, 241)
    r = unbalanced_grid(grid)
    idx = np.nonzero(np.isfinite(r[:-1]) & np.isfinite(r[1:]) & (np.sign(r[:-1]) != np.sign(r[1:])))[0]
    if len(idx) == 0:
        return math.nan
    theta2: float = brentq(unbalanced, grid[idx[0]], grid[idx[0] + 1], xtol=1e-14)
    return theta2
