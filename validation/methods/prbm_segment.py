"""PRBM adapter, single segments under end loads: a case -> the segment models of ``prbm.segments`` ->
the requested outputs.

Frames: x along the undeformed segment from the fixed end, force = values * direction, CCW moments.
The tip loads of each level are summed into (F_x, F_y, M); the PRBM load ratio follows as P = F_y,
n = -F_x/F_y ([bapat2015]: end force (-nP, P)).

* fixed-free / fixed-pinned, straight: force only -> ``fixed_pinned_tip`` (eqs 41-49; options
  ``family`` = 'pauly-midha' (default) or 'howell' [ananthasuresh_l18, 05:41], ``extrapolate``); moment
  only -> ``pure_moment_tip`` [ananthasuresh_l18, 16:59-21:58]; force and moment ->
  ``fixed_guided_monotonic_tip`` (equivalent initial curvature, valid without inflection); follower
  force -> ``composite_beam_tip(follower=True)``.  A 'layers' section uses EI = sum E_i I_i (sliding
  layers).  Options ``friction_mu`` and ``contact_angle_deg`` apply the capstan factor exp(-mu beta)
  (eq 211) to the forces.
* fixed-free, initially curved: ``curved_fixed_pinned_tip`` (eqs 53-61).
* fixed-guided without a model: force only -> ``fixed_guided_tip`` (two springs, eq 63); with a
  moment -> ``fixed_guided_monotonic_tip``.
* a prescribed tip motion (one 'displacement' along d, or one 'rotation', alone): the load that reaches
  it, a force along d or a moment, by a bracketed root on its magnitude over the model above
  (``prbm.load_for_motion``); a straight fixed-guided segment moved across its axis in closed form
  (``fixed_guided_displaced_tip``, eq 63).  No options needed.
Outputs: x = a, y = b, dx, dy (from the unloaded tip), rotation = theta0 (deg), force_x = -nP,
force_y = P, moment (CCW), prb_angle (deg), strain_energy (PRBM springs); at 'root' the clamp's
reaction_x, reaction_y, reaction_moment (minus the tip's total load and its moment about the root).
Applicability (``MethodRun.applicability``, per level): ``INFLECTION`` where a force
and an end moment bend the PRBM's deformed state through an inflection point (tip and root moments of
opposite signs: Table 2.1 and eq (12)) while the monotonic model (eq 62) was used; ``LOAD_RATIO`` where
n lies outside the fit family's range (only reached with ``extrapolate`` = 'warn' or 'allow'; 'raise'
refuses the case); ``DEFLECTION`` where |Theta - Theta_i| passes the fits' printed 65 deg (eqs 51-52);
``OUTSIDE_VALIDITY`` where the PRBM error atlas expects more than 5 % of L or does not map the load
(``validation.methods.prbm_atlas``), with the expected error of every level in ``MethodRun.expected_error``.
Shapes: ``extras['shapes']`` holds, per level, the PRB links as (n, 2) polylines in the case frame:
fixed-pinned segment root -> pivot -> tip; two-spring fixed-guided root -> pivot -> pivot -> tip.

Speed: a case has a few load levels, so everything between the case and the library
call, and between the library's result and the requested values, is plain Python floats level by level
(a numpy call's fixed overhead exceeds the arithmetic of a 10-level array); the library is called
once over all the levels.  The arithmetic is that of the equivalent array expressions, in the same
order, so the values are the same to the last bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, TypedDict

import numpy as np
from numpy.typing import NDArray

import prbm
from prbm.fits import THETA_RANGE, fit_family
from prbm.result import PRBMResult
from validation.case.method_options import PrbmOptions
from validation.case.quantities import boundary_held_tip, unloaded_tip_angle
from validation.methods.base import Applicability, DeferredList, MethodRun, NotApplicable
from validation.methods.prbm_atlas import flag_levels
from validation.methods.prbm_common import levels, per_level, pick, plain

REACTIONS = {"reaction_x", "reaction_y", "reaction_moment"}
_FROM_ROTATION = {"rotation", "force_x", "force_y"} | REACTIONS  # the outputs that read the tip's rotation
_FROM_PRB_ANGLE = {"prb_angle", "strain_energy"}
INFLECTION_WARNING = (
    "inflection point expected: the bending moment changes sign between tip and root "
    "(seed 000 Table 2.1, eq (12)); the monotonic-curvature PRBM (eq 62) does not fit this load, "
    "use segment.model = 'inflection' (fixed-guided)"
)


@dataclass
class TipLoads:
    """The end loads of every level, summed, in the segment frame (x along the undeformed segment), as
    plain floats; whether any level has a transverse force or an end moment."""

    Fx: list[float]
    Fy: list[float]
    M: list[float]
    follower: bool
    has_force: bool
    has_moment: bool

    def ratio(self) -> list[float]:
        """The load ratio n = -F_x/F_y of every level (0 where F_y = 0; a purely axial force is refused)."""
        ratio = []
        for fx, fy in zip(self.Fx, self.Fy):
            if fy == 0.0 and fx != 0.0:
                raise NotApplicable("a purely axial end force: outside every PRBM n-fit (n infinite)")
            ratio.append(-fx / fy if fy != 0.0 else 0.0)
        return ratio

    def scaled(self, factor: float) -> "TipLoads":
        """The forces times ``factor`` (the capstan factor), the moments unchanged."""
        return TipLoads(
            [f * factor for f in self.Fx],
            [f * factor for f in self.Fy],
            self.M,
            self.follower,
            self.has_force,
            self.has_moment,
        )


def tip_loads(case, n: int | None = None) -> TipLoads:
    """The case's tip loads summed per level (0 + each load's value times its direction component);
    ``n`` the number of levels (``case.n_levels()``, the first load's levels, when not given)."""
    per_load = [load.levels() for load in case.loads]
    if n is None:
        n = len(per_load[0]) if per_load else 1
    Fx = Fy = M = [0.0] * n
    follower = False
    for i, (load, values) in enumerate(zip(case.loads, per_load)):
        if load.point != "tip":
            raise NotApplicable(f"loads.{i} acts on '{load.point}'; the segment PRBMs take end loads only")
        if load.kind == "force":
            dx, dy = float(load.direction[0]), float(load.direction[1])
            Fx = [f + v * dx for f, v in zip(Fx, values)]
            Fy = [f + v * dy for f, v in zip(Fy, values)]
            follower |= load.follower
        elif load.kind == "moment":
            M = [m + float(v) for m, v in zip(M, values)]
        else:
            raise NotApplicable(
                f"a prescribed {load.kind} at the tip: give the PRBM inverse inputs in [methods.prbm] options instead"
            )
    return TipLoads(Fx, Fy, M, follower, any(f != 0.0 for f in Fy), any(m != 0.0 for m in M))


@dataclass
class SegmentSolve:
    """A segment model's result, the unloaded tip (a0, b0) and what the adapter says about the choice."""

    res: PRBMResult
    a0: float
    b0: float
    message: str = ""


class FitOptions(NamedTuple):
    """The fit options every segment model takes: ``family`` and ``extrapolate``."""

    family: str
    extrapolate: str


class _TipKeywords(TypedDict):
    """The keywords every ``prbm`` tip model takes: the segment's length and EI, and the fit options."""

    length: float
    EI: float
    family: str
    extrapolate: str


def _tip_keywords(L: float, EI: float, fit: FitOptions) -> _TipKeywords:
    return {"length": L, "EI": EI, "family": fit.family, "extrapolate": fit.extrapolate}


def run_segment(case, requests, options: PrbmOptions) -> tuple[dict, MethodRun]:
    """The requested values and the run of a single segment under end loads (not the inflection model)."""
    seg = case.segment
    L, EI, kappa = seg.length, seg.bending_stiffness(), seg.initial_curvature()
    fit = FitOptions(options.family, options.extrapolate)
    mu, contact = options.friction_mu, options.contact_angle_deg
    motion = prescribed_motion(case)
    if motion is not None:
        if mu or contact:
            raise NotApplicable(
                "friction_mu / contact_angle_deg with a prescribed motion: the tip load is the "
                "unknown, there is no applied force to correct"
            )
        loads, solved = _solve_prescribed(case, motion, L, EI, kappa, fit)
        ratio = loads.ratio()
    else:
        loads = tip_loads(case)
        if mu or contact:
            capstan = prbm.capstan_factor(float(mu), math.radians(float(contact)))
            if capstan != 1.0:
                loads = loads.scaled(capstan)
        ratio = loads.ratio()
        solved = _forward(case, loads, ratio, L, EI, kappa, fit)
    n = len(loads.Fy)
    wanted = {r.quantity for r in requests}
    if wanted & REACTIONS:
        for r in requests:
            if r.quantity in REACTIONS and r.point != "root":
                raise NotApplicable(f"'{r.quantity}' is a support load: ask for it at 'root' (got '{r.point}')")
    if loads.has_moment:  # the inflection check below reads the forces the tip receives
        wanted |= {"force_x", "force_y"}
    out = _segment_outputs(case, loads, solved, n, wanted)
    res = solved.res
    info = MethodRun(values={}, converged=bool(res.converged), message=solved.message or res.message)
    lc = res.level_converged
    if lc is not None and np.size(lc) in (1, n):
        info.level_converged = dict(enumerate(levels(lc, n)))
    info.extras = {"model": res.model, "constants": plain(res.constants)}
    if loads.has_moment:  # no end moment: the bending moment cannot change sign (eq 12)
        _warn_inflection(info, loads.M, out["force_x"], out["force_y"], out["x"], out["y"], solved.a0, solved.b0)
    _flag_fit_range(info, loads, ratio, res, fit, n)
    flag_levels(
        info,
        seg.boundary,
        kappa * L,
        fit.family,
        loads.Fx,
        loads.Fy,
        loads.M,
        loads.follower,
        L,
        EI,
        prescribed=motion is not None,
    )
    info.extras["shapes"] = DeferredList(lambda: _segment_shapes(seg, res, n, kappa) or [])  # the report reads it
    return pick(out, requests, "segment"), info


def _forward(
    case, loads: TipLoads, ratio: list[float], L: float, EI: float, kappa: float, fit: FitOptions
) -> SegmentSolve:
    """The segment model that fits the boundary and the end loads (module docstring), solved."""
    boundary = case.segment.boundary
    if boundary in ("fixed-free", "fixed-pinned") and kappa == 0.0:
        return _free_straight(loads, ratio, L, EI, fit)
    if boundary in ("fixed-free", "fixed-pinned"):
        return _free_curved(loads, ratio, L, EI, kappa, fit)
    if boundary in ("fixed-guided", "fixed-fixed"):
        return _guided(case, loads, ratio, L, EI, kappa, fit)
    raise NotApplicable(
        f"boundary '{boundary}' as a single segment case: the seeds' curved "
        "pinned-pinned PRBM (prbm.curved_pinned_pinned) takes a chord force only"
    )


@dataclass(frozen=True)
class PrescribedMotion:
    """The one prescribed tip motion of a segment case: ``kind`` 'displacement' (``values`` along the unit
    ``direction``, length units) or 'rotation' (``values`` in degrees, CCW)."""

    kind: str
    direction: tuple[float, float]
    values: list[float]


def prescribed_motion(case) -> PrescribedMotion | None:
    """The case's prescribed tip motion, or None when every load is a force or a moment.  One prescribed
    displacement or rotation at the tip and no other load is the problem solved here; anything else
    (two prescribed components, a prescribed motion beside applied loads) is refused."""
    motions = [ld for ld in case.loads if ld.kind in ("displacement", "rotation")]
    if not motions:
        return None
    if len(case.loads) > 1:
        raise NotApplicable(
            "a prescribed tip motion together with other loads or motions: the segment PRBM "
            "solves one prescribed displacement or rotation alone (for the two-condition "
            "problem give the PRBM inverse inputs in [methods.prbm] options)"
        )
    load = motions[0]
    if load.point != "tip":
        raise NotApplicable(f"a prescribed {load.kind} at '{load.point}': the segment PRBMs take end loads only")
    direction = (float(load.direction[0]), float(load.direction[1])) if load.kind == "displacement" else (0.0, 0.0)
    return PrescribedMotion(load.kind, direction, [float(v) for v in load.levels()])


def _solve_prescribed(
    case, motion: PrescribedMotion, L: float, EI: float, kappa: float, fit: FitOptions
) -> tuple[TipLoads, SegmentSolve]:
    """The tip load that reaches the prescribed motion, and the model solved under it.

    A displacement s along the unit d is reached by a force F d (the tip is free across d, so the load
    holding it acts along d): F solves (u(F d)) . d = s, u the tip's displacement from the unloaded tip.
    A rotation phi is reached by a moment M: theta0(M) - theta0(0) = phi.  The straight fixed-guided
    segment moved across its axis has the closed form ``prbm.fixed_guided_displaced_tip``
    [bapat2015, eq 63]; every other case is the forward model of ``_forward`` and a bracketed root on the
    load magnitude (``prbm.load_for_motion``), started from the small-deflection stiffness."""
    seg = case.segment
    n = len(motion.values)
    dx, dy = motion.direction
    guided = seg.boundary in ("fixed-guided", "fixed-fixed")
    if motion.kind == "displacement" and guided and kappa == 0.0 and dx == 0.0:
        if boundary_held_tip(case) != ["rz"]:
            raise NotApplicable(
                "fixed-fixed tip with its x held: the seeds' fixed-guided PRBMs leave the tip free to translate"
            )
        res = prbm.fixed_guided_displaced_tip([v * dy for v in motion.values], length=L, EI=EI, family=fit.family)
        res.constants["k"] = 2.0 * np.asarray(res.constants["k_each"])  # U = 2 (k_each Theta^2/2)
        Fy = levels(res.outputs["P"], n)
        return (
            _motion_loads(motion, [f * dy for f in Fy]),  # along (0, dy), |dy| = 1
            SegmentSolve(res, L, 0.0, "prescribed transverse tip displacement: closed form (eq 63)"),
        )

    unloaded = unloaded_tip_angle(L, kappa)
    a0 = b0 = None

    def response(s: float) -> float:
        nonlocal a0, b0
        loads = _motion_loads(motion, [s])
        solved = _forward(case, loads, loads.ratio(), L, EI, kappa, fit)
        if not solved.res.converged:
            return math.nan
        o = solved.res.outputs
        if motion.kind == "rotation":
            return float(np.ravel(o["theta0"])[0]) - unloaded
        a0, b0 = solved.a0, solved.b0
        return (float(np.ravel(o["a"])[0]) - a0) * dx + (float(np.ravel(o["b"])[0]) - b0) * dy

    stiffness = EI / L if motion.kind == "rotation" else (12.0 if guided else 3.0) * EI / L**3
    targets = [math.radians(v) if motion.kind == "rotation" else v for v in motion.values]
    magnitudes = []
    for level, target in enumerate(targets):
        found = prbm.load_for_motion(response, target, guess=abs(target) * stiffness)
        if not found.converged:
            raise NotApplicable(f"prescribed {motion.kind} at level {level}: {found.message}")
        magnitudes.append(found.x)
    loads = _motion_loads(motion, magnitudes)
    solved = _forward(case, loads, loads.ratio(), L, EI, kappa, fit)
    solved.message = "; ".join(
        m for m in (solved.message, f"prescribed {motion.kind}: load found by a bracketed root on its magnitude") if m
    )
    return loads, solved


def _motion_loads(motion: PrescribedMotion, magnitudes: list[float]) -> TipLoads:
    """The tip loads of magnitudes s (one per level) that hold the motion: a moment s for a rotation,
    a force s d along the displacement's unit direction d."""
    zeros = [0.0] * len(magnitudes)
    if motion.kind == "rotation":
        return TipLoads(zeros, zeros, list(magnitudes), False, False, any(m != 0.0 for m in magnitudes))
    dx, dy = motion.direction
    Fy = [s * dy for s in magnitudes]
    return TipLoads([s * dx for s in magnitudes], Fy, zeros, False, any(f != 0.0 for f in Fy), False)


def _free_straight(loads: TipLoads, ratio: list[float], L: float, EI: float, fit: FitOptions) -> SegmentSolve:
    """A straight fixed-free (fixed-pinned) segment: the model that fits its load (module docstring)."""
    kw = _tip_keywords(L, EI, fit)
    has_F, has_M = loads.has_force, loads.has_moment
    if loads.follower:
        if has_M:
            raise NotApplicable("follower force with an end moment: no PRBM in the seeds")
        loaded = [r for r, fy in zip(ratio, loads.Fy) if fy != 0.0]  # an unloaded level has no ratio
        if loaded and not all(abs(r - loaded[0]) <= 1e-8 + 1e-5 * abs(loaded[0]) for r in loaded):  # np.allclose
            raise NotApplicable("follower force with a varying load ratio")
        return SegmentSolve(
            prbm.composite_beam_tip(loads.Fy, loaded[0] if loaded else 0.0, follower=True, **kw), L, 0.0
        )
    if has_F and has_M:
        return SegmentSolve(
            prbm.fixed_guided_monotonic_tip(loads.Fy, ratio, loads.M, **kw),
            L,
            0.0,
            "force and moment: equivalent initial curvature kappa0 = M l/EI (eq 62), no inflection",
        )
    if has_M:
        return SegmentSolve(prbm.pure_moment_tip(loads.M, length=L, EI=EI), L, 0.0)
    return SegmentSolve(prbm.fixed_pinned_tip(loads.Fy, ratio, **kw), L, 0.0)


def _free_curved(
    loads: TipLoads, ratio: list[float], L: float, EI: float, kappa: float, fit: FitOptions
) -> SegmentSolve:
    """An initially curved fixed-free segment (eqs 53-61); an end moment adds to the curvature (eq 62)."""
    if loads.follower:
        raise NotApplicable("a follower force on an initially curved segment: no PRBM in the seeds")
    kw = _tip_keywords(L, EI, fit)
    if loads.has_moment:
        res = _stack(
            [
                prbm.curved_fixed_pinned_tip(fy, r, curvature=m / EI + kappa, **kw)
                for fy, r, m in zip(loads.Fy, ratio, loads.M)
            ]
        )
    else:
        res = prbm.curved_fixed_pinned_tip(loads.Fy, ratio, curvature=kappa, **kw)
    return SegmentSolve(res, math.sin(kappa * L) / kappa, (1 - math.cos(kappa * L)) / kappa)


def _guided(
    case, loads: TipLoads, ratio: list[float], L: float, EI: float, kappa: float, fit: FitOptions
) -> SegmentSolve:
    """A straight fixed-guided segment: two springs (eq 63), or monotonic with an end moment (eq 62)."""
    translations = [dof for dof in boundary_held_tip(case) if dof != "rz"]
    if translations:
        raise NotApplicable(
            f"fixed-fixed tip with {', '.join(translations)} held: the seeds' "
            "fixed-guided PRBMs leave the tip free to translate"
        )
    if kappa != 0.0:
        raise NotApplicable("initially curved fixed-guided segment without model = 'inflection'")
    if loads.follower:
        raise NotApplicable("a follower force on a fixed-guided segment: no PRBM in the seeds")
    kw = _tip_keywords(L, EI, fit)
    if loads.has_moment:
        return SegmentSolve(prbm.fixed_guided_monotonic_tip(loads.Fy, ratio, loads.M, **kw), L, 0.0)
    res = prbm.fixed_guided_tip(loads.Fy, ratio, **kw)
    res.constants["k"] = 2.0 * np.asarray(res.constants["k_each"])  # U = 2 (k_each Theta^2/2)
    return SegmentSolve(res, L, 0.0)


def _segment_outputs(case, loads: TipLoads, solved: SegmentSolve, n: int, wanted: set[str]) -> dict:
    """The ``wanted`` outputs of a segment over the levels (always x, y), as lists of floats, under the
    quantity contract (validation/case/quantities.py): rotation from the unloaded tangent angle, a held
    tip freedom reports the load that holds it."""
    seg = case.segment
    res = solved.res
    o = res.outputs
    a, b = levels(o["a"], n), levels(o["b"], n)
    out = {"x": a, "y": b, "moment": loads.M}
    if "dx" in wanted:
        out["dx"] = [v - solved.a0 for v in a]
    if "dy" in wanted:
        out["dy"] = [v - solved.b0 for v in b]
    if wanted & _FROM_ROTATION:
        unloaded = unloaded_tip_angle(seg.length, seg.initial_curvature())
        rotation = [t - unloaded for t in levels(o["theta0"], n)]
        Fx, Fy = loads.Fx, loads.Fy
        if loads.follower:  # the force the tip receives has turned with it
            r, fx, fy = np.array(rotation), np.array(Fx), np.array(Fy)
            Fx, Fy = (fx * np.cos(r) - fy * np.sin(r)).tolist(), (fx * np.sin(r) + fy * np.cos(r)).tolist()
        out.update({"force_x": Fx, "force_y": Fy, "rotation": [math.degrees(t) for t in rotation]})
    if "rz" in boundary_held_tip(case):
        if "M" not in o:
            raise NotApplicable(f"the PRBM ({res.model}) gives no moment holding the {seg.boundary} tip")
        out["moment"] = levels(o["M"], n)
    if wanted & REACTIONS:  # the clamp balances the tip's total load: R = -F, M_R = -(M + a F_y - b F_x)
        Fx, Fy, Mt = out["force_x"], out["force_y"], out["moment"]
        out["reaction_x"] = [-f for f in Fx]
        out["reaction_y"] = [-f for f in Fy]
        out["reaction_moment"] = [-(m + x * fy - y * fx) for m, x, y, fx, fy in zip(Mt, a, b, Fx, Fy)]
    if "Theta" in o and wanted & _FROM_PRB_ANGLE:
        Theta = levels(o["Theta"], n)
        if "prb_angle" in wanted:
            out["prb_angle"] = [math.degrees(t) for t in Theta]
        k = res.constants.get("k")
        if k is not None and "strain_energy" in wanted:
            Ti = levels(res.constants.get("Theta_i", 0.0), n)
            out["strain_energy"] = [0.5 * kk * ((t - ti) * (t - ti)) for kk, t, ti in zip(levels(k, n), Theta, Ti)]
    return out


def _flag_fit_range(
    info: MethodRun, loads: TipLoads, ratio: list[float], res: PRBMResult, fit: FitOptions, n: int
) -> None:
    """Flag the levels a model with the n-fits ([bapat2015, eqs 41-43], [ananthasuresh_l18, 05:41]) solved
    outside the fits' ranges: the load ratio n outside the family's published range (reached only with
    ``extrapolate`` 'warn' or 'allow'; 'raise' refuses the case), or the PRB angle |Theta - Theta_i| past the printed
    Theta range of the fits (``prbm.fits.THETA_RANGE``, 65 deg)."""
    if "K_theta" not in res.constants or "family" not in res.constants or not loads.has_force:
        return  # not a model of the n-fits (pure moment: its own constants)
    if fit.extrapolate != "raise":  # with 'raise' a ratio outside the fits has refused the case already
        family = fit_family(res.constants["family"])
        lower, upper = family.lower, family.upper
        for level, (r, fy) in enumerate(zip(ratio, loads.Fy)):
            effective = -r if fy < 0 else r  # the fits are evaluated at the mirrored ratio for P < 0
            if fy != 0 and not (lower < effective <= upper):
                info.flag(level, Applicability.LOAD_RATIO)
    if "Theta" in res.outputs:
        Ti = levels(res.constants.get("Theta_i", 0.0), n)
        for level, (t, ti) in enumerate(zip(levels(res.outputs["Theta"], n), Ti)):
            if abs(t - ti) > THETA_RANGE:
                info.flag(level, Applicability.DEFLECTION)


def _warn_inflection(info: MethodRun, M, Fx, Fy, a, b, a0: float, b0: float) -> None:
    """Mark the levels whose end force and moment give an inflection point: the moment at the tip (M) and
    at the root (M + F_y a - F_x b) of opposite signs (Table 2.1's opposite senses, and the sufficient
    condition (12)), on the PRBM's own deformed state or on the unloaded one (a0, b0): the monotonic
    model's state can land on the branch without the inflection that the beam has."""
    inflected = [
        level
        for level, (m, fx, fy, x, y) in enumerate(zip(M, Fx, Fy, a, b))
        if m * (m + fy * x - fx * y) < 0 or m * (m + fy * a0 - fx * b0) < 0
    ]
    for level in inflected:
        info.level_messages[level] = INFLECTION_WARNING
        info.flag(level, Applicability.INFLECTION)
    if inflected:
        info.extras["inflection_levels"] = inflected


def _stack(results: list[PRBMResult]) -> PRBMResult:
    """One result over the levels from one result per level."""
    keys = results[0].outputs.keys()
    out: dict[str, NDArray[np.float64] | float] = {k: np.array([float(r.outputs[k]) for r in results]) for k in keys}
    return PRBMResult(
        all(r.converged for r in results),
        results[0].message,
        out,
        results[0].constants,
        results[0].model,
        level_converged=np.array([r.converged for r in results]),
    )


def _segment_shapes(seg, res: PRBMResult, n: int, kappa: float) -> list | None:
    """Per level, the PRB links of a single-segment case in the case frame (fixed end at the origin).

    Fixed-free / fixed-pinned (straight): root -> characteristic pivot (1 - gamma) l -> tip.
    Fixed-guided, two springs (eq 63): root -> pivot (1 - gamma) l/2 -> + gamma l e^{i Theta} -> tip.
    Other models (curved, monotonic fixed-guided, composite, pure moment) give no chain here."""
    o, c = res.outputs, res.constants
    if kappa != 0.0 or "Theta" not in o or "gamma" not in c:
        return None
    guided = seg.boundary in ("fixed-guided", "fixed-fixed")
    if guided and any(t != 0.0 for t in levels(o.get("theta0", 0.0), n)):
        return None
    L = seg.length
    gamma, Theta, a, b = (per_level(np.asarray(v, float).ravel(), n) for v in (c["gamma"], o["Theta"], o["a"], o["b"]))
    # (level, point, x/y): one array for all the levels, each level's polyline a view; the arithmetic is
    # elementwise (+, -, *, /: the same bits as in plain floats)
    chains = np.zeros((n, 4 if guided else 3, 2))
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
    return [[chains[i]] if ok else [] for i, ok in enumerate(finite)]
