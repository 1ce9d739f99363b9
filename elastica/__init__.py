"""Exact references for planar compliant segments: elliptic-integral solutions and a shooting solver."""
from elastica.elliptic import (EllipticTip, cantilever_tip_load, curved_fixed_pinned_from_angle,
                               curved_fixed_pinned_tip, fixed_guided_inflection_from_angle,
                               fixed_guided_inflection_tips, fixed_guided_monotonic_tip,
                               fixed_pinned_from_angle, fixed_pinned_tip, pure_moment_tip, slfp_tip)
from elastica.shooting import (ElasticaProblem, ElasticaResult, MomentConstraint, TipConstraint,
                               loaded_start, section_moment, solve_elastica, solve_path,
                               unloaded_tip)

__all__ = ["EllipticTip", "cantilever_tip_load", "curved_fixed_pinned_from_angle",
           "curved_fixed_pinned_tip", "fixed_guided_inflection_from_angle",
           "fixed_guided_inflection_tips", "fixed_guided_monotonic_tip", "fixed_pinned_from_angle",
           "fixed_pinned_tip", "pure_moment_tip", "slfp_tip", "ElasticaProblem", "ElasticaResult",
           "MomentConstraint", "TipConstraint", "loaded_start", "section_moment", "solve_elastica",
           "solve_path", "unloaded_tip"]
