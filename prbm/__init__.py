"""Pseudo-rigid-body models (PRBM) of compliant segments and mechanisms; no knowledge of case files.

Lengths and forces in any consistent units; angles in radians (degrees only in case files and
reports). Results are ``PRBMResult`` (``converged``, ``message``, ``outputs``, ``constants``).

>>> import prbm
>>> tip = prbm.fixed_pinned_tip(0.0, length=2.0, EI=1.0)     # no load: the undeformed tip
>>> tip.converged, float(tip.outputs["a"]), float(tip.outputs["b"])
(True, 2.0, 0.0)
>>> tip.constants["gamma"]                                   # Pauly-Midha fit at n = 0 (Howell: 0.8517)
0.851892
>>> prbm.fixed_pinned_tip(1.0, length=1.0, EI=-1.0)
Traceback (most recent call last):
...
ValueError: fixed_pinned_tip: EI must be finite and > 0, got -1.0
"""
from prbm.composite import capstan_factor, composite_beam_tip, layered_bending_stiffness
from prbm.coupled_segment import BodyLoad, body_end_loads, inflection_pivots, solve_segment_with_body
from prbm.dof import SEGMENT_MODES, ModeShape, PRBMTopology, Segment, grubler
from prbm.domain import (boundary_curves, curved_fixed_pinned_domain, fit_radius, fixed_fixed_monotonic_domain,
                         fixed_guided_domain, fixed_pinned_domain, slfp_domain)
from prbm.fits import (FAMILIES, HOWELL, PAULY_MIDHA, PURE_MOMENT_C_THETA, PURE_MOMENT_GAMMA,
                       PURE_MOMENT_K_THETA, PURE_MOMENT_SPRING, FitFamily, FitRangeError, FitRangeWarning,
                       PiecewiseFit, fit_family, load_angle, load_ratio)
from prbm.inflection import InflectionBeam, inflection_state, solve_displacements, solve_loads
from prbm.builder import BeamModel, BeamRule, Geometry, PRBModel, Rules, build
from prbm.mechanisms import FourBar, SliderCrank
from prbm.network import (GROUND, Couple, Force, LockedNetwork, Network, NetworkResult, Pin,
                          PrescribedDisplacement, PrescribedRotation, Slider, TorsionSpring, solve, trace)
from prbm.result import PRBMResult
from prbm.turning_loads import (DeadDirection, FollowerDirection, TipPose, TowardPoint, fixed_pinned_turning_tip,
                                input_angle_under_turning_forces)
from prbm.segments import (curved_fixed_pinned_tip, curved_pinned_pinned, fixed_guided_monotonic_tip,
                           fixed_guided_tip, fixed_pinned_from_tip, fixed_pinned_tip, pure_moment_from_tip,
                           pure_moment_tip, slfp_end_tip, slfp_tip, spring_angle)

__all__ = [
    "capstan_factor", "composite_beam_tip", "layered_bending_stiffness",
    "BodyLoad", "body_end_loads", "inflection_pivots", "solve_segment_with_body",
    "SEGMENT_MODES", "ModeShape", "PRBMTopology", "Segment", "grubler",
    "boundary_curves", "curved_fixed_pinned_domain", "fit_radius", "fixed_fixed_monotonic_domain",
    "fixed_guided_domain", "fixed_pinned_domain", "slfp_domain",
    "FAMILIES", "HOWELL", "PAULY_MIDHA", "PURE_MOMENT_C_THETA", "PURE_MOMENT_GAMMA", "PURE_MOMENT_K_THETA",
    "PURE_MOMENT_SPRING", "FitFamily", "FitRangeError", "FitRangeWarning", "PiecewiseFit", "fit_family",
    "load_angle", "load_ratio",
    "InflectionBeam", "inflection_state", "solve_displacements", "solve_loads",
    "FourBar", "SliderCrank", "PRBMResult",
    "BeamModel", "BeamRule", "Geometry", "PRBModel", "Rules", "build",
    "GROUND", "Couple", "Force", "LockedNetwork", "Network", "NetworkResult", "Pin", "PrescribedDisplacement",
    "PrescribedRotation", "Slider", "TorsionSpring", "solve", "trace",
    "curved_fixed_pinned_tip", "curved_pinned_pinned", "fixed_guided_monotonic_tip", "fixed_guided_tip",
    "fixed_pinned_from_tip", "fixed_pinned_tip", "pure_moment_from_tip", "pure_moment_tip", "slfp_end_tip", "slfp_tip",
    "spring_angle",
    "DeadDirection", "FollowerDirection", "TipPose", "TowardPoint", "fixed_pinned_turning_tip",
    "input_angle_under_turning_forces",
]
