"""Critical points along a solution path.

A limit point is an extremum of the load factor lambda(s) along the path
(s: arc length, or the control displacement); there det K changes sign.
Its load is refined by the Hermite cubic through the two bracketing states
with their slopes d lambda/ds = 1/||K^-1 f_ref||_W (error O(ds^4)), or a
parabola through three states when slopes are unknown.  A sign change of
det K without an extremum of lambda is reported as a bifurcation; so is a
step whose unstable state was replaced by a stable one (`stability`), with the
note ``branch_switch``.

Angles are in radians (degrees appear only in case files and reports).
"""

from __future__ import annotations

import numpy as np

from typing import TYPE_CHECKING

from .options import CriticalPoint
from .types import FloatArray

if TYPE_CHECKING:
    from .newton import Path

__all__ = ["critical_points", "refine_extremum"]


def refine_extremum(x: FloatArray, y: FloatArray, dy: FloatArray) -> tuple[float, float]:
    """Extremum of lambda(s) near x[1]: Hermite cubic on the bracketing interval
    when the slopes d lambda/ds are known (error O(ds^4)), else a parabola."""
    cands: list[tuple[float, float]] = []
    if np.all(np.isfinite(dy)):
        for j in (0, 1):
            if dy[j] * dy[j + 1] <= 0:
                h = x[j + 1] - x[j]
                t = np.linspace(0.0, 1.0, 2001)
                h00, h10 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t
                h01, h11 = -2 * t**3 + 3 * t**2, t**3 - t**2
                p = h00 * y[j] + h10 * h * dy[j] + h01 * y[j + 1] + h11 * h * dy[j + 1]
                kk = int(np.argmax(p) if y[1] > y[0] else np.argmin(p))
                cands.append((float(p[kk]), float(x[j] + t[kk] * h)))
    if cands:
        best = max(cands, key=lambda c: c[0]) if y[1] > y[0] else min(cands, key=lambda c: c[0])
        return best
    c2, c1, c0 = np.polyfit(x - x[1], y, 2)
    xm = -c1 / (2 * c2) if c2 != 0 else 0.0
    if abs(xm) > max(abs(x[0] - x[1]), abs(x[2] - x[1])):
        return float(y[1]), float(x[1])
    return float(c0 + c1 * xm + c2 * xm * xm), float(x[1] + xm)


def critical_points(path: Path) -> list[CriticalPoint]:
    """Limit points (extremum of lambda with det sign change) and bifurcations, by step."""
    if len(path.step_lams) < 2 and not path.branch_switches:
        return []  # one step (or none): no extremum, no sign change between steps
    lams = np.array(path.step_lams)
    s = np.array(path.step_s) if path.step_s else np.arange(len(lams), dtype=float)
    signs = np.array(path.det_signs)
    found = []
    n = len(lams)
    slopes = np.array(path.step_slope) if len(path.step_slope) == n else np.full(n, np.nan)
    for i in range(1, n - 1):
        d1, d2 = lams[i] - lams[i - 1], lams[i + 1] - lams[i]
        if d1 * d2 < 0:
            lam_c, s_c = refine_extremum(s[i - 1 : i + 2], lams[i - 1 : i + 2], slopes[i - 1 : i + 2])
            found.append(CriticalPoint("limit", "maximum" if d1 > 0 else "minimum", i, float(lam_c), float(s_c)))
    limit_steps = {f.step for f in found}
    for i in range(1, n):
        if signs[i] * signs[i - 1] < 0:
            near = any(abs(i - j) <= 1 or abs(i - 1 - j) <= 1 for j in limit_steps)
            if not near:
                found.append(CriticalPoint("bifurcation", "det K changes sign", i, float(lams[i]), float(s[i])))
    for i, note in path.branch_switches:
        # the step that crossed: its unstable state was replaced by a stable one
        found.append(
            CriticalPoint("bifurcation", "det K changes sign", i, float(lams[i]), float(s[i]), branch_switch=note)
        )
    return sorted(found, key=lambda f: f.step)
