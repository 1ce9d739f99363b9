"""The PRBM adapter for loads that turn with the structure or act along the beam.

Frames as in ``validation/methods/prbm.py``: a segment's x runs along the undeformed segment from its
fixed end (the origin), forces are ``values x direction``, CCW moments; a four-bar's frame has O2, the
characteristic pivot, at ``[methods.prbm] origin`` of the case frame.

* A straight fixed-free / fixed-pinned segment with an end force ``toward = [x, y]`` (a rope to a fixed
  point, turned by ``angle``): the fixed-pinned PRBM [bapat2015, eqs 41-49] of the dead force that acts at
  equilibrium, whose tip gives back that force's direction by the load law
  (``prbm.turning_loads.fixed_pinned_turning_tip``): the fits at the equilibrium load ratio n,
  gamma K_Theta (EI/l) Theta = gamma l (F_y cos Theta - F_x sin Theta).  The capstan options ``friction_mu``,
  ``contact_angle_deg`` scale the magnitude (eq 211).  Other end loads beside it are refused.
* A straight cantilevered segment with distributed or self-weight loads, ``model = 'chain'``: the Chain
  Algorithm [bapat2015, §2.2, eqs 26-40], the one segment model of the sources that takes loads
  along the segment (at its nodes): each element's q L_i lumped half to each of its end nodes
  (``prbm.chain.lumped_uniform_load``; self-weight q = section weight per length x gravity direction),
  dead end forces and moments at the last node.  No source gives a one-spring PRBM for a load along the
  segment, so without a ``model`` option the adapter chooses the chain and its number of elements
  (``chain_count``): it doubles the elements from ``CHAIN_FIRST`` until two successive chains put every
  requested level's tip within ``chain_tol`` x L of each other (at most ``CHAIN_MOST`` elements) and reports
  the finer one.  The chain of n elements converges as O(1/n^2) (the lumping is the trapezoid rule, each
  element a cubic: the tip moves by a factor 4 less at each doubling, measured 3.9-4.0 from q L^3/EI =
  0.01 to 30), so the finer chain's error is about a third of the last difference, below chain_tol x L / 3.
  ``chain_elements`` fixes the count instead; ``model = 'chain'`` keeps its fixed count (default 40).  An
  explicit other model (one-spring or mechanism) is refused with the reason.  Follower (pressure) loads
  are refused: the chain's nodal loads are dead loads in the global frame.
* The input segment of a PRB four-bar (``[methods.prbm] links``) with a follower force (``body`` = the
  segment) or a force ``toward`` a point at A, the end of PRB link 2 (``link2_turning_forces``, used by
  ``prbm_fourbar.fourbar_drive``): equilibrium (**) of ``prbm.turning_loads``, the moment about O2 of
  the force at A = O2 + R2 e^{i theta2}; the segment end turns by c_theta (theta2 - theta20), c_theta
  of the fit family at n = 0 (the ratio whose gamma and K_Theta set the printed k1).

Option ``zero_level``: positions measured from that level's state (x = X0 + x(level) - x(zero_level)),
as the FEM's option of the same name (an experiment zeroed under a load present throughout).
Outputs: x, y, dx, dy, rotation (deg), force_x, force_y (the end force acting at equilibrium), moment
(the end moment); with a force toward a point also prb_angle (deg) and strain_energy (the PRBM spring).
"""

from __future__ import annotations

import cmath
import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

import prbm
from prbm.fits import THETA_RANGE, FitRangeError, fit_family
from prbm.lazy import LazyModule
from prbm.result import PRBMResult
from validation.case.method_options import PrbmOptions
from validation.methods.base import Applicability, MethodRun, NotApplicable, Request
from validation.methods.prbm_atlas import chain_levels, flag_atlas_levels
from validation.methods.prbm_common import pick

if TYPE_CHECKING:  # loaded at first use (below); named here for the static import walks (run-cache hash)
    from prbm import chain as chain_model
    from prbm import turning_loads
else:  # both import scipy.optimize: only a case that asks for them pays for it (handles() runs on every case)
    chain_model = LazyModule("prbm.chain")
    turning_loads = LazyModule("prbm.turning_loads")

ALONG_BEAM = ("distributed", "self_weight")


def handles(case, options: PrbmOptions) -> bool:
    """A segment case with a load along the segment or a force toward a fixed point (this module runs it)."""
    return case.segment is not None and any(ld.kind in ALONG_BEAM or ld.toward is not None for ld in case.loads)


def turning_fourbar(case, options: PrbmOptions) -> bool:
    """A hand-given PRB four-bar with a follower force or a force toward a point (``link2_turning_forces``)."""
    return (
        case.mechanism is not None
        and bool(options.links)
        and any(ld.kind == "force" and (ld.follower or ld.toward is not None) for ld in case.loads)
    )


def run(case, requests: list[Request], options: PrbmOptions) -> MethodRun:
    t0 = time.perf_counter()
    seg = case.segment
    if seg.initial_curvature() != 0.0:
        raise NotApplicable("a load along the segment or toward a point on an initially curved segment: no seed PRBM")
    try:
        if any(ld.kind in ALONG_BEAM for ld in case.loads):
            info = _chain(case, _with_zero_level(requests, options), options)
        else:
            info = _turning_segment(case, _with_zero_level(requests, options), options)
    except FitRangeError as exc:
        raise NotApplicable(f"PRBM fit range: {exc}") from None
    _apply_zero_level(info, requests, options, case)
    info.wall_time = time.perf_counter() - t0
    return info


# --- a force toward a fixed point on a fixed-pinned segment ----------------------------------------
def _turning_segment(case, requests, options) -> MethodRun:
    seg = case.segment
    if seg.boundary not in ("fixed-free", "fixed-pinned"):
        raise NotApplicable(
            f"a force toward a fixed point on a {seg.boundary} segment: the seeds' turning-load "
            "PRBM here is the fixed-pinned one (eqs 41-49)"
        )
    loads = [ld for ld in case.loads if ld.kind != "force" or ld.toward is None]
    turning = [ld for ld in case.loads if ld.kind == "force" and ld.toward is not None]
    if loads or len(turning) != 1:
        raise NotApplicable(
            "a force toward a fixed point together with other end loads: the PRBM here takes that one force alone"
        )
    load = turning[0]
    if load.point != "tip":
        raise NotApplicable(f"a force toward a fixed point at '{load.point}': the segment PRBM takes end loads only")
    law = turning_loads.TowardPoint(complex(*load.toward), math.radians(load.angle))
    F = np.asarray(load.levels(), float) * prbm.capstan_factor(
        options.friction_mu, math.radians(options.contact_angle_deg)
    )
    L, EI = seg.length, seg.bending_stiffness()
    res = turning_loads.fixed_pinned_turning_tip(
        F, law, length=L, EI=EI, family=options.family, extrapolate=options.extrapolate
    )
    o, c = res.outputs, res.constants
    out = {
        "x": o["a"],
        "y": o["b"],
        "dx": o["a"] - L,
        "dy": o["b"],
        "rotation": np.degrees(o["theta0"]),
        "force_x": o["Fx"],
        "force_y": o["Fy"],
        "moment": np.zeros(len(F)),
        "prb_angle": np.degrees(o["Theta"]),
        "strain_energy": 0.5 * c["k"] * o["Theta"] ** 2,
    }
    out["strain_energy"] = np.where(F == 0.0, 0.0, out["strain_energy"])
    info = MethodRun(values=pick(out, requests, "segment"), converged=bool(res.converged), message=res.message)
    converged = res.level_converged if res.level_converged is not None else np.full(len(F), res.converged)
    info.level_converged = {lv: bool(ok) for lv, ok in enumerate(converged.tolist())}
    info.extras = {
        "model": res.model,
        "constants": {k: np.asarray(v).tolist() if k != "family" else v for k, v in c.items()},
        "shapes": [
            [np.array([[0.0, 0.0], [(1 - g) * L, 0.0], [a, b]])] if np.isfinite(g) else []
            for g, a, b in zip(c["gamma"].tolist(), np.asarray(o["a"]).tolist(), np.asarray(o["b"]).tolist())
        ],
    }
    for lv, angle in enumerate(np.abs(o["Theta"]).tolist()):
        if angle > THETA_RANGE:
            info.flag(lv, Applicability.DEFLECTION)
    info.message = f"{res.model}: {res.message}"
    return info


# --- loads along the segment: the Chain Algorithm with lumped loads ----------------------------------
@dataclass
class ChainLevel:
    """One level's chain solve and the nodal loads it carried."""

    res: PRBMResult
    loads: chain_model.NodalLoads


def _chain_loads(case, beam: chain_model.ChainBeam, level: int) -> chain_model.NodalLoads:
    """The nodal loads of one level: distributed and self-weight loads lumped, end loads at the tip."""
    seg = case.segment
    total = chain_model.NodalLoads.at_tip(beam)
    for i, load in enumerate(case.loads):
        v = float(load.levels()[level])
        if load.kind in ALONG_BEAM:
            if load.follower:
                raise NotApplicable(
                    f"loads.{i}: a follower distributed load (pressure): the Chain Algorithm's "
                    "nodal loads are dead loads (seed 000 eqs 26-28)"
                )
            d = np.asarray(load.direction, float)
            if load.kind == "self_weight":
                weight = seg.section.weight_per_length()
                if weight is None:
                    raise NotApplicable(f"loads.{i}: self-weight without the section's weight density")
                d = d / math.hypot(*d) * weight
            total = total.plus(chain_model.lumped_uniform_load(beam, v * d[0], v * d[1]))
        elif load.point != "tip":
            raise NotApplicable(
                f"loads.{i} acts on '{load.point}'; the chain takes end loads and loads along the segment"
            )
        elif load.kind == "force" and (load.follower or load.toward is not None or load.body is not None):
            raise NotApplicable(
                f"loads.{i}: a turning end force with a load along the segment: not modelled "
                "(the chain's nodal loads are dead loads)"
            )
        elif load.kind == "force":
            total = total.plus(chain_model.NodalLoads.at_tip(beam, v * load.direction[0], v * load.direction[1]))
        elif load.kind == "moment":
            total = total.plus(chain_model.NodalLoads.at_tip(beam, m=v))
        else:
            raise NotApplicable(f"loads.{i}: a prescribed {load.kind}; the chain takes forces and moments here")
    return total


CHAIN_FIRST = 10
"""Elements of the first chain of the automatic choice (its tip is within 3 % of L of the limit even at
q L^3/EI = 30, the largest shipped load, so the doubling starts in the O(1/n^2) range)."""
CHAIN_MOST = 320
"""Most elements the automatic choice tries: 1e-5 L at q L^3/EI = 30 (a few seconds per level beyond)."""


@dataclass
class ChainChoice:
    """The chain a case's load along the segment is solved with, and why that count."""

    beam: chain_model.ChainBeam
    levels: dict[int, ChainLevel]
    reason: str
    met: bool = True
    """False when the automatic choice reached ``CHAIN_MOST`` elements without meeting its target."""


GUIDED_HELD = ("rz",)
"""The tip freedoms a fixed-guided segment's chain holds (its tip keeps its angle, moves freely)."""


def _solve_chain(case, beam: chain_model.ChainBeam, levels: list[int], steps: int) -> dict[int, ChainLevel]:
    """Each level's chain: a free tip (``chain_tip``), or a fixed-guided segment's tip held in rotation
    (``chain_held_path``, its tip moment an unknown), each from the unloaded chain in ``steps`` steps."""
    out = {}
    guided = case.segment.boundary == "fixed-guided"
    for lv in levels:
        loads = _chain_loads(case, beam, lv)
        res = (
            chain_model.chain_held_path(beam, loads, GUIDED_HELD, [1.0], max_step=1.0 / steps)[0]
            if guided
            else chain_model.chain_tip(beam, loads, steps=steps)
        )
        out[lv] = ChainLevel(res, loads)
    return out


def _tip(level: ChainLevel) -> complex:
    return complex(float(level.res.outputs["a"]), float(level.res.outputs["b"]))


def _held_moment(level: ChainLevel) -> float:
    """The end moment a held tip needs (0 for a free tip)."""
    return float(np.asarray(level.res.outputs.get("M", 0.0)))


def _change(solved: dict[int, ChainLevel], refined: dict[int, ChainLevel], levels: list[int], L: float) -> float:
    """How far a doubling moved the chain: the largest tip move over L, or (a held tip) the largest change of
    its end moment over the largest end moment of the levels."""
    change = max(abs(_tip(refined[lv]) - _tip(solved[lv])) for lv in levels) / L
    scale = max(abs(_held_moment(refined[lv])) for lv in levels)
    if scale > 0.0:
        change = max(change, max(abs(_held_moment(refined[lv]) - _held_moment(solved[lv])) for lv in levels) / scale)
    return change


def chain_count(case, levels: list[int], options: PrbmOptions) -> ChainChoice:
    """The chain for a load along the segment: the count the options fix (``model = 'chain'``: its
    ``chain_elements``, default 40; ``chain_elements`` alone), or else the automatic choice: n = CHAIN_FIRST,
    2n, 4n, ... until max over the levels of |tip_2n - tip_n| < chain_tol x L, and for a held (guided) tip
    also |M_2n - M_n| < chain_tol x max |M| (the finer chain kept)."""
    seg = case.segment
    steps = options.chain_steps
    EI = seg.bending_stiffness()
    if options.model == "chain" or "chain_elements" in options.model_fields_set:
        beam = chain_model.ChainBeam(seg.length, EI, options.chain_elements)
        given = "model = 'chain'" if options.model == "chain" else "chain_elements"
        return ChainChoice(beam, _solve_chain(case, beam, levels, steps), f"{beam.elements} elements ({given})")
    tol = options.chain_tol
    most = min(CHAIN_MOST, case.limits.elements)
    beam = chain_model.ChainBeam(seg.length, EI, min(CHAIN_FIRST, most))
    solved = _solve_chain(case, beam, levels, steps)
    change = math.inf
    while True:
        finer = chain_model.ChainBeam(seg.length, EI, 2 * beam.elements)
        if finer.elements > most:
            return ChainChoice(
                beam,
                solved,
                f"{beam.elements} elements, the most the automatic choice tries "
                f"(limits.elements or {CHAIN_MOST}): the tip (or a held end's moment) still moved "
                f"by {change:.2e} of its scale at the last doubling, over the target {tol:g} "
                "(chain_tol)",
                met=False,
            )
        refined = _solve_chain(case, finer, levels, steps)
        change = _change(solved, refined, levels, seg.length)
        beam, solved = finer, refined
        if change < tol:
            return ChainChoice(
                beam,
                solved,
                f"{beam.elements} elements, chosen for the load along the segment: the "
                f"tip (and a held end's moment) moved by {change:.2e} of its scale (L, the largest "
                f"moment) from {beam.elements // 2} elements, below the target {tol:g} (chain_tol; "
                f"O(1/n^2), so about {change / 3:.1e} from the limit)",
            )


def _chain(case, requests, options) -> MethodRun:
    seg = case.segment
    model = options.model
    if model not in (None, "chain"):
        i, load = next((i, ld) for i, ld in enumerate(case.loads) if ld.kind in ALONG_BEAM)
        raise NotApplicable(
            f"loads.{i}: a {load.kind.replace('_', '-')} load along the segment: model = '{model}' "
            "takes end loads only, as every one-spring PRBM of the seeds; the Chain Algorithm "
            "(seed 000 section 2.2) takes loads at its nodes: give model = 'chain', or no model "
            "to let the adapter choose it"
        )
    if seg.boundary not in ("fixed-free", "fixed-pinned", "fixed-guided"):
        raise NotApplicable(
            f"a load along a {seg.boundary} segment: the Chain Algorithm here models a "
            "cantilever (free end) or a guided end (tip angle held); its inextensible elements "
            "cannot bend with the tip's x held, and its root is clamped"
        )
    choice = chain_count(case, sorted({r.level for r in requests}), options)
    solved = choice.levels
    info = MethodRun(values={})
    for req in requests:
        table = (
            _chain_table(seg.length, solved[req.level])
            if req.point == "tip"
            else _chain_root(solved[req.level])
            if req.point == "root"
            else {}
        )
        if req.quantity not in table:
            raise NotApplicable(f"the Chain Algorithm gives no '{req.quantity}' at '{req.point}'")
        info.values[req] = table[req.quantity]
    info.level_converged = {lv: bool(s.res.converged) and choice.met for lv, s in solved.items()}
    info.level_messages = {lv: s.res.message for lv, s in solved.items()}
    info.converged = all(info.level_converged.values())
    info.message = (
        f"Chain Algorithm (seed 000 eqs 26-40), {choice.reason}; loads along the segment "
        "lumped half to each element end; " + "; ".join(f"level {lv}: {m}" for lv, m in info.level_messages.items())
    )
    info.extras = {
        "model": f"Chain Algorithm with lumped loads, seed 000 section 2.2, {choice.beam.elements} elements",
        "chain_elements": choice.beam.elements,
        "shapes": [
            [solved[lv].res.extras["nodes"]] if lv in solved and "nodes" in solved[lv].res.extras else []
            for lv in range(case.n_levels())
        ],
    }
    if seg.boundary != "fixed-guided":  # the atlas maps the chain with a free tip
        along, tip_loaded = _along_segment(case)
        flag_atlas_levels(
            info, chain_levels(choice.beam.elements, along, tip_loaded, seg.length, seg.bending_stiffness())
        )
    return info


def _along_segment(case) -> tuple[list[tuple[float, float]], bool]:
    """Per level, the uniform dead load (w_x, w_y) per length along the segment (distributed loads and
    self-weight summed), and whether an end load acts beside it."""
    seg = case.segment
    n = case.n_levels()
    wx, wy, tip = [0.0] * n, [0.0] * n, False
    for load in case.loads:
        values = [float(v) for v in load.levels()]
        if load.kind in ALONG_BEAM:
            d = np.asarray(load.direction, float)
            if load.kind == "self_weight":
                d = d / math.hypot(*d) * (seg.section.weight_per_length() or math.nan)
            wx = [w + v * d[0] for w, v in zip(wx, values)]
            wy = [w + v * d[1] for w, v in zip(wy, values)]
        else:
            tip = tip or any(v != 0.0 for v in values)
    return list(zip(wx, wy)), tip


def _chain_table(L: float, level: ChainLevel) -> dict[str, float]:
    """x, y, dx, dy, rotation at the tip and the tip's end loads (applied, plus what a held freedom needs)."""
    o, f = level.res.outputs, level.loads
    a, b = float(o["a"]), float(o["b"])
    held = [float(np.asarray(o[k])) if k in o else 0.0 for k in ("Fx", "Fy", "M")]
    return {
        "x": a,
        "y": b,
        "dx": a - L,
        "dy": b,
        "rotation": math.degrees(float(o["theta0"])),
        "force_x": float(f.fx[-1]) + held[0],
        "force_y": float(f.fy[-1]) + held[1],
        "moment": float(f.m[-1]) + held[2],
    }


def _chain_root(level: ChainLevel) -> dict[str, float]:
    """The root's position (the clamp) and the support's loads on the chain: minus every load it carries
    (the nodal loads, the clamp's node's share included, and a held tip's loads), the moment about the root
    taken on the deformed nodes."""
    o, f = level.res.outputs, level.loads
    nodes = level.res.extras.get("nodes")
    if nodes is None:
        return {"x": 0.0, "y": 0.0, "dx": 0.0, "dy": 0.0, "rotation": 0.0}
    fx, fy, m = f.fx.copy(), f.fy.copy(), f.m.copy()
    for name, column in (("Fx", fx), ("Fy", fy), ("M", m)):
        if name in o:
            column[-1] += float(np.asarray(o[name]))
    moment = float(np.sum(nodes[:, 0] * fy - nodes[:, 1] * fx) + np.sum(m))
    return {
        "x": 0.0,
        "y": 0.0,
        "dx": 0.0,
        "dy": 0.0,
        "rotation": 0.0,
        "reaction_x": -float(np.sum(fx)),
        "reaction_y": -float(np.sum(fy)),
        "reaction_moment": -moment,
    }


# --- zero_level --------------------------------------------------------------------------------------
ZEROED = ("x", "y", "dx", "dy")


def _with_zero_level(requests, options) -> list[Request]:
    zero = options.zero_level
    if zero is None:
        return list(requests)
    extra = [Request(r.quantity, r.point, int(zero)) for r in requests if r.quantity in ZEROED]
    return list(dict.fromkeys(list(requests) + extra))


def _apply_zero_level(info: MethodRun, requests, options, case) -> None:
    """Positions from the zero level's state: v(level) - (v(zero) - v(unloaded)), as the FEM option."""
    zero = options.zero_level
    if zero is None:
        return
    if not 0 <= int(zero) < case.n_levels():
        raise NotApplicable(f"zero_level = {zero}: the case has {case.n_levels()} load levels")
    unloaded = {"x": case.segment.length, "y": 0.0, "dx": 0.0, "dy": 0.0}
    shifted = {}
    for req in requests:
        value = info.values[req]
        if req.quantity in ZEROED:
            value -= info.values[Request(req.quantity, req.point, int(zero))] - unloaded[req.quantity]
        shifted[req] = value
    info.values = shifted


# --- the input segment of a PRB four-bar ----------------------------------------------------------------
@dataclass(frozen=True)
class LinkForce:
    """A force at the end A of PRB link 2: its magnitudes per level and its law (four-bar frame)."""

    values: np.ndarray
    law: turning_loads.LoadLaw


def link2_turning_forces(case, R2: float, theta20: float, options: PrbmOptions) -> list[LinkForce] | None:
    """The forces at A = O2 + R2 e^{i theta20} as laws in the four-bar frame (O2 at the origin), or None
    when none of them turns (dead forces keep their own path in ``prbm_fourbar``)."""
    forces = [ld for ld in case.loads if ld.kind == "force"]
    if not any(ld.follower or ld.toward is not None for ld in forces):
        return None
    origin = complex(*options.origin)
    nodes = {nd.name: complex(nd.x, nd.y) for nd in case.mechanism.nodes}
    beams = {b.name for b in case.mechanism.beams}
    A = origin + R2 * cmath.exp(1j * theta20)
    out = []
    for i, load in enumerate(forces):
        law: turning_loads.LoadLaw
        if abs(nodes.get(load.point, complex(math.inf)) - A) > 1e-3 * R2:
            raise NotApplicable(
                f"a force at '{load.point}': the PRB four-bar takes forces at the end of PRB link 2 "
                "only (the tip of its fixed-pinned input segment)"
            )
        if load.toward is not None:
            law = turning_loads.TowardPoint(complex(*load.toward) - origin, math.radians(load.angle))
        elif load.follower:
            if load.body is not None and load.body not in beams:
                raise NotApplicable(
                    f"a follower force turning with '{load.body}': the PRB four-bar maps only the "
                    "input segment's end rotation, c_theta (theta2 - theta20)"
                )
            law = turning_loads.FollowerDirection(complex(*load.direction))
        else:
            law = turning_loads.DeadDirection(complex(*load.direction))
        scale = math.hypot(*load.direction) if load.direction is not None else 1.0
        out.append(LinkForce(np.asarray(load.levels(), float) * scale, law))
    return out


def theta2_under_turning_forces(
    fb, forces: list[LinkForce], torques: np.ndarray, theta20: float, options: PrbmOptions
) -> np.ndarray:
    """The input angle of every level under the forces at A and the couples (eq (**) of
    ``prbm.turning_loads``); c_theta of the fit family at n = 0."""
    c_theta = float(fit_family(options.family).parameters(0.0)[1])
    if not math.isfinite(c_theta):
        raise NotApplicable("a follower force on the four-bar's segment needs c_theta; the fit family gives none")
    theta2 = []
    for lv, torque in enumerate(np.asarray(torques, float).tolist()):
        active = [(float(f.values[lv]), f.law) for f in forces if f.values[lv] != 0.0]
        theta2.append(
            turning_loads.input_angle_under_turning_forces(fb, active, theta20=theta20, c_theta=c_theta, torque=torque)
        )
    return np.array(theta2)
