"""The inverse tip problem a segment case may pose beside its forward loads: one definition for
every method that solves it (the FEM and elastica adapters read it; the PRBM's own
``problem = 'displacement'`` options use the same names).

[bapat2015, §3.5.2] (Tables 3.3-3.6) specifies the tip of a clamped segment by its position
and slope and asks for the end loads: the tip's y = ``b`` (length units) and its absolute slope
``theta0_deg`` (degrees) are prescribed at every level, and the remaining tip freedom (x) is fixed
by exactly one of

* ``a``: the tip's x is prescribed too (Case 1, Table 3.3);
* ``n``: the axial load is tied to the transverse one, F_x = -n P with P = F_y (Cases 2a/2b,
  Tables 3.4-3.5; n = 0 is a free x with no axial load);
* ``axial_load``: a fixed axial load F_x (force units; in the dissertation's signs F_x = -nP);
* ``l1``: the bending moment vanishes at arc length l1 from the clamp, an inflection point
  (Case 2c, Table 3.6).

In a case file it is the option table ``inverse`` of ``[methods.fem]`` or ``[methods.elastica]``,
each entry a per-level list (or one value for every level), e.g.
``inverse = { b = [12.0, 12.0], theta0_deg = [40.0, 40.0], n = [0.25, 1.25] }``. Optional ``I``
or ``EI`` give the section the inverse problem is solved with (default: the method's own); the FEM
also takes ``elements`` and ``richardson`` there (its mesh and extrapolation for this problem). The
method then reports the loads needed (``force_x``, ``force_y``, ``moment`` at the tip: the total
load acting on the tip) from the inverse problem, and every other output from its forward solve
under the case's loads, so the dissertation's forward columns (analyses under the PRBM loads) are kept.
With ``tip_x = true`` (FEM) the tip's ``x`` is that of the inverse solution too: the end position
a that b, theta0 and the tie lead to (section 3.6's vector loop asks for the same a; with the tie
``a`` the x is prescribed, so ``tip_x`` is refused there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

from validation.case.method_options import FemInverseOptions, InverseOptions
from validation.methods.base import MethodRun, NotApplicable

LOAD_OUTPUTS = ("force_x", "force_y", "moment")
POSITION_OUTPUT = "x"  # the tip's x of the inverse solution, with ``tip_x = true``


class Tie(Enum):
    """What fixes the tip's x freedom (module docstring); the value is the option's name."""

    POSITION_X = "a"
    LOAD_RATIO = "n"
    AXIAL_LOAD = "axial_load"
    INFLECTION = "l1"


@dataclass(frozen=True)
class InverseLevel:
    """The prescribed tip state of one load level."""

    b: float  # tip y, length units
    theta0: float  # absolute tip slope, rad
    tie: Tie
    value: float  # a (length), n (1), axial load (force) or l1 (length)


@dataclass(frozen=True)
class InverseSpec:
    levels: tuple[InverseLevel, ...]
    I: float | None = None
    EI: float | None = None
    tip_x: bool = False  # the tip's x is reported from the inverse solution (FEM)


def _per_level(value: float | list[float], name: str, n: int, where: str) -> list[float]:
    values = list(value) if isinstance(value, list) else [value] * n
    if len(values) != n:
        raise NotApplicable(f"{where}.{name}: {len(values)} values for {n} load levels")
    return values


def inverse_spec(case, table: InverseOptions | None, method: str) -> InverseSpec | None:
    """The inverse problem of the ``inverse`` option table (its model: the names, finite values and exactly
    one tie are checked there), or None when there is none."""
    if table is None:
        return None
    where = f"methods.{method}.inverse"
    if case.segment is None:
        raise NotApplicable(f"{where}: the inverse tip problem is posed on a single segment")
    if case.segment.boundary == "pinned-pinned":
        raise NotApplicable(f"{where}: needs a segment clamped at its root (boundary is pinned-pinned)")
    tie = next(t for t in Tie if getattr(table, t.value) is not None)
    n = case.n_levels()
    b = _per_level(table.b, "b", n, where)
    theta = _per_level(table.theta0_deg, "theta0_deg", n, where)
    value = _per_level(getattr(table, tie.value), tie.value, n, where)
    if tie is Tie.INFLECTION and not all(0.0 < s < case.segment.length for s in value):
        raise NotApplicable(f"{where}.l1: must lie inside the segment (0, {case.segment.length:g})")
    levels = tuple(InverseLevel(b[i], math.radians(theta[i]), tie, value[i]) for i in range(n))
    tip_x = isinstance(table, FemInverseOptions) and table.tip_x
    if tip_x and tie is Tie.POSITION_X:
        raise NotApplicable(f"{where}.tip_x: the tip's x is prescribed (a); it is no result of the inverse problem")
    return InverseSpec(levels, table.I, table.EI, tip_x)


def merge_runs(forward: MethodRun | None, inverse: MethodRun) -> MethodRun:
    """One run from the forward outputs and the inverse problem's tip loads."""
    if forward is None:
        return inverse
    levels = set(forward.level_converged) | set(inverse.level_converged)
    ok = {lv: forward.level_converged.get(lv, True) and inverse.level_converged.get(lv, True) for lv in levels}
    msgs = {
        lv: "; ".join(
            m for m in (forward.level_messages.get(lv), inverse.level_messages.get(lv)) if m and m != "converged"
        )
        or "converged"
        for lv in levels
    }
    message = "; ".join(m for m in (forward.message, inverse.message) if m and m != "converged")
    return MethodRun(
        values=forward.values | inverse.values,
        converged=forward.converged and inverse.converged,
        message=message or "converged",
        wall_time=forward.wall_time + inverse.wall_time,
        error_estimate=forward.error_estimate | inverse.error_estimate,
        unreliable_estimate=forward.unreliable_estimate | inverse.unreliable_estimate,
        level_converged=ok,
        level_messages=msgs,
        extras=forward.extras,
    )
