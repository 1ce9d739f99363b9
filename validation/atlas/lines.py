"""One line of the atlas: the exact elastica followed along growing load, the PRBM at the same loads,
and the PRBM's error at every level split into its path and stiffness parts.

Along a line the shape inputs are fixed and the load magnitude grows (``validation.atlas.models``).

* Exact: ``elastica.solve_path`` continued level to level from the unloaded beam (the equilibrium a
  slowly loaded segment reaches).  A level the continuation cannot reach ends the line (status
  ``exact not converged``); a level whose tip has turned more than the model's ``stop_rotation_deg``
  ends it too (``beyond the atlas``): past that the segment curls and no PRB model is meant for it.
  The SLFP's rigid arm makes the flexure's end moment depend on its end angle,
  M = (1 - lambda) L (cos theta F_y - sin theta F_x); that scalar equation is solved by a secant on M
  with the shooting solve inside.
* Errors at equal load, in % of the model's reference length L:
  tip error |r_PRBM - r|, tip-angle error theta_PRBM - theta (deg).
* The split [bapat2015, section 2.3]: the seed's accuracy claim is about the *path* (where the tip is
  for a given deflection), so the PRBM is also read at the exact solution's path coordinate c (the tip
  angle; b for a guided end; the chord for a pinned-pinned arc), by interpolating it along a dense load
  grid of the same line on the part where c grows with the load (monotone cubic interpolation, PCHIP):
  path error |r_PRBM(c) - r| (% of L and % of the deflection |r - r_0|), and stiffness error
  F_PRBM(c)/F - 1 (%), the load the PRBM needs for the same deflection.  Where the PRBM never reaches
  c the split is NaN.
* The locus error: the distance from the exact tip to the curve the PRBM's tip traces as the load grows
  (its dense line as a polyline), in % of L and of the deflection.  It is the measure of Howell and
  Midha's claim that the PRB link's end follows the beam's end ([bapat2015, section 2.3]: gamma was chosen
  so that the circle stays near the exact path), free of how the PRBM parameterises that curve (its
  tip angle c_theta Theta, its load).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np
from scipy.interpolate import PchipInterpolator

from elastica.shooting import ElasticaResult, solve_path, unloaded_tip
from validation.atlas.models import AtlasModel, PrbmLine

STATUS_OK = "ok"
STATUS_BEYOND = "beyond the atlas"
STATUS_EXACT_FAILED = "exact not converged"
STATUS_PRBM_FAILED = "prbm gives no answer"


@dataclass
class ExactLine:
    """The exact tip (x, y, theta) of every level in the atlas frame, and each level's status."""

    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    status: list[str]
    seconds: float


def _frame(model: AtlasModel, shape: dict, x: float, y: float, theta: float) -> tuple[float, float, float]:
    """A tip of the exact problem (x, y, theta) in the atlas frame: the chord of a pinned-pinned arc (twice
    the half's end along the mid-span tangent), or the end of an SLFP's rigid arm."""
    if model.coordinate == "chord":
        return 2.0 * x, 0.0, 0.0
    if model.exact_solver == "slfp":
        arm = 1.0 - shape["flexure_fraction"]
        return x + arm * math.cos(theta), y + arm * math.sin(theta), theta
    return x, y, theta


def unloaded(model: AtlasModel, shape: dict) -> tuple[float, float, float]:
    """The unloaded tip (x, y, theta) in the atlas frame."""
    problem = model.exact_problem(shape, 0.0)
    return _frame(model, shape, *unloaded_tip(problem.length, problem.curvature))


def _slfp_level(
    model: AtlasModel, shape: dict, F: float, start: ElasticaResult | None, moment: float
) -> tuple[ElasticaResult | None, float]:
    """The flexure's end state with the rigid arm's moment consistent with its end angle (secant on M)."""
    arm = 1.0 - shape["flexure_fraction"]
    base = model.exact_problem(shape, F)
    Fx, Fy = base.force

    def solve(M: float) -> tuple[ElasticaResult, float]:
        r = solve_path(replace(base, moment=M), start=start, n_samples=2)
        return r, M - arm * (math.cos(r.theta) * Fy - math.sin(r.theta) * Fx)

    m0 = moment if start is not None else arm * Fy
    r0, g0 = solve(m0)
    if not r0.converged:
        return None, m0
    m1 = m0 - g0 if g0 != 0.0 else m0
    for _ in range(30):
        if abs(g0) <= 1e-11 * max(1.0, abs(m0)):
            return r0, m0
        r1, g1 = solve(m1)
        if not r1.converged:
            return None, m1
        if g1 == g0:
            return (r1, m1) if abs(g1) <= 1e-9 else (None, m1)
        m0, m1, r0, g0 = m1, m1 - g1 * (m1 - m0) / (g1 - g0), r1, g1
    return None, m0


def exact_line(model: AtlasModel, shape: dict, loads: np.ndarray) -> ExactLine:
    """The exact elastica at every load of a line, by continuation (module docstring)."""
    t0 = time.perf_counter()
    count = loads.size
    x, y, th = np.full(count, np.nan), np.full(count, np.nan), np.full(count, np.nan)
    status = [STATUS_OK] * count
    theta_0 = unloaded(model, shape)[2]
    stop = math.radians(model.stop_rotation_deg)
    prev, moment = None, 0.0
    for j, F in enumerate(loads):
        if model.exact_solver == "slfp":
            r, moment = _slfp_level(model, shape, float(F), prev, moment)
        else:
            r = solve_path(model.exact_problem(shape, float(F)), start=prev, n_samples=2)
            r = r if r.converged else None
        if r is None:
            status[j:] = [STATUS_EXACT_FAILED] * (count - j)
            break
        if abs(r.theta - theta_0) > stop or (model.coordinate == "chord" and abs(r.theta) > stop):
            status[j:] = [STATUS_BEYOND] * (count - j)
            break
        x[j], y[j], th[j] = _frame(model, shape, r.x, r.y, r.theta)
        prev = r
    return ExactLine(x, y, th, status, time.perf_counter() - t0)


def dense_loads(loads: np.ndarray, per_level: int) -> np.ndarray:
    """The loads with ``per_level - 1`` points between neighbours (geometric where the loads are) and
    geometric ones from a thousandth of the first load up to it, so that the PRBM's path is resolved
    from near the unloaded state (where the relative errors are read) on."""
    first = loads[0] * np.geomspace(1e-3, 1.0, 4 * max(per_level, 1) + 1)[:-1]
    if per_level <= 1:
        return np.concatenate([first, loads])
    parts = [first]
    for lo, hi in zip(loads[:-1], loads[1:]):
        parts.append(np.geomspace(lo, hi, per_level + 1)[:-1] if lo > 0 else np.linspace(lo, hi, per_level + 1)[:-1])
    parts.append(loads[-1:])
    return np.concatenate(parts)


def coordinate(model: AtlasModel, x, y, theta) -> np.ndarray:
    """The path coordinate of tip states (module docstring)."""
    if model.coordinate == "b":
        return np.asarray(y, float)
    if model.coordinate == "chord":
        return np.asarray(x, float)
    return np.asarray(theta, float)


def _monotone_run(c: np.ndarray, ok: np.ndarray) -> tuple[int, int]:
    """[first, stop): from the first solved point, the run over which c is finite, solved and strictly
    increasing (a model that gives no answer at the smallest loads starts later)."""
    good = ok & np.isfinite(c)
    first = int(np.argmax(good)) if good.any() else c.size
    bad = np.flatnonzero(~good[first:])
    stop = first + int(bad[0]) if bad.size else c.size
    rises = np.flatnonzero(np.diff(c[first:stop]) <= 0.0)
    return first, (first + int(rises[0]) + 1 if rises.size else stop)


@dataclass
class Split:
    """The PRBM read at the exact path coordinate: its load and tip there (NaN where not reached)."""

    load: np.ndarray
    x: np.ndarray
    y: np.ndarray


def split_at_coordinate(
    model: AtlasModel, exact: ExactLine, dense: np.ndarray, prb: PrbmLine, c_unloaded: float
) -> Split:
    """The PRBM's load and tip at each exact level's path coordinate, along its own dense line."""
    c_exact = coordinate(model, exact.x, exact.y, exact.theta) - c_unloaded
    c_prbm = coordinate(model, prb.x, prb.y, prb.theta) - c_unloaded
    finite = c_exact[np.isfinite(c_exact) & (c_exact != 0.0)]
    sense = 1.0 if finite.size == 0 or finite[0] > 0 else -1.0
    c_exact, c_prbm = sense * c_exact, sense * c_prbm
    first, stop = _monotone_run(c_prbm, prb.ok)
    nan = np.full(c_exact.shape, np.nan)
    if stop - first < 2:
        return Split(nan, nan.copy(), nan.copy())
    run = slice(first, stop)
    c = c_prbm[run]
    inside = (c_exact >= c[0]) & (c_exact <= c[-1])
    out = Split(nan.copy(), nan.copy(), nan.copy())
    for name, values in (("load", dense[run]), ("x", prb.x[run]), ("y", prb.y[run])):
        getattr(out, name)[inside] = PchipInterpolator(c, values)(c_exact[inside])
    return out


def locus_distance(px: np.ndarray, py: np.ndarray, ok: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The distance from each point (x, y) to the polyline through the solved PRBM tips (px, py)."""
    keep = ok & np.isfinite(px) & np.isfinite(py)
    ax, ay = px[keep][:-1], py[keep][:-1]
    bx, by = px[keep][1:], py[keep][1:]
    out = np.full(np.shape(x), np.nan)
    if ax.size == 0:
        return out
    dx, dy = bx - ax, by - ay
    length2 = np.where(dx * dx + dy * dy > 0.0, dx * dx + dy * dy, 1.0)
    for j, (qx, qy) in enumerate(zip(x, y)):
        if not (math.isfinite(qx) and math.isfinite(qy)):
            continue
        t = np.clip(((qx - ax) * dx + (qy - ay) * dy) / length2, 0.0, 1.0)
        out[j] = float(np.min(np.hypot(ax + t * dx - qx, ay + t * dy - qy)))
    return out


def solve_line(model: AtlasModel, shape: dict, loads: np.ndarray) -> list[dict]:
    """Every level of one line as a row: the inputs, the exact and PRBM tips, the errors and status."""
    exact = exact_line(model, shape, loads)
    t0 = time.perf_counter()
    dense = dense_loads(loads, model.dense)
    prb = model.prbm(shape, dense)
    at_levels = np.searchsorted(dense, loads)
    prbm_seconds = time.perf_counter() - t0
    x0, y0, t0_ = unloaded(model, shape)
    split = split_at_coordinate(model, exact, dense, prb, float(coordinate(model, x0, y0, t0_)))
    L = model.reference_length
    locus = locus_distance(prb.x, prb.y, prb.ok, exact.x, exact.y)
    rows = []
    per_point = (exact.seconds + prbm_seconds) / max(loads.size, 1)
    for j, F in enumerate(loads):
        i = at_levels[j]
        px, py, pt, ok = prb.x[i], prb.y[i], prb.theta[i], bool(prb.ok[i])
        ex, ey, et = exact.x[j], exact.y[j], exact.theta[j]
        status = exact.status[j]
        if status == STATUS_OK and not ok:
            status = STATUS_PRBM_FAILED
        deflection = math.hypot(ex - x0, ey - y0)
        path = math.hypot(split.x[j] - ex, split.y[j] - ey)
        rows.append(
            {
                **shape,
                "load": float(F),
                "status": status,
                "in_fit_range": bool(prb.in_fit[i]),
                "exact_x": ex,
                "exact_y": ey,
                "exact_theta_deg": math.degrees(et),
                "exact_rotation_deg": math.degrees(et - t0_),
                "deflection": 100.0 * deflection / L,
                "prbm_x": px,
                "prbm_y": py,
                "prbm_theta_deg": math.degrees(pt),
                "prb_angle_deg": math.degrees(prb.prb_angle[i]),
                "tip_error": 100.0 * math.hypot(px - ex, py - ey) / L,
                "angle_error_deg": math.degrees(pt - et),
                "path_error": 100.0 * path / L,
                "path_error_rel": 100.0 * path / deflection if deflection > 0 else math.nan,
                "stiffness_error": 100.0 * (split.load[j] / F - 1.0),
                "locus_error": 100.0 * locus[j] / L,
                "locus_error_rel": 100.0 * locus[j] / deflection if deflection > 0 else math.nan,
                "seconds": per_point,
            }
        )
    return rows
