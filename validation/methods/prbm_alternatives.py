"""Adapter for the alternative segment models of [bapat2015, ch. 2], chosen by ``[methods.prbm] model``.

* ``model = "theta-dependent"``: the fixed-pinned PRBM with K_Theta(n, Theta) of eq (51) or (52)
  (``prbm.theta_dependent``); option ``theta_fit`` = "51", "52" or "52-tension".  A straight
  fixed-free / fixed-pinned segment with a tip force (no moment).
* ``model = "chain"``: the Chain Algorithm, eqs (26)-(40) (``prbm.chain``), of a straight cantilevered
  segment (fixed-free, or fixed-guided with its end rotation free under a moment) with tip forces and
  moment; options ``chain_elements`` (by default the number section 3.4 used), ``chain_steps`` (load
  increments; the defaults are ``method_options.PrbmOptions``'s).  ``problem = "displacement"`` with ``b``,
  ``theta0_deg`` and ``n`` (per level) solves for the tip loads instead (the Chain row of Table 3.1).
* ``model = "lyon"``: Lyon et al.'s fixed-guided PRBM, eqs (64)-(70) (``prbm.lyon``), under a tip force.
* ``model = "feasible-l1"``: section 3.6's vector loop, eqs (105)-(107) (``prbm.feasible_l1``), for the
  fixed-guided beam with ``b``, ``theta0_deg`` and ``l1`` given (per level): the end's x (a = l - R5) and
  the PRB angle Theta1; a level whose l1 is not feasible is NotApplicable with the reason.

Frames and signs as in ``validation/methods/prbm.py``: x along the undeformed segment from the clamp,
force = values x direction, CCW moments; outputs x = a, y = b, dx, dy, rotation (deg), force_x, force_y,
moment (CCW), prb_angle (deg, theta-dependent).
"""

from __future__ import annotations

import math
import time

from typing import TYPE_CHECKING

from prbm.fits import FitRangeError
from prbm.lazy import LazyModule
from validation.case.method_options import PrbmOptions
from validation.methods.base import MethodRun, NotApplicable, Request
from validation.methods.prbm_atlas import flag_atlas_levels, theta_dependent_levels

if TYPE_CHECKING:  # loaded at first use (below); named here for the static import walks (run-cache hash)
    from prbm import chain as chain_model
    from prbm import feasible_l1
    from prbm import lyon as lyon_model
    from prbm import theta_dependent
else:  # these models import scipy.optimize: only a case that asks for one pays for it
    chain_model = LazyModule("prbm.chain")
    feasible_l1 = LazyModule("prbm.feasible_l1")
    lyon_model = LazyModule("prbm.lyon")
    theta_dependent = LazyModule("prbm.theta_dependent")

MODELS = ("theta-dependent", "chain", "lyon", "feasible-l1")


def run(case, requests: list[Request], options: PrbmOptions) -> MethodRun:
    t0 = time.perf_counter()
    model = options.model
    if model is None:
        raise NotApplicable(f"no alternative PRBM model named: give [methods.prbm] model, one of {', '.join(MODELS)}")
    seg = case.segment
    if seg is None:
        raise NotApplicable(f"model '{model}' is a single-segment model; this case is a mechanism")
    if seg.initial_curvature() != 0.0:
        raise NotApplicable(f"model '{model}': the seed gives it for initially straight segments only")
    if model == "chain" and options.problem == "displacement":
        rows = _chain_inverse(case, requests, options)
    elif model == "feasible-l1":
        rows = _loop(case, requests, options)
    else:
        loads = _tip_loads(case)
        solve = {"theta-dependent": _theta_dependent, "chain": _chain, "lyon": _lyon}[model]
        asked = _levels(requests)
        EI = seg.bending_stiffness()
        rows = [solve(case, loads[lv], options, EI) if lv in asked else None for lv in range(case.n_levels())]
    info = MethodRun(values={})
    for req in requests:
        table, _ = rows[req.level]
        if req.quantity not in table:
            raise NotApplicable(f"the {model} model gives no '{req.quantity}'")
        info.values[req] = float(table[req.quantity])
    for lv, row in enumerate(rows):
        if row is not None:
            info.level_converged[lv] = bool(row[1].converged)
            info.level_messages[lv] = row[1].message
    info.converged = all(info.level_converged.values())
    info.message = "; ".join(f"level {lv}: {m}" for lv, m in info.level_messages.items())
    info.extras = {"model": next(r[1].model for r in rows if r is not None)}
    if model == "theta-dependent":
        flag_atlas_levels(info, theta_dependent_levels(options.theta_fit, loads, seg.length, EI))
    info.wall_time = time.perf_counter() - t0
    return info


def _levels(requests) -> set[int]:
    return {r.level for r in requests}


def _tip_loads(case) -> list[tuple[float, float, float]]:
    """(F_x, F_y, M) at the tip for each level (dead loads only): 0 + each load's value times its
    direction component, in plain floats."""
    n = case.n_levels()
    Fx, Fy, M = [0.0] * n, [0.0] * n, [0.0] * n
    for i, load in enumerate(case.loads):
        if load.point != "tip":
            raise NotApplicable(f"loads.{i} acts on '{load.point}'; these segment models take end loads only")
        if load.kind == "force" and (load.follower or load.body is not None or load.toward is not None):
            raise NotApplicable(f"loads.{i}: only dead forces of fixed direction")
        values = [float(v) for v in load.levels()]
        if load.kind == "force":
            dx, dy = float(load.direction[0]), float(load.direction[1])
            Fx = [f + v * dx for f, v in zip(Fx, values)]
            Fy = [f + v * dy for f, v in zip(Fy, values)]
        elif load.kind == "moment":
            M = [m + v for m, v in zip(M, values)]
        else:
            raise NotApplicable(f"loads.{i}: a prescribed {load.kind}; these models take forces and moments")
    return list(zip(Fx, Fy, M))


def _table(case, a, b, theta0, Fx, Fy, M, **extra) -> dict[str, float]:
    L = case.segment.length
    return {
        "x": a,
        "y": b,
        "dx": a - L,
        "dy": b,
        "rotation": math.degrees(theta0),
        "force_x": Fx,
        "force_y": Fy,
        "moment": M,
        **extra,
    }


def _theta_dependent(case, load, options, EI: float):
    Fx, Fy, M = load
    seg = case.segment
    if seg.boundary not in ("fixed-free", "fixed-pinned"):
        raise NotApplicable(f"the Theta-dependent K_Theta (eqs 51, 52) is a fixed-pinned model, not {seg.boundary}")
    if M != 0.0:
        raise NotApplicable("the Theta-dependent K_Theta (eqs 51, 52) is fitted for an end force only")
    if Fy == 0.0:
        raise NotApplicable("no transverse end force: the fit's load ratio n = -F_x/F_y is undefined")
    try:
        res = theta_dependent.theta_dependent_tip(Fy, -Fx / Fy, length=seg.length, EI=EI, fit=options.theta_fit)
    except FitRangeError as exc:
        raise NotApplicable(f"PRBM fit range: {exc}") from None
    o = res.outputs
    return _table(
        case, float(o["a"]), float(o["b"]), float(o["theta0"]), Fx, Fy, M, prb_angle=math.degrees(float(o["Theta"]))
    ), res


def _chain_beam(case, options, EI: float) -> chain_model.ChainBeam:
    seg = case.segment
    if seg.boundary not in ("fixed-free", "fixed-pinned", "fixed-guided"):
        raise NotApplicable(f"the Chain Algorithm here models a cantilevered segment, not {seg.boundary}")
    return chain_model.ChainBeam(seg.length, EI, options.chain_elements)


def _chain(case, load, options, EI: float):
    Fx, Fy, M = load
    if case.segment.boundary == "fixed-guided" and M == 0.0:
        raise NotApplicable(
            "fixed-guided end without a moment load: the Chain Algorithm here needs "
            "the end moment given (no rotation condition)"
        )
    beam = _chain_beam(case, options, EI)
    res = chain_model.chain_tip(beam, chain_model.NodalLoads.at_tip(beam, Fx, Fy, M), steps=options.chain_steps)
    o = res.outputs
    return _table(case, float(o["a"]), float(o["b"]), float(o["theta0"]), Fx, Fy, M), res


def _per_level(options: PrbmOptions, key: str, lv: int) -> float:
    v = getattr(options, key)
    if v is None:
        raise NotApplicable(f"problem = 'displacement' needs [methods.prbm] {key}")
    return float(v[lv] if isinstance(v, list) else v)


def _chain_inverse(case, requests, options):
    beam = _chain_beam(case, options, case.segment.bending_stiffness())
    asked = _levels(requests)
    rows = []
    for lv in range(case.n_levels()):
        if lv not in asked:
            rows.append(None)
            continue
        n = _per_level(options, "n", lv)
        res = chain_model.chain_from_tip(
            beam,
            b=_per_level(options, "b", lv),
            theta0=math.radians(_per_level(options, "theta0_deg", lv)),
            n=n,
            steps=options.chain_steps,
        )
        o = res.outputs
        rows.append(
            (
                _table(
                    case,
                    float(o["a"]),
                    float(o["b"]),
                    float(o["theta0"]),
                    -float(o["nP"]),
                    float(o["P"]),
                    float(o["M"]),
                ),
                res,
            )
        )
    return rows


def _lyon(case, load, options, EI: float):
    Fx, Fy, M = load
    seg = case.segment
    if seg.boundary not in ("fixed-guided", "fixed-fixed"):
        raise NotApplicable(f"Lyon et al.'s PRBM (eqs 64-70) is a fixed-guided model, not {seg.boundary}")
    if M != 0.0:
        raise NotApplicable(
            "Lyon et al.'s PRBM (eqs 64-70) takes the end force only; its equal-torque condition fixes the end moment"
        )
    try:
        res = lyon_model.lyon_tip(Fx, Fy, length=seg.length, EI=EI)
    except FitRangeError as exc:
        raise NotApplicable(f"PRBM fit range: {exc}") from None
    o = res.outputs
    return _table(case, float(o["a"]), float(o["b"]), float(o["theta0"]), Fx, Fy, float(o["M"])), res


def _loop(case, requests, options):
    seg = case.segment
    if seg.boundary not in ("fixed-guided", "fixed-fixed"):
        raise NotApplicable(f"the section 3.6 vector loop is a fixed-guided model, not {seg.boundary}")
    asked = _levels(requests)
    rows = []
    for lv in range(case.n_levels()):
        if lv not in asked:
            rows.append(None)
            continue
        b, theta0 = _per_level(options, "b", lv), math.radians(_per_level(options, "theta0_deg", lv))
        st = feasible_l1.loop_closure(length=seg.length, b=b, theta0=theta0, l1=_per_level(options, "l1", lv))
        if not st.feasible:
            raise NotApplicable(f"level {lv}: l1 = {st.l1:g} is not feasible: {st.reason}")
        res = _LoopResult(True, "feasible", "section 3.6 vector loop, seed 000 eqs (105)-(107)")
        table = _table(case, st.a, b, theta0, 0.0, 0.0, 0.0, prb_angle=math.degrees(st.Theta1))
        for key in ("force_x", "force_y", "moment"):  # the loop is kinematic: it gives no loads
            del table[key]
        rows.append((table, res))
    return rows


class _LoopResult:
    """The few fields run() reads from a library result, for the loop (which solves no loads)."""

    def __init__(self, converged: bool, message: str, model: str) -> None:
        self.converged, self.message, self.model = converged, message, model
