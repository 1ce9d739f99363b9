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

Mechanisms with no hand-given ``links`` (and not the one-beam-with-body case below): the PRB model
is built from the geometry by the seeds' rules and solved as a general rigid-link network
(``validation/methods/prbm_network.py``, ``prbm.build``, ``prbm.solve``); ``model = 'network'``
does so even when links are given.

Mechanisms: a PRB four-bar from ``[methods.prbm]`` options in the case-file format of chapters 6, 7
and 9: ``links = {r1 = [x, y], ..., r5, r6}`` (position-1 vectors Z1..Z6), ``springs = {k1..k4}``,
``energy_free = {theta2, theta3, theta4}`` (deg), ``coupler_point`` (node name, default 'P').
Drive, per level: input torques (a 'moment' load at 'input' or on a body) -> equilibrium by minimum
total potential energy; or ``precision = {phi = [...]}`` (input rotations from position 1, deg) or
``{psi = [...]}`` (output rotations) -> the precision positions, ``free_levels`` = levels at the
unloaded pose (``drive = 'precision'`` forces this
when both are given).  Outputs: dx, dy of the coupler point from the unloaded pose, x, y (O2 at
``origin``, default [0, 0]), input_angle, input_torque (eq 182), strain_energy (eq 181),
mechanical_advantage (``ma = {F_i, d_i, d_o}``, eqs 190, 192), dof (eq 208 on the PRBM, see
``prbm.dof``).  The unloaded pose, when ``energy_free.theta3`` is given, is placed with the printed
energy-free angles by the dyad Z2 e^{i(theta20 - theta21)} + Z5 e^{i(theta30 - theta31)} (as the
seed does), not re-solved from the loop (the printed vectors close only to about 0.002 in).

One beam fixed at one end whose other end carries rigid links (chapter 5 Example 1), no ``links``
option: ``prbm.solve_segment_with_body`` (dead loads at body nodes moved to the beam end with the
current offset, M + r x F), see ``_segment_with_body``.

Shapes: ``extras['shapes']`` holds, per level, the PRB links as (n, 2) polylines in the case frame:
fixed-pinned segment root -> pivot -> tip; two-spring fixed-guided root -> pivot -> pivot -> tip;
inflection model root -> pivot 1 -> inflection point -> pivot 2 -> end; four-bar O2-A-B-O4 and the
coupler A-P-B; segment + body the segment chain then each body link through its nodes.
"""
from __future__ import annotations

import cmath
import math
import time

import numpy as np
from scipy.optimize import brentq

from validation.methods import prbm_ma, prbm_network
from validation.methods.base import MethodRun, NotApplicable, Request, reject_loads_along_beams
from validation.case.quantities import boundary_held_tip, unloaded_tip_angle

DEG = math.pi / 180.0


def run(case, requests: list[Request], options: dict) -> MethodRun:
    import prbm

    t0 = time.perf_counter()
    reject_loads_along_beams(case, "the PRBM")
    try:
        if prbm_ma.handles(case, options):                      # chapter 7 MA by prbm.compliance
            values, run_info = prbm_ma.run(case, requests, options)
        elif case.segment is not None:
            values, run_info = _segment(prbm, case, requests, options)
        else:
            values, run_info = _mechanism(prbm, case, requests, options)
    except prbm.FitRangeError as exc:
        raise NotApplicable(f"PRBM fit range: {exc}") from None
    run_info.wall_time = time.perf_counter() - t0
    run_info.values = values
    return run_info


# --- segments -------------------------------------------------------------------------------------
def _tip_loads(case, n: int):
    Fx, Fy, M = np.zeros(n), np.zeros(n), np.zeros(n)
    follower = False
    for i, load in enumerate(case.loads):
        if load.point != "tip":
            raise NotApplicable(f"loads.{i} acts on '{load.point}'; the segment PRBMs take end loads only")
        v = np.asarray(load.levels(), float)
        if load.kind == "force":
            d = np.asarray(load.direction, float)
            Fx += v * d[0]
            Fy += v * d[1]
            follower |= load.follower
        elif load.kind == "moment":
            M += v
        else:
            raise NotApplicable(f"a prescribed {load.kind} at the tip: give the PRBM inverse inputs in "
                                "[methods.prbm] options instead")
    return Fx, Fy, M, follower


def _segment(prbm, case, requests, options):
    seg = case.segment
    L = seg.length
    EI = seg.bending_stiffness()
    n = case.n_levels()
    family = options.get("family", "pauly-midha")
    extrapolate = options.get("extrapolate", "raise")
    out: dict[str, np.ndarray] = {}
    info = MethodRun(values={})
    kappa = seg.initial_curvature()
    model = seg.model

    if seg.boundary in ("fixed-guided", "fixed-fixed") and model == "inflection":
        return _inflection(prbm, case, requests, options, EI)

    Fx, Fy, M, follower = _tip_loads(case, n)
    capstan = prbm.capstan_factor(float(options.get("friction_mu", 0.0)),
                                  math.radians(float(options.get("contact_angle_deg", 0.0))))
    Fx, Fy = Fx * capstan, Fy * capstan
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(Fy != 0, -Fx / np.where(Fy != 0, Fy, 1.0), 0.0)
    if np.any((Fy == 0) & (Fx != 0)):
        raise NotApplicable("a purely axial end force: outside every PRBM n-fit (n infinite)")
    a0, b0 = L, 0.0
    if seg.boundary in ("fixed-free", "fixed-pinned") and kappa == 0.0:
        has_F, has_M = np.any(Fy != 0), np.any(M != 0)
        if follower:
            if has_M:
                raise NotApplicable("follower force with an end moment: no PRBM in the seeds")
            if not np.allclose(ratio, ratio[0]):
                raise NotApplicable("follower force with a varying load ratio")
            res = prbm.composite_beam_tip(Fy, ratio[0], length=L, EI=EI, follower=True, family=family,
                                          extrapolate=extrapolate)
        elif has_F and has_M:
            res = prbm.fixed_guided_monotonic_tip(Fy, ratio, M, length=L, EI=EI, family=family,
                                                  extrapolate=extrapolate)
            info.message = "force and moment: equivalent initial curvature kappa0 = M l/EI (eq 62), no inflection"
        elif has_M:
            res = prbm.pure_moment_tip(M, length=L, EI=EI)
        else:
            res = prbm.fixed_pinned_tip(Fy, ratio, length=L, EI=EI, family=family, extrapolate=extrapolate)
    elif seg.boundary in ("fixed-free", "fixed-pinned"):
        if follower:
            raise NotApplicable("a follower force on an initially curved segment: no PRBM in the seeds")
        if np.any(M != 0):
            kappas = M / EI + kappa
            res = _stack([prbm.curved_fixed_pinned_tip(fy, r, length=L, EI=EI, curvature=k, family=family,
                                                       extrapolate=extrapolate)
                          for fy, r, k in zip(Fy, ratio, kappas)])
        else:
            res = prbm.curved_fixed_pinned_tip(Fy, ratio, length=L, EI=EI, curvature=kappa, family=family,
                                               extrapolate=extrapolate)
        a0, b0 = math.sin(kappa * L) / kappa, (1 - math.cos(kappa * L)) / kappa
    elif seg.boundary in ("fixed-guided", "fixed-fixed"):
        translations = [dof for dof in boundary_held_tip(case) if dof != "rz"]
        if translations:
            raise NotApplicable(f"fixed-fixed tip with {', '.join(translations)} held: the seeds' "
                                "fixed-guided PRBMs leave the tip free to translate")
        if kappa != 0.0:
            raise NotApplicable("initially curved fixed-guided segment without model = 'inflection'")
        if follower:
            raise NotApplicable("a follower force on a fixed-guided segment: no PRBM in the seeds")
        if np.any(M != 0):
            res = prbm.fixed_guided_monotonic_tip(Fy, ratio, M, length=L, EI=EI, family=family,
                                                  extrapolate=extrapolate)
        else:
            res = prbm.fixed_guided_tip(Fy, ratio, length=L, EI=EI, family=family, extrapolate=extrapolate)
            res.constants["k"] = 2.0 * np.asarray(res.constants["k_each"])  # U = 2 (k_each Theta^2/2)
    else:
        raise NotApplicable(f"boundary '{seg.boundary}' as a single segment case: the seeds' curved "
                            "pinned-pinned PRBM (prbm.curved_pinned_pinned) takes a chord force only")
    o = res.outputs
    a = _per_level(o["a"], n)
    b = _per_level(o["b"], n)
    # the quantity contract (validation/case/quantities.py): rotation from the unloaded tangent angle,
    # a held tip freedom reports the load that holds it
    rotation = _per_level(o["theta0"] - unloaded_tip_angle(L, kappa), n)
    if follower:  # the force the tip receives has turned with it
        Fx, Fy = Fx * np.cos(rotation) - Fy * np.sin(rotation), Fx * np.sin(rotation) + Fy * np.cos(rotation)
    out = {"x": a, "y": b, "dx": a - a0, "dy": b - b0, "force_x": Fx, "force_y": Fy, "moment": M,
           "rotation": np.degrees(rotation)}
    held = boundary_held_tip(case)
    if "rz" in held:
        if "M" not in o:
            raise NotApplicable(f"the PRBM ({res.model}) gives no moment holding the {seg.boundary} tip")
        out["moment"] = _per_level(o["M"], n)
    if "Theta" in o:
        Theta = _per_level(o["Theta"], n)
        out["prb_angle"] = np.degrees(Theta)
        k = res.constants.get("k")
        if k is not None:
            Ti = res.constants.get("Theta_i", 0.0)
            out["strain_energy"] = 0.5 * np.asarray(k) * (Theta - Ti) ** 2
    info.converged = bool(res.converged)
    info.message = info.message or res.message
    lc = res.level_converged
    info.level_converged = dict(enumerate(_per_level(lc, n).tolist())) \
        if lc is not None and np.size(lc) in (1, n) else {}
    info.extras = {"model": res.model, "constants": _plain(res.constants)}
    _warn_inflection(info, M, Fx, Fy, a, b)
    shapes = _segment_shapes(seg, res, n, kappa)
    if shapes:
        info.extras["shapes"] = shapes
    return _pick(out, requests, "segment"), info


INFLECTION_WARNING = ("inflection point expected: the bending moment changes sign between tip and root "
                      "(seed 000 Table 2.1, eq (12)); the monotonic-curvature PRBM (eq 62) does not fit this load, "
                      "use segment.model = 'inflection' (fixed-guided)")


def _warn_inflection(info: MethodRun, M, Fx, Fy, a, b) -> None:
    """Mark the levels whose end force and moment give an inflection point in the deformed PRBM state:
    the moment at the tip (M) and at the root (M + F_y a - F_x b) of opposite signs (Table 2.1's
    opposite senses, and the sufficient condition (12) evaluated on the PRBM's own deformed shape)."""
    root = M + Fy * a - Fx * b
    inflected = np.nonzero((M * root) < 0)[0]
    for level in inflected.tolist():
        info.level_messages[level] = INFLECTION_WARNING
    if len(inflected):
        info.extras["inflection_levels"] = inflected.tolist()


def _per_level(v, n: int) -> np.ndarray:
    """v as an array over the n load levels (a scalar repeated); np.broadcast_to without its overhead."""
    v = np.asarray(v)
    return v if v.shape == (n,) else np.broadcast_to(v, (n,))


def _stack(results):
    from prbm.result import PRBMResult

    keys = results[0].outputs.keys()
    out = {k: np.array([float(r.outputs[k]) for r in results]) for k in keys}
    return PRBMResult(all(r.converged for r in results), results[0].message, out, results[0].constants,
                      results[0].model, level_converged=np.array([r.converged for r in results]))


def _plain(d):
    plain = {}
    for k, v in d.items():
        if isinstance(v, np.ndarray):
            plain[k] = v.tolist()
        elif isinstance(v, (np.floating, np.integer)):
            plain[k] = v.item()
        else:
            plain[k] = v
    return plain


def _pick(out: dict, requests, what: str) -> dict:
    values = {}
    columns = {}  # quantity -> its levels as plain floats (one conversion per quantity, not per request)
    for req in requests:
        column = columns.get(req.quantity)
        if column is None:
            if req.quantity not in out:
                raise NotApplicable(f"the PRBM gives no '{req.quantity}' for this {what}")
            column = columns[req.quantity] = np.atleast_1d(out[req.quantity]).ravel().tolist()
        values[req] = float(column[req.level] if len(column) > 1 else column[0])
    return values


def _inflection(prbm, case, requests, options, EI):
    seg = case.segment
    n = case.n_levels()
    beam = prbm.InflectionBeam(seg.length, EI, options.get("family", "pauly-midha"))
    problem = options.get("problem", "loads")
    prefer = options.get("prefer", "energy")
    if isinstance(prefer, dict):
        prefer = next(iter(prefer.items()))
    needed = sorted({r.level for r in requests})
    results = {}
    if problem == "loads":
        Fx, Fy, M, follower = _tip_loads(case, n)
        if follower:
            raise NotApplicable("follower loads on the chapter-3 fixed-guided PRBM")
        for lv in needed:
            results[lv] = prbm.solve_loads(beam, float(Fy[lv]), float(-Fx[lv]), float(-M[lv]), prefer=prefer)
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


# --- mechanisms -----------------------------------------------------------------------------------
def _complex(pair) -> complex:
    return complex(float(pair[0]), float(pair[1]))


def _topology(prbm, mech):
    """PRBM topology (bodies, joints, segments) of a [mechanism] for the DOF count (eq 208)."""
    ground_links = set()
    fixed_nodes = {s.node for s in mech.supports if s.kind == "fixed"}
    for link in mech.links:
        if fixed_nodes & set(link.nodes):
            ground_links.add(link.name)
    bodies = 1 + len([l for l in mech.links if l.name not in ground_links])
    joints = 0
    pinned_ends = set()
    beam_names = {b.name for b in mech.beams}
    for joint in mech.joints:
        joints += len(joint.members) - 1
        for m in joint.members:
            if m in beam_names:
                pinned_ends.add((m, joint.node))
    for s in mech.supports:
        if s.kind == "pinned":
            joints += 1
            if s.member in beam_names:
                pinned_ends.add((s.member, s.node))
        elif s.kind in ("slider", "guided"):
            joints += 1
    segments = []
    for beam in mech.beams:
        kind = beam.segment_type
        if kind is None:
            pins = sum((beam.name, end) in pinned_ends for end in (beam.start, beam.end))
            kind = {0: "fixed-guided", 1: "fixed-pinned"}.get(pins)
            if kind is None:
                raise NotApplicable(f"beam '{beam.name}' pinned at both ends: no PRBM segment type")
        if kind not in prbm.SEGMENT_MODES:
            raise NotApplicable(f"segment type '{kind}' has no mode table")
        segments.append(prbm.Segment(kind, beam.name))
    return prbm.PRBMTopology(bodies, joints, segments)


def _mechanism(prbm, case, requests, options):
    mech = case.mechanism
    n = case.n_levels()
    info = MethodRun(values={})
    quantities = {r.quantity for r in requests}
    values = {}
    if "dof" in quantities:
        topo = _topology(prbm, mech)
        max_mode = int(options.get("max_mode", 2))
        dof = topo.max_dof(max_mode)
        info.extras["mode_table"] = topo.mode_table(max_mode)
        info.extras["procedure"] = topo.procedure(max_mode)      # chapter 8 steps, energy order
        info.extras["min_dof"] = topo.min_dof(max_mode)
        info.extras["expected_mode"] = topo.expected_mode(max_mode)
        for r in requests:
            if r.quantity == "dof":
                values[r] = float(dof)
        requests = [r for r in requests if r.quantity != "dof"]
        if not requests:
            first = next(step for step in info.extras["procedure"] if step["F_C"] >= 1)
            info.message = (f"maximum DOF {dof}, minimum {topo.min_dof(max_mode)} (Grubler on the PRBM, modes up "
                            f"to {max_mode}; first static mode {first['modes']}: F_C = f_r + f_e = "
                            f"{first['f_r']} + {first['f_e']})")
            return values, info
    links = options.get("links")
    kinds = sorted(sup.kind for sup in mech.supports)
    if not links and not mech.links and len(mech.beams) == 1 and kinds == ["pinned", "slider"]:
        values.update(_pinned_pinned_beam(prbm, case, requests, info))
        return values, info
    if not links and _one_beam_carrying_a_body(mech) and options.get("model") != "network":
        values.update(_segment_with_body(prbm, case, requests, options, info))
        return values, info
    if links and "r11" in links:
        return _slider(prbm, case, requests, options, links, values, info)
    if not links or options.get("model") == "network":
        values.update(prbm_network.run_mechanism(case, requests, options, info))
        return values, info
    if not {"r1", "r2", "r3", "r4"} <= set(links):
        raise NotApplicable("[methods.prbm] links: a PRB four-bar needs r1..r4 (or give no links: the PRB "
                            "model is then built from the geometry)")
    Z = {k: _complex(v) for k, v in links.items()}
    sp = options.get("springs", {})
    springs = tuple(float(sp.get(f"k{i}", 0.0)) for i in range(1, 5))
    standard = {"k1": "O2", "k2": "A", "k3": "B", "k4": "O4"}
    for key, joint in (options.get("spring_joints") or {}).items():
        if standard.get(key) != joint:
            raise NotApplicable(f"spring {key} at joint '{joint}': only k1..k4 at O2, A, B, O4 are mapped")
    slfp = options.get("slfp")
    if slfp and not sp:
        E = mech.E
        if E is None:
            raise NotApplicable("SLFP springs need the mechanism's E")
        # eq (186): k_i = E I_i / l_i, I_i = w t_i^3 / 12
        springs = tuple(E * float(slfp["width"]) * t**3 / 12.0 / l for t, l in zip(slfp["t"], slfp["l"]))
    fb = prbm.FourBar(Z["r1"], Z["r2"], Z["r3"], Z["r4"], Z.get("r5", 0j), springs=springs)
    t21, t31, t41 = fb.theta_ref
    ef = options.get("energy_free")
    if ef:
        t20 = float(ef["theta2"]) * DEG
        t3c, t4c = (float(v) for v in fb.angles(t20))
        t30 = float(ef["theta3"]) * DEG if "theta3" in ef else t3c
        t40 = float(ef["theta4"]) * DEG if "theta4" in ef else t4c
        fb.theta_free = (t20, t30, t40)
        P_free = Z["r2"] * cmath.exp(1j * (t20 - t21)) + Z.get("r5", 0j) * cmath.exp(1j * (t30 - t31)) \
            if "theta3" in ef else complex(fb.coupler_point(t20))
    else:
        t20 = t21
        P_free = complex(fb.coupler_point(t21))
    # drive
    torque = None
    for load in case.loads:
        if load.kind == "moment":
            torque = (torque if torque is not None else np.zeros(n)) + np.asarray(load.levels(), float)
    force_at_A = _link2_end_forces(case, fb, t20, complex(*options.get("origin", [0.0, 0.0])))
    precision = options.get("precision", {})
    drive = options.get("drive", "torque" if torque is not None or force_at_A is not None else "precision")
    if drive == "torque" and force_at_A is not None:
        base = torque if torque is not None else np.zeros(n)
        theta2 = np.array([_theta2_under_force(fb, complex(f), float(t), t20) for f, t in zip(force_at_A, base)])
        info.level_converged = {i: bool(np.isfinite(t)) for i, t in enumerate(theta2)}
        info.message = "PRB four-bar under a dead force at the end of PRB link 2 (its moment about O2 follows the link)"
    elif drive == "torque":
        if torque is None:
            raise NotApplicable("drive = 'torque' but the case has no input moment")
        res = fb.positions_under_torque(torque)
        theta2 = res.outputs["theta2"]
        info.level_converged = {i: bool(c) for i, c in enumerate(res.level_converged)}
    elif "phi" in precision:
        theta2 = t21 + np.asarray(precision["phi"], float) * DEG
    elif "psi" in precision:
        # output rotations from position 1 as re-solved by the loop (the printed vectors close to ~1e-3)
        t41c = float(fb.angles(t21)[1])
        theta2 = np.array([_theta2_for_output(fb, t41c + p * DEG, t21) for p in precision["psi"]])
    else:
        raise NotApplicable("no input torque and no precision positions (phi or psi) to drive the four-bar")
    levels_free = options.get("free_levels", [])
    theta2 = np.asarray(theta2, float)
    if len(theta2) != n:
        raise NotApplicable(f"{len(theta2)} precision positions for {n} load levels")
    free = np.zeros(n, bool)
    free[[lv for lv in levels_free if -n <= lv < n]] = True
    theta2 = np.where(free, t20, theta2)
    angles = fb.angles(theta2)  # (Theta3, Theta4) at every level, shared by the outputs below
    P = np.where(free, P_free, fb.coupler_point(theta2, angles))
    origin = complex(*options.get("origin", [0.0, 0.0]))
    torque = fb.input_torque(theta2, angles)
    out = {"dx": (P - P_free).real, "dy": (P - P_free).imag, "x": (P + origin).real, "y": (P + origin).imag,
           "input_angle": np.degrees(theta2), "input_torque": torque,
           "strain_energy": fb.strain_energy(theta2, angles)}
    ma = options.get("ma")
    if ma and {"F_i", "d_i", "d_o"} <= set(ma):
        out["mechanical_advantage"] = fb.compliant_ma(theta2, float(ma["F_i"]), float(ma["d_i"]), float(ma["d_o"]),
                                                      angles, torque=torque)
    point = options.get("coupler_point", "P")
    if "origin" not in options and any(r.quantity in ("x", "y") for r in requests):
        raise NotApplicable("x, y of the PRB four-bar are in its own frame (O2 at the origin): give "
                            "[methods.prbm] origin = [x, y], where O2 is in the case frame")
    for r in requests:
        if r.quantity in ("dx", "dy", "x", "y") and r.point != point:
            raise NotApplicable(f"the PRB four-bar tracks the coupler point '{point}' only, not '{r.point}'")
    values.update(_pick(out, requests, "four-bar"))
    info.extras["shapes"] = _fourbar_shapes(fb, theta2, P, origin, angles[0])
    info.message = info.message or f"PRB four-bar, drive = {drive}"
    info.extras.update({"loop_error": fb.loop_error, "theta_free_deg": [math.degrees(t) for t in fb.theta_free]})
    return values, info


def _link2_end_forces(case, fb, theta20: float, origin: complex):
    """Per level, the dead force (complex) on the node at the end of PRB link 2 (A = O2 + R2 e^{i theta20}
    in the unloaded pose), or None when the case has no force; a force elsewhere is not modelled."""
    forces = [ld for ld in case.loads if ld.kind == "force"]
    if not forces:
        return None
    nodes = {nd.name: complex(nd.x, nd.y) for nd in case.mechanism.nodes}
    A = origin + fb.R2 * cmath.exp(1j * theta20)
    total = np.zeros(case.n_levels(), complex)
    for load in forces:
        if load.follower or abs(nodes.get(load.point, complex(math.inf)) - A) > 1e-3 * fb.R2:
            raise NotApplicable(f"a force at '{load.point}': the PRB four-bar takes dead forces at the end of "
                                "PRB link 2 only (the segment tip of a fixed-pinned input segment)")
        total += np.asarray(load.levels(), float) * complex(*load.direction)
    return total


def _theta2_under_force(fb, force: complex, torque: float, theta20: float, span: float = math.radians(120)) -> float:
    """Input angle where the spring torque dU/dtheta2 (eq 182) balances a couple plus the moment about O2
    of a dead force at A = R2 e^{i theta2}: Im(conj(A) F). The first root from theta20 in the direction
    the load turns link 2 (Brent on a bracketing grid), nan if none within ``span``."""
    def unbalanced(t):
        A = fb.R2 * np.exp(1j * np.asarray(t))
        return fb.input_torque(t) - torque - (np.conj(A) * force).imag
    start = -float(unbalanced(theta20))
    if start == 0.0:
        return theta20
    grid = theta20 + math.copysign(1.0, start) * np.linspace(0.0, span, 241)
    r = unbalanced(grid)
    idx = np.nonzero(np.isfinite(r[:-1]) & np.isfinite(r[1:]) & (np.sign(r[:-1]) != np.sign(r[1:])))[0]
    if len(idx) == 0:
        return math.nan
    return brentq(lambda t: float(unbalanced(t)), grid[idx[0]], grid[idx[0] + 1], xtol=1e-14)


def _slider(prbm, case, requests, options, links, values, info):
    """Slider-crank (chapter 7): crank angle from the prescribed slider displacement of each level,
    compliance torque eq (196) as input_torque, MA = MA_R (1 - F_c/F_i) with eq (199) (ma = {F_i, d_i})."""
    sp = options.get("springs", {})
    sc = prbm.SliderCrank.from_vectors(_complex(links["r11"]), _complex(links["r2"]), _complex(links["r3"]),
                                       springs=tuple(float(sp.get(f"k{i}", 0.0)) for i in range(1, 4)),
                                       f_k=float(sp.get("f_k", 0.0)))
    dx = None
    for load in case.loads:
        if load.kind == "displacement":
            dx = np.asarray(load.levels(), float) * float(load.direction[0]) / math.hypot(*load.direction)
    if dx is None:
        raise NotApplicable("slider-crank: give the slider displacement per level (a 'displacement' load)")
    theta2 = np.array([sc.theta2_at(float(d)) for d in dx])
    out = {"input_angle": np.degrees(theta2), "input_torque": sc.compliance_torque(theta2)}
    ma = options.get("ma") or {}
    if {"F_i", "d_i"} <= set(ma):
        out["mechanical_advantage"] = sc.compliant_ma(theta2, float(ma["F_i"]), float(ma["d_i"]))
    values.update(_pick(out, requests, "slider-crank"))
    info.message = "PRB slider-crank, crank angle from the prescribed slider displacement (eqs 196, 199, 192)"
    return values, info


def _theta2_for_output(fb, theta4_target: float, theta2_start: float) -> float:
    """Input angle giving output angle theta4_target, nearest to theta2_start (within +-90 deg):
    the closed-form inverse ``FourBar.input_for_output``; the bracketed scan if that finds none."""
    theta2 = fb.input_for_output(theta4_target, theta2_start)
    return theta2 if theta2 is not None else _theta2_for_output_scan(fb, theta4_target, theta2_start)


def _theta2_for_output_scan(fb, theta4_target: float, theta2_start: float) -> float:
    """Input angle giving output angle theta4_target, nearest to theta2_start (bracketed scan and
    Brent on the forward solution; the reference for ``_theta2_for_output``)."""
    from scipy.optimize import brentq

    grid = theta2_start + np.linspace(-math.pi / 2, math.pi / 2, 721)
    r = np.angle(np.exp(1j * (fb.angles(grid)[1] - theta4_target)))
    ok = np.isfinite(r[:-1]) & np.isfinite(r[1:]) & (np.sign(r[:-1]) != np.sign(r[1:])) & (np.abs(r[:-1] - r[1:]) < 1)
    idx = np.nonzero(ok)[0]
    if len(idx) == 0:
        raise NotApplicable("output rotation not reachable")
    i = idx[np.argmin(np.abs(grid[idx] - theta2_start))]
    return brentq(lambda t: float(np.angle(np.exp(1j * (fb.angles(t)[1] - theta4_target)))), grid[i], grid[i + 1],
                  xtol=1e-14)


# --- pseudo-rigid-body link shapes (MethodRun.extras['shapes']) ------------------------------------
def _xy(points) -> np.ndarray:
    """Complex points -> an (n, 2) polyline."""
    z = np.asarray(points, complex)
    return np.column_stack([z.real, z.imag])


def _segment_shapes(seg, res, n: int, kappa: float) -> list | None:
    """Per level, the PRB links of a single-segment case in the case frame (fixed end at the origin).

    Fixed-free / fixed-pinned (straight): root -> characteristic pivot (1 - gamma) l -> tip.
    Fixed-guided, two springs (eq 63): root -> pivot (1 - gamma) l/2 -> + gamma l e^{i Theta} -> tip.
    Other models (curved, monotonic fixed-guided, composite, pure moment) give no chain here."""
    o, c = res.outputs, res.constants
    if kappa != 0.0 or "Theta" not in o or "gamma" not in c or np.any(np.asarray(o.get("theta0", 0.0)) != 0.0) \
            and seg.boundary in ("fixed-guided", "fixed-fixed"):
        return None
    L = seg.length
    gamma, Theta, a, b = (_per_level(np.asarray(v, float), n) for v in (c["gamma"], o["Theta"], o["a"], o["b"]))
    if seg.boundary in ("fixed-free", "fixed-pinned"):
        nodes = [(0.0, 0.0), ((1 - gamma) * L, 0.0), (a, b)]
    else:
        p1 = (1 - gamma) * L / 2
        nodes = [(0.0, 0.0), (p1, 0.0), (p1 + gamma * L * np.cos(Theta), gamma * L * np.sin(Theta)), (a, b)]
    # one (n, nodes, 2) array; each level's polyline is a view of it
    chains = np.empty((n, len(nodes), 2))
    for j, (x, y) in enumerate(nodes):
        chains[:, j, 0] = x
        chains[:, j, 1] = y
    finite = np.isfinite(gamma + Theta + a + b).tolist()
    return [[chains[i]] if finite[i] else [] for i in range(n)]


def _fourbar_shapes(fb, theta2, P, origin: complex, theta3=None) -> list:
    """Per level: the PRB four-bar O2-A-B-O4 and the coupler triangle A-P-B (O2 at ``origin``)."""
    theta2 = np.atleast_1d(theta2)
    if theta3 is None:
        theta3, _ = fb.angles(theta2)
    A = fb.R2 * np.exp(1j * theta2)
    B = A + fb.R3 * np.exp(1j * np.atleast_1d(theta3))
    loops = np.column_stack([np.zeros_like(A), A, B, np.full_like(A, fb.Z1)]) + origin  # (n, 4)
    triangles = np.column_stack([A, np.atleast_1d(P), B]) + origin  # (n, 3)
    loops = np.stack([loops.real, loops.imag], axis=-1)
    triangles = np.stack([triangles.real, triangles.imag], axis=-1)
    finite = np.isfinite(B).tolist()
    return [[loops[i], triangles[i]] if finite[i] else [] for i in range(len(finite))]


# --- one segment carrying a rigid body (chapter 5 Example 1) ---------------------------------------
def _segment_with_body(prbm, case, requests, options, info) -> dict:
    """A [mechanism] of one beam, fixed at one end, whose other end E carries the rigid links through E.

    The loads of each level (forces and couples at nodes of those links, dead) are given to
    ``prbm.solve_segment_with_body`` in the beam frame (x from the fixed end O along O->E), which
    transfers them to E with the current offsets (M + r x F) and solves the segment model forward.
    Segment model: ``segment_type = 'fixed-guided-inflection'`` (or option ``segment_model =
    'inflection'``) -> the chapter-3/5 inflection PRBM (eqs 83-104 = 131-152); 'fixed-pinned',
    'fixed-free' or none -> fixed_pinned_tip / pure_moment_tip / fixed_guided_monotonic_tip as for a
    single segment.  Outputs at any body node (or E): x, y, dx, dy, rotation (of the body, deg),
    strain_energy (PRBM springs).  Shapes: the PRB chain of the beam and the body through its nodes.
    """
    mech = case.mechanism
    beam = mech.beams[0]
    nodes = {nd.name: complex(nd.x, nd.y) for nd in mech.nodes}
    fixed = {s.node for s in mech.supports if s.kind == "fixed"}
    if len(mech.supports) != 1 or not fixed & {beam.start, beam.end}:
        raise NotApplicable("one beam with one fixed end and nothing else supported is the only "
                            "non-four-bar mechanism the PRBM adapter models")
    root, end = (beam.start, beam.end) if beam.start in fixed else (beam.end, beam.start)
    if any(j.node == end for j in mech.joints):
        raise NotApplicable(f"a joint at the beam end '{end}': the body is not rigidly attached")
    if beam.curvature != 0.0:
        raise NotApplicable("an initially curved beam carrying a rigid body")
    body_links = [lk for lk in mech.links if end in lk.nodes]
    body = {end} | {nd for lk in body_links for nd in lk.nodes}
    O, E = nodes[root], nodes[end]
    L = abs(E - O)
    to_local = cmath.exp(-1j * cmath.phase(E - O))
    if beam.section.kind == "layers":
        EI = sum(l.E * l.width * l.thickness**3 / 12.0 for l in beam.section.layers)
    else:
        EI = (beam.E or mech.E) * beam.section.inertia()
    kind = beam.segment_type or ("fixed-guided-inflection" if options.get("segment_model") == "inflection"
                                 else "fixed-pinned")
    family = options.get("family", "pauly-midha")
    if kind in ("fixed-guided-inflection", "inflection"):
        model = prbm.InflectionBeam(L, EI, family)
    elif kind in ("fixed-pinned", "fixed-free"):
        model = _tip_model(prbm, L, EI, family, options.get("extrapolate", "raise"))
    elif kind == "slfp":  # the beam is the flexure; the body is the rigid segment (eqs 71-76)
        def model(F: complex, M: float):
            return prbm.slfp_end_tip(F, M, flexure_length=L, EI=EI)
    else:
        raise NotApplicable(f"segment type '{kind}' carrying a rigid body: not modelled")

    n = case.n_levels()
    per_level = [[] for _ in range(n)]
    for i, load in enumerate(case.loads):
        if load.point not in body:
            raise NotApplicable(f"loads.{i} acts on '{load.point}', not on the body carried by '{beam.name}'")
        if load.kind not in ("force", "moment") or load.follower:
            raise NotApplicable(f"loads.{i}: only dead forces and couples on the body are modelled")
        r0 = (nodes[load.point] - E) * to_local
        for lv, v in enumerate(load.levels()):
            if load.kind == "force":
                F = complex(*load.direction) * v * to_local
                per_level[lv].append(prbm.BodyLoad(r0, force=F))
            else:
                per_level[lv].append(prbm.BodyLoad(r0, moment=v))
    offsets = {name: (nodes[name] - E) * to_local for name in body}
    needed = sorted({r.level for r in requests} | set(range(n)))
    results = {lv: prbm.solve_segment_with_body(model, per_level[lv], offsets, rest=(L, 0.0, 0.0),
                                                prefer=_prefer(options)) for lv in needed}
    to_global = 1.0 / to_local
    values = {}
    for req in requests:
        res = results[req.level]
        if req.point not in body:
            raise NotApplicable(f"point '{req.point}' is not on the body carried by '{beam.name}'")
        z = O + res.extras["points"][req.point] * to_global
        table = {"x": z.real, "y": z.imag, "dx": (z - nodes[req.point]).real, "dy": (z - nodes[req.point]).imag,
                 "rotation": math.degrees(float(res.outputs["rotation"])),
                 "strain_energy": float(res.outputs.get("U", res.outputs.get("strain_energy", np.nan)))}
        if req.quantity not in table:
            raise NotApplicable(f"the PRBM of a segment with a rigid body gives no '{req.quantity}'")
        values[req] = float(table[req.quantity]) if res.converged else math.nan
    shapes = []
    link_order = [lk.nodes for lk in body_links]
    for lv in range(n):
        res = results[lv]
        if not res.converged:
            shapes.append([])
            continue
        seg = res.extras["segment"]
        if seg is None:
            chain = np.array([0.0, L])
        elif isinstance(model, prbm.InflectionBeam):
            chain = prbm.inflection_pivots(seg.outputs) @ np.array([1.0, 1j])
        else:
            g = float(np.asarray(seg.constants.get("gamma", 0.5 if kind == "slfp" else np.nan)).ravel()[0])
            chain = np.array([0.0, (1 - g) * L, complex(float(res.outputs["a"]), float(res.outputs["b"]))])
        lines = [_xy(O + chain * to_global)]
        for names in link_order:
            lines.append(_xy([O + res.extras["points"][nm] * to_global for nm in names]))
        shapes.append(lines)
    info.converged = all(results[lv].converged for lv in needed)
    info.level_converged = {lv: bool(results[lv].converged) for lv in needed}
    info.level_messages = {lv: results[lv].message for lv in needed}
    info.message = f"PRBM {kind} segment '{beam.name}' carrying a rigid body (M + r x F at the current pose); " + \
        "; ".join(f"level {lv}: {results[lv].message}" for lv in needed)
    info.extras.update({"shapes": shapes, "model": results[needed[-1]].model,
                        "end_loads": {lv: {k: float(results[lv].outputs[k]) for k in ("Fx", "Fy", "M")}
                                      for lv in needed}})
    return values


def _one_beam_carrying_a_body(mech) -> bool:
    """One beam, fixed at one end by the only support, its other end not released by a joint
    (chapter 5 Example 1): the segment-with-body path and its chapter-3/5 models apply."""
    if len(mech.beams) != 1 or len(mech.supports) != 1 or mech.supports[0].kind != "fixed":
        return False
    beam = mech.beams[0]
    root = mech.supports[0].node
    if root not in (beam.start, beam.end):
        return False
    end = beam.end if root == beam.start else beam.start
    return not any(j.node == end for j in mech.joints)


def _pinned_pinned_beam(prbm, case, requests, info) -> dict:
    """One initially curved beam pinned at one end and on a slider along its chord at the other, a
    force along the chord at the slider: ``prbm.curved_pinned_pinned`` (two curved fixed-pinned halves
    fixed at mid-span, seed 000 section 2.3.5). Outputs at the slider node: x, y, dx, dy (the chord's
    change along the chord), force_x, force_y (the applied force)."""
    mech = case.mechanism
    beam = mech.beams[0]
    nodes = {nd.name: complex(nd.x, nd.y) for nd in mech.nodes}
    slider = next(s for s in mech.supports if s.kind == "slider")
    if slider.node not in (beam.start, beam.end):
        raise NotApplicable("the slider does not hold the beam's end")
    pin = beam.start if slider.node == beam.end else beam.end
    chord_vector = nodes[slider.node] - nodes[pin]
    chord0 = abs(chord_vector)
    along = chord_vector / chord0
    if slider.direction is None or abs(abs(complex(*slider.direction) / abs(complex(*slider.direction))
                                           * along.conjugate()) - 1.0) > 1e-9 \
            or abs((complex(*slider.direction) * along.conjugate()).imag) > 1e-9 * abs(complex(*slider.direction)):
        raise NotApplicable("the slider's free direction is not along the chord")
    if beam.curvature == 0.0:
        raise NotApplicable("a straight pinned-pinned beam under a chord force does not bend (no PRBM)")
    n = case.n_levels()
    force = np.zeros(n, complex)
    for i, load in enumerate(case.loads):
        if load.point != slider.node or load.kind != "force" or load.follower:
            raise NotApplicable(f"loads.{i}: only a dead force at the slider '{slider.node}' is modelled")
        force += np.asarray(load.levels(), float) * complex(*load.direction)
    if np.any(np.abs((force * along.conjugate()).imag) > 1e-12 * np.maximum(np.abs(force), 1e-300)):
        raise NotApplicable("the force at the slider is not along the chord")
    F_axial = (force * along.conjugate()).real  # + pulls the pins apart
    EI = beam.section.stiffness(beam.E or mech.E)[1]
    kappa = beam.curvature
    length = 2.0 / abs(kappa) * math.asin(min(1.0, abs(kappa) * chord0 / 2.0))  # arc over the chord
    res = prbm.curved_pinned_pinned(F_axial, length=length, EI=EI, curvature=abs(kappa))
    chord = np.broadcast_to(res.outputs["chord"], (n,))
    tip = nodes[pin] + chord * along
    table = {"x": tip.real, "y": tip.imag, "dx": (tip - nodes[slider.node]).real,
             "dy": (tip - nodes[slider.node]).imag, "force_x": force.real, "force_y": force.imag}
    values = {}
    for req in requests:
        if req.point != slider.node or req.quantity not in table:
            raise NotApplicable(f"the curved pinned-pinned PRBM gives no '{req.quantity}' at '{req.point}'")
        values[req] = float(table[req.quantity][req.level])
    info.converged = bool(res.converged)
    info.level_converged = {lv: bool(ok) for lv, ok in enumerate(np.broadcast_to(res.level_converged, (n,)))}
    info.message = f"{res.model}; constant gamma = {res.constants['gamma']}, K_Theta = {res.constants['K_theta']}"
    info.extras.update({"model": res.model, "constants": _plain(res.constants)})
    return values


def _prefer(options):
    prefer = options.get("prefer", "energy")
    return next(iter(prefer.items())) if isinstance(prefer, dict) else prefer


def _tip_model(prbm, L, EI, family, extrapolate):
    """tip(F, M) of a straight fixed-free segment (segment frame, M CCW), as the single-segment branch."""
    def tip(F: complex, M: float):
        if F.imag == 0 and F.real != 0:
            raise NotApplicable("a purely axial end force: outside every PRBM n-fit (n infinite)")
        if F == 0:
            return prbm.pure_moment_tip(M, length=L, EI=EI)
        n_ratio = -F.real / F.imag
        if M == 0:
            return prbm.fixed_pinned_tip(F.imag, n_ratio, length=L, EI=EI, family=family, extrapolate=extrapolate)
        return prbm.fixed_guided_monotonic_tip(F.imag, n_ratio, M, length=L, EI=EI, family=family,
                                               extrapolate=extrapolate)
    return tip
