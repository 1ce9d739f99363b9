"""Adapter: a case -> the pseudo-rigid-body models of ``prbm`` -> the requested outputs.

Segments (x along the undeformed segment from the fixed end, force = values * direction, CCW
moments).  The tip loads of each level are summed into (F_x, F_y, M); the PRBM load ratio follows
as P = F_y, n = -F_x/F_y (seed 000: end force (-nP, P)).

* fixed-free / fixed-pinned, straight: force only -> ``fixed_pinned_tip`` (eqs 41-49; options
  ``family`` = 'pauly-midha' (default) or 'howell' (seed 004), ``extrapolate``); moment only ->
  ``pure_moment_tip`` (seed 004); force and moment -> ``fixed_guided_monotonic_tip`` (equivalent
  initial curvature, valid without inflection); follower force -> ``composite_beam_tip(follower=True)``.
  A 'layers' section uses EI = sum E_i I_i (sliding layers).  Options ``friction_mu`` and
  ``contact_angle_deg`` apply the capstan factor exp(-mu beta) (eq 211) to the forces.
* fixed-free, initially curved: ``curved_fixed_pinned_tip`` (eqs 53-61).
* fixed-guided / fixed-fixed with ``segment.model = 'inflection'``: the chapter-3 PRBM (eqs 83-104).
  Options: ``problem = 'loads'`` (default; P, nP, M from the case loads, M opposing = -moment) or
  ``problem = 'displacement'`` with per-level lists ``b``, ``theta0_deg`` and one of ``a``, ``n``,
  ``l1`` (Tables 3.3-3.6); ``prefer`` = 'energy' (default) or {key = value} to pick among roots.
  All roots found are in ``extras['roots']``.
* fixed-guided without a model: force only -> ``fixed_guided_tip`` (two springs, eq 63); with a
  moment -> ``fixed_guided_monotonic_tip``.
Outputs: x = a, y = b, dx, dy (from the unloaded tip), rotation = theta0 (deg), force_x = -nP,
force_y = P, moment (CCW), prb_angle (deg), strain_energy (PRBM springs).
Applicability (issue 14 item 3; ``MethodRun.applicability``, per level, the results table's column):
``INFLECTION`` where a force and an end moment bend the PRBM's deformed state through an inflection
point (tip and root moments of opposite signs: Table 2.1 and eq (12)) while the monotonic model
(eq 62) was used; ``LOAD_RATIO`` where n lies outside the fit family's range (only reached with
``extrapolate`` = 'warn' or 'allow'; 'raise' refuses the case); ``DEFLECTION`` where |Theta - Theta_i|
passes the fits' printed 65 deg (eqs 51-52).

Mechanisms (``_mechanism`` dispatches): 'dof' requests and hand-given four-bars and slider-cranks
(``links`` option) -> ``prbm_fourbar.py``; one beam carrying a rigid body (chapter 5 Example 1) and
the curved pinned-pinned beam on a slider -> ``prbm_body.py``; every other mechanism, or
``model = 'network'`` -> the PRB model built from the geometry by the seeds' rules and solved as a
general rigid-link network (``prbm_network.py``, ``prbm.build``, ``prbm.solve``).

Shapes: ``extras['shapes']`` holds, per level, the PRB links as (n, 2) polylines in the case frame:
fixed-pinned segment root -> pivot -> tip; two-spring fixed-guided root -> pivot -> pivot -> tip;
inflection model root -> pivot 1 -> inflection point -> pivot 2 -> end (the mechanism modules
describe theirs).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

import prbm
from prbm.fits import THETA_RANGE, fit_family
from prbm.result import PRBMResult
from validation.methods import (prbm_alternatives, prbm_body, prbm_fourbar, prbm_inflection, prbm_ma,
                                prbm_network, prbm_readings)
from validation.methods.base import (Applicability, MethodRun, NotApplicable, Request,
                                     reject_loads_along_beams)
from validation.methods.prbm_common import DEG, pick, plain
from validation.methods.prbm_common import per_level as _per_level
from validation.methods.prbm_common import prefer as prefer_option
from validation.case.quantities import boundary_held_tip, unloaded_tip_angle


def run(case, requests: list[Request], options: dict) -> MethodRun:
    t0 = time.perf_counter()
    if prbm_readings.handles(case, options):  # loads along the segment, a force toward a point (issue 20)
        return prbm_readings.run(case, requests, options)
    if not prbm_readings.turning_fourbar(case, options):
        reject_loads_along_beams(case, "the PRBM")
    if options.get("model") in prbm_alternatives.MODELS:  # seed 000 chapter 2's other segment models
        return prbm_alternatives.run(case, requests, options)
    try:
        if prbm_ma.handles(case, options):                      # chapter 7 MA by prbm.compliance
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
@dataclass
class TipLoads:
    """The end loads of every level, summed, in the segment frame (x along the undeformed segment);
    whether any level has a transverse force or an end moment."""

    Fx: np.ndarray
    Fy: np.ndarray
    M: np.ndarray
    follower: bool
    has_force: bool
    has_moment: bool

    def ratio(self) -> np.ndarray:
        """The load ratio n = -F_x/F_y of every level (0 where F_y = 0; a purely axial force is refused).
        Level by level in plain floats (a few levels: numpy's per-call cost would dominate)."""
        ratio = []
        for fx, fy in zip(self.Fx.tolist(), self.Fy.tolist()):
            if fy == 0.0 and fx != 0.0:
                raise NotApplicable("a purely axial end force: outside every PRBM n-fit (n infinite)")
            ratio.append(-fx / fy if fy != 0.0 else 0.0)
        return np.array(ratio)


def _tip_loads(case, n: int) -> TipLoads:
    Fx, Fy, M = np.zeros(n), np.zeros(n), np.zeros(n)
    follower = False
    for i, load in enumerate(case.loads):
        if load.point != "tip":
            raise NotApplicable(f"loads.{i} acts on '{load.point}'; the segment PRBMs take end loads only")
        v = np.asarray(load.levels(), float)
        if load.kind == "force":
            d = load.direction
            Fx += v * float(d[0])
            Fy += v * float(d[1])
            follower |= load.follower
        elif load.kind == "moment":
            M += v
        else:
            raise NotApplicable(f"a prescribed {load.kind} at the tip: give the PRBM inverse inputs in "
                                "[methods.prbm] options instead")
    return TipLoads(Fx, Fy, M, follower, bool(Fy.any()), bool(M.any()))


@dataclass
class SegmentSolve:
    """A segment model's result, the unloaded tip (a0, b0) and what the adapter says about the choice."""

    res: PRBMResult
    a0: float
    b0: float
    message: str = ""


@dataclass(frozen=True)
class FitOptions:
    """The fit options every segment model takes: ``family`` and ``extrapolate``."""

    family: str
    extrapolate: str


def _segment(case, requests, options):
    seg = case.segment
    L = seg.length
    EI = seg.bending_stiffness()
    n = case.n_levels()
    fit = FitOptions(options.get("family", "pauly-midha"), options.get("extrapolate", "raise"))
    kappa = seg.initial_curvature()
    if seg.boundary in ("fixed-guided", "fixed-fixed") and seg.model == "inflection":
        return _inflection(case, requests, options, EI)
    loads = _tip_loads(case, n)
    capstan = prbm.capstan_factor(float(options.get("friction_mu", 0.0)),
                                  math.radians(float(options.get("contact_angle_deg", 0.0))))
    if capstan != 1.0:
        loads.Fx, loads.Fy = loads.Fx * capstan, loads.Fy * capstan
    ratio = loads.ratio()
    if seg.boundary in ("fixed-free", "fixed-pinned") and kappa == 0.0:
        solved = _free_straight(loads, ratio, L, EI, fit)
    elif seg.boundary in ("fixed-free", "fixed-pinned"):
        solved = _free_curved(loads, ratio, L, EI, kappa, fit)
    elif seg.boundary in ("fixed-guided", "fixed-fixed"):
        solved = _guided(case, loads, ratio, L, EI, kappa, fit)
    else:
        raise NotApplicable(f"boundary '{seg.boundary}' as a single segment case: the seeds' curved "
                            "pinned-pinned PRBM (prbm.curved_pinned_pinned) takes a chord force only")
    wanted = {r.quantity for r in requests}
    if loads.has_moment:  # the inflection check below reads the forces the tip receives
        wanted |= {"force_x", "force_y"}
    out = _segment_outputs(case, loads, solved, n, wanted)
    res = solved.res
    info = MethodRun(values={}, converged=bool(res.converged), message=solved.message or res.message)
    lc = res.level_converged
    info.level_converged = dict(enumerate(_per_level(lc, n).tolist())) \
        if lc is not None and np.size(lc) in (1, n) else {}
    info.extras = {"model": res.model, "constants": plain(res.constants)}
    if loads.has_moment:  # no end moment: the bending moment cannot change sign (eq 12)
        _warn_inflection(info, loads.M, out["force_x"], out["force_y"], out["x"], out["y"], solved.a0, solved.b0)
    _flag_fit_range(info, loads, ratio, res, fit, n)
    shapes = _segment_shapes(seg, res, n, kappa)
    if shapes:
        info.extras["shapes"] = shapes
    return pick(out, requests, "segment"), info


def _free_straight(loads: TipLoads, ratio, L: float, EI: float, fit: FitOptions) -> SegmentSolve:
    """A straight fixed-free (fixed-pinned) segment: the model that fits its load (module docstring)."""
    kw = {"length": L, "EI": EI, "family": fit.family, "extrapolate": fit.extrapolate}
    has_F, has_M = loads.has_force, loads.has_moment
    if loads.follower:
        if has_M:
            raise NotApplicable("follower force with an end moment: no PRBM in the seeds")
        loaded = ratio[loads.Fy != 0.0]  # an unloaded level has no ratio (n = 0 there is a placeholder)
        if len(loaded) and not np.allclose(loaded, loaded[0]):
            raise NotApplicable("follower force with a varying load ratio")
        return SegmentSolve(prbm.composite_beam_tip(loads.Fy, loaded[0] if len(loaded) else 0.0, follower=True,
                                                    **kw), L, 0.0)
    if has_F and has_M:
        return SegmentSolve(prbm.fixed_guided_monotonic_tip(loads.Fy, ratio, loads.M, **kw), L, 0.0,
                            "force and moment: equivalent initial curvature kappa0 = M l/EI (eq 62), no inflection")
    if has_M:
        return SegmentSolve(prbm.pure_moment_tip(loads.M, length=L, EI=EI), L, 0.0)
    return SegmentSolve(prbm.fixed_pinned_tip(loads.Fy, ratio, **kw), L, 0.0)


def _free_curved(loads: TipLoads, ratio, L: float, EI: float, kappa: float, fit: FitOptions) -> SegmentSolve:
    """An initially curved fixed-free segment (eqs 53-61); an end moment adds to the curvature (eq 62)."""
    if loads.follower:
        raise NotApplicable("a follower force on an initially curved segment: no PRBM in the seeds")
    kw = {"length": L, "EI": EI, "family": fit.family, "extrapolate": fit.extrapolate}
    if loads.has_moment:
        kappas = loads.M / EI + kappa
        res = _stack([prbm.curved_fixed_pinned_tip(fy, r, curvature=k, **kw)
                      for fy, r, k in zip(loads.Fy, ratio, kappas)])
    else:
        res = prbm.curved_fixed_pinned_tip(loads.Fy, ratio, curvature=kappa, **kw)
    return SegmentSolve(res, math.sin(kappa * L) / kappa, (1 - math.cos(kappa * L)) / kappa)


def _guided(case, loads: TipLoads, ratio, L: float, EI: float, kappa: float, fit: FitOptions) -> SegmentSolve:
    """A straight fixed-guided segment: two springs (eq 63), or monotonic with an end moment (eq 62)."""
    translations = [dof for dof in boundary_held_tip(case) if dof != "rz"]
    if translations:
        raise NotApplicable(f"fixed-fixed tip with {', '.join(translations)} held: the seeds' "
                            "fixed-guided PRBMs leave the tip free to translate")
    if kappa != 0.0:
        raise NotApplicable("initially curved fixed-guided segment without model = 'inflection'")
    if loads.follower:
        raise NotApplicable("a follower force on a fixed-guided segment: no PRBM in the seeds")
    kw = {"length": L, "EI": EI, "family": fit.family, "extrapolate": fit.extrapolate}
    if loads.has_moment:
        return SegmentSolve(prbm.fixed_guided_monotonic_tip(loads.Fy, ratio, loads.M, **kw), L, 0.0)
    res = prbm.fixed_guided_tip(loads.Fy, ratio, **kw)
    res.constants["k"] = 2.0 * np.asarray(res.constants["k_each"])  # U = 2 (k_each Theta^2/2)
    return SegmentSolve(res, L, 0.0)


def _segment_outputs(case, loads: TipLoads, solved: SegmentSolve, n: int, wanted: set[str]) -> dict:
    """The ``wanted`` outputs of a segment over the levels (always x, y), under the quantity contract
    (validation/case/quantities.py): rotation from the unloaded tangent angle, a held tip freedom
    reports the load that holds it."""
    seg = case.segment
    res = solved.res
    o = res.outputs
    a = _per_level(o["a"], n)
    b = _per_level(o["b"], n)
    out = {"x": a, "y": b, "moment": loads.M}
    if "dx" in wanted:
        out["dx"] = a - solved.a0
    if "dy" in wanted:
        out["dy"] = b - solved.b0
    if wanted & {"rotation", "force_x", "force_y"}:
        rotation = _per_level(o["theta0"] - unloaded_tip_angle(seg.length, seg.initial_curvature()), n)
        Fx, Fy = loads.Fx, loads.Fy
        if loads.follower:  # the force the tip receives has turned with it
            Fx, Fy = Fx * np.cos(rotation) - Fy * np.sin(rotation), Fx * np.sin(rotation) + Fy * np.cos(rotation)
        out.update({"force_x": Fx, "force_y": Fy, "rotation": np.degrees(rotation)})
    if "rz" in boundary_held_tip(case):
        if "M" not in o:
            raise NotApplicable(f"the PRBM ({res.model}) gives no moment holding the {seg.boundary} tip")
        out["moment"] = _per_level(o["M"], n)
    if "Theta" in o and wanted & {"prb_angle", "strain_energy"}:
        Theta = _per_level(o["Theta"], n)
        out["prb_angle"] = np.degrees(Theta)
        k = res.constants.get("k")
        if k is not None:
            Ti = res.constants.get("Theta_i", 0.0)
            out["strain_energy"] = 0.5 * np.asarray(k) * (Theta - Ti) ** 2
    return out


INFLECTION_WARNING = ("inflection point expected: the bending moment changes sign between tip and root "
                      "(seed 000 Table 2.1, eq (12)); the monotonic-curvature PRBM (eq 62) does not fit this load, "
                      "use segment.model = 'inflection' (fixed-guided)")


def _flag_fit_range(info: MethodRun, loads: TipLoads, ratio, res: PRBMResult, fit: FitOptions, n: int) -> None:
    """Flag the levels a model with the n-fits (seed 000 eqs 41-43, seed 004) solved outside the fits'
    ranges: the load ratio n outside the family's published range (reached only with ``extrapolate``
    'warn' or 'allow'; 'raise' refuses the case), or the PRB angle |Theta - Theta_i| past the printed
    Theta range of the fits (``prbm.fits.THETA_RANGE``, 65 deg)."""
    if "K_theta" not in res.constants or "family" not in res.constants or not loads.has_force:
        return  # not a model of the n-fits (pure moment: its own constants, seed 004)
    if fit.extrapolate != "raise":  # with 'raise' a ratio outside the fits has refused the case already
        family = fit_family(res.constants["family"])
        effective = np.where(loads.Fy < 0, -ratio, ratio)  # the fits are evaluated at the mirrored ratio for P < 0
        outside = ~((effective > family.lower) & (effective <= family.upper)) & (loads.Fy != 0)
        for level in np.nonzero(outside)[0].tolist():
            info.flag(level, Applicability.LOAD_RATIO)
    if "Theta" in res.outputs:
        turned = np.abs(_per_level(res.outputs["Theta"], n) - res.constants.get("Theta_i", 0.0)).tolist()
        for level, angle in enumerate(turned):
            if angle > THETA_RANGE:
                info.flag(level, Applicability.DEFLECTION)


def _warn_inflection(info: MethodRun, M, Fx, Fy, a, b, a0, b0) -> None:
    """Mark the levels whose end force and moment give an inflection point: the moment at the tip (M) and
    at the root (M + F_y a - F_x b) of opposite signs (Table 2.1's opposite senses, and the sufficient
    condition (12)), on the PRBM's own deformed state or on the unloaded one (a0, b0): the monotonic
    model's state can land on the branch without the inflection that the beam has."""
    root = M + Fy * a - Fx * b
    unloaded = M + Fy * a0 - Fx * b0
    inflected = np.nonzero(((M * root) < 0) | ((M * unloaded) < 0))[0]
    for level in inflected.tolist():
        info.level_messages[level] = INFLECTION_WARNING
        info.flag(level, Applicability.INFLECTION)
    if len(inflected):
        info.extras["inflection_levels"] = inflected.tolist()


def _stack(results: list[PRBMResult]) -> PRBMResult:
    """One result over the levels from one result per level."""
    keys = results[0].outputs.keys()
    out = {k: np.array([float(r.outputs[k]) for r in results]) for k in keys}
    return PRBMResult(all(r.converged for r in results), results[0].message, out, results[0].constants,
                      results[0].model, level_converged=np.array([r.converged for r in results]))


def _inflection(case, requests, options, EI):
    seg = case.segment
    n = case.n_levels()
    beam = prbm.InflectionBeam(seg.length, EI, options.get("family", "pauly-midha"))
    problem = options.get("problem", "loads")
    prefer = prefer_option(options)
    needed = sorted({r.level for r in requests})
    results = {}
    if problem == "loads":
        loads = _tip_loads(case, n)
        if loads.follower:
            raise NotApplicable("follower loads on the chapter-3 fixed-guided PRBM")
        for lv in needed:
            results[lv] = prbm.solve_loads(beam, float(loads.Fy[lv]), float(-loads.Fx[lv]), float(-loads.M[lv]),
                                           prefer=prefer)
    elif problem == "displacement":
        def per_level(key, lv):
            v = options.get(key)
            return None if v is None else float(v[lv] if isinstance(v, list) else v)

        for lv in needed:
            kw = {k: per_level(k, lv) for k in ("a", "n", "l1")}
            results[lv] = prbm.solve_displacements(beam, b=per_level("b", lv),
                                                   theta0=per_level("theta0_deg", lv) * DEG, prefer=prefer,
                                                   **{k: v for k, v in kw.items() if v is not None})
    else:
        raise NotApplicable(f"unknown PRBM problem '{problem}' (use 'loads' or 'displacement')")
    values = {}
    info = MethodRun(values={})
    messages = []
    for req in requests:
        res = results[req.level]
        o = res.outputs
        table = {"x": o["a"], "y": o["b"], "dx": o["a"] - seg.length, "dy": o["b"],
                 "rotation": np.degrees(o["theta0"]), "force_x": -o["nP"], "force_y": o["P"],
                 "moment": -o["M"]}
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
    info.extras = {"roots": {lv: [{k: v for k, v in root.items()} for root in res.roots[0]]
                             for lv, res in results.items()},
                   "model": "fixed-guided with one inflection point, seed 000 eqs (83)-(104)",
                   "shapes": {lv: [prbm.inflection_pivots(res.outputs)] if res.converged else []
                              for lv, res in results.items()}}
    return values, info


def _segment_shapes(seg, res, n: int, kappa: float) -> list | None:
    """Per level, the PRB links of a single-segment case in the case frame (fixed end at the origin).

    Fixed-free / fixed-pinned (straight): root -> characteristic pivot (1 - gamma) l -> tip.
    Fixed-guided, two springs (eq 63): root -> pivot (1 - gamma) l/2 -> + gamma l e^{i Theta} -> tip.
    Other models (curved, monotonic fixed-guided, composite, pure moment) give no chain here."""
    o, c = res.outputs, res.constants
    guided = seg.boundary in ("fixed-guided", "fixed-fixed")
    if kappa != 0.0 or "Theta" not in o or "gamma" not in c or guided and np.any(np.asarray(o.get("theta0", 0.0)) != 0.0):
        return None
    L = seg.length
    gamma, Theta, a, b = (_per_level(np.asarray(v, float), n) for v in (c["gamma"], o["Theta"], o["a"], o["b"]))
    chains = np.zeros((n, 4 if guided else 3, 2))  # one array; each level's polyline is a view of it
    if guided:
        p1 = (1 - gamma) * L / 2
        chains[:, 1, 0] = p1
        chains[:, 2, 0] = p1 + gamma * L * np.cos(Theta)
        chains[:, 2, 1] = gamma * L * np.sin(Theta)
    else:
        chains[:, 1, 0] = (1 - gamma) * L
    chains[:, -1, 0] = a
    chains[:, -1, 1] = b
    finite = np.isfinite(gamma + Theta + a + b).tolist()
    return [[chains[i]] if finite[i] else [] for i in range(n)]


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
    links = options.get("links")
    kinds = sorted(sup.kind for sup in mech.supports)
    if not links and not mech.links and len(mech.beams) == 1 and kinds == ["pinned", "slider"]:
        values.update(prbm_body.run_pinned_pinned(case, requests, info))
    elif not links and prbm_body.one_beam_carrying_a_body(mech) and options.get("model") != "network":
        values.update(prbm_body.run_segment_with_body(case, requests, options, info))
    elif links and "r11" in links:
        values.update(prbm_fourbar.run_slider(case, requests, options, info))
    elif not links or options.get("model") == "network":
        values.update(prbm_network.run_mechanism(case, requests, options, info))
    else:
        values.update(prbm_fourbar.run_fourbar(case, requests, options, info))
    return values, info
