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

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # what a type checker and the static import walks see; at run time names load on first use
    from prbm.composite import capstan_factor, composite_beam_tip, layered_bending_stiffness
    from prbm.coupled_segment import BodyLoad, body_end_loads, inflection_pivots, solve_segment_with_body
    from prbm.dof import SEGMENT_MODES, ModeShape, PRBMTopology, Segment, grubler
    from prbm.domain import (
        boundary_curves,
        curved_fixed_pinned_domain,
        fit_radius,
        fixed_fixed_monotonic_domain,
        fixed_guided_domain,
        fixed_pinned_domain,
        slfp_domain,
    )
    from prbm.fits import (
        FAMILIES,
        HOWELL,
        PAULY_MIDHA,
        PURE_MOMENT_C_THETA,
        PURE_MOMENT_GAMMA,
        PURE_MOMENT_K_THETA,
        PURE_MOMENT_SPRING,
        FitFamily,
        FitRangeError,
        FitRangeWarning,
        PiecewiseFit,
        fit_family,
        load_angle,
        load_ratio,
    )
    from prbm.inflection import InflectionBeam, inflection_state, solve_displacements, solve_loads
    from prbm.builder import BeamModel, BeamRule, Geometry, PRBModel, Rules, build
    from prbm.mechanisms import FourBar, SliderCrank
    from prbm.network import (
        GROUND,
        Couple,
        Force,
        LockedNetwork,
        Network,
        NetworkResult,
        Pin,
        PrescribedDisplacement,
        PrescribedRotation,
        Slider,
        TorsionSpring,
        solve,
        trace,
    )
    from prbm.prescribed import LoadForMotion, fixed_guided_displaced_tip, load_for_motion
    from prbm.result import PRBMResult
    from prbm.turning_loads import (
        DeadDirection,
        FollowerDirection,
        TipPose,
        TowardPoint,
        fixed_pinned_turning_tip,
        input_angle_under_turning_forces,
    )
    from prbm.segments import (
        curved_fixed_pinned_tip,
        curved_pinned_pinned,
        fixed_guided_monotonic_tip,
        fixed_guided_tip,
        fixed_pinned_from_tip,
        fixed_pinned_tip,
        pure_moment_from_tip,
        pure_moment_tip,
        slfp_end_tip,
        slfp_tip,
        spring_angle,
    )

__all__ = [
    "capstan_factor",
    "composite_beam_tip",
    "layered_bending_stiffness",
    "BodyLoad",
    "body_end_loads",
    "inflection_pivots",
    "solve_segment_with_body",
    "SEGMENT_MODES",
    "ModeShape",
    "PRBMTopology",
    "Segment",
    "grubler",
    "boundary_curves",
    "curved_fixed_pinned_domain",
    "fit_radius",
    "fixed_fixed_monotonic_domain",
    "fixed_guided_domain",
    "fixed_pinned_domain",
    "slfp_domain",
    "FAMILIES",
    "HOWELL",
    "PAULY_MIDHA",
    "PURE_MOMENT_C_THETA",
    "PURE_MOMENT_GAMMA",
    "PURE_MOMENT_K_THETA",
    "PURE_MOMENT_SPRING",
    "FitFamily",
    "FitRangeError",
    "FitRangeWarning",
    "PiecewiseFit",
    "fit_family",
    "load_angle",
    "load_ratio",
    "InflectionBeam",
    "inflection_state",
    "solve_displacements",
    "solve_loads",
    "FourBar",
    "SliderCrank",
    "PRBMResult",
    "LoadForMotion",
    "fixed_guided_displaced_tip",
    "load_for_motion",
    "BeamModel",
    "BeamRule",
    "Geometry",
    "PRBModel",
    "Rules",
    "build",
    "GROUND",
    "Couple",
    "Force",
    "LockedNetwork",
    "Network",
    "NetworkResult",
    "Pin",
    "PrescribedDisplacement",
    "PrescribedRotation",
    "Slider",
    "TorsionSpring",
    "solve",
    "trace",
    "curved_fixed_pinned_tip",
    "curved_pinned_pinned",
    "fixed_guided_monotonic_tip",
    "fixed_guided_tip",
    "fixed_pinned_from_tip",
    "fixed_pinned_tip",
    "pure_moment_from_tip",
    "pure_moment_tip",
    "slfp_end_tip",
    "slfp_tip",
    "spring_angle",
    "DeadDirection",
    "FollowerDirection",
    "TipPose",
    "TowardPoint",
    "fixed_pinned_turning_tip",
    "input_angle_under_turning_forces",
]

_EXPORTS = {  # public name -> the module that defines it (imported at the first use of a name)
    **dict.fromkeys(("capstan_factor", "composite_beam_tip", "layered_bending_stiffness"), "prbm.composite"),
    **dict.fromkeys(
        ("BodyLoad", "body_end_loads", "inflection_pivots", "solve_segment_with_body"), "prbm.coupled_segment"
    ),
    **dict.fromkeys(("SEGMENT_MODES", "ModeShape", "PRBMTopology", "Segment", "grubler"), "prbm.dof"),
    **dict.fromkeys(
        (
            "boundary_curves",
            "curved_fixed_pinned_domain",
            "fit_radius",
            "fixed_fixed_monotonic_domain",
            "fixed_guided_domain",
            "fixed_pinned_domain",
            "slfp_domain",
        ),
        "prbm.domain",
    ),
    **dict.fromkeys(
        (
            "FAMILIES",
            "HOWELL",
            "PAULY_MIDHA",
            "PURE_MOMENT_C_THETA",
            "PURE_MOMENT_GAMMA",
            "PURE_MOMENT_K_THETA",
            "PURE_MOMENT_SPRING",
            "FitFamily",
            "FitRangeError",
            "FitRangeWarning",
            "PiecewiseFit",
            "fit_family",
            "load_angle",
            "load_ratio",
        ),
        "prbm.fits",
    ),
    **dict.fromkeys(("InflectionBeam", "inflection_state", "solve_displacements", "solve_loads"), "prbm.inflection"),
    **dict.fromkeys(("BeamModel", "BeamRule", "Geometry", "PRBModel", "Rules", "build"), "prbm.builder"),
    **dict.fromkeys(("FourBar", "SliderCrank"), "prbm.mechanisms"),
    **dict.fromkeys(
        (
            "GROUND",
            "Couple",
            "Force",
            "LockedNetwork",
            "Network",
            "NetworkResult",
            "Pin",
            "PrescribedDisplacement",
            "PrescribedRotation",
            "Slider",
            "TorsionSpring",
            "solve",
            "trace",
        ),
        "prbm.network",
    ),
    **dict.fromkeys(("PRBMResult",), "prbm.result"),
    **dict.fromkeys(("LoadForMotion", "fixed_guided_displaced_tip", "load_for_motion"), "prbm.prescribed"),
    **dict.fromkeys(
        (
            "DeadDirection",
            "FollowerDirection",
            "TipPose",
            "TowardPoint",
            "fixed_pinned_turning_tip",
            "input_angle_under_turning_forces",
        ),
        "prbm.turning_loads",
    ),
    **dict.fromkeys(
        (
            "curved_fixed_pinned_tip",
            "curved_pinned_pinned",
            "fixed_guided_monotonic_tip",
            "fixed_guided_tip",
            "fixed_pinned_from_tip",
            "fixed_pinned_tip",
            "pure_moment_from_tip",
            "pure_moment_tip",
            "slfp_end_tip",
            "slfp_tip",
            "spring_angle",
        ),
        "prbm.segments",
    ),
}


def __getattr__(name: str) -> object:
    """PEP 562: a public name imports its module on first use (``import prbm`` alone imports no
    solver, so scipy.optimize is loaded only by the models that need it)."""
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'prbm' has no attribute '{name}'")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
