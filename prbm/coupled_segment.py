"""One compliant segment whose free end carries a rigid body, loaded at points of that body.

Frame: the segment's own, x along the undeformed segment from its fixed end (origin), y transverse,
CCW angles and moments.  The body is rigidly attached at the segment end E; a body point p sits at
the undeformed offset r0_p = p - E.  When the end has turned by gamma = theta0 - theta0_rest, the
point is at

    p = (a + i b) + r0_p e^{i gamma}.

Dead loads (fixed direction) F_k and couples M_k act at body points r0_k.  Transferred to the end
([bapat2015, eq 173] read backwards, with the *current* offset):

    F_E = sum_k F_k,        M_E(theta0) = sum_k M_k + sum_k Im(conj(r_k) F_k),  r_k = r0_k e^{i gamma}

so the end moment depends on the end rotation, and equilibrium is the fixed point
theta0 = theta0_model(F_E, M_E(theta0)).  (Eq (173) itself uses the undeformed offset r0, i.e. it
transfers the design loads with the body not yet rotated; see ``cases/chapter5/example1.toml``.)

Segment models:

* ``InflectionBeam`` (fixed-guided with one inflection point, [bapat2015, eqs 83-104] =
  chapter-5 eqs (131)-(152)): eq (99)/(147) takes M_E(theta0) and the three equations
  (95), (96), (99) are solved together (``solve_loads`` with a moment function), so the root
  search and ordering are those of the chapter-3 solver.
* any callable ``tip(F, M) -> PRBMResult`` giving ``a``, ``b``, ``theta0`` for an end force
  F = Fx + i Fy and CCW end moment M (e.g. ``fixed_pinned_tip``): the scalar fixed point is solved
  by the secant method from the rotation under the loads transferred with the undeformed offsets.

A level whose loads are all zero is the unloaded pose (a, b, theta0) = ``rest``.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import cmath
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import root_scalar

from prbm.inflection import InflectionBeam, Prefer, solve_loads
from prbm.result import Levels, PRBMResult

__all__ = ["BodyLoad", "body_end_loads", "solve_segment_with_body", "inflection_pivots"]


@dataclass(frozen=True)
class BodyLoad:
    """A dead load on the rigid body: force Fx + i Fy and CCW couple at undeformed offset r0 from E."""

    offset: complex
    force: complex = 0j
    moment: float = 0.0


def body_end_loads(loads: list[BodyLoad], rotation: ArrayLike) -> tuple[complex, NDArray[np.float64]]:
    """(F_E, M_E) at the segment end for the body turned by ``rotation`` (rad, vectorised)."""
    rotation = np.asarray(rotation, float)
    F = sum((ld.force for ld in loads), 0j)
    M = np.zeros_like(rotation)
    for ld in loads:
        r = ld.offset * np.exp(1j * rotation)
        M = M + ld.moment + (np.conj(r) * ld.force).imag
    return F, M


def inflection_pivots(outputs: Mapping[str, Levels]) -> NDArray[np.float64]:
    """PRB chain of the inflection model, eqs (103)-(104) term by term: fixed end, pivot 1,
    inflection point, pivot 2, end; an (5, 2) array in the segment frame."""
    o = {k: float(np.asarray(v)) for k, v in outputs.items() if np.size(v) == 1}
    g1, l1, T1 = o["gamma1"], o["l1"], o["Theta1"]
    g2, l2, T2, t0 = o["gamma2"], o["l2"], o["Theta2"], o["theta0"]
    z = [0j, (1 - g1) * l1]
    z.append(z[-1] + g1 * l1 * cmath.exp(1j * T1))
    z.append(z[-1] + g2 * l2 * cmath.exp(1j * (T2 + t0)))
    z.append(z[-1] + (1 - g2) * l2 * cmath.exp(1j * t0))
    return np.array([[p.real, p.imag] for p in z])


def solve_segment_with_body(
    segment: InflectionBeam | Callable[[complex, float], PRBMResult],
    loads: list[BodyLoad],
    points: dict[str, complex] | None = None,
    *,
    rest: tuple[float, float, float] | None = None,
    prefer: Prefer = "energy",
    xtol: float = 1e-12,
    maxiter: int = 60,
) -> PRBMResult:
    """Equilibrium of segment + rigid body under dead loads at body points.

    segment: an ``InflectionBeam`` or a callable tip(F, M) (see the module docstring).
    loads: the ``BodyLoad``s of this level.  points: body points, name -> undeformed offset from E.
    rest: the unloaded end (a, b, theta0); default (length, 0, 0) of a straight ``InflectionBeam``.
    Returns outputs a, b, theta0, rotation (= theta0 - rest theta0), Fx, Fy, M (end loads, CCW),
    the segment model's own outputs, and ``extras['points']`` = name -> position (complex) and
    ``extras['segment']`` = the segment model's result.
    """
    t_start = time.perf_counter()
    points = dict(points or {})
    if rest is None:
        if not isinstance(segment, InflectionBeam):
            raise ValueError("give 'rest' = (a, b, theta0) of the unloaded end for a tip callable")
        rest = (segment.length, 0.0, 0.0)
    a0, b0, t_rest = rest
    F, _ = body_end_loads(loads, 0.0)
    unloaded = F == 0 and all(ld.moment == 0 for ld in loads)

    def moment(theta0: ArrayLike) -> NDArray[np.float64]:
        return body_end_loads(loads, np.asarray(theta0) - t_rest)[1]

    seg: PRBMResult | None
    outputs: dict[str, Levels]
    if unloaded:
        seg = None
        a, b, t0 = a0, b0, t_rest
        ok, msg, nit = True, "unloaded", 0
        outputs = {}
    elif isinstance(segment, InflectionBeam):
        # chapter-3 convention: P transverse, nP = -Fx (compressive positive), M opposing = -M_ccw
        seg = solve_loads(segment, F.imag, -F.real, lambda t: -moment(t), prefer=prefer, xtol=xtol)
        o = seg.outputs
        a, b, t0 = float(o["a"]), float(o["b"]), float(o["theta0"])
        ok, msg, nit = bool(seg.converged), seg.message, seg.nit
        outputs = {k: v for k, v in o.items() if k not in ("M", "P", "nP")}
    else:

        def theta_of(theta0: float) -> float:
            return float(np.asarray(segment(F, float(moment(theta0))).outputs["theta0"]).ravel()[0])

        first = theta_of(t_rest)
        second = theta_of(first)
        if second == first:  # the end moment does not turn with the end (every load at E): no iteration
            root, found, flag, nit = first, True, "the end loads do not depend on theta0", 1
        else:
            sol = root_scalar(
                lambda t: theta_of(t) - t, x0=first, x1=second, method="secant", xtol=xtol, maxiter=maxiter
            )
            root, found, flag, nit = sol.root, sol.converged, sol.flag, sol.iterations
        seg = segment(F, float(moment(root)))
        o = seg.outputs
        a, b, t0 = (float(np.asarray(o[k]).ravel()[0]) for k in ("a", "b", "theta0"))
        ok = bool(found and seg.converged and abs(t0 - root) < 1e-8)
        msg = f"secant on theta0: {flag}; segment: {seg.message}"
        outputs = {k: v for k, v in o.items() if k not in ("M", "P", "nP", "n")}
    rotation = t0 - t_rest
    end = complex(a, b)
    positions = {name: end + r0 * cmath.exp(1j * rotation) for name, r0 in points.items()}
    outputs.update(
        {
            "a": np.asarray(a),
            "b": np.asarray(b),
            "theta0": np.asarray(t0),
            "rotation": np.asarray(rotation),
            "Fx": np.asarray(F.real),
            "Fy": np.asarray(F.imag),
            "M": np.asarray(float(moment(t0))),
        }
    )
    constants = dict(seg.constants) if seg is not None else {}
    model = "segment + rigid body, end loads M + r x F with the current offset; " + (
        seg.model if seg is not None else "unloaded"
    )
    return PRBMResult(
        ok,
        msg,
        outputs,
        constants,
        model,
        time.perf_counter() - t_start,
        nit,
        np.array([ok]),
        roots=seg.roots if seg is not None else None,
        extras={"points": positions, "segment": seg},
    )
