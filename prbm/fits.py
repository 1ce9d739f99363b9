"""Parameter fits of the fixed-pinned (fixed-free, end-force) PRBM: gamma(n), K_Theta(n), c_theta(n).

Two published families are implemented, each exactly as printed, with its stated n-range enforced:

* ``PAULY_MIDHA``: [bapat2015, eqs 41-43]: (41) gamma, (42) c_theta, (43) K_Theta, coefficients of
  Pauly & Midha, valid for -4 < n <= 10.  This is the family the dissertation uses in chapter 3
  (eqs 83-92) and chapter 9.
* ``HOWELL``: [ananthasuresh_l18, 05:41] (slide "A PRB of a cantilever beam with an arbitrary tip-load",
  after Howell 2001): gamma on -5 < n < 10 (three branches, open intervals as printed), K_Theta on
  -5 < n <= 10.  The lecture gives no c_theta; ``c_theta`` of this family is therefore unavailable.

Load ratio ([bapat2015, eq 43] where-clause, sign fixed by reproducing Tables 3.2-3.6): the end force is
(F_x, F_y) = (-nP, P), i.e. n > 0 is compressive (pushes toward the clamp); phi = atan2(1, -n).

The piecewise fits jump at their breakpoints (they are separate regressions).  The jumps are
properties of the published fits, not errors of this code; ``breakpoint_jumps()`` lists them:
Pauly-Midha gamma jumps -0.000248 at n = -1.5 and +0.002432 at n = -0.5, c_theta -0.000281 and
K_Theta -0.000965 at n = -0.5; Howell gamma jumps -0.004627 at n = 0.5, K_Theta +0.002153 at
n = -2.5 and +0.003902 at n = -1 (upper branch minus lower branch).  A branch is chosen by the
printed inequality (lower < n <= upper); for Howell's open gamma intervals the printed endpoints
n = 0.5 and n = -1.8316 belong to no branch, and this code assigns them to the lower branch
(documented choice; gamma is continuous at -1.8316 to 2e-6).

Outside the stated range a ``FitRangeError`` is raised (``extrapolate="raise"``, the default), or a
``FitRangeWarning`` is issued and the nearest branch is evaluated (``extrapolate="warn"``).  Solvers
that need to evaluate trial points outside the range use ``extrapolate="allow"`` internally and
check their converged answer against the range afterwards.

Pure end moment [ananthasuresh_l18, 16:59-21:58]: gamma = 0.7346 and a torsion spring of 1.5164 EI/L.
The lecture calls 1.5164 the spring constant in units of EI/L; in Howell's
notation k = gamma K_Theta EI/L, so its K_Theta would be 1.5164/0.7346 = 2.0643.  Since the exact
tip slope of a cantilever under an end moment is ML/EI = 1.5164 Theta, c_theta = 1.5164 follows.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray


class FitRangeError(ValueError):
    """A load ratio outside the range over which a published fit was made."""


class FitRangeWarning(UserWarning):
    """A fit was evaluated outside its published range (extrapolation requested with 'warn')."""


_SCALAR_LOOP_MAX = 64  # up to this many load ratios, evaluate level by level in plain floats


@dataclass(frozen=True)
class Branch:
    lower: float  # open lower end
    upper: float  # closed upper end (lower < n <= upper)
    coefficients: tuple[float, ...]  # c0 + c1 n + c2 n^2 + ...


@dataclass(frozen=True)
class PiecewiseFit:
    name: str
    source: str
    branches: tuple[Branch, ...]

    @property
    def lower(self) -> float:
        return self.branches[0].lower

    @property
    def upper(self) -> float:
        return self.branches[-1].upper

    @overload
    def __call__(self, n: float, extrapolate: str = "raise") -> float: ...

    @overload
    def __call__(self, n: NDArray[Any], extrapolate: str = "raise") -> NDArray[np.float64]: ...

    def __call__(self, n: float | NDArray[Any], extrapolate: str = "raise") -> float | NDArray[np.float64]:
        """Evaluate at load ratio(s) n (scalar or array)."""
        if isinstance(n, float) or np.ndim(n) == 0:  # scalar fast path (root finders call this in their inner loop)
            x = float(n)
            branches = self.branches
            if not (branches[0].lower < x <= branches[-1].upper):  # ``lower`` < x <= ``upper``
                self._out_of_range(x, extrapolate)
            return self._horner(x)
        n_arr = np.asarray(n, dtype=float)
        if n_arr.size <= _SCALAR_LOOP_MAX:
            # a few load levels: the scalar Horner loop once per distinct ratio (the same arithmetic as polyval)
            ratios = n_arr.ravel().tolist()
            distinct = set(ratios)
            lower, upper = self.lower, self.upper
            value = {x: self._horner(x) for x in distinct if lower < x <= upper}
            if len(value) == len(distinct):  # all inside the range (else the array path reports it)
                return np.array([value[x] for x in ratios], dtype=float).reshape(n_arr.shape)
        outside = ~((n_arr > self.lower) & (n_arr <= self.upper))
        if np.any(outside):
            bad = n_arr[outside] if n_arr.ndim else n_arr
            self._out_of_range(float(np.ravel(bad)[0]), extrapolate)
        out = np.empty_like(n_arr)
        for i, br in enumerate(self.branches):
            lo = -np.inf if i == 0 else br.lower
            hi = np.inf if i == len(self.branches) - 1 else br.upper
            mask = (n_arr > lo) & (n_arr <= hi)
            out[mask] = np.polynomial.polynomial.polyval(n_arr[mask], br.coefficients)
        return float(out) if out.ndim == 0 else out

    def _horner(self, x: float) -> float:
        """The fit at one float x (branch by the printed inequalities, nearest branch outside them)."""
        branches = self.branches
        br = branches[-1]
        for cand in branches[:-1]:
            if x <= cand.upper:
                br = cand
                break
        value = 0.0
        for c in reversed(br.coefficients):
            value = value * x + c
        return value

    def _out_of_range(self, x: float, extrapolate: str) -> None:
        message = (
            f"{self.name}: load ratio n = {x:.6g} outside the fitted range "
            f"{self.lower} < n <= {self.upper} ({self.source})"
        )
        if extrapolate == "raise":
            raise FitRangeError(message)
        if extrapolate == "warn":
            warnings.warn(message + "; nearest branch extrapolated", FitRangeWarning, stacklevel=3)
        elif extrapolate != "allow":
            raise ValueError(f"extrapolate must be 'raise', 'warn' or 'allow', not {extrapolate!r}")

    def breakpoint_jumps(self) -> list[tuple[float, float]]:
        """(n_b, value just above n_b minus value at n_b) for every internal breakpoint."""
        jumps = []
        for left, right in zip(self.branches[:-1], self.branches[1:]):
            nb = left.upper
            below = np.polynomial.polynomial.polyval(nb, left.coefficients)
            above = np.polynomial.polynomial.polyval(nb, right.coefficients)
            jumps.append((nb, float(above - below)))
        return jumps


@dataclass(frozen=True)
class FitFamily:
    """gamma, K_Theta and (if published) c_theta as functions of the load ratio n."""

    name: str
    gamma: PiecewiseFit
    K_theta: PiecewiseFit
    c_theta: PiecewiseFit | None

    @property
    def lower(self) -> float:
        fits = [self.gamma, self.K_theta] + ([self.c_theta] if self.c_theta else [])
        return max(f.lower for f in fits)

    @property
    def upper(self) -> float:
        fits = [self.gamma, self.K_theta] + ([self.c_theta] if self.c_theta else [])
        return min(f.upper for f in fits)

    @overload
    def parameters(self, n: float, extrapolate: str = "raise") -> tuple[float, float, float]: ...

    @overload
    def parameters(
        self, n: NDArray[Any], extrapolate: str = "raise"
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

    def parameters(
        self, n: float | NDArray[Any], extrapolate: str = "raise"
    ) -> tuple[float | NDArray[np.float64], float | NDArray[np.float64], float | NDArray[np.float64]]:
        """(gamma, c_theta, K_theta) at n.  c_theta is NaN when the family publishes none."""
        g = self.gamma(n, extrapolate)
        k = self.K_theta(n, extrapolate)
        if self.c_theta is None:
            c = math.nan if np.ndim(g) == 0 else np.full_like(g, np.nan)
        else:
            c = self.c_theta(n, extrapolate)
        return g, c, k

    @overload
    def model_parameters(self, n: float, extrapolate: str = "raise") -> tuple[float, float, float]: ...

    @overload
    def model_parameters(
        self, n: NDArray[Any], extrapolate: str = "raise"
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

    def model_parameters(
        self, n: float | NDArray[Any], extrapolate: str = "raise"
    ) -> tuple[float | NDArray[np.float64], float | NDArray[np.float64], float | NDArray[np.float64]]:
        """``parameters`` for a segment model: extrapolated values that give no PRB model (gamma <= 0 or
        K_theta <= 0, which the polynomials reach far outside their ranges) raise FitRangeError.  (A
        solver's trial point may read ``parameters`` there; a model's answer may not.)"""
        g, c, k = self.parameters(n, extrapolate)
        if extrapolate != "raise" and not (np.all(g > 0.0) and np.all(k > 0.0)):
            raise FitRangeError(_unphysical(self.name, n, g, k))
        return g, c, k


def _unphysical(family: str, n: ArrayLike, gamma: ArrayLike, K_theta: ArrayLike) -> str:
    """Why an extrapolated fit gives no PRB model: a characteristic radius or a spring that is not
    positive (the fits' polynomials reach that far outside their published ranges; the spring equation
    (*) has no meaningful root with k <= 0)."""
    bad = ~((np.asarray(gamma) > 0.0) & (np.asarray(K_theta) > 0.0))
    i = int(np.flatnonzero(np.atleast_1d(bad))[0])
    pick = [float(np.atleast_1d(v)[i]) for v in np.broadcast_arrays(n, gamma, K_theta)]
    return (
        f"{family} fits extrapolated to n = {pick[0]:g} give gamma = {pick[1]:.4g} and K_theta = "
        f"{pick[2]:.4g}: no PRB model there (it needs gamma > 0 and K_theta > 0)"
    )


_S000 = "seed 000 (Bapat 2015) eq"
PAULY_MIDHA = FitFamily(
    name="pauly-midha",
    gamma=PiecewiseFit(
        "gamma(n)",
        _S000 + " (41)",
        (
            Branch(-4.0, -1.5, (0.855651, -0.016438)),
            Branch(-1.5, -0.5, (0.852138, -0.018615)),
            Branch(-0.5, 10.0, (0.851892, -0.020805, 0.005867, -0.000895, 0.000069, -0.000002)),
        ),
    ),
    c_theta=PiecewiseFit(
        "c_theta(n)",
        _S000 + " (42)",
        (
            Branch(-4.0, -0.5, (1.238945, 0.012035, 0.00454)),
            Branch(-0.5, 10.0, (1.238845, 0.009113, -0.001929, 0.000191, -0.000007)),
        ),
    ),
    K_theta=PiecewiseFit(
        "K_theta(n)",
        _S000 + " (43)",
        (
            Branch(-4.0, -0.5, (2.66041, -0.069005, -0.002268)),
            Branch(-0.5, 10.0, (2.648834, -0.074727, 0.026328, -0.004609, 0.000390, -0.000013)),
        ),
    ),
)

_S004 = "seed 004 (PRB lecture), slide 'arbitrary tip-load'"
HOWELL = FitFamily(
    name="howell",
    gamma=PiecewiseFit(
        "gamma(n)",
        _S004,
        (
            Branch(-5.0, -1.8316, (0.912364, 0.0145928)),
            Branch(-1.8316, 0.5, (0.852144, -0.0182867)),
            Branch(0.5, 10.0 - 1e-12, (0.841655, -0.0067807, 0.000438)),  # printed 0.5 < n < 10.0 (open)
        ),
    ),
    c_theta=None,
    K_theta=PiecewiseFit(
        "K_theta(n)",
        _S004,
        (
            Branch(-5.0, -2.5, (3.024112, 0.121290, 0.003169)),
            Branch(-2.5, -1.0, (1.967647, -2.616021, -3.738166, -2.649437, -0.891906, -0.113063)),
            Branch(-1.0, 10.0, (2.654855, -0.509896e-1, 0.126749e-1, -0.142039e-2, 0.584525e-4)),
        ),
    ),
)

_CONSTANT_SOURCE = "seed 004 (PRB lecture): the usual averages gamma = 0.85, K_theta = 2.65; c_theta = 1.24"
CONSTANT = FitFamily(  # the load-independent averages of the n-fits, over the Pauly-Midha range of n
    name="constant",
    gamma=PiecewiseFit("gamma", _CONSTANT_SOURCE, (Branch(-4.0, 10.0, (0.85,)),)),
    c_theta=PiecewiseFit("c_theta", _CONSTANT_SOURCE, (Branch(-4.0, 10.0, (1.24,)),)),
    K_theta=PiecewiseFit("K_theta", _CONSTANT_SOURCE, (Branch(-4.0, 10.0, (2.65,)),)),
)

FAMILIES = {"pauly-midha": PAULY_MIDHA, "howell": HOWELL, "constant": CONSTANT}


def fit_family(name: str | FitFamily) -> FitFamily:
    if isinstance(name, FitFamily):
        return name
    try:
        return FAMILIES[name]
    except KeyError:
        raise ValueError(f"unknown fit family {name!r}; known: {', '.join(FAMILIES)}") from None


# The PRB angle range of the fixed-pinned fits: the only range the dissertation prints for them is that of the
# Theta-dependent K_Theta fits (51)-(52), "0 < Theta <= 65 deg" [bapat2015, §2.3.1]; past it the
# end-point error grows quickly (notes seed-ch2-4 section 4.1: 0.2-1.4 % of l up to Theta ~ 60 deg,
# 3.8 % and 7.7 % at 97 and 120 deg).
THETA_RANGE = math.radians(65.0)

# Pure end moment [ananthasuresh_l18, 16:59-21:58].
PURE_MOMENT_GAMMA = 0.7346
PURE_MOMENT_SPRING = 1.5164  # k = 1.5164 EI/L (the lecture's wording: "torsion spring constant")
PURE_MOMENT_K_THETA = PURE_MOMENT_SPRING / PURE_MOMENT_GAMMA  # Howell's K_Theta, k = gamma K_Theta EI/L
PURE_MOMENT_C_THETA = PURE_MOMENT_SPRING  # from the exact theta_0 = M L / EI


@overload
def load_angle(n: float) -> float: ...


@overload
def load_angle(n: NDArray[Any]) -> NDArray[np.float64]: ...


def load_angle(n: float | NDArray[Any]) -> float | NDArray[np.float64]:
    """phi = atan2(1, -n) in (0, pi): direction of the end force (-nP, P) for P > 0."""
    return np.arctan2(1.0, -np.asarray(n, dtype=float)) if np.ndim(n) else math.atan2(1.0, -float(n))


@overload
def load_ratio(phi: float) -> float: ...


@overload
def load_ratio(phi: NDArray[Any]) -> NDArray[np.float64]: ...


def load_ratio(phi: float | NDArray[Any]) -> float | NDArray[np.float64]:
    """n = -1/tan(phi) = -cos(phi)/sin(phi) [bapat2015, eqs 93/94]."""
    n: float | NDArray[np.float64] = -np.cos(phi) / np.sin(phi)
    return n
