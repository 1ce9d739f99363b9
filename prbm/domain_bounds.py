"""Pseudo-rigid-body representations of the boundaries of characteristic deflection domains
[bapat2015, ch. 4], as curves a/l(b/l) to overlay on a cloud of end points.

* ``prbm_arc``: a bound drawn as the path of a PRB link of length gamma l about the characteristic
  pivot (1 - gamma) l on the undeformed axis (eqs 48, 49): a/l = 1 - gamma + sqrt(gamma^2 - (b/l)^2).
  The chapter's gamma_l, gamma_u (eqs 110, 111, 113, 114, 118) are radii of such arcs.
* ``clamp_arc``: the approximate lower bound of the fixed-guided segment with one inflection point,
  a circle of radius gamma-bar_l l about the fixed end (eq 117): a/l = sqrt(gamma-bar^2 - (b/l)^2).
* ``inflection_lower_bound``: the sixth-order curve fit of that lower bound (eq 116, R^2 = 0.998),
  a^ = 0.934 - 0.0591 b^ - 1.6211 b^2 + 4.9649 b^3 - 11.366 b^4 + 13.746 b^5 - 7.0759 b^6, with
  a^ = a/l and b^ = b/l; its coefficients are the dissertation's model (as the n-fits of ``prbm.fits``).
* ``slfp_arc_radius``: the domain of a segment with a small-length flexural pivot is an arc of radius
  l/2 + L about the middle of the flexure (eq 127; a length, not a factor).

Where b/l exceeds the arc's radius the arcs return NaN (the arc does not reach that height).

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["prbm_arc", "clamp_arc", "inflection_lower_bound", "slfp_arc_radius", "INFLECTION_LOWER_FIT"]

INFLECTION_LOWER_FIT = (0.934, -0.0591, -1.6211, 4.9649, -11.366, 13.746, -7.0759)  # eq (116), b^0..b^6


def _root(r2: NDArray[np.float64]) -> NDArray[np.float64]:
    with np.errstate(invalid="ignore"):
        return np.where(r2 >= 0.0, np.sqrt(np.where(r2 >= 0.0, r2, 0.0)), np.nan)


def prbm_arc(gamma: float, b: ArrayLike) -> NDArray[np.float64]:
    """a/l of the PRB arc of radius gamma about ((1 - gamma), 0) at height b/l (eqs 48, 49)."""
    b = np.asarray(b, float)
    return 1.0 - gamma + _root(gamma**2 - b**2)


def clamp_arc(gamma_bar: float, b: ArrayLike) -> NDArray[np.float64]:
    """a/l of the circle of radius gamma-bar about the fixed end at height b/l (eq 117)."""
    b = np.asarray(b, float)
    return _root(gamma_bar**2 - b**2)


def inflection_lower_bound(b: ArrayLike) -> NDArray[np.float64]:
    """Eq (116): the curve fit of the lower bound of the one-inflection fixed-guided domain."""
    a: NDArray[np.float64] = np.polynomial.polynomial.polyval(np.asarray(b, float), INFLECTION_LOWER_FIT)
    return a


def slfp_arc_radius(flexure_length: float, rigid_length: float) -> float:
    """Eq (127): radius l/2 + L of the arc traced by the end of an SLFP segment."""
    if flexure_length <= 0.0 or rigid_length < 0.0:
        raise ValueError("slfp_arc_radius: flexure_length must be > 0 and rigid_length >= 0")
    return flexure_length / 2.0 + rigid_length
