"""PRBM adapter for chapter 7's mechanical advantage evaluated with ``prbm.compliance``
[bapat2015, eqs 192-198, 205], selected by ``[methods.prbm] ma = {model = "compliance", ...}``.

* Slider mechanism (``links`` with r11, r2, r3; springs k1..k3, f_k), Type 1: the levels are work-piece
  locations, the slider travel dx of a ``displacement`` load; the crank angle follows from the loop
  (``prbm.SliderCrank.theta2_at``), the coupler angle on the branch of position 1 in the turn of its
  printed angle (``prbm.SliderCrank.theta3``), the compliance torque is eq (196) and MA_R = d_i/|I12 I24|
  (eq 199/206).  With the input torque T_i = sigma F_i d_i (sigma the sign of the case's input
  moment, +1 without one) the held slider gives F_o v_o = (T_i - T_c) omega2, so
  MA = MA_R (1 - T_c/(sigma F_i d_i)) (eq 192 with signs: the compliance opposes the input when T_c
  has the input's sense).  Outputs ``mechanical_advantage``, ``input_torque`` (T_c), ``input_angle``.
* Four-bar with the input on link 4 and two output ports on links 2 and 3 (Compliers, Example 3),
  Type 2: one work-piece location, link 4 turned by ``ma.location_deg`` from the measured pose (the
  energy-free pose, Theta20 etc. = position 1); the levels are the input forces F_i of a ``force``
  load's values (its point and direction are not used: the input force is F_i at d_in normal to
  link 4); MA_R by eq (205), T_c by eq (195) (the virtual-work form, ``prbm.compliance``), and
  MA = MA_R (1 - T_c/(sigma F_i d_in)), sigma the sense of the closing rotation.  The input forces may
  instead be ``ma.F_i`` (one per level) when the case's load is the work-piece location itself, a
  ``displacement`` of a point on link 4 (what the FEM holds to find T_c as the moment at O4): that
  displacement must be the one link 4 turned by ``location_deg`` gives the point, else NotApplicable.

Options (``ma``): F_i, d_i (slider) or d_in, d_out2, d_out3, location_deg (four-bar).

A value that is not finite (MA at a singular pose, where the output cannot move, or with no input
force) is a run that did not converge, with the quantity and level named, never a silent NaN.
"""

from __future__ import annotations

import cmath
import math
from typing import TYPE_CHECKING

import numpy as np

import prbm
from prbm.lazy import LazyModule
from validation.case.method_options import PrbmMechanicalAdvantageOptions, PrbmOptions
from validation.methods.base import Misconfigured, MethodRun, NotApplicable
from validation.methods.prbm_common import per_level, slider_angles

if TYPE_CHECKING:  # loaded at first use (below); named here for the static import walks (run-cache hash)
    from prbm import compliance
else:  # imports scipy.optimize: only a case that asks for the compliance MA pays for it
    compliance = LazyModule("prbm.compliance")

DEG = math.pi / 180.0


def handles(case, options: PrbmOptions) -> bool:
    """True when the case asks for this adapter: a mechanism with ma.model = 'compliance'."""
    return case.mechanism is not None and options.ma is not None and options.ma.model == "compliance"


def _complex(pair) -> complex:
    return complex(float(pair[0]), float(pair[1]))


def _ma_options(options: PrbmOptions) -> PrbmMechanicalAdvantageOptions:
    """``[methods.prbm] ma`` (``handles`` has checked it is given)."""
    if options.ma is None:
        raise NotApplicable("ma.model = 'compliance' needs [methods.prbm] ma")
    return options.ma


def _needs(ma: PrbmMechanicalAdvantageOptions, keys: tuple[str, ...], what: str) -> NotApplicable:
    """The refusal of a model whose options ``keys`` are not all given, naming those missing."""
    missing = [k for k in keys if getattr(ma, k) is None]
    return NotApplicable(f"[methods.prbm] ma: {what} needs {', '.join(missing)}")


def _input_sense(case) -> float:
    moments = [ld for ld in case.loads if ld.kind == "moment"]
    if not moments:
        return 1.0
    total = np.sum([np.asarray(ld.levels(), float) for ld in moments], axis=0)
    signs = np.sign(total[total != 0.0])
    if signs.size == 0 or np.any(signs != signs[0]):
        raise NotApplicable("the input moment changes sign over the levels: no single driving sense")
    return float(signs[0])


def _slider(case, options: PrbmOptions) -> dict[str, np.ndarray]:
    links, ma = options.links or {}, _ma_options(options)
    if ma.F_i is None or ma.d_i is None:
        raise _needs(ma, ("F_i", "d_i"), "a slider Type 1 MA")
    Z11, Z2, Z3 = (_complex(links[k]) for k in ("r11", "r2", "r3"))
    springs = (options.spring("k1"), options.spring("k2"), options.spring("k3"))
    sc = prbm.SliderCrank.from_vectors(Z11, Z2, Z3)
    travel = [ld for ld in case.loads if ld.kind == "displacement"]
    if len(travel) != 1:
        raise NotApplicable("slider Type 1 MA: give the work-piece locations as one 'displacement' load")
    d = np.asarray(travel[0].direction, float)
    dx = np.asarray(travel[0].levels(), float) * d[0] / math.hypot(*d)
    theta2 = slider_angles(sc, dx)
    theta3 = np.asarray(sc.theta3(theta2), float)
    pose = compliance.SliderPose(sc.R2, sc.R3, theta2, theta3, sc.theta2_ref, sc.theta3_ref, sc.x_ref)
    T_c = compliance.slider_compliance(pose, springs, options.spring("f_k"), "crank")
    F_i = per_level(np.asarray(ma.F_i, float), case.n_levels())  # one value, or one per level
    d_i = ma.d_i
    rigid = sc.rigid_ma(theta2, d_i)
    return {
        "mechanical_advantage": compliance.compliant_ma(rigid, T_c / d_i, _input_sense(case) * F_i),
        "input_torque": T_c,
        "input_angle": np.degrees(theta2),
    }


def _compliers(case, options: PrbmOptions) -> dict[str, np.ndarray]:
    links, ma = options.links or {}, _ma_options(options)
    d_in, d_out2, d_out3, location_deg = ma.d_in, ma.d_out2, ma.d_out3, ma.location_deg
    if d_in is None or d_out2 is None or d_out3 is None or location_deg is None:
        raise _needs(ma, ("d_in", "d_out2", "d_out3", "location_deg"), "a two-port Type 2 MA (eq 205)")
    Z1, Z2, Z3, Z4 = (_complex(links[k]) for k in ("r1", "r2", "r3", "r4"))
    try:
        fb = prbm.FourBar(Z1, Z2, Z3, Z4)
    except ValueError as exc:  # the links do not make a four-bar: the case's input, not a solver failure
        raise Misconfigured(f"links: {exc}") from None
    t20, t30, t40 = fb.theta_ref
    target = t40 + location_deg * DEG
    theta2 = fb.input_for_output(target, t20)
    if theta2 is None:
        raise NotApplicable(f"the four-bar cannot turn link 4 by {location_deg} deg from its measured pose")
    theta3 = float(fb.angles(theta2)[0])
    pose = compliance.FourBarPose(fb.R2, fb.R3, fb.R4, theta2, theta3, target, t20, t30, t40)
    springs = (options.spring("k1"), options.spring("k2"), options.spring("k3"), options.spring("k4"))
    T_c = float(compliance.fourbar_compliance_torque(pose, springs, input_link=4))
    rigid = float(compliance.two_port_rigid_ma(pose, fb.Z1, d_in, d_out2, d_out3))
    _check_location(case, location_deg * DEG)
    F_i = _input_forces(case, ma)
    if np.any(F_i <= 0.0):
        raise NotApplicable("Type 2 MA: the input forces must be positive (magnitudes)")
    sense = math.copysign(1.0, location_deg)
    n = case.n_levels()
    return {
        "mechanical_advantage": compliance.compliant_ma(rigid, T_c / d_in, sense * F_i),
        "input_torque": np.full(n, T_c),
        "input_angle": np.full(n, math.degrees(target)),
    }


def _input_forces(case, ma: PrbmMechanicalAdvantageOptions) -> np.ndarray:
    """F_i per level: ``ma.F_i`` or the values of the case's one 'force' load."""
    forces = [ld for ld in case.loads if ld.kind == "force"]
    if ma.F_i is not None:
        if forces:
            raise NotApplicable("Type 2 MA: give F_i either as ma.F_i or as a 'force' load, not both")
        F_i = np.broadcast_to(np.asarray(ma.F_i, float), (case.n_levels(),))
    elif len(forces) == 1:
        F_i = np.asarray(forces[0].levels(), float)
    else:
        raise NotApplicable("Type 2 MA: give the input forces F_i as the values of one 'force' load (or ma.F_i)")
    return F_i


def _check_location(case, turn: float) -> None:
    """A 'displacement' load on the case must be the motion of its point when the link carrying it (link 4,
    pinned at a support) turns by ``turn`` (rad) from the measured pose: the work-piece location the PRBM
    evaluates."""
    mech = case.mechanism
    nodes = {nd.name: complex(nd.x, nd.y) for nd in mech.nodes}
    for i, ld in enumerate(case.loads):
        if ld.kind != "displacement":
            continue
        pivots = [
            s.node
            for link in mech.links
            if ld.point in link.nodes
            for s in mech.supports
            if s.node in link.nodes and s.node != ld.point
        ]
        if len(pivots) != 1:
            raise NotApplicable(
                f"loads.{i}: the work-piece location must move a point of the input link, pinned at one support"
            )
        arm = nodes[ld.point] - nodes[pivots[0]]
        d = complex(*ld.direction) / abs(complex(*ld.direction))
        expected = (arm * (cmath.exp(1j * turn) - 1.0) * d.conjugate()).real
        if any(abs(v - expected) > 1e-4 * abs(arm) for v in ld.levels()):
            raise NotApplicable(
                f"loads.{i}: displacement {ld.levels()[0]:.6g} of '{ld.point}' is not the "
                f"{expected:.6g} that the input link turned by location_deg gives it"
            )


def run(case, requests, options: PrbmOptions) -> tuple[dict, MethodRun]:
    """Values per request and the run record (see the module docstring)."""
    links = options.links or {}
    if "r11" in links:
        out, what = _slider(case, options), "PRB slider, eqs (192), (196), (199)"
    elif {"r1", "r2", "r3", "r4"} <= set(links):
        out, what = _compliers(case, options), "PRB four-bar, input on link 4, eqs (192), (195), (205)"
    else:
        raise NotApplicable("ma.model = 'compliance' needs [methods.prbm] links: r11, r2, r3 (slider) or r1..r4")
    values = {}
    for req in requests:
        if req.quantity not in out:
            raise NotApplicable(f"the PRB MA model gives no '{req.quantity}'")
        column = np.atleast_1d(out[req.quantity])
        values[req] = float(column[req.level] if column.size > 1 else column[0])
    lost = next((req for req, value in values.items() if not math.isfinite(value)), None)
    if lost is not None:
        return values, MethodRun(
            values=values,
            converged=False,
            message=f"{what}: no finite {lost.quantity} "
            f"at level {lost.level} (a singular pose of the PRB mechanism, or no input force)",
        )
    return values, MethodRun(values=values, message=f"{what} (prbm.compliance)")
