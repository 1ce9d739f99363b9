"""Exact references for planar compliant segments: elliptic-integral solutions and a shooting solver.

Elliptic results are normalised by the length and EI; shooting results are in the problem's units;
angles in radians everywhere (degrees only in case files and reports).

>>> import elastica
>>> round(float(elastica.cantilever_tip_load(10.0).b), 5)    # b/L at P L^2/EI = 10 (exact: 0.810609)
0.81061
>>> elastica.cantilever_tip_load(0.0).b                       # no load: undeformed
0.0
>>> tip = elastica.solve_elastica(1.0, 1.0, force=(0.0, 10.0))
>>> tip.converged, round(tip.y, 5)
(True, 0.81061)
"""

from elastica.elliptic import (
    EllipticTip,
    cantilever_tip_load,
    curved_fixed_pinned_from_angle,
    curved_fixed_pinned_tip,
    fixed_guided_inflection_from_angle,
    fixed_guided_inflection_tips,
    fixed_guided_monotonic_tip,
    fixed_pinned_from_angle,
    fixed_pinned_tip,
    pure_moment_tip,
    slfp_tip,
)
from elastica.shooting import (
    ElasticaProblem,
    ElasticaResult,
    MomentConstraint,
    PointedForce,
    TipConstraint,
    dead_equivalent,
    line_angles,
    loaded_start,
    pointing_error,
    section_moment,
    solve_elastica,
    solve_path,
    unloaded_tip,
)

__all__ = [
    "EllipticTip",
    "cantilever_tip_load",
    "curved_fixed_pinned_from_angle",
    "curved_fixed_pinned_tip",
    "fixed_guided_inflection_from_angle",
    "fixed_guided_inflection_tips",
    "fixed_guided_monotonic_tip",
    "fixed_pinned_from_angle",
    "fixed_pinned_tip",
    "pure_moment_tip",
    "slfp_tip",
    "ElasticaProblem",
    "ElasticaResult",
    "MomentConstraint",
    "PointedForce",
    "TipConstraint",
    "dead_equivalent",
    "line_angles",
    "loaded_start",
    "pointing_error",
    "section_moment",
    "solve_elastica",
    "solve_path",
    "unloaded_tip",
]
