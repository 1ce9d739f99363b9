"""Adapter: a case -> the pseudo-rigid-body models of ``prbm`` -> the requested outputs.

Segments (x along the undeformed segment from the fixed end, force = values * direction, CCW
moments; the tip loads of each level summed into (F_x, F_y, M), P = F_y, n = -F_x/F_y as in the end
force (-nP, P) of [bapat2015]):

* fixed-free / fixed-pinned (straight or initially curved), and fixed-guided without a model:
  ``prbm_segment.py`` (fixed_pinned_tip, pure_moment_tip, fixed_guided_monotonic_tip, composite_beam_tip,
  curved_fixed_pinned_tip, fixed_guided_tip; its docstring lists the models, options, outputs and the
  applicability flags).
* fixed-guided / fixed-fixed with ``segment.model = 'inflection'``: the chapter-3 PRBM (eqs 83-104),
  here.  Options: ``problem = 'loads'`` (default; P, nP, M from the case loads, M opposing = -moment) or
  ``problem = 'displacement'`` with per-level lists ``b``, ``theta0_deg`` and one of ``a``, ``n``,
  ``l1`` (Tables 3.3-3.6); ``prefer`` = 'energy' (default) or {key = value} to pick among roots.
  All roots found are in ``extras['roots']``.
* loads along the segment or toward a point: ``prbm_readings.py``; the other segment models of
  [bapat2015, ch. 2] (``model`` option): ``prbm_alternatives.py``.

Mechanisms (``_mechanism`` dispatches): 'dof' requests and hand-given four-bars and slider-cranks
(``links`` option) -> ``prbm_fourbar.py``; one beam carrying a rigid body (chapter 5 Example 1) and
the curved pinned-pinned beam on a slider -> ``prbm_body.py``; every other mechanism, or
``model = 'network'`` -> the PRB model built from the geometry by the rules of ``prbm.builder`` and solved as a
general rigid-link network (``prbm_network.py``, ``prbm.build``, ``prbm.solve``).

Shapes: ``extras['shapes']`` holds, per level, the PRB links as (n, 2) polylines in the case frame:
inflection model root -> pivot 1 -> inflection point -> pivot 2 -> end (``prbm_segment.py`` and the
mechanism modules describe theirs).
"""

from __future__ import annotations

import time
from enum import Enum
from typing import TYPE_CHECKING

import numpy as np

import prbm
from prbm.lazy import LazyModule
from validation.case.method_options import PrbmOptions
from validation.methods import prbm_alternatives, prbm_ma, prbm_readings, prbm_segment
from validation.methods.base import MethodRun, NotApplicable, Request, reject_loads_along_beams
from validation.methods.prbm_common import DEG
from validation.methods.prbm_common import prefer as prefer_option

if TYPE_CHECKING:  # loaded at first use (below); named here for the static import walks (run-cache hash)
    from validation.methods import prbm_body, prbm_fourbar, prbm_inflection, prbm_network
else:  # the mechanism parts import scipy and the network solver: a segment case does not load them
    prbm_body = LazyModule("validation.methods.prbm_body")
    prbm_fourbar = LazyModule("validation.methods.prbm_fourbar")
    prbm_inflection = LazyModule("validation.methods.prbm_inflection")
    prbm_network = LazyModule("validation.methods.prbm_network")


def run(case, requests: list[Request], options: PrbmOptions) -> MethodRun:
    t0 = time.perf_counter()
    if prbm_readings.handles(case, options):  # loads along the segment, a force toward a point
        return prbm_readings.run(case, requests, options)
    if not prbm_readings.turning_fourbar(case, options):
        reject_loads_along_beams(
            case,
            "the PRBM",
            turning=_takes_turning_loads(case, options),
            why="no seed PRB model of a mechanism takes loads along its beams (the Chain "
            "Algorithm models one cantilevered segment)",
        )
    if options.model in prbm_alternatives.MODELS:  # the other segment models of [bapat2015, ch. 2]
        return prbm_alternatives.run(case, requests, options)
    try:
        if prbm_ma.handles(case, options):  # chapter 7 MA by prbm.compliance
            values, run_info = prbm_ma.run(case, requests, options)
        elif case.segment is not None:
            values, run_info = _segment(case, requests, options)
        else:
            values, run_info = _mechanism(case, requests, options)
    except prbm.FitRangeError as exc:
        raise NotApplicable(f"PRBM fit range: {exc}") from None
    run_info.wall_time = time.perf_counter() - t0
    run_info.values = values
    return run_info


# --- segments -------------------------------------------------------------------------------------
def _segment(case, requests, options):
    if case.segment.boundary in ("fixed-guided", "fixed-fixed") and case.segment.model == "inflection":
        return _inflection(case, requests, options, case.segment.bending_stiffness())
    return prbm_segment.run_segment(case, requests, options)


def _inflection(case, requests, options, EI):
    seg = case.segment
    n = case.n_levels()
    beam = prbm.InflectionBeam(seg.length, EI, options.family)
    problem = options.problem
    prefer = prefer_option(options)
    needed = sorted({r.level for r in requests})
    results = {}
    if problem == "loads":
        loads = prbm_segment.tip_loads(case, n)
        if loads.follower:
            raise NotApplicable("follower loads on the chapter-3 fixed-guided PRBM")
        for lv in needed:
            results[lv] = prbm.solve_loads(
                beam, float(loads.Fy[lv]), float(-loads.Fx[lv]), float(-loads.M[lv]), prefer=prefer
            )
    elif problem == "displacement":

        def per_level(key, lv):
            v = getattr(options, key)
            return None if v is None else float(v[lv] if isinstance(v, list) else v)

        for lv in needed:
            kw = {k: per_level(k, lv) for k in ("a", "n", "l1")}
            results[lv] = prbm.solve_displacements(
                beam,
                b=per_level("b", lv),
                theta0=per_level("theta0_deg", lv) * DEG,
                prefer=prefer,
                **{k: v for k, v in kw.items() if v is not None},
            )
    else:
        raise NotApplicable(f"unknown PRBM problem '{problem}' (use 'loads' or 'displacement')")
    values = {}
    info = MethodRun(values={})
    messages = []
    for req in requests:
        res = results[req.level]
        o = res.outputs
        table = {
            "x": o["a"],
            "y": o["b"],
            "dx": o["a"] - seg.length,
            "dy": o["b"],
            "rotation": np.degrees(o["theta0"]),
            "force_x": -o["nP"],
            "force_y": o["P"],
            "moment": -o["M"],
        }
        if "U" in o:
            table["strain_energy"] = o["U"]
        if req.quantity not in table:
            raise NotApplicable(f"the chapter-3 PRBM gives no '{req.quantity}'")
        values[req] = float(table[req.quantity])
    for lv, res in results.items():
        info.level_converged[lv] = bool(res.converged)
        info.level_messages[lv] = res.message
        messages.append(f"level {lv}: {res.message}")
    info.converged = all(r.converged for r in results.values())
    info.message = "; ".join(messages)
    info.extras = {
        "roots": {lv: [{k: v for k, v in root.items()} for root in res.roots[0]] for lv, res in results.items()},
        "model": "fixed-guided with one inflection point, seed 000 eqs (83)-(104)",
        "shapes": {lv: [prbm.inflection_pivots(res.outputs)] if res.converged else [] for lv, res in results.items()},
    }
    return values, info


# --- mechanisms -----------------------------------------------------------------------------------
def _mechanism(case, requests, options):
    mech = case.mechanism
    info = MethodRun(values={})
    values = {}
    if any(r.quantity == "dof" for r in requests):
        values, requests = prbm_fourbar.dof_values(mech, requests, options, info)
        if not requests:
            return values, info
    if prbm_inflection.applies(case, options):  # chapter 5: inflection segments on one rigid coupler
        values.update(prbm_inflection.run_coupler(case, requests, info))
        return values, info
    route = _route(case, options)
    if route is Route.PINNED_PINNED:
        values.update(prbm_body.run_pinned_pinned(case, requests, info))
    elif route is Route.SEGMENT_WITH_BODY:
        values.update(prbm_body.run_segment_with_body(case, requests, options, info))
    elif route is Route.SLIDER:
        values.update(prbm_fourbar.run_slider(case, requests, options, info))
    elif route is Route.NETWORK:
        values.update(prbm_network.run_mechanism(case, requests, options, info))
    else:
        values.update(prbm_fourbar.run_fourbar(case, requests, options, info))
    return values, info


class Route(Enum):
    """Which PRB model a mechanism case is solved with."""

    PINNED_PINNED = "one pinned-pinned beam on a slider"
    SEGMENT_WITH_BODY = "one beam carrying a rigid body"
    SLIDER = "the hand-given PRB slider-crank"
    NETWORK = "the PRB network built from the geometry"
    FOURBAR = "the hand-given PRB four-bar"


def _route(case, options: PrbmOptions) -> Route:
    """The PRB model of a mechanism case (after the chapter-5 inflection coupler and the DOF analysis)."""
    mech, links = case.mechanism, options.links
    kinds = sorted(sup.kind for sup in mech.supports)
    if not links and not mech.links and len(mech.beams) == 1 and kinds == ["pinned", "slider"]:
        return Route.PINNED_PINNED
    if not links and prbm_body.one_beam_carrying_a_body(mech) and options.model != "network":
        return Route.SEGMENT_WITH_BODY
    if links and "r11" in links:
        return Route.SLIDER
    if not links or options.model == "network":
        return Route.NETWORK
    return Route.FOURBAR


def _takes_turning_loads(case, options: PrbmOptions) -> bool:
    """Whether the case's PRB model takes forces toward a fixed point and forces turning with a named body:
    the network built from a mechanism's geometry (``prbm.network``: pulls and followers on its bodies)."""
    return (
        case.mechanism is not None
        and not prbm_ma.handles(case, options)
        and not prbm_inflection.applies(case, options)
        and _route(case, options) is Route.NETWORK
    )
