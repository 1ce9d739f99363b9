"""Fixed-guided segments with one inflection point each, joined by one rigid coupler [bapat2015, ch. 5].

The fully-compliant "Type A" mechanisms of [bapat2015, §5.5] (Examples 2 and 3): every segment j
is clamped at its root O_j and rigidly attached at its end E_j to one rigid coupler that carries the
coupler point P.  Each segment is the chapter-3/5 PRBM of a fixed-guided beam with one inflection
point (three pivots: two characteristic pivots and the instantaneous pin at the inflection point;
[bapat2015, eqs 131-152] = (83)-(104), ``prbm.inflection``).

Forward model (the dissertation's verification: "specifying the transverse deflection and rotation of the
rigid coupler", Tables 5.5-5.6).  The coupler point is moved by s along a unit direction u and the
coupler turned by gamma; its motion t along w = i u is free and carries no external force.  For a
trial t the coupler pose fixes every segment end (the vector loop of eq 154):

    P = P_0 + s u + t w,   E_j = P + (E_j0 - P_0) e^{i gamma},   z_j = (E_j - O_j) e^{-i theta1_j},
    a_j = Re z_j,  b_j = Im z_j,  theta0_j = gamma,

with theta1_j = arg(E_j0 - O_j) the undeformed segment direction (eq 156).  The displacement-specified
problem of each segment (case 1: a, b, theta0 -> P, nP, M; ``solve_displacements``, eqs (143)-(152))
gives the end load (-nP, P) applied to the beam in its own frame, F_j = (-nP_j + i P_j) e^{i theta1_j}
in the global frame (eqs (171)-(172)).  The coupler receives -F_j from each segment, so its free
direction is in equilibrium when

    sum_j Re(conj(w) F_j) = 0,                                           (the free-direction condition)

one equation in t.  The strain energy is the PRBM springs' (eq 165, = (1/2) sum k_i Theta_i^2 per
segment).  A segment with b < 0 is solved as its mirror image (b, theta0 -> -b, -theta0), which flips
P, M and the angles and keeps nP.

Where each segment can be.  Inside the fits' range (-4 < n <= 10, eqs 131-140) the PRBM is nearly
inextensible: for a given (b, theta0) its end coordinate a moves only a little as n runs over the range
(the axial force is bounded by n).  So each segment reaches only a window of t, found by the case-2
problem (b, theta0, n -> a; Tables 3.4-3.5) at load ratios across the range (``reachable_window``).
A coupler whose segments' windows do not overlap has no PRBM state within the fits: that is reported
as not converged with both windows (never a placeholder); otherwise the equilibrium is found by a scan
of the overlap for a sign change and Brent's method.

Speed: along a scan each segment's solve is continued from its previous root (MINPACK hybrd from the
last state, in 1, 4 or 16 steps of the given end), the multistart of ``prbm.inflection`` the fallback;
a continued root is accepted only when it is valid by the same rules, so where several valid roots
exist the one reported is the one the scan follows.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import cmath
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq, root

from prbm.inflection import InflectionBeam, _point_ends, _point_force, _point_state, _valid, solve_displacements
from prbm.result import Levels, PRBMResult

__all__ = [
    "GuidedSegment",
    "CouplerDrive",
    "SegmentState",
    "Window",
    "segment_state",
    "reachable_window",
    "free_force",
    "solve_coupler",
]

MODEL = (
    "fixed-guided segments with one inflection point (seed 000 eqs (131)-(152)) on one rigid coupler, "
    "one coupler translation and its rotation prescribed, the other translation free (seed 000 section 5.5)"
)
RATIOS = (-3.95, -3.0, -2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0)

#: the variables of eqs (131)-(152) at one point in plain floats: every one (``_point_state``), or only
#: r96, a and b (``_point_ends``); arguments (beam, F, phi1, theta0, l1, theta10)
Equations: TypeAlias = Callable[[InflectionBeam, float, float, float, float, float], dict[str, float]]
#: the end (a, b, theta0) of a segment, in its frame, at the free translation t
Ends: TypeAlias = Callable[[float], tuple[float, float, float]]
#: the residuals of a warm-started problem at x, and the state there, with the given equations
WarmResidual: TypeAlias = Callable[
    [Sequence[float] | NDArray[np.float64], Equations], tuple[NDArray[np.float64], dict[str, float]]
]


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

    def beam(self) -> InflectionBeam:
        return InflectionBeam(self.length, self.EI, self.family)


@dataclass(frozen=True)
class CouplerDrive:
    """The coupler's prescribed motion: point P0 moved by s along the unit direction ``along``, the
    coupler turned by gamma (rad); the translation t along i * along is free."""

    point: complex
    along: complex
    s: float
    gamma: float

    @property
    def free(self) -> complex:
        return 1j * self.along / abs(self.along)

    def position(self, t: float) -> complex:
        return self.point + self.s * self.along / abs(self.along) + t * self.free

    def end(self, seg: GuidedSegment, t: float) -> complex:
        """E_j (global) at the free translation t."""
        return self.position(t) + (seg.end - self.point) * cmath.exp(1j * self.gamma)

    def segment_end(self, seg: GuidedSegment, t: float) -> tuple[float, float, float]:
        """(a, b, theta0) of the segment end in the segment's frame (eq 154)."""
        z = (self.end(seg, t) - seg.root) * cmath.exp(-1j * seg.theta1)
        return z.real, z.imag, float(self.gamma)


@dataclass
class SegmentState:
    """One segment at one coupler pose: the end in its own frame, the PRBM end loads, validity."""

    segment: GuidedSegment
    a: float
    b: float
    theta0: float
    valid: bool
    message: str
    P: float = math.nan  # transverse end force on the beam (segment frame)
    nP: float = math.nan  # axial end force on the beam, compressive positive
    moment: float = math.nan  # CCW end moment on the beam
    energy: float = math.nan  # PRBM spring energy (eq 165)
    n: float = math.nan
    l1: float = math.nan

    @property
    def force(self) -> complex:
        """End force on the beam, global frame: (-nP + i P) e^{i theta1} (eqs 171-172)."""
        return complex(-self.nP, self.P) * cmath.exp(1j * self.segment.theta1)


@dataclass(frozen=True)
class Window:
    """The free translations t a segment reaches with n inside the fits (t at each load ratio tried)."""

    segment: str
    t: tuple[float, ...]
    ratios: tuple[float, ...]

    @property
    def empty(self) -> bool:
        return not self.t

    @property
    def low(self) -> float:
        return min(self.t)

    @property
    def high(self) -> float:
        return max(self.t)


class _Warm:
    """A segment's last PRBM root, to start the next solve from (the states along a scan are close);
    the multistart solve of ``prbm.inflection`` is the fallback when the warm start fails or gives an
    invalid root, so the answer is the same, only found faster."""

    def __init__(self) -> None:
        self.x: NDArray[np.float64] | None = None
        self.t: float | None = None  # the free translation of the last case-1 root
        self.given: NDArray[np.float64] | None = None  # (n, b, theta0) of the last case-2 root

    def case1(self, beam: InflectionBeam, ends: Ends, t: float) -> tuple[dict[str, float], str] | str:
        """The case-1 state at the free translation t (``ends(t)`` = (a, b, theta0) as solved) and how it
        was found: continued from the last root in 1, 4 or 16 steps of t, else the multistart; or the
        multistart's message."""
        if self.x is not None and self.t is not None:
            for steps in (1, 4, 16):
                state = self._continue(beam, ends, self.x, self.t, t, steps)
                if state is not None:
                    return state, "valid (warm start)"
        a, b, theta0 = ends(t)
        res = solve_displacements(beam, a=a, b=b, theta0=theta0)
        if not res.converged:
            return res.message
        o = res.outputs
        self.x, self.t = np.array([float(o["phi1"]), float(o["l1"]) / beam.length, float(o["theta10"])]), t
        return {k: float(v) for k, v in o.items()}, res.message

    def _continue(
        self, beam: InflectionBeam, ends: Ends, x0: NDArray[np.float64], t0: float, t: float, steps: int
    ) -> dict[str, float] | None:
        """The case-1 state at t continued from the root x0 at t0 in ``steps`` steps of t; None if a step fails."""
        x, state = x0, None
        for k in range(1, steps + 1):
            a, b, theta0 = ends(t0 + (t - t0) * k / steps)
            state = _warm_root(beam, x, lambda y, eqs: _case1_residual(beam, y, a, b, theta0, eqs), 3)
            if state is None:
                return None
            x = np.array([state["phi1"], state["l1"] / beam.length, state["theta10"]])
        self.x, self.t = x, t
        return state

    def case2(self, beam: InflectionBeam, b: float, theta0: float, n: float) -> dict[str, float] | None:
        """(b, theta0, n) -> the state dict of the valid root, or None: continued from the last case-2 root
        in 1, 4 or 16 steps of (n, b, theta0), else the multistart."""
        given = np.array([n, b, theta0])
        if self.x is not None and self.given is not None:
            for steps in (1, 4, 16):
                x, state = self.x[1:], None
                for k in range(1, steps + 1):
                    nk, bk, thk = (self.given + (given - self.given) * k / steps).tolist()
                    phi1 = math.atan2(1.0, -nk)
                    state = _warm_root(
                        beam, x, lambda y, eqs: _case1_residual(beam, [phi1, *y], None, bk, thk, eqs), 2, phi1=phi1
                    )
                    if state is None:
                        break
                    x = np.array([state["l1"] / beam.length, state["theta10"]])
                if state is not None:
                    self.x, self.given = np.r_[math.atan2(1.0, -n), x], given
                    return state
        res = solve_displacements(beam, b=b, theta0=theta0, n=n)
        if not res.converged:
            return None
        o = res.outputs
        self.x, self.given = np.array([math.atan2(1.0, -n), float(o["l1"]) / beam.length, float(o["theta10"])]), given
        return {k: float(v) for k, v in o.items()}


def _state(
    beam: InflectionBeam,
    phi1: float,
    l1_ratio: float,
    theta10: float,
    theta0: float,
    equations: Equations = _point_state,
) -> dict[str, float]:
    """Every variable of eqs (131)-(152) with F from eq (143) (as ``prbm.inflection`` does), in plain floats
    (``equations=_point_ends``: only r96, a and b, what the residuals read)."""
    l1 = l1_ratio * beam.length
    return equations(beam, _point_force(beam, phi1, l1, theta10), phi1, theta0, l1, theta10)


def _case1_residual(
    beam: InflectionBeam,
    x: Sequence[float] | NDArray[np.float64],
    a: float | None,
    b: float,
    theta0: float,
    equations: Equations = _point_state,
) -> tuple[NDArray[np.float64], dict[str, float]]:
    """Residuals (144), (151), (152) (without (152) when a is None) of the state at x = (phi1, l1/l, theta10),
    and the state (every variable, or with ``equations=_point_ends`` only r96, a and b)."""
    with np.errstate(all="ignore"):
        st = _state(beam, x[0], x[1], x[2], theta0, equations)
    r = [st["r96"], (st["b"] - b) / beam.length]
    if a is not None:
        r.append((st["a"] - a) / beam.length)
    return np.array(r), st


def _warm_root(
    beam: InflectionBeam, x0: ArrayLike, residual: WarmResidual, size: int, phi1: float | None = None
) -> dict[str, float] | None:
    """Newton-type solve (MINPACK hybrd) from x0; the state if it converged to a valid root, else None.
    ``residual(x, equations)`` -> (residuals, state): the solve reads the residuals of ``_point_ends``, the
    converged point is judged on its whole state (``_point_state``), the same floats."""
    full: Callable[[NDArray[np.float64]], NDArray[np.float64]] = (
        (lambda x: np.r_[phi1, x]) if phi1 is not None else (lambda x: x)
    )
    try:
        with np.errstate(all="ignore"):
            sol = root(
                lambda x: residual(x.tolist(), _point_ends)[0],
                np.asarray(x0, float),
                method="hybr",
                options={"xtol": 1e-12},
            )
        r, st = residual(sol.x, _point_state)
    except (ValueError, ZeroDivisionError, ArithmeticError):
        return None
    if not np.all(np.isfinite(r)) or np.linalg.norm(r) > 1e-9 or len(r) != size:
        return None
    if st["F"] < 0 or not _valid(beam, st)[0]:
        return None
    x = full(sol.x)
    return st | {"phi1": float(x[0])}


def _mirrored(seg: GuidedSegment, a: float, b: float, theta0: float) -> tuple[float, float, float]:
    """sign, (b, theta0) as solved: the displacement problems search P > 0 (prbm.inflection)."""
    sign = -1.0 if b < 0 else 1.0
    return sign, sign * b, sign * theta0


def segment_state(seg: GuidedSegment, drive: CouplerDrive, t: float, warm: _Warm | None = None) -> SegmentState:
    """The case-1 problem (a, b, theta0 -> P, nP, M) of one segment at the free translation t."""
    a, b, theta0 = drive.segment_end(seg, t)
    sign = -1.0 if b < 0 else 1.0

    def ends(tk: float) -> tuple[float, float, float]:
        ak, bk, thk = drive.segment_end(seg, tk)
        return ak, sign * bk, sign * thk  # mirrored when b < 0 (the search is for P > 0)

    found = (warm or _Warm()).case1(seg.beam(), ends, t)
    if isinstance(found, str):
        return SegmentState(seg, a, b, theta0, False, f"segment '{seg.name}': {found}")
    o, message = found
    # eq (147)'s M opposes P (clockwise for P > 0): the CCW moment on the beam is -M; mirrored: P, M flip
    return SegmentState(
        seg,
        a,
        b,
        theta0,
        True,
        message,
        P=sign * o["P"],
        nP=o["nP"],
        moment=-sign * o["M"],
        energy=o["U"],
        n=o["n"],
        l1=o["l1"],
    )


def _t_at_ratio(seg: GuidedSegment, drive: CouplerDrive, n: float, warm: _Warm) -> float | None:
    """The free translation at which the segment's case-2 end (b, theta0, n -> a) meets the coupler's."""
    w = drive.free * cmath.exp(-1j * seg.theta1)  # the free direction in the segment frame
    if abs(w.real) < 1e-3:
        return None  # the free motion hardly changes a: a single segment cannot fix it
    t, previous = 0.0, None
    for _ in range(30):
        a, b, theta0 = drive.segment_end(seg, t)
        _, b_s, th_s = _mirrored(seg, a, b, theta0)
        state = warm.case2(seg.beam(), b_s, th_s, n)  # n of the problem solved (mirrored: -n)
        if state is None:
            return None
        gap = state["a"] - a
        step = _secant_step(t, gap, previous, gap / w.real)
        previous = (t, gap)
        t += step
        if abs(step) < 1e-9 * seg.length:
            return t
    return None


def _secant_step(t: float, gap: float, previous: tuple[float, float] | None, first: float) -> float:
    """The secant step on gap(t) = a_case2(t) - a_coupler(t) from the last two iterates. The first step
    (gap / Re w) takes a_case2 as constant; the secant also follows how a_case2 moves with t, so it
    converges superlinearly where the first step's iteration is only linear. ``first`` where there is no
    usable secant (the first iterate, or a flat or non-finite slope)."""
    if previous is None or previous[0] == t:
        return first
    slope = (gap - previous[1]) / (t - previous[0])
    return -gap / slope if slope != 0.0 and math.isfinite(slope) else first


def reachable_window(seg: GuidedSegment, drive: CouplerDrive, ratios: Sequence[float] = RATIOS) -> Window:
    """The t the segment reaches with its load ratio n at each of ``ratios`` (case 2, Tables 3.4-3.5)."""
    warm = _Warm()
    found = [(n, _t_at_ratio(seg, drive, n, warm)) for n in ratios]
    reached = [(n, t) for n, t in found if t is not None]
    return Window(seg.name, tuple(t for _, t in reached), tuple(n for n, _ in reached))


def free_force(
    segments: list[GuidedSegment], drive: CouplerDrive, t: float, warms: list[_Warm] | None = None
) -> tuple[float, list[SegmentState]]:
    """sum_j Re(conj(w) F_j): the free-direction force the segments need (NaN if a segment has no valid root)."""
    warms = warms or [_Warm() for _ in segments]
    states = [segment_state(s, drive, t, wm) for s, wm in zip(segments, warms)]
    if not all(st.valid for st in states):
        return math.nan, states
    w = drive.free
    return sum((st.force * w.conjugate()).real for st in states), states


def solve_coupler(segments: list[GuidedSegment], drive: CouplerDrive, *, samples: int = 9) -> PRBMResult:
    """The free translation t at which the coupler needs no force along it (see the module docstring).

    Outputs: t, strain_energy (sum of the segments' PRBM springs), force_along and moment (the load the
    coupler needs at P to hold the prescribed translation and rotation; moment CCW about P).
    ``extras``: windows, states, the bracket."""
    t0 = time.perf_counter()
    windows = [reachable_window(s, drive) for s in segments]
    text = "; ".join(
        f"{w.segment}: t in [{w.low:.4g}, {w.high:.4g}]" if not w.empty else f"{w.segment}: none" for w in windows
    )
    low, high = (
        (max(w.low for w in windows), min(w.high for w in windows))
        if not any(w.empty for w in windows)
        else (math.inf, -math.inf)
    )
    if not low < high:
        return _failed(
            f"no PRBM state within the fits (-4 < n <= 10): the segments reach disjoint windows of "
            f"the free translation ({text})",
            windows,
            t0,
        )
    pad = 1e-6 * (high - low)
    grid = np.linspace(low + pad, high - pad, samples)
    warms = [_Warm() for _ in segments]
    values = [free_force(segments, drive, float(t), warms)[0] for t in grid]
    brackets = [
        (float(grid[i]), float(grid[i + 1]))
        for i in range(samples - 1)
        if np.isfinite(values[i]) and np.isfinite(values[i + 1]) and values[i] * values[i + 1] <= 0
    ]
    if not brackets:
        return _failed(f"the free-direction force keeps one sign over the overlap of the windows ({text})", windows, t0)
    lo, hi = min(brackets, key=lambda br: abs(br[0] + br[1]))
    t = brentq(lambda x: free_force(segments, drive, x, warms)[0], lo, hi, xtol=1e-12 * max(abs(lo), 1.0), rtol=1e-12)
    force, states = free_force(segments, drive, t, warms)
    ok = all(st.valid for st in states) and abs(force) <= 1e-6 * max(abs(st.force) for st in states)
    P = drive.position(t)
    total = sum(st.force for st in states)
    moment = sum(st.moment + _cross(drive.end(st.segment, t) - P, st.force) for st in states)
    out: dict[str, Levels] = {
        "t": np.asarray(t),
        "strain_energy": np.asarray(sum(st.energy for st in states)),
        "force_along": np.asarray((total * (drive.along / abs(drive.along)).conjugate()).real),
        "moment": np.asarray(moment),
    }
    message = f"coupler equilibrium at t = {t:.6g} ({text}); " + "; ".join(
        f"{st.segment.name}: n = {st.n:.3g}, {st.message}" for st in states
    )
    return PRBMResult(
        ok,
        message if ok else "free-direction force left at a jump between PRBM roots; " + message,
        out,
        {"segments": [s.name for s in segments]},
        MODEL,
        time.perf_counter() - t0,
        0,
        np.array([ok]),
        extras={"windows": windows, "states": states, "bracket": (lo, hi)},
    )


def _failed(message: str, windows: list[Window], t0: float) -> PRBMResult:
    return PRBMResult(
        False, message, {}, {}, MODEL, time.perf_counter() - t0, 0, np.array([False]), extras={"windows": windows}
    )


def _cross(r: complex, F: complex) -> float:
    """The planar cross product r x F."""
    return r.real * F.imag - r.imag * F.real
