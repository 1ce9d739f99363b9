"""The PRBM adapter's hand-given linkages: a PRB four-bar or slider-crank from ``[methods.prbm]`` links,
and the degrees of freedom of a mechanism's PRBM (eq 208).

Options, in the case-file format of chapters 6, 7 and 9: ``links = {r1 = [x, y], ..., r5, r6}``
(position-1 vectors Z1..Z6), ``springs = {k1..k4}`` (or ``slfp = {width, t, l}``: k_i = E I_i / l_i,
eq 186), ``energy_free = {theta2, theta3, theta4}`` (deg), ``coupler_point`` (node name, default 'P'),
``origin`` (where O2 is in the case frame).
Drive, per level: input torques (a 'moment' load) -> equilibrium by minimum total potential energy
(the general network solver, ``prbm.FourBar.positions_under_torque``); a dead force at the end of PRB
link 2 (its moment about O2 follows the link); or ``precision = {phi = [...]}`` (input rotations from
position 1, deg) or ``{psi = [...]}`` (output rotations) -> the precision positions; ``free_levels`` =
levels at the unloaded pose (``drive = 'precision'`` forces this when both are given).
Outputs: dx, dy of the coupler point from the unloaded pose, x, y (O2 at ``origin``), input_angle,
input_torque (eq 182), strain_energy (eq 181), mechanical_advantage (``ma = {F_i, d_i, d_o}``, eqs
190, 192). The unloaded pose, when ``energy_free.theta3`` is given, is placed with the printed
energy-free angles by the dyad Z2 e^{i(theta20 - theta21)} + Z5 e^{i(theta30 - theta31)} (as [bapat2015]
does), not re-solved from the loop (the printed vectors close only to about 0.002 in).
Slider-crank (``links.r11``): crank angle from the prescribed slider displacement of each level,
compliance torque eq (196) as input_torque, MA = MA_R (1 - F_c/F_i) with eq (199) (``ma = {F_i, d_i}``).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

import prbm
from validation.case.method_options import PrbmOptions, PrecisionOptions
from validation.methods.base import Misconfigured, MethodRun, NotApplicable
from validation.methods import prbm_readings
from validation.methods.prbm_common import DEG, per_input_force, pick, slider_angles


def _complex(pair) -> complex:
    return complex(float(pair[0]), float(pair[1]))


def topology(mech) -> prbm.PRBMTopology:
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


def dof_values(mech, requests, options: PrbmOptions, info: MethodRun) -> tuple[dict, list]:
    """The 'dof' requests (the maximum DOF of the PRBM, eq 208 with the mode tables, modes up to
    ``max_mode``) and the requests left; the chapter-8 procedure in ``info.extras``."""
    topo = topology(mech)
    max_mode = options.max_mode
    dof = topo.max_dof(max_mode)
    info.extras["mode_table"] = topo.mode_table(max_mode)
    info.extras["procedure"] = topo.procedure(max_mode)  # chapter 8 steps, energy order
    info.extras["min_dof"] = topo.min_dof(max_mode)
    info.extras["expected_mode"] = topo.expected_mode(max_mode)
    values = {r: float(dof) for r in requests if r.quantity == "dof"}
    rest = [r for r in requests if r.quantity != "dof"]
    if not rest:
        first = next(step for step in info.extras["procedure"] if step["F_C"] >= 1)
        info.message = (
            f"maximum DOF {dof}, minimum {topo.min_dof(max_mode)} (Grubler on the PRBM, modes up "
            f"to {max_mode}; first static mode {first['modes']}: F_C = f_r + f_e = "
            f"{first['f_r']} + {first['f_e']})"
        )
    return values, rest


@dataclass
class FourBarSetup:
    """The PRB four-bar of the options and its unloaded pose: input angle theta20 (rad), the
    position-1 input angle theta21, the coupler point there (O2 at the origin)."""

    fb: prbm.FourBar
    theta20: float
    theta21: float
    P_free: complex


def fourbar_from_options(case, options: PrbmOptions) -> FourBarSetup:
    """``prbm.FourBar`` from links r1..r5, springs k1..k4 (or slfp sizes) and energy_free angles."""
    links = options.links or {}
    if not {"r1", "r2", "r3", "r4"} <= set(links):
        raise NotApplicable(
            "[methods.prbm] links: a PRB four-bar needs r1..r4 (or give no links: the PRB "
            "model is then built from the geometry)"
        )
    Z = {k: _complex(v) for k, v in links.items()}
    springs = (options.spring("k1"), options.spring("k2"), options.spring("k3"), options.spring("k4"))
    standard = {"k1": "O2", "k2": "A", "k3": "B", "k4": "O4"}
    for key, joint in (options.spring_joints or {}).items():
        if standard.get(key) != joint:
            raise NotApplicable(f"spring {key} at joint '{joint}': only k1..k4 at O2, A, B, O4 are mapped")
    slfp = options.slfp
    if slfp and not options.springs:
        E = case.mechanism.E
        if E is None:
            raise NotApplicable("SLFP springs need the mechanism's E")
        if len(slfp.t) != 4:
            raise Misconfigured(f"slfp: a PRB four-bar has four springs k1..k4, the options size {len(slfp.t)}")
        # eq (186): k_i = E I_i / l_i, I_i = w t_i^3 / 12
        k1, k2, k3, k4 = (E * slfp.width * t**3 / 12.0 / l for t, l in zip(slfp.t, slfp.l))
        springs = (k1, k2, k3, k4)
    try:
        fb = prbm.FourBar(Z["r1"], Z["r2"], Z["r3"], Z["r4"], Z.get("r5", 0j), springs=springs)
    except ValueError as exc:  # the links do not make a four-bar: the case's input, not a solver failure
        raise Misconfigured(f"links: {exc}") from None
    t21, t31, _ = fb.theta_ref
    ef = options.energy_free
    if not ef:
        return FourBarSetup(fb, t21, t21, complex(fb.coupler_point(t21)))
    t20 = float(ef["theta2"]) * DEG
    t3c, t4c = (float(v) for v in fb.angles(t20))
    t30 = float(ef["theta3"]) * DEG if "theta3" in ef else t3c
    t40 = float(ef["theta4"]) * DEG if "theta4" in ef else t4c
    fb.theta_free = (t20, t30, t40)
    P_free = (
        Z["r2"] * cmath.exp(1j * (t20 - t21)) + Z.get("r5", 0j) * cmath.exp(1j * (t30 - t31))
        if "theta3" in ef
        else complex(fb.coupler_point(t20))
    )
    return FourBarSetup(fb, t20, t21, P_free)


def _input_torques(case) -> np.ndarray | None:
    """The summed input moment of every level, or None when the case has none."""
    torque = None
    for load in case.loads:
        if load.kind == "moment":
            torque = (torque if torque is not None else np.zeros(case.n_levels())) + np.asarray(load.levels(), float)
    return torque


@dataclass
class Drive:
    """The input angle of every level (rad), the levels held at the unloaded pose, the drive's name."""

    theta2: np.ndarray
    free: np.ndarray
    name: str


def fourbar_drive(case, setup: FourBarSetup, options: PrbmOptions, info: MethodRun) -> Drive:
    """The input angle of every level and the drive that set it (see the module docstring)."""
    fb, t20, t21 = setup.fb, setup.theta20, setup.theta21
    n = case.n_levels()
    torque = _input_torques(case)
    turning = prbm_readings.link2_turning_forces(case, fb.R2, t20, options)  # follower / rope at A
    force_at_A = None if turning else _link2_end_forces(case, fb, t20, complex(*options.origin))
    precision = options.precision or PrecisionOptions()
    drive = options.drive or ("torque" if torque is not None or force_at_A is not None or turning else "precision")
    if drive == "torque" and turning:
        theta2 = prbm_readings.theta2_under_turning_forces(
            fb, turning, torque if torque is not None else np.zeros(n), t20, options
        )
        info.level_converged = {i: bool(np.isfinite(t)) for i, t in enumerate(theta2)}
        info.message = "PRB four-bar under a turning force at the end of PRB link 2 (eq (**) of prbm.turning_loads)"
    elif drive == "torque" and force_at_A is not None:
        base = torque if torque is not None else np.zeros(n)
        theta2 = np.array([_theta2_under_force(fb, complex(f), float(t), t20) for f, t in zip(force_at_A, base)])
        info.level_converged = {i: bool(np.isfinite(t)) for i, t in enumerate(theta2)}
        info.message = "PRB four-bar under a dead force at the end of PRB link 2 (its moment about O2 follows the link)"
    elif drive == "torque":
        if torque is None:
            raise NotApplicable("drive = 'torque' but the case has no input moment")
        res = fb.positions_under_torque(torque)
        theta2 = np.asarray(res.outputs["theta2"], float)
        converged = res.level_converged if res.level_converged is not None else np.full(n, res.converged)
        info.level_converged = {i: bool(c) for i, c in enumerate(converged)}
    elif precision.phi is not None:
        theta2 = t21 + np.asarray(precision.phi, float) * DEG
    elif precision.psi is not None:
        # output rotations from position 1 as re-solved by the loop (the printed vectors close to ~1e-3)
        t41c = float(fb.angles(t21)[1])
        theta2 = np.array([_theta2_for_output(fb, t41c + p * DEG, t21) for p in precision.psi])
    else:
        raise NotApplicable("no input torque and no precision positions (phi or psi) to drive the four-bar")
    theta2 = np.asarray(theta2, float)
    if len(theta2) != n:
        raise NotApplicable(f"{len(theta2)} precision positions for {n} load levels")
    free = np.zeros(n, bool)
    free[[lv for lv in options.free_levels if -n <= lv < n]] = True
    return Drive(np.where(free, t20, theta2), free, drive)


def run_fourbar(case, requests, options: PrbmOptions, info: MethodRun) -> dict:
    """The requested outputs of the PRB four-bar of the options (see the module docstring)."""
    setup = fourbar_from_options(case, options)
    fb = setup.fb
    drive = fourbar_drive(case, setup, options, info)
    theta2, free = drive.theta2, drive.free
    angles = fb.angles(theta2)  # (Theta3, Theta4) at every level, shared by the outputs below
    P = np.where(free, setup.P_free, fb.coupler_point(theta2, angles))
    origin = complex(*options.origin)
    P_free = setup.P_free
    out = {
        "dx": (P - P_free).real,
        "dy": (P - P_free).imag,
        "x": (P + origin).real,
        "y": (P + origin).imag,
        "input_angle": np.degrees(theta2),
    }
    wanted = {r.quantity for r in requests}
    ma = options.ma
    has_ma = ma is not None and ma.F_i is not None and ma.d_i is not None and ma.d_o is not None
    # the network virtual work (eq 182) and the energy only when the case asks for them
    if "input_torque" in wanted or (has_ma and "mechanical_advantage" in wanted):
        out["input_torque"] = fb.input_torque(theta2, angles)
    if "strain_energy" in wanted:
        out["strain_energy"] = fb.strain_energy(theta2, angles)
    if (
        ma is not None
        and ma.F_i is not None
        and ma.d_i is not None
        and ma.d_o is not None
        and "mechanical_advantage" in wanted
    ):
        d_i, d_o, torque = ma.d_i, ma.d_o, out["input_torque"]
        out["mechanical_advantage"] = per_input_force(
            lambda F_i: fb.compliant_ma(theta2, F_i, d_i, d_o, angles, torque=torque), ma.F_i, len(theta2)
        )
    point = options.coupler_point
    if "origin" not in options.model_fields_set and any(r.quantity in ("x", "y") for r in requests):
        raise NotApplicable(
            "x, y of the PRB four-bar are in its own frame (O2 at the origin): give "
            "[methods.prbm] origin = [x, y], where O2 is in the case frame"
        )
    for r in requests:
        if r.quantity in ("dx", "dy", "x", "y") and r.point != point:
            raise NotApplicable(f"the PRB four-bar tracks the coupler point '{point}' only, not '{r.point}'")
    values = pick(out, requests, "four-bar")
    info.extras["shapes"] = fourbar_shapes(fb, theta2, P, origin, angles[0])
    info.message = info.message or f"PRB four-bar, drive = {drive.name}"
    theta_free = fb.theta_free if fb.theta_free is not None else fb.theta_ref  # set by FourBar itself
    info.extras.update({"loop_error": fb.loop_error, "theta_free_deg": [math.degrees(t) for t in theta_free]})
    return values


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
            raise NotApplicable(
                f"a force at '{load.point}': the PRB four-bar takes dead forces at the end of "
                "PRB link 2 only (the segment tip of a fixed-pinned input segment)"
            )
        total += np.asarray(load.levels(), float) * complex(*load.direction)
    return total


def _theta2_under_force(fb, force: complex, torque: float, theta20: float, span: float = math.radians(120)) -> float:
    """Input angle where the spring torque dU/dtheta2 (eq 182) balances a couple plus the moment about O2
    of a dead force at A = R2 e^{i theta2}: the dead-force case of
    ``prbm.input_angle_under_turning_forces`` (the same first-root search from theta20)."""
    forces = [(abs(force), prbm.DeadDirection(force))] if force != 0 else []
    return prbm.input_angle_under_turning_forces(fb, forces, theta20=theta20, c_theta=1.0, torque=torque, span=span)


def run_slider(case, requests, options: PrbmOptions, info: MethodRun) -> dict:
    """Slider-crank (chapter 7): crank angle from the prescribed slider displacement of each level,
    compliance torque eq (196) as input_torque, MA = MA_R (1 - F_c/F_i) with eq (199) (ma = {F_i, d_i})."""
    links = options.links or {}
    sc = prbm.SliderCrank.from_vectors(
        _complex(links["r11"]),
        _complex(links["r2"]),
        _complex(links["r3"]),
        springs=(options.spring("k1"), options.spring("k2"), options.spring("k3")),
        f_k=options.spring("f_k"),
    )
    dx = None
    for load in case.loads:
        if load.kind == "displacement":
            dx = np.asarray(load.levels(), float) * float(load.direction[0]) / math.hypot(*load.direction)
    if dx is None:
        raise NotApplicable("slider-crank: give the slider displacement per level (a 'displacement' load)")
    theta2 = slider_angles(sc, dx)
    out = {"input_angle": np.degrees(theta2), "input_torque": sc.compliance_torque(theta2)}
    ma = options.ma
    if ma is not None and ma.F_i is not None and ma.d_i is not None:
        d_i = ma.d_i
        out["mechanical_advantage"] = per_input_force(
            lambda F_i: sc.compliant_ma(theta2, F_i, d_i), ma.F_i, len(theta2)
        )
    info.message = "PRB slider-crank, crank angle from the prescribed slider displacement (eqs 196, 199, 192)"
    return pick(out, requests, "slider-crank")


def _theta2_for_output(fb, theta4_target: float, theta2_start: float) -> float:
    """Input angle giving output angle theta4_target, nearest to theta2_start (within +-90 deg):
    the closed-form inverse ``FourBar.input_for_output``; the bracketed scan if that finds none."""
    theta2 = fb.input_for_output(theta4_target, theta2_start)
    return theta2 if theta2 is not None else _theta2_for_output_scan(fb, theta4_target, theta2_start)


def _theta2_for_output_scan(fb, theta4_target: float, theta2_start: float) -> float:
    """Input angle giving output angle theta4_target, nearest to theta2_start (bracketed scan and
    Brent on the forward solution; the reference for ``_theta2_for_output``)."""
    grid = theta2_start + np.linspace(-math.pi / 2, math.pi / 2, 721)
    r = np.angle(np.exp(1j * (fb.angles(grid)[1] - theta4_target)))
    ok = np.isfinite(r[:-1]) & np.isfinite(r[1:]) & (np.sign(r[:-1]) != np.sign(r[1:])) & (np.abs(r[:-1] - r[1:]) < 1)
    idx = np.nonzero(ok)[0]
    if len(idx) == 0:
        raise NotApplicable("output rotation not reachable")
    i = idx[np.argmin(np.abs(grid[idx] - theta2_start))]
    return brentq(
        lambda t: float(np.angle(np.exp(1j * (fb.angles(t)[1] - theta4_target)))), grid[i], grid[i + 1], xtol=1e-14
    )


def fourbar_shapes(fb, theta2, P, origin: complex, theta3=None) -> list:
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
