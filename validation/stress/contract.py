"""Generated segment configurations held to the quantity contract (``validation/case/quantities.py``).

A ``Configuration`` is one segment a user could write (boundary, straight or curved, unit system,
size, one kind of tip load); ``build_case`` turns it into a validated ``Case``. Two checks hold
each method to the contract on it:

* ``linear_limit_check``: at a small load (dimensionless size eps), every quantity a method claims
  against linear beam theory (``validation.stress.linear_beam``, Castigliano from the textbook): the FEM
  within 3x its own error estimate plus O(eps); the elastica and the BCM within O(eps) plus the
  axial stretch |N| L/EA the inextensible models leave out; the PRBM within its own known
  linear-limit error ``PRBM_LINEAR_ERROR`` of its load's compliance scale (``compliance_scale``:
  sigma_1 |f|, the largest motion a load of that size produces), with the sign of linear theory on
  every component that is not small, and no offset (zero motion at zero load).
* ``large_deflection_check``: at a large load, the FEM against the elastica within 3x the FEM's
  error estimate plus the axial stretch (a value whose estimate the FEM marks unreliable is not
  judged: there is no bound to hold it to); the PRBM against the elastica recorded (its error is the
  finding) but never a convention error: same sign of every clear component and an error below
  ``CONVENTION_LIMIT`` of the motion scale, the larger of the elastica's motion and the load's
  compliance scale capped at L (a reversed sign or an absolute-instead-of-relative angle is 100 % or
  more of it).

Both are used by ``tests/validation/test_quantity_contract.py`` (hypothesis) and ``prbm-validate stress --long``.
A method that raises NotApplicable is only accepted where ``applicable`` says it may.
"""

from __future__ import annotations

import importlib.util
import math
import random

import numpy as np
from dataclasses import asdict, dataclass, replace

from validation.case.capabilities import method_quantities
from validation.stress.linear_beam import FREEDOMS, LinearTip, flexibility, solve_tip
from validation.methods.base import MethodRun, RunStatus
from validation.case.quantities import boundary_held_tip
from validation.run.runner import requests_for, run_method
from validation.case.schema import Case

BOUNDARIES = ("fixed-free", "fixed-pinned", "fixed-guided", "fixed-fixed", "pinned-pinned")
LOADS = (
    "transverse",
    "oblique",
    "tension",
    "compression",
    "moment",
    "force_moment",
    "follower",
    "displacement_x",
    "displacement_y",
    "rotation",
)
# a pinned root with a tip free to move across the chord is a mechanism: these loads keep it a structure
PINNED_PINNED_LOADS = ("tension", "compression", "moment", "rotation", "displacement_x")
UNIT_RANGES = {  # (length range, modulus range) of plausible segments in each unit system
    "SI": ((0.02, 2.0), (1e9, 2.1e11)),
    "mm-N": ((10.0, 500.0), (1e3, 2.1e5)),
    "in-lb": ((0.5, 40.0), (1.5e5, 3e7)),
    "dimensionless": ((1.0, 1.0), (1.0, 1.0)),
}
# the OpenSees peer (the 'peer' extra) is held to the contract where it is installed
METHODS = ("fem", "elastica", "prbm", "bcm") + (("opensees",) if importlib.util.find_spec("openseespy") else ())
TIP = ("x", "y", "dx", "dy", "rotation", "force_x", "force_y", "moment")
ROOT = ("reaction_x", "reaction_y", "reaction_moment")
# The PRBM is judged against the compliance scale of its load, not the motion of that one load
# (``compliance_scale``): a one-DOF PRBM is a rank-one stand-in for the segment's 3x3 tip compliance,
# so along the segment's stiff direction (a force near the chord of a curved segment) the true motion
# is small and the PRBM's error, though small against what a load of that size does elsewhere, is
# several times that motion (kappa L = 1.6, a force at 60 deg: 5x; found by this contract). Against
# sigma_1 |f| (the largest motion a load of that magnitude produces) the linear-limit error of the
# straight fixed-pinned fit is 2 % of position and 6 % of rotation (gamma = 0.85, c_theta/K_Theta =
# 0.468 against 1/2; [bapat2015, eqs 41-49]); the initially curved model (eqs (53)-(61) with its
# assumed theta0 map) reaches 6 % of position and 15 % of rotation at kappa L = 1.6 (measured over
# every force direction inside the n-fits). 20 % bounds every model tried.
PRBM_LINEAR_ERROR = 0.20
CONVENTION_LIMIT = 0.60


@dataclass(frozen=True)
class Configuration:
    """One generated segment: geometry, unit system, one kind of tip load of dimensionless size
    ``magnitude`` (F L^2/EI, M L/EI, delta/L or a rotation in rad), at ``angle_deg`` for a force."""

    boundary: str
    units: str
    length: float
    E: float
    slenderness: float
    kappa_L: float
    load: str
    magnitude: float
    angle_deg: float = 90.0
    moment_ratio: float = 0.5

    def label(self) -> str:
        return ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in asdict(self).items())

    @property
    def thickness(self) -> float:
        return self.length / self.slenderness

    def stiffness(self) -> tuple[float, float]:
        """(EI, EA) of the segment's section."""
        if self.units == "dimensionless":
            return 1.0, 12.0 * self.slenderness**2
        h = self.thickness
        return self.E * h**4 / 12.0, self.E * h * h


AXIAL_HELD_LOADS = ("transverse", "moment", "rotation", "displacement_y")


def membrane_factor(boundary: str, load: str, slenderness: float, kappa_L: float = 0.0) -> float:
    """How much faster than the load the nonlinearity grows when the tip's axial motion is held: the
    shortening of a bent beam, ~eps^2 L, stretches it by a force ~EA eps^2 = 12 (L/h)^2 eps^2 EI/L^2,
    against a load eps EI/L^2; 1 when the tip may move axially."""
    held = boundary in ("fixed-fixed", "pinned-pinned") and load in AXIAL_HELD_LOADS and kappa_L == 0.0
    return 12.0 * slenderness**2 if held else 1.0


def random_configuration(
    rng: random.Random, *, small: bool, boundaries=BOUNDARIES, loads=LOADS, curved: bool | None = None
) -> Configuration:
    """A configuration drawn from ``rng``; ``small``: magnitude 1e-6..1e-5, else a large deflection."""
    boundary = rng.choice(boundaries)
    allowed = [ld for ld in loads if boundary != "pinned-pinned" or ld in PINNED_PINNED_LOADS]
    load = rng.choice(allowed)
    units = rng.choice(list(UNIT_RANGES))
    (l0, l1), (e0, e1) = UNIT_RANGES[units]
    is_curved = rng.random() < 0.4 if curved is None else curved
    kappa_L = rng.choice((-1, 1)) * rng.uniform(0.3, 1.6) if is_curved else 0.0
    slenderness = 10 ** rng.uniform(1.7, 2.7)
    if small:
        magnitude = 10 ** rng.uniform(-6, -5) / membrane_factor(boundary, load, slenderness, kappa_L)
    else:
        magnitude = {
            "moment": rng.uniform(0.3, 3.0),
            "rotation": rng.uniform(0.2, 1.4),
            "displacement_y": rng.uniform(0.05, 0.4),
            "displacement_x": rng.uniform(-0.2, -0.02),
        }.get(load, rng.uniform(0.3, 6.0))
    angle = {
        "transverse": rng.choice((90.0, -90.0)),
        "tension": 0.0,
        "compression": 180.0,
        "displacement_x": 0.0,
        "displacement_y": 90.0,
    }.get(load, rng.uniform(20.0, 160.0) * rng.choice((1, -1)))
    return Configuration(
        boundary=boundary,
        units=units,
        length=math.exp(rng.uniform(math.log(l0), math.log(l1))),
        E=math.exp(rng.uniform(math.log(e0), math.log(e1))),
        slenderness=slenderness,
        kappa_L=kappa_L,
        load=load,
        magnitude=magnitude,
        angle_deg=angle,
        moment_ratio=rng.uniform(0.2, 1.0) * rng.choice((1, -1)),
    )


def _load_entries(c: Configuration, levels: int) -> list[dict]:
    EI, _ = c.stiffness()
    L = c.length
    ramp = [(k + 1) / levels for k in range(levels)]
    a = math.radians(c.angle_deg)
    force = [0.0 if abs(v) < 1e-12 else v for v in (math.cos(a), math.sin(a))]  # [-1, 0], not [-1, 1e-16]
    F, M = c.magnitude * EI / L**2, c.magnitude * EI / L
    if c.load in ("transverse", "oblique", "tension", "compression", "follower"):
        return [dict(kind="force", direction=force, values=[F * r for r in ramp], follower=c.load == "follower")]
    if c.load == "moment":
        return [dict(kind="moment", values=[M * r for r in ramp])]
    if c.load == "force_moment":
        return [
            dict(kind="force", direction=force, values=[F * r for r in ramp]),
            dict(kind="moment", values=[c.moment_ratio * M * r for r in ramp]),
        ]
    if c.load == "rotation":
        return [dict(kind="rotation", values=[math.degrees(c.magnitude) * r for r in ramp])]
    direction = [1.0, 0.0] if c.load == "displacement_x" else [0.0, 1.0]
    return [dict(kind="displacement", direction=direction, values=[c.magnitude * L * r for r in ramp])]


def build_case(c: Configuration, methods=METHODS, *, levels: int = 1, fem_elements: int = 8) -> Case:
    """The configuration as a validated case asking every method for every quantity it claims."""
    if c.units == "dimensionless":
        section = dict(kind="inertia", I=1.0, A=12.0 * c.slenderness**2)
        E, L = 1.0, 1.0
    else:
        section = dict(kind="rectangle", width=c.thickness, thickness=c.thickness)
        E, L = c.E, c.length
    segment = dict(boundary=c.boundary, length=L, E=E, section=section)
    if c.kappa_L:
        segment["curvature"] = c.kappa_L / L
    options = {"fem": {"elements": fem_elements, "error_estimate": True, "levels": 2}}
    outputs = [dict(quantity=q, point="tip", methods=[m for m in methods if q in method_quantities(m)]) for q in TIP]
    outputs += [dict(quantity=q, point="root", methods=[m for m in methods if q in method_quantities(m)]) for q in ROOT]
    # the PRBM's strain energy is its springs' (only the single- and two-spring models have one)
    outputs.append(
        dict(
            quantity="strain_energy",
            methods=[m for m in methods if "strain_energy" in method_quantities(m) and m != "prbm"],
        )
    )
    outputs = [o for o in outputs if o["methods"]]
    data = dict(
        case=dict(
            id="contract",
            title="generated contract configuration",
            group="contract",
            units=c.units,
            description=c.label(),
        ),
        segment=segment,
        loads=[dict(ld, point="tip") for ld in _load_entries(c, levels)],
        outputs=outputs,
        methods={m: options.get(m, {}) for m in methods},
    )
    return Case.model_validate(data)


def linear_reference(c: Configuration, case: Case, *, inextensible: bool = False) -> LinearTip:
    """Linear theory of the configuration's (last-level) loads with the contract's boundary rule;
    ``inextensible``: EA infinite (the elastica's model)."""
    EI, EA = c.stiffness()
    EA = 1e12 * EI / c.length**2 if inextensible else EA  # (inf would leave a held axial force undetermined)
    seg = case.require_segment()
    L = seg.length
    held = set(boundary_held_tip(case))
    motion = {dof: 0.0 for dof in held}
    load = {"ux": 0.0, "uy": 0.0, "rz": 0.0}
    for ld in case.loads:
        v = ld.levels()[-1]
        if ld.kind == "force":
            load["ux"] += v * ld.require_direction()[0]
            load["uy"] += v * ld.require_direction()[1]
        elif ld.kind == "moment":
            load["rz"] += v
        elif ld.kind == "rotation":
            motion["rz"] = math.radians(v)
        else:
            motion["ux" if ld.require_direction()[0] else "uy"] = v
    return solve_tip(
        L,
        seg.initial_curvature(),
        EI,
        EA,
        root_pinned=seg.boundary == "pinned-pinned",
        given_load=load,
        given_motion=motion,
    )


def expected(tip: LinearTip) -> dict[tuple[str, str], float]:
    (ux, uy, th), (fx, fy, m) = tip.motion, tip.load
    xt, yt = tip.tip
    return {
        ("x", "tip"): xt + ux,
        ("y", "tip"): yt + uy,
        ("dx", "tip"): ux,
        ("dy", "tip"): uy,
        ("rotation", "tip"): math.degrees(th),
        ("force_x", "tip"): fx,
        ("force_y", "tip"): fy,
        ("moment", "tip"): m,
        ("reaction_x", "root"): tip.reaction[0],
        ("reaction_y", "root"): tip.reaction[1],
        ("reaction_moment", "root"): tip.reaction[2],
        ("strain_energy", ""): tip.strain_energy,
    }


@dataclass(frozen=True)
class Scales:
    """What 'small' means for each quantity of one configuration: the motion scale (length), the load
    scale (force), the length L, and the stretch |N| L/EA the inextensible models leave out."""

    motion: float
    load: float
    length: float
    stretch: float
    energy: float

    def of(self, quantity: str) -> float:
        if quantity in ("x", "y", "dx", "dy"):
            return self.motion
        if quantity == "rotation":
            return math.degrees(self.motion / self.length)
        if quantity in ("force_x", "force_y", "reaction_x", "reaction_y"):
            return self.load
        if quantity in ("moment", "reaction_moment"):
            return self.load * self.length
        return self.energy

    def rounding_of(self, quantity: str, axial_stiffness: float) -> float:
        """What double-precision rounding leaves in a converged solve: 100 eps of the length, and of the
        axial stiffness EA for loads (a Newton residual cannot be resolved below ~eps EA)."""
        eps = 100 * np.finfo(float).eps
        if quantity in ("x", "y", "dx", "dy"):
            return eps * self.length
        if quantity == "rotation":
            return math.degrees(eps)
        if quantity in ("force_x", "force_y", "reaction_x", "reaction_y"):
            return eps * axial_stiffness
        if quantity in ("moment", "reaction_moment"):
            return eps * axial_stiffness * self.length
        return eps * (axial_stiffness * self.motion + self.load * self.length)

    def stretch_of(self, quantity: str) -> float:
        """Share of the difference the axial stretch may explain (inextensible models)."""
        if quantity in ("x", "y", "dx", "dy"):
            return self.stretch
        if quantity == "rotation":
            return math.degrees(self.stretch / self.length)
        if quantity in ("force_x", "force_y", "reaction_x", "reaction_y"):
            return self.load * self.stretch / max(self.motion, 1e-300)
        if quantity in ("moment", "reaction_moment"):
            return self.load * self.length * self.stretch / max(self.motion, 1e-300)
        return self.load * self.stretch


def scales(c: Configuration, tip: LinearTip) -> Scales:
    EI, EA = c.stiffness()
    L = c.length if c.units != "dimensionless" else 1.0
    (ux, uy, th), (fx, fy, m) = tip.motion, tip.load
    motion = max(abs(ux), abs(uy), abs(th) * L)
    load = max(abs(fx), abs(fy), abs(m) / L, abs(tip.reaction[2]) / L)
    return Scales(motion=motion, load=load, length=L, stretch=load * L / EA, energy=max(abs(tip.strain_energy), 1e-300))


def compliance_scale(c: Configuration, case: Case, tip: LinearTip) -> float:
    """sigma_1 |f|: the largest tip motion (u_x, u_y, theta L) that a tip load of this one's size
    (F_x, F_y, M/L) produces in the linear limit, the boundary's held tip freedoms condensed out of the
    compliance (the PRBM's error scale, see ``PRBM_LINEAR_ERROR``)."""
    EI, EA = c.stiffness()
    L = case.require_segment().length
    D = np.diag([1.0, 1.0, L])
    C = D @ flexibility(L, case.require_segment().initial_curvature(), EI, EA) @ D
    held = [i for i, name in enumerate(FREEDOMS) if name in boundary_held_tip(case)]
    free = [i for i in range(3) if i not in held]
    Cf = C[np.ix_(free, free)]
    if held:
        Cf = Cf - C[np.ix_(free, held)] @ np.linalg.solve(C[np.ix_(held, held)], C[np.ix_(held, free)])
    f = (np.asarray(tip.load) / np.array([1.0, 1.0, L]))[free]
    return float(np.linalg.norm(Cf, 2) * np.linalg.norm(f))


@dataclass
class ContractResult:
    """One method on one configuration: compared quantities, the failures (empty = conforms)."""

    method: str
    applicable: bool
    compared: int
    failures: list[str]
    detail: str = ""

    @property
    def passed(self) -> bool:
        return not self.failures


def applicable(method: str, c: Configuration) -> bool:
    """Where a method is expected to model a configuration (elsewhere NotApplicable is the answer)."""
    straight = c.kappa_L == 0.0
    if method == "fem":
        return True
    if method == "elastica":  # pinned-pinned and fixed-fixed segments through the (extensible) mechanism
        # solver; elsewhere the inextensible segment solver, which cannot stretch a straight segment axially
        return c.boundary in ("pinned-pinned", "fixed-fixed") or not (straight and c.load == "displacement_x")
    if method == "bcm":
        return straight and c.boundary != "pinned-pinned" and c.load != "follower"
    if method == "prbm":
        return _prbm_applicable(c)
    if method == "opensees":  # straight, clamped root, free tip, proportional dead forces and moments
        return (
            straight
            and c.load in ("transverse", "oblique", "tension", "compression", "moment", "force_moment")
            and not boundary_held_tip(build_case(c, ("fem",)))
            and c.boundary != "pinned-pinned"
        )
    return False


def elastica_extensible(c: Configuration) -> bool:
    """Where the elastica adapter solves the segment with the mechanism solver, whose beams stretch (EA):
    a pinned-pinned segment, and a straight fixed-fixed one whose tip's x is held or prescribed; there the
    reference is the extensible one, as the FEM's (validation/methods/elastica.py)."""
    held_x = c.load in AXIAL_HELD_LOADS or c.load == "displacement_x"
    return c.boundary == "pinned-pinned" or (c.boundary == "fixed-fixed" and c.kappa_L == 0.0 and held_x)


def _prbm_applicable(c: Configuration) -> bool:
    """The segment PRBMs of the sources that the adapter maps (load ratio n inside the fits' range); a
    prescribed transverse displacement or rotation is reached by the load along it (``prbm_segment``'s
    prescribed motion; an axial one would need a purely axial force, outside every n-fit)."""
    if (
        c.load not in ("transverse", "oblique", "moment", "force_moment", "follower", "displacement_y", "rotation")
        or c.boundary == "pinned-pinned"
    ):
        return False
    if c.load not in ("moment", "rotation"):
        n = -math.cos(math.radians(c.angle_deg)) / math.sin(math.radians(c.angle_deg))
        if not -3.5 <= n <= 9.5:  # Pauly-Midha fits: -4 <= n <= 10 [bapat2015, eqs 45-49]
            return False
    if c.boundary == "fixed-fixed" and c.load not in ("oblique", "force_moment"):
        return False  # a tip translation held: the guided PRBMs let the tip translate
    guided = c.boundary in ("fixed-guided", "fixed-fixed")
    if c.load == "follower" and (guided or c.kappa_L != 0.0):
        return False
    if guided and c.kappa_L != 0.0:
        return False
    return c.load != "force_moment" or not _inflection_expected(c)


def _inflection_expected(c: Configuration) -> bool:
    """A segment whose bending moment changes sign between tip (M) and root (M + F_y x_t - F_x y_t):
    [bapat2015, Table 2.1] (possible only for P and M of opposite sense); in the small-load limit."""
    a = math.radians(c.angle_deg)
    k = c.kappa_L
    xt, yt = (math.sin(k) / k, (1 - math.cos(k)) / k) if k else (1.0, 0.0)
    return c.moment_ratio * (c.moment_ratio + math.sin(a) * xt - math.cos(a) * yt) < 0


def _compare(
    method: str,
    run: MethodRun,
    reference: dict,
    sc: Scales,
    *,
    eps: float,
    estimate_factor: float,
    include_stretch: bool,
    relative: float | None = None,
    rotation_relative: float | None = None,
    axial_stiffness: float = 0.0,
    against: str = "linear theory",
) -> tuple[int, list[str]]:
    failures, compared = [], 0
    for req, value in run.values.items():
        key = (req.quantity, req.point)
        if key not in reference:
            continue
        if estimate_factor and _estimate_unreliable(run, req):
            continue  # no bound to hold the value to: the run says its estimate is unreliable
        want = reference[key]
        scale = sc.of(req.quantity)
        if relative is not None:
            if req.quantity == "strain_energy":
                continue
            share = rotation_relative if req.quantity == "rotation" and rotation_relative else relative
            tol = share * scale + 1e-9 * scale
        else:
            turn = (
                run.error_estimate.get(req._replace(quantity="rotation", point="tip"), 0.0)
                if req.quantity in ("force_x", "force_y")
                else 0.0
            )  # a follower force turns with the tip
            tol = (
                estimate_factor * (run.error_estimate.get(req, 0.0) + sc.load * math.radians(turn))
                + (20 * eps + 1e-7) * scale
                + sc.rounding_of(req.quantity, axial_stiffness)
            )
            if include_stretch:
                tol += 2.0 * sc.stretch_of(req.quantity)
        compared += 1
        if not math.isfinite(value) or abs(value - want) > tol:
            failures.append(
                f"{method} {req.quantity}@{req.point or '-'} = {value:.6g}, {against} {want:.6g} (allowed {tol:.3g})"
            )
        elif relative is not None and abs(want) > 0.3 * scale and value * want < 0:
            failures.append(f"{method} {req.quantity}@{req.point} = {value:.6g}: sign opposite to {against} {want:.6g}")
    return compared, failures


def _estimate_unreliable(run: MethodRun, req) -> bool:
    """The value's error estimate is marked unreliable (or, for a follower force, the tip rotation's,
    which its tolerance uses)."""
    turn = req._replace(quantity="rotation", point="tip")
    return req in run.unreliable_estimate or (
        req.quantity in ("force_x", "force_y") and turn in run.unreliable_estimate
    )


def _not_judged(run: MethodRun, reference: dict) -> str:
    """The detail of a run whose values `_compare` left unjudged for an unreliable estimate (else '')."""
    skipped = [r for r in run.values if (r.quantity, r.point) in reference and _estimate_unreliable(run, r)]
    return f"{len(skipped)} value(s) not judged: the FEM marks their error estimate unreliable" if skipped else ""


def _nonlinearity(c: Configuration, sc: Scales) -> float:
    """Size of the terms linear theory leaves out, relative to its answer: the motion's own size (eps, or
    its membrane growth when the tip cannot move axially) or the load parameter |f| L^2/EI (the
    geometric stiffness of an axial force, large for a prescribed motion along a stiff direction)."""
    EI, _ = c.stiffness()
    return max(c.magnitude * membrane_factor(c.boundary, c.load, c.slenderness, c.kappa_L), sc.load * sc.length**2 / EI)


def run_contract_method(case: Case, method: str) -> MethodRun:
    """The method's run on the case, or an empty run if the case asks it for nothing."""
    return run_method(case, method) if requests_for(case, method) else MethodRun(values={})


def linear_limit_check(c: Configuration, methods=METHODS) -> list[ContractResult]:
    """Every method against linear beam theory at the configuration's (small) load."""
    case = build_case(c, methods)
    tip = linear_reference(c, case)
    ref = expected(tip)
    inextensible = expected(linear_reference(c, case, inextensible=True))
    sc = scales(c, tip)
    results = []
    for method in methods:
        run = run_contract_method(case, method)
        na = run.status is RunStatus.NOT_APPLICABLE
        expect = applicable(method, c)
        if na or not run.values:
            ok = na and not expect
            results.append(
                ContractResult(
                    method,
                    False,
                    0,
                    [] if ok else [f"{method}: {'expected to apply' if expect else 'no NotApplicable'}: {run.message}"],
                )
            )
            continue
        if not expect and method == "prbm" and _inflection_expected(c) and run.extras.get("inflection_levels"):
            results.append(ContractResult(method, True, 0, [], "warned: inflection point expected"))
            continue
        if not expect:
            results.append(
                ContractResult(
                    method, True, 0, [f"{method} gave values where it has no model (expected NotApplicable)"]
                )
            )
            continue
        if not run.converged:
            results.append(ContractResult(method, True, 0, [f"{method} did not converge: {run.message}"]))
            continue
        if method == "prbm":
            prbm_scale = replace(sc, motion=max(sc.motion, compliance_scale(c, case, tip)))
            n, failures = _compare(
                method,
                run,
                ref,
                prbm_scale,
                eps=c.magnitude,
                estimate_factor=0.0,
                include_stretch=False,
                relative=PRBM_LINEAR_ERROR,
            )
            failures += _prbm_offset(c, methods)
        else:
            n, failures = _compare(
                method,
                run,
                inextensible if method == "elastica" and not elastica_extensible(c) else ref,
                sc,
                eps=_nonlinearity(c, sc),
                estimate_factor=3.0,
                include_stretch=False,
                axial_stiffness=c.stiffness()[1],
            )
        results.append(ContractResult(method, True, n, failures, _not_judged(run, ref)))
    return results


def _prbm_offset(c: Configuration, methods) -> list[str]:
    """The PRBM at zero load: every motion zero (no offset from the unloaded shape)."""
    zero = build_case(Configuration(**(asdict(c) | {"magnitude": 0.0})), ("prbm",))
    run = run_contract_method(zero, "prbm")
    out = []
    for req, value in run.values.items():
        if req.quantity in ("dx", "dy", "rotation") and abs(value) > 1e-12 * (
            1 if req.quantity == "rotation" else zero.require_segment().length
        ):
            out.append(f"prbm {req.quantity} = {value:.6g} at zero load (offset)")
    return out


def large_deflection_check(c: Configuration, methods=("fem", "elastica", "prbm")) -> list[ContractResult]:
    """FEM against the exact elastica (3x the FEM's estimate plus the stretch); the PRBM recorded, with
    no convention error."""
    case = build_case(c, methods, levels=4, fem_elements=8)
    runs = {m: run_contract_method(case, m) for m in methods}
    exact = runs.get("elastica")
    if exact is None or not exact.converged:  # the reference says it did not converge: nothing to judge
        return [ContractResult("elastica", False, 0, [], f"elastica gave no reference: {exact and exact.message}")]
    last = case.n_levels() - 1
    ref = {(r.quantity, r.point): v for r, v in exact.values.items() if r.level == last}
    EI, EA = c.stiffness()
    L = case.require_segment().length
    motion = max(abs(ref[("dx", "tip")]), abs(ref[("dy", "tip")]), abs(math.radians(ref[("rotation", "tip")])) * L)
    load = max(abs(ref[("force_x", "tip")]), abs(ref[("force_y", "tip")]), abs(ref[("moment", "tip")]) / L)
    sc = Scales(
        motion=motion,
        load=load,
        length=L,
        stretch=load * L / EA,
        energy=max(abs(ref.get(("strain_energy", ""), 0.0)), 1e-300),
    )
    results = []
    for method in methods:
        if method == "elastica":
            continue
        run = runs[method]
        refused = run.status is RunStatus.NOT_APPLICABLE
        if refused or not run.values:
            ok = not applicable(method, c) and refused
            results.append(ContractResult(method, False, 0, [] if ok else [f"{method}: {run.message}"]))
            continue
        if not run.converged:
            results.append(ContractResult(method, True, 0, [f"{method} did not converge: {run.message}"]))
            continue
        at_last = MethodRun(
            values={r: v for r, v in run.values.items() if r.level == last},
            error_estimate={r: v for r, v in run.error_estimate.items() if r.level == last},
            unreliable_estimate={r: v for r, v in run.unreliable_estimate.items() if r.level == last},
        )
        if method == "prbm":
            results.append(_prbm_large(c, case, run, at_last, ref, sc, last))
        else:
            n, failures = _compare(
                method, at_last, ref, sc, eps=0.0, estimate_factor=3.0, include_stretch=True, against="elastica"
            )
            results.append(ContractResult(method, True, n, failures, _not_judged(at_last, ref)))
    return results


def _prbm_large(
    c: Configuration, case: Case, run: MethodRun, at_last: MethodRun, ref: dict, sc: Scales, last: int
) -> ContractResult:
    """The PRBM at a large load: its error against the elastica recorded; judged for conventions only
    (``CONVENTION_LIMIT`` of the larger of the elastica's motion and the load's compliance scale, at
    most L). Where the PRBM itself warns that its deformed state has an inflection point (the
    monotonic force-and-moment model, eq (62), does not fit: [bapat2015, Table 2.1, eq 12]), the
    error is recorded and not judged, as in the linear limit."""
    L = case.require_segment().length
    reach = min(compliance_scale(c, case, linear_reference(c, case)), L)
    prbm_scale = replace(sc, motion=max(sc.motion, reach))
    worst = max(
        (
            abs(v - ref[(r.quantity, r.point)]) / prbm_scale.of(r.quantity)
            for r, v in at_last.values.items()
            if (r.quantity, r.point) in ref and r.quantity in ("x", "y", "rotation")
        ),
        default=math.nan,
    )
    if last in run.extras.get("inflection_levels", ()):
        return ContractResult(
            "prbm",
            True,
            0,
            [],
            f"warned: inflection point expected (PRBM error {worst:.3g} of the motion scale, recorded, not judged)",
        )
    if not applicable("prbm", c):
        return ContractResult(
            "prbm",
            True,
            0,
            [
                "prbm gave values where it has no model (expected NotApplicable "
                f"or an inflection warning); PRBM error {worst:.3g}"
            ],
        )
    n, failures = _compare(
        "prbm",
        at_last,
        ref,
        prbm_scale,
        eps=0.0,
        estimate_factor=0.0,
        include_stretch=False,
        relative=CONVENTION_LIMIT,
        against="elastica",
    )
    return ContractResult("prbm", True, n, failures, f"PRBM error {worst:.3g} of the motion scale")
