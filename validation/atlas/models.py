"""The PRBM segment models the atlas maps, each beside the exact elastica problem it approximates.

Every model is written for a unit segment (length L = 1, EI = 1), so its inputs are the dimensionless
groups an engineer would form: the force F L^2/EI, a moment M L/EI, a distributed load w L^3/EI, the
initial curvature kappa0 = L/R, angles in degrees.  A model's input space is a grid of *lines*: the
shape inputs (load angle, kappa0, moment ratio, ...) fixed along a line, the load magnitude growing
along it, so that the exact elastica follows each line by continuation from the unloaded beam (the
equilibrium a slowly loaded segment reaches), and the PRBM answers at the same loads.

For each model:

* ``shape_axes``: the inputs held along a line (grid values, full and coarse);
* ``load``: the magnitude axis (geometric spacing from the linear range to past where the model claims
  to hold);
* ``exact_problem(shape, load)``: the ``elastica.ElasticaProblem`` at one level (``None`` where the model
  needs its own exact solve, e.g. the SLFP's rigid arm);
* ``prbm(shape, loads)``: the PRBM's tip (x, y, theta) and PRB angle on an array of loads;
* ``coordinate``: the path coordinate (the tip angle for a free tip, b for a guided one, the chord for
  a pinned-pinned arc) at which the path error is taken.

References: [bapat2015] eqs 41-49 (fixed-pinned), 51-52 (Theta-dependent K_Theta), 53-61 (curved),
62 (monotonic fixed-guided / force plus moment), 63 (fixed-guided with inflection), 71-82 (SLFP),
26-40 (Chain Algorithm), section 2.3.5 (pinned-pinned), section 9.2 (follower force);
[ananthasuresh_l18] (Howell's fits, the constant gamma = 0.85, K_Theta = 2.65).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np

import prbm
from elastica.shooting import ElasticaProblem
from prbm import chain as chain_model
from prbm.fits import FitRangeError
from prbm.theta_dependent import theta_dependent_tip


@dataclass(frozen=True)
class Axis:
    """One input of a model: a column name, a label with its unit, and its grid (full and coarse)."""

    name: str
    label: str
    lo: float
    hi: float
    full: int
    coarse: int
    spacing: str = "linear"  # linear | geometric

    def values(self, coarse: bool) -> np.ndarray:
        count = self.coarse if coarse else self.full
        if count == 1:
            return np.array([self.lo])
        if self.spacing == "geometric":
            return np.geomspace(self.lo, self.hi, count)
        return np.linspace(self.lo, self.hi, count)


@dataclass
class PrbmLine:
    """The PRBM on an array of loads: tip x, y (of L), tip angle theta (rad), PRB angle (rad), whether
    each level solved and was inside the fits' printed load-ratio range."""

    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    prb_angle: np.ndarray
    ok: np.ndarray
    in_fit: np.ndarray


@dataclass(frozen=True)
class AtlasModel:
    """A PRBM model, its input grid and its exact counterpart (see the module docstring)."""

    name: str
    title: str
    source: str
    shape_axes: tuple[Axis, ...]
    load: Axis
    prbm: Callable[[dict, np.ndarray], PrbmLine]
    exact_problem: Callable[[dict, float], ElasticaProblem]
    coordinate: str = "tip angle"  # tip angle | b | chord
    reference_length: float = 1.0  # errors are in % of this length
    stop_rotation_deg: float = 170.0  # the exact line stops past this tip rotation
    dense: int = 4  # PRBM evaluations per level for the path/stiffness split
    notes: str = ""
    map_axes: tuple[str, str] = ("", "")  # the two inputs its region map is drawn over
    exact_solver: str = "shooting"  # shooting | slfp (the rigid-arm moment by a secant)

    def shapes(self, coarse: bool) -> list[dict]:
        """Every line's shape inputs: the Cartesian product of the shape axes."""
        grids = [axis.values(coarse) for axis in self.shape_axes]
        mesh = np.meshgrid(*grids, indexing="ij") if grids else []
        count = mesh[0].size if grids else 1
        return [{axis.name: float(m.ravel()[i]) for axis, m in zip(self.shape_axes, mesh)} for i in range(count)]

    def points(self, coarse: bool) -> int:
        lines = len(self.shapes(coarse))
        return lines * (self.load.coarse if coarse else self.load.full)

    @property
    def inputs(self) -> tuple[str, ...]:
        return tuple(a.name for a in self.shape_axes) + (self.load.name,)


def _angle_force(shape: dict, F: float) -> tuple[float, float]:
    phi = math.radians(shape["load_angle_deg"])
    return F * math.cos(phi), F * math.sin(phi)


def _ratio(shape: dict) -> float:
    """n of the force (-nP, P) at the load angle phi (P > 0): n = -cot phi."""
    phi = math.radians(shape["load_angle_deg"])
    n = -math.cos(phi) / math.sin(phi)
    return 0.0 if abs(n) < 1e-12 else n  # cos(90 deg) is 6e-17 in floating point: a transverse force has n = 0


def _nan_line(count: int) -> PrbmLine:
    nan = np.full(count, np.nan)
    return PrbmLine(nan, nan.copy(), nan.copy(), nan.copy(), np.zeros(count, bool), np.zeros(count, bool))


def _fit_range(n: float, family: str) -> bool:
    fam = prbm.fit_family(family)
    return bool(fam.lower < n <= fam.upper)


def _quiet(call):
    """Run a PRBM call with its range warnings silenced (the atlas records the range itself)."""
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return call()


def _from_result(res, loads: np.ndarray, in_fit: bool, theta_key: str = "theta0", prb: str = "Theta") -> PrbmLine:
    o = res.outputs
    ok = np.broadcast_to(np.asarray(res.level_converged, bool), loads.shape).copy()
    shape = loads.shape
    return PrbmLine(
        np.broadcast_to(np.asarray(o["a"], float), shape).copy(),
        np.broadcast_to(np.asarray(o["b"], float), shape).copy(),
        np.broadcast_to(np.asarray(o[theta_key], float), shape).copy(),
        np.broadcast_to(np.asarray(o[prb], float), shape).copy(),
        ok,
        np.full(shape, in_fit),
    )


def _fixed_pinned(family: str) -> Callable[[dict, np.ndarray], PrbmLine]:
    def run(shape: dict, loads: np.ndarray) -> PrbmLine:
        n = _ratio(shape)
        P = loads * math.sin(math.radians(shape["load_angle_deg"]))
        try:
            res = _quiet(lambda: prbm.fixed_pinned_tip(P, n, length=1.0, EI=1.0, family=family, extrapolate="allow"))
        except (FitRangeError, ValueError):
            return _nan_line(loads.size)
        return _from_result(res, loads, _fit_range(n, family))

    return run


def _theta_dependent(fit: str) -> Callable[[dict, np.ndarray], PrbmLine]:
    def run(shape: dict, loads: np.ndarray) -> PrbmLine:
        n = _ratio(shape)
        line = _nan_line(loads.size)
        line.in_fit[:] = True
        P = loads * math.sin(math.radians(shape["load_angle_deg"]))
        for i, p in enumerate(P):
            try:
                o = _quiet(lambda: theta_dependent_tip(float(p), n, length=1.0, EI=1.0, fit=fit)).outputs
            except (FitRangeError, ValueError):
                continue  # outside the fit's printed n or Theta range: the model gives no answer
            line.x[i], line.y[i], line.theta[i], line.prb_angle[i] = o["a"], o["b"], o["theta0"], o["Theta"]
            line.ok[i] = True
        return line

    return run


def _curved(shape: dict, loads: np.ndarray) -> PrbmLine:
    n = _ratio(shape)
    P = loads * math.sin(math.radians(shape["load_angle_deg"]))
    try:
        res = _quiet(
            lambda: prbm.curved_fixed_pinned_tip(
                P, n, length=1.0, EI=1.0, curvature=shape["kappa0"], extrapolate="allow"
            )
        )
    except (FitRangeError, ValueError):
        return _nan_line(loads.size)
    return _from_result(res, loads, _fit_range(n, "pauly-midha"))


def _pure_moment(shape: dict, loads: np.ndarray) -> PrbmLine:
    res = _quiet(lambda: prbm.pure_moment_tip(loads, length=1.0, EI=1.0))
    return _from_result(res, loads, True)


def _force_moment(shape: dict, loads: np.ndarray) -> PrbmLine:
    """Force F at the load angle and a tip moment M = mu F L of the same level (eq 62)."""
    n = _ratio(shape)
    P = loads * math.sin(math.radians(shape["load_angle_deg"]))
    M = shape["moment_ratio"] * loads
    try:
        res = _quiet(lambda: prbm.fixed_guided_monotonic_tip(P, n, M, length=1.0, EI=1.0, extrapolate="allow"))
    except (FitRangeError, ValueError):
        return _nan_line(loads.size)
    return _from_result(res, loads, _fit_range(n, "pauly-midha"))


def _follower(shape: dict, loads: np.ndarray) -> PrbmLine:
    """A follower force at ``follower_angle_deg`` from the deformed tip tangent (section 9.2)."""
    n = _ratio({"load_angle_deg": shape["follower_angle_deg"]})
    P = loads * math.sin(math.radians(shape["follower_angle_deg"]))
    try:
        res = _quiet(lambda: prbm.composite_beam_tip(P, n, length=1.0, EI=1.0, follower=True, extrapolate="allow"))
    except (FitRangeError, ValueError):
        return _nan_line(loads.size)
    return _from_result(res, loads, _fit_range(n, "pauly-midha"))


def _fixed_guided(shape: dict, loads: np.ndarray) -> PrbmLine:
    n = _ratio(shape)
    P = loads * math.sin(math.radians(shape["load_angle_deg"]))
    try:
        res = _quiet(lambda: prbm.fixed_guided_tip(P, n, length=1.0, EI=1.0, extrapolate="allow"))
    except (FitRangeError, ValueError):
        return _nan_line(loads.size)
    return _from_result(res, loads, _fit_range(n, "pauly-midha"))


def _pinned_pinned(shape: dict, loads: np.ndarray) -> PrbmLine:
    """The chord of a circular arc under a chord force (tension +1, compression -1 from ``sense``); the
    atlas's x is the chord, y and theta are those of the half-model's end (section 2.3.5)."""
    F = shape["sense"] * loads
    res = _quiet(lambda: prbm.curved_pinned_pinned(F, length=1.0, EI=1.0, curvature=shape["kappa0"]))
    o = res.outputs
    chord = np.asarray(o["chord"], float)
    line = PrbmLine(
        chord,
        np.zeros_like(chord),
        np.zeros_like(chord),
        np.asarray(o["Theta"], float),
        np.broadcast_to(np.asarray(res.level_converged, bool), loads.shape).copy(),
        np.ones(loads.shape, bool),
    )
    return line


def _slfp(shape: dict, loads: np.ndarray) -> PrbmLine:
    """Flexure of length lambda L and a rigid arm of (1 - lambda) L (total 1), force at the arm's end."""
    lam = shape["flexure_fraction"]
    n = _ratio(shape)
    P = loads * math.sin(math.radians(shape["load_angle_deg"]))
    res = _quiet(lambda: prbm.slfp_tip(P, n, flexure_length=lam, rigid_length=1.0 - lam, EI=1.0))
    return _from_result(res, loads, True)


def _chain(shape: dict, loads: np.ndarray) -> PrbmLine:
    """The Chain Algorithm (40 elements, the number [bapat2015] section 3.4 uses) under a uniform dead
    load w per unit length at the load angle, continued level to level (``prbm.chain.chain_path``)."""
    phi = math.radians(shape["load_angle_deg"])
    beam = chain_model.ChainBeam(1.0, 1.0, 40)
    unit = chain_model.lumped_uniform_load(beam, math.cos(phi), math.sin(phi))
    line = _nan_line(loads.size)
    line.in_fit[:] = True
    for i, res in enumerate(_quiet(lambda: chain_model.chain_path(beam, unit, loads))):
        if res.converged:
            o = res.outputs
            line.x[i], line.y[i], line.theta[i], line.prb_angle[i], line.ok[i] = (
                o["a"],
                o["b"],
                o["theta0"],
                o["theta0"],
                True,
            )
    return line


def _force_problem(shape: dict, F: float) -> ElasticaProblem:
    return ElasticaProblem(force=_angle_force(shape, F))


LOAD_ANGLE = Axis("load_angle_deg", "load angle phi (deg from the undeformed axis)", 5.0, 175.0, 35, 9)
FORCE = Axis("load", "force F L^2/EI", 0.05, 60.0, 300, 24, "geometric")


MODELS: dict[str, AtlasModel] = {
    m.name: m
    for m in (
        AtlasModel(
            "fixed_pinned_pauly_midha",
            "fixed-pinned, Pauly-Midha n-fits",
            "[bapat2015, eqs 41-49]",
            (LOAD_ANGLE,),
            FORCE,
            _fixed_pinned("pauly-midha"),
            _force_problem,
            map_axes=("load_angle_deg", "load"),
        ),
        AtlasModel(
            "fixed_pinned_howell",
            "fixed-pinned, Howell's n-fits",
            "[ananthasuresh_l18]",
            (LOAD_ANGLE,),
            FORCE,
            _fixed_pinned("howell"),
            _force_problem,
            coordinate="b",
            notes="Howell's fits publish no c_theta: no tip angle, the path is read at b",
            map_axes=("load_angle_deg", "load"),
        ),
        AtlasModel(
            "fixed_pinned_constant",
            "fixed-pinned, constant gamma = 0.85, K_Theta = 2.65",
            "[ananthasuresh_l18]; [bapat2015, eqs 44-49]",
            (LOAD_ANGLE,),
            FORCE,
            _fixed_pinned("constant"),
            _force_problem,
            map_axes=("load_angle_deg", "load"),
        ),
        AtlasModel(
            "theta_dependent_51",
            "fixed-pinned, Theta-dependent K_Theta (eq 51)",
            "[bapat2015, eqs 41, 42, 51]",
            (LOAD_ANGLE,),
            FORCE,
            _theta_dependent("51"),
            _force_problem,
            dense=2,
            map_axes=("load_angle_deg", "load"),
        ),
        AtlasModel(
            "theta_dependent_52",
            "fixed-pinned, Theta-dependent K_Theta (eq 52)",
            "[bapat2015, eqs 41, 42, 52]",
            (LOAD_ANGLE,),
            FORCE,
            _theta_dependent("52"),
            _force_problem,
            dense=2,
            map_axes=("load_angle_deg", "load"),
        ),
        AtlasModel(
            "curved_fixed_pinned",
            "initially curved fixed-pinned",
            "[bapat2015, eqs 53-61]",
            (
                Axis("kappa0", "initial curvature kappa0 = L/R", 0.0, 3.0, 16, 4),
                Axis("load_angle_deg", LOAD_ANGLE.label, 5.0, 175.0, 18, 5),
            ),
            Axis("load", FORCE.label, 0.05, 60.0, 40, 12, "geometric"),
            _curved,
            lambda s, F: ElasticaProblem(curvature=s["kappa0"], force=_angle_force(s, F)),
            map_axes=("kappa0", "load"),
        ),
        AtlasModel(
            "pure_moment",
            "end moment only (circular arc PRBM)",
            "[ananthasuresh_l18]; [bapat2015, eq 14]",
            (),
            Axis("load", "moment M L/EI", 0.01, 6.0, 10000, 200, "geometric"),
            _pure_moment,
            lambda s, M: ElasticaProblem(moment=M),
            dense=1,
            stop_rotation_deg=350.0,
            map_axes=("load", "load"),
        ),
        AtlasModel(
            "force_moment",
            "force plus end moment, monotonic curvature (fixed-guided without inflection)",
            "[bapat2015, eqs 62, 14, 17]",
            (
                Axis("moment_ratio", "moment ratio mu = M/(F L)", -1.0, 2.0, 16, 4),
                Axis("load_angle_deg", LOAD_ANGLE.label, 10.0, 170.0, 17, 5),
            ),
            Axis("load", FORCE.label, 0.05, 40.0, 40, 12, "geometric"),
            _force_moment,
            lambda s, F: ElasticaProblem(force=_angle_force(s, F), moment=s["moment_ratio"] * F),
            map_axes=("moment_ratio", "load"),
        ),
        AtlasModel(
            "follower",
            "fixed-pinned under a follower end force",
            "[bapat2015, section 9.2]",
            (Axis("follower_angle_deg", "follower angle (deg from the deformed tip tangent)", 30.0, 150.0, 25, 5),),
            Axis("load", FORCE.label, 0.05, 30.0, 400, 30, "geometric"),
            _follower,
            lambda s, F: ElasticaProblem(
                follower=(
                    F * math.cos(math.radians(s["follower_angle_deg"])),
                    F * math.sin(math.radians(s["follower_angle_deg"])),
                )
            ),
            dense=2,
            map_axes=("follower_angle_deg", "load"),
        ),
        AtlasModel(
            "fixed_guided",
            "fixed-guided with an inflection point (two springs)",
            "[bapat2015, eq 63]",
            (LOAD_ANGLE,),
            Axis("load", FORCE.label, 0.1, 150.0, 300, 24, "geometric"),
            _fixed_guided,
            lambda s, F: ElasticaProblem(force=_angle_force(s, F), tip_angle=0.0),
            coordinate="b",
            map_axes=("load_angle_deg", "load"),
        ),
        AtlasModel(
            "pinned_pinned",
            "initially curved pinned-pinned arc under a chord force",
            "[bapat2015, section 2.3.5]",
            (
                Axis("kappa0", "arc angle kappa0 = L/R", 0.2, 3.0, 50, 6),
                Axis("sense", "chord force (+1 tension, -1 compression)", -1.0, 1.0, 2, 2),
            ),
            Axis("load", "chord force F L^2/EI", 0.05, 60.0, 100, 16, "geometric"),
            _pinned_pinned,
            lambda s, F: ElasticaProblem(length=0.5, curvature=s["kappa0"], force=(s["sense"] * F, 0.0)),
            coordinate="chord",
            map_axes=("kappa0", "load"),
        ),
        AtlasModel(
            "slfp",
            "small-length flexural pivot with a rigid arm",
            "[bapat2015, eqs 71-82]",
            (
                Axis("flexure_fraction", "flexure length / total length", 0.02, 0.3, 8, 3),
                Axis("load_angle_deg", LOAD_ANGLE.label, 10.0, 170.0, 17, 5),
            ),
            Axis("load", "force F L^2/EI (L: total length)", 0.01, 20.0, 80, 12, "geometric"),
            _slfp,
            lambda s, F: ElasticaProblem(length=s["flexure_fraction"], force=_angle_force(s, F)),
            exact_solver="slfp",
            map_axes=("flexure_fraction", "load"),
        ),
        AtlasModel(
            "chain",
            "Chain Algorithm (40 links), uniform distributed load",
            "[bapat2015, eqs 26-40]",
            (Axis("load_angle_deg", "distributed-load angle (deg)", 10.0, 170.0, 33, 5),),
            Axis("load", "distributed load w L^3/EI", 0.1, 60.0, 310, 16, "geometric"),
            _chain,
            lambda s, w: ElasticaProblem(distributed=_angle_force(s, w)),
            dense=1,
            map_axes=("load_angle_deg", "load"),
        ),
    )
}


def model(name: str) -> AtlasModel:
    try:
        return MODELS[name]
    except KeyError:
        raise ValueError(f"unknown atlas model {name!r}; known: {', '.join(MODELS)}") from None
